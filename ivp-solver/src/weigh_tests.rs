//! The weighing passes (AVX2 and scalar) against a copy of the plain scalar loops
//! they replace, bit for bit, over random pieces full of the awkward values.

use super::*;
use ivp::function::max_val;

/// A small xorshift generator (the tests need no more).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    /// Mostly ordinary numbers, often a signed zero, NaN (several payloads and
    /// signs), an infinity or a huge or tiny value.
    fn value(&mut self) -> f64 {
        const ODD: [f64; 12] = [
            0.0,
            -0.0,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            1e308,
            -1e308,
            f64::MAX,
            f64::MIN_POSITIVE,
            -5e-324,
            1.0,
            -1.0,
        ];
        match self.below(10) {
            0..=2 => ODD[self.below(ODD.len())],
            3 => f64::from_bits(0x7ff8_0000_0000_0000 | (self.next() & 0xf_ffff)),
            4 => -f64::from_bits(0x7ff8_0000_0000_0000 | (self.next() & 0xf_ffff)),
            5 => (self.below(9) as f64 - 4.0) * 0.5,
            _ => (self.next() % 2_000_001) as f64 / 1000.0 - 1000.0,
        }
    }
    fn bound(&mut self) -> i32 {
        match self.below(8) {
            0 => [0, -1, 1, i32::MAX, i32::MIN][self.below(5)],
            _ => self.below(400) as i32,
        }
    }
}

/// The scalar extremes as they were: first piece reaching each extreme kept.
fn plain_extremes(bounds: &[i32], weights: &[f64], od: usize) -> (f64, f64) {
    let piece = |b: &[i32], w: &[f64]| {
        let (mut lo, mut hi) = (w[od], w[od]);
        for d in 0..od {
            let x = w[d];
            let (l, h) = (f64::from(b[2 * d]), f64::from(b[2 * d + 1]));
            if x < 0.0 {
                hi += x * l;
                lo += x * h;
            } else {
                hi += x * h;
                lo += x * l;
            }
        }
        (lo, hi)
    };
    let (mut mn, mut mx) = piece(bounds, weights);
    for (b, w) in bounds
        .chunks_exact(2 * od)
        .zip(weights.chunks_exact(od + 1))
        .skip(1)
    {
        let (lo, hi) = piece(b, w);
        if lo < mn {
            mn = lo;
        }
        if hi > mx {
            mx = hi;
        }
    }
    (mn, mx)
}

/// The scalar weighing as it was (any dimensions, one loop).
fn plain_weigh(
    wg: &Weighing,
    src: &[f64],
    od: usize,
    weights: &mut [f64],
    boxes: Option<&[i32]>,
    piece_ub: &mut Vec<f64>,
) -> f64 {
    piece_ub.clear();
    let dim = wg.pts.len();
    let (bl, wl) = (2 * dim, dim + 1);
    let (shift, scale, pwt) = (wg.shift, wg.scale, wg.pwt);
    let one = |w: &mut [f64], s: &[f64]| {
        if wg.norm {
            w[dim] = ((s[od] + shift) * scale) * pwt;
            for i in 0..od {
                w[wg.map[i]] = (s[i] * scale) * pwt;
            }
        } else {
            w[dim] = s[od] * pwt;
            for i in 0..od {
                w[wg.map[i]] = s[i] * pwt;
            }
        }
        let mut t = w[dim].abs();
        for d in 0..dim {
            t += w[d].abs() * f64::from((wg.pts[d] - 1).max(0));
        }
        t
    };
    let keep = |most: f64, t: f64| if t > most || t.is_nan() { t } else { most };
    let mut most = 0.0f64;
    let pieces = weights.chunks_exact_mut(wl).zip(src.chunks_exact(od + 1));
    match boxes {
        Some(b) => {
            piece_ub.resize((weights.len() / wl).min(src.len() / (od + 1)), 0.0);
            let pieces = weights.chunks_exact_mut(wl).zip(src.chunks_exact(od + 1));
            for (((w, s), b), ub) in pieces.zip(b.chunks_exact(bl)).zip(piece_ub.iter_mut()) {
                most = keep(most, one(w, s));
                *ub = max_val(&b[..bl], &w[..wl]);
            }
        }
        None => {
            for (w, s) in pieces {
                most = keep(most, one(w, s));
            }
        }
    }
    most
}

/// The values' bits, every NaN as one: which NaN an operation on two NaNs returns is
/// left to the compiler (LLVM may swap an addition's operands; even the unrolled
/// scalar loops give other NaN payloads than this plain copy, in release and debug
/// builds differently), and every NaN compares alike downstream.
fn bits(v: &[f64]) -> Vec<u64> {
    v.iter()
        .map(|x| {
            if x.is_nan() {
                f64::NAN.to_bits()
            } else {
                x.to_bits()
            }
        })
        .collect()
}

/// Random pieces: `n` of `od` dimensions (bounds, weights); `zeros` makes every
/// weight a signed zero (ties between -0.0 and +0.0 everywhere).
fn pieces(rng: &mut Rng, n: usize, od: usize, zeros: bool) -> (Vec<i32>, Vec<f64>) {
    let b = (0..2 * od * n).map(|_| rng.bound()).collect();
    let w = (0..(od + 1) * n)
        .map(|_| match zeros {
            true => [0.0, -0.0][rng.below(2)],
            false => rng.value(),
        })
        .collect();
    (b, w)
}

#[test]
fn extremes_equal_the_plain_loop_bit_for_bit() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for round in 0..20_000 {
        let od = 1 + rng.below(4);
        let n = 1 + rng.below(23);
        let (mut b, mut w) = pieces(&mut rng, n, od, round % 5 == 0);
        // Half the rounds boxes as a checked function has them: the corners are only
        // ever made from such.
        let valid = round % 4 < 2;
        if valid {
            make_checked(&mut rng, &mut b);
        }
        if round % 7 == 0 {
            // Ordinary numbers only: the lanes' ties and order matter, not NaN.
            for x in w.iter_mut().filter(|x| !x.is_finite()) {
                *x = 2.0;
            }
        }
        let want = plain_extremes(&b, &w, od);
        // The AVX2 pass also reading the boxes from their corners, made from the boxes
        // in the problem's order: the function's, or its two dimensions swapped.
        let mut made = vec![];
        let swap = round % 2 == 0;
        if od == 2 && valid && avx2() {
            let mut problem = b.clone();
            if swap {
                problem.chunks_exact_mut(4).for_each(|x| x.rotate_left(2));
            }
            // SAFETY: the CPU has AVX2.
            unsafe { corners2(&problem, &mut made) };
        }
        let corners = (!made.is_empty()).then_some((&made[..], swap));
        // The AVX2 passes read a checked function's boxes only (see `weigh_simd`).
        let simd = avx2() && valid;
        for (simd, corners) in [(false, None), (simd, None), (simd, corners)] {
            let got = extremes::<0>(&b, &w, od, simd, corners);
            assert_eq!(
                bits(&[got.0, got.1]),
                bits(&[want.0, want.1]),
                "od {od} n {n} simd {simd}: {got:?} vs {want:?}\n{b:?}\n{w:?}"
            );
        }
    }
}

#[test]
fn weigh_equals_the_plain_loop_bit_for_bit() {
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    for round in 0..20_000 {
        let dim = 1 + rng.below(3);
        // Half the rounds the hot shape: two dimensions in problem order.
        let od = if round % 2 == 0 && dim == 2 {
            2
        } else {
            1 + rng.below(dim)
        };
        let mut map: Vec<usize> = (0..dim).collect();
        if rng.below(3) == 0 {
            map.swap(0, rng.below(dim));
        }
        map.truncate(od);
        let identity = od == dim && map.iter().enumerate().all(|(d, &t)| d == t);
        let pts: Vec<i32> = (0..dim)
            .map(|_| [0, 1, 2, 41, 360, i32::MAX][rng.below(6)])
            .collect();
        let n = rng.below(23);
        let (_, src) = pieces(&mut rng, n, od, round % 5 == 0);
        let (mut boxes, _) = pieces(&mut rng, n, dim, false);
        // Half the rounds boxes as a checked function has them (see above).
        let valid = round % 4 < 2;
        if valid {
            make_checked(&mut rng, &mut boxes);
        }
        let norm = rng.below(2) == 0;
        let (shift, scale) = match round % 3 {
            0 => (rng.value(), rng.value()),
            _ => (
                rng.below(500) as f64 - 250.0,
                100.0 / (101.0 + rng.below(900) as f64),
            ),
        };
        let pwt = [rng.value(), 1.0, 0.5, 100.0][rng.below(4)];
        let wg = Weighing {
            map: &map,
            identity,
            norm,
            shift,
            scale,
            pwt,
            pts: &pts,
        };
        let old: Vec<f64> = (0..n * (dim + 1)).map(|_| rng.value()).collect();
        let with_boxes = rng.below(3) != 0;
        let b = with_boxes.then_some(&boxes[..]);
        let (mut want_w, mut want_ub) = (old.clone(), vec![7.0]);
        let want = plain_weigh(&wg, &src, od, &mut want_w, b, &mut want_ub);
        let mut made = vec![];
        if dim == 2 && valid && avx2() {
            // SAFETY: the CPU has AVX2.
            unsafe { corners2(&boxes, &mut made) };
        }
        // The AVX2 passes read a checked function's boxes only (see `weigh_simd`).
        let simd = avx2() && (valid || !with_boxes);
        for (simd, corners) in [(false, None), (simd, None), (simd, Some(&made[..]))] {
            let (mut w, mut ub) = (old.clone(), vec![7.0]);
            let got = weigh_with(&wg, &src, od, &mut w, (b, corners), &mut ub, simd);
            let what = format!("round {round} od {od} dim {dim} n {n} simd {simd}");
            assert_eq!(bits(&[got]), bits(&[want]), "{what}: {got} vs {want}");
            assert_eq!(bits(&w), bits(&want_w), "{what}: weights");
            assert_eq!(bits(&ub), bits(&want_ub), "{what}: piece_ub");
        }
    }
}

/// `boxes` (`[lo, hi]` pairs) made as a checked function has them: `0 <= lo <= hi`,
/// often with a zero bound.
fn make_checked(rng: &mut Rng, boxes: &mut [i32]) {
    for x in boxes.chunks_exact_mut(2) {
        let (l, h) = (x[0].unsigned_abs() % 400, x[1].unsigned_abs() % 400);
        x.copy_from_slice(&[l.min(h) as i32, l.max(h) as i32]);
        if rng.below(4) == 0 {
            x[0] = 0;
        }
    }
}
