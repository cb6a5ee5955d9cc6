//! Bit sets over the pieces of the problem's last function, for searches where it has
//! a one-cell grid and no [`LastIndex`](super::last_index::LastIndex) (the function
//! above it is one cell too: two waypoints, say).
//!
//! Without them every node at the last level tests every piece for intersection.
//! With them a node's candidates are the AND, over the dimensions, of "pieces whose
//! low end is at most the node's high end" and "pieces whose high end is at least the
//! node's low end": exactly the pieces meeting the node, visited in increasing bit
//! order, which is array order, the one-cell grid order. The same leaves in the same
//! order: nothing of the search changes.

/// Largest piece count indexed (the candidates of a node live on the stack).
const MAX_PIECES: usize = 64 * WORDS;
const WORDS: usize = 4;

#[derive(Debug, Default)]
pub(super) struct LastBits {
    /// Whether the sets in memory were made from `key_boxes` over `key_pts`.
    made: bool,
    key_boxes: Vec<i32>,
    key_pts: Vec<i32>,
    /// Words per set.
    words: usize,
    /// Per dimension `d` at set `off[d] + v`: the pieces with `lo_d <= v`; at
    /// `off[d] + pts_d + v`: the pieces with `hi_d >= v` (`v` in `0..pts_d`).
    sets: Vec<u64>,
    off: Vec<usize>,
}

/// "lo <= v" accumulates upwards over the rows of `lo`, "hi >= v" downwards over those
/// of `hi` (`W` words a row): a running OR per word, row by row (one load, OR and store
/// per word; no index arithmetic to strength-reduce, so it stays cheap whatever the
/// compiler inlines around it).
#[inline(always)]
fn running_or<const W: usize>(lo: &mut [u64], hi: &mut [u64]) {
    let mut acc = [0u64; W];
    for row in lo.chunks_exact_mut(W) {
        for (a, x) in acc.iter_mut().zip(row) {
            *a |= *x;
            *x = *a;
        }
    }
    let mut acc = [0u64; W];
    for row in hi.chunks_exact_mut(W).rev() {
        for (a, x) in acc.iter_mut().zip(row) {
            *a |= *x;
            *x = *a;
        }
    }
}

impl LastBits {
    /// Make (or keep, for the same boxes and points) the sets of `n` pieces `boxes`
    /// (problem order) over a domain of `pts` points. False, and no sets, when `n` is
    /// beyond [`MAX_PIECES`] or a box is empty or leaves the domain.
    pub(super) fn make(&mut self, boxes: &[i32], n: usize, pts: &[i32]) -> bool {
        let dim = pts.len();
        if n == 0 || n > MAX_PIECES || boxes.len() < n * 2 * dim {
            self.made = false;
            return false;
        }
        let boxes = &boxes[..n * 2 * dim];
        if self.made && self.key_pts == pts && self.key_boxes == boxes {
            return true;
        }
        self.made = false;
        let inside = boxes.chunks_exact(2 * dim).all(|b| {
            (0..dim).all(|d| 0 <= b[2 * d] && b[2 * d] <= b[2 * d + 1] && b[2 * d + 1] < pts[d])
        });
        if !inside {
            return false;
        }
        self.key_boxes.clear();
        self.key_boxes.extend_from_slice(boxes);
        self.key_pts.clear();
        self.key_pts.extend_from_slice(pts);
        let words = n.div_ceil(64);
        self.words = words;
        self.off.clear();
        let mut total = 0;
        for &p in pts {
            self.off.push(total);
            total += 2 * p as usize;
        }
        self.sets.clear();
        self.sets.resize(total * words, 0);
        for (d, &p) in pts.iter().enumerate() {
            let (p, base) = (p as usize, self.off[d]);
            for (k, b) in boxes.chunks_exact(2 * dim).enumerate() {
                let bit = 1u64 << (k % 64);
                self.sets[(base + b[2 * d] as usize) * words + k / 64] |= bit;
                self.sets[(base + p + b[2 * d + 1] as usize) * words + k / 64] |= bit;
            }
            let (lo, hi) = self.sets[base * words..(base + 2 * p) * words].split_at_mut(p * words);
            // The word count made a constant: a row is a fixed-size array, no check per row.
            match words {
                1 => running_or::<1>(lo, hi),
                2 => running_or::<2>(lo, hi),
                3 => running_or::<3>(lo, hi),
                _ => running_or::<WORDS>(lo, hi),
            }
        }
        self.made = true;
        true
    }

    /// Words per set of the sets made.
    pub(super) fn words(&self) -> usize {
        self.words
    }

    /// The pieces meeting box `b` into `out` (bit `k` of word `k / 64` = piece `k`);
    /// false when `b` leaves the domain (then `out` means nothing).
    #[inline]
    pub(super) fn meeting(&self, b: &[i32], out: &mut [u64; WORDS]) -> bool {
        // The word count made a constant: each set read as one array (one check).
        match self.words {
            1 => self.meeting_w::<1>(b, out),
            2 => self.meeting_w::<2>(b, out),
            3 => self.meeting_w::<3>(b, out),
            _ => self.meeting_w::<WORDS>(b, out),
        }
    }

    /// [`LastBits::meeting`] with `W == self.words`.
    #[inline(always)]
    fn meeting_w<const W: usize>(&self, b: &[i32], out: &mut [u64; WORDS]) -> bool {
        let set = |i: usize| -> Option<&[u64; W]> { self.sets.get(i * W..)?.first_chunk() };
        // (A constant length: stores, no call to fill a slice. The other words are
        // left as they are.)
        out[..W].fill(u64::MAX);
        for ((bd, &p), &base) in b.chunks_exact(2).zip(&self.key_pts).zip(&self.off) {
            let (lo, hi) = (bd[0], bd[1]);
            if lo < 0 || hi >= p || lo > hi {
                return false;
            }
            let (Some(low_ok), Some(high_ok)) = (
                set(base + hi as usize),
                set(base + p as usize + lo as usize),
            ) else {
                return false;
            };
            for w in 0..W {
                out[w] &= low_ok[w] & high_ok[w];
            }
        }
        true
    }
}
