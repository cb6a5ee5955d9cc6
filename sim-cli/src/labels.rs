//! A small label placer for the pictures: labels that cover neither each other nor the
//! lines they annotate.
//!
//! The picture first tells the [`Placer`] what is drawn: line segments (tracks, paths,
//! closest-approach lines, obstacle edges) and small boxes (start circles, end squares,
//! tick dots, the legend). Then it places its labels one at a time, most important
//! first. Each label has an anchor (the point it names), a clearance around the anchor
//! (the radius of the mark drawn there), a text and a [`Style`] (font size, bold, leader
//! line or not). The placer tries a fixed list of candidate spots: eight directions
//! around the anchor at a small gap, then the same eight at three larger gaps (see
//! [`GAPS`] and [`DIRECTIONS`]), each moved inside the drawing's bounds if it would
//! leave them, and takes the first spot whose estimated text box covers no placed label,
//! no segment and no box. When none is free it takes the spot with the least overlap
//! (the first of those tied), so a label is never dropped. The placed box, and the
//! leader line of a label that landed on one of the two outer rings, then count as
//! obstacles for the labels after it.
//!
//! Everything is in screen pixels (y down). There is no randomness and no hash-map
//! iteration: the same calls give the same spots, hence the same SVG bytes.
//!
//! The text box is an estimate (the pictures do not know the font's metrics): see
//! [`text_size`]. A spatial grid of [`CELL`]-pixel cells keeps long tracks cheap: a
//! candidate is tested only against the items in the cells its box covers.

/// A screen rectangle: left, top, width, height (px).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect {
    pub x: f64,
    pub y: f64,
    pub w: f64,
    pub h: f64,
}

impl Rect {
    /// The square of half-side `r` around `(x, y)`.
    pub fn around(x: f64, y: f64, r: f64) -> Rect {
        Rect {
            x: x - r,
            y: y - r,
            w: 2.0 * r,
            h: 2.0 * r,
        }
    }

    /// Area of the intersection with `o` (0 when apart or only touching).
    pub fn overlap(&self, o: &Rect) -> f64 {
        let w = (self.x + self.w).min(o.x + o.w) - self.x.max(o.x);
        let h = (self.y + self.h).min(o.y + o.h) - self.y.max(o.y);
        if w > 0.0 && h > 0.0 {
            w * h
        } else {
            0.0
        }
    }

    /// The same rectangle moved the least to lie inside `b` (its top left corner
    /// inside when it is the larger).
    fn clamped(&self, b: &Rect) -> Rect {
        Rect {
            x: self.x.min(b.x + b.w - self.w).max(b.x),
            y: self.y.min(b.y + b.h - self.h).max(b.y),
            ..*self
        }
    }

    /// Length of the part of segment `a`–`b` inside the rectangle (Liang–Barsky clip).
    pub fn clip_len(&self, a: (f64, f64), b: (f64, f64)) -> f64 {
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        let edges = [
            (-dx, a.0 - self.x),
            (dx, self.x + self.w - a.0),
            (-dy, a.1 - self.y),
            (dy, self.y + self.h - a.1),
        ];
        for (p, q) in edges {
            if p == 0.0 {
                if q < 0.0 {
                    return 0.0;
                }
            } else {
                let t = q / p;
                if p < 0.0 {
                    t0 = t0.max(t);
                } else {
                    t1 = t1.min(t);
                }
            }
        }
        if t1 > t0 {
            (t1 - t0) * dx.hypot(dy)
        } else {
            0.0
        }
    }
}

/// How a label is drawn, as far as placing it goes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Style {
    /// Font size (px).
    pub size: f64,
    pub bold: bool,
    /// Draw a leader line when the label lands far from its anchor.
    pub leader: bool,
}

/// The estimated box of `text` at `size` px: width = characters × average glyph width,
/// the average being 0.56 em for regular Helvetica/Arial (digits are 0.556 em, lower
/// case letters about 0.5, the colon and dot 0.28) and 0.6 em for bold; height = 0.97 em
/// (ascent 0.75 em above the baseline, descent 0.22 em below). Plus 1.5 px on every side
/// for the white halo (stroke width 3).
pub fn text_size(text: &str, size: f64, bold: bool) -> (f64, f64) {
    let em = if bold { 0.6 } else { 0.56 };
    let n = text.chars().count() as f64;
    (n * em * size + 3.0, 0.97 * size + 3.0)
}

/// Baseline offset of a text from the top of its estimated box (halo pad + ascent).
fn ascent(size: f64) -> f64 {
    1.5 + 0.75 * size
}

/// Gaps (px) between the anchor's clearance and the box: near first, then farther.
const GAPS: [f64; 4] = [2.0, 8.0, 18.0, 32.0];

/// Directions tried at each gap, as (x, y) signs (y down): below right first (where the
/// pictures used to put the time), then above right, right, left, the other diagonals,
/// below and above.
const DIRECTIONS: [(i8, i8); 8] = [
    (1, 1),
    (1, -1),
    (1, 0),
    (-1, 0),
    (-1, -1),
    (-1, 1),
    (0, 1),
    (0, -1),
];

/// A segment covered by a box counts this much per pixel of length (the area of a 3 px
/// wide line plus its label's halo) in the least-overlap choice.
const SEGMENT_WEIGHT: f64 = 4.0;
/// Side of a grid cell (px).
const CELL: f64 = 32.0;

#[derive(Clone, Copy, Debug)]
enum Item {
    Segment((f64, f64), (f64, f64)),
    Mark(Rect),
    Label(Rect),
}

/// A placed label: its text's baseline start (`x`, `y`, for `text-anchor="start"`), its
/// estimated box, and a leader line (from the edge of the anchor's clearance to the
/// nearest point of the box) when its style asks for one and the box is off the near
/// spots (gap index 2 or more), where a reader may need it to tell which mark the label
/// names.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placed {
    pub x: f64,
    pub y: f64,
    pub rect: Rect,
    pub leader: Option<((f64, f64), (f64, f64))>,
}

/// The leader line from `anchor` (clearance `clear`) to the box `r`, if it is far.
fn leader(r: &Rect, anchor: (f64, f64), clear: f64) -> Option<((f64, f64), (f64, f64))> {
    let to = (
        anchor.0.clamp(r.x + 1.5, r.x + r.w - 1.5),
        anchor.1.clamp(r.y + 1.5, r.y + r.h - 1.5),
    );
    let (dx, dy) = (to.0 - anchor.0, to.1 - anchor.1);
    let d = dx.hypot(dy);
    (d > clear + 2.0).then(|| ((anchor.0 + dx * clear / d, anchor.1 + dy * clear / d), to))
}

/// See the module documentation.
pub struct Placer {
    bounds: Rect,
    items: Vec<Item>,
    cols: usize,
    rows: usize,
    /// Indices into `items`, per grid cell (row-major).
    grid: Vec<Vec<usize>>,
}

impl Placer {
    /// A placer whose labels must stay inside `bounds`.
    pub fn new(bounds: Rect) -> Placer {
        let cols = ((bounds.x + bounds.w) / CELL).ceil().max(1.0) as usize + 1;
        let rows = ((bounds.y + bounds.h) / CELL).ceil().max(1.0) as usize + 1;
        Placer {
            bounds,
            items: Vec::new(),
            cols,
            rows,
            grid: vec![Vec::new(); cols * rows],
        }
    }

    /// The grid cells (column and row ranges) a rectangle touches.
    fn cells(
        &self,
        r: &Rect,
    ) -> (
        std::ops::RangeInclusive<usize>,
        std::ops::RangeInclusive<usize>,
    ) {
        let c = |v: f64, n: usize| ((v / CELL).floor().max(0.0) as usize).min(n - 1);
        (
            c(r.x, self.cols)..=c(r.x + r.w, self.cols),
            c(r.y, self.rows)..=c(r.y + r.h, self.rows),
        )
    }

    fn add(&mut self, item: Item) {
        let r = match item {
            Item::Segment(a, b) => Rect {
                x: a.0.min(b.0),
                y: a.1.min(b.1),
                w: (a.0 - b.0).abs(),
                h: (a.1 - b.1).abs(),
            },
            Item::Mark(r) | Item::Label(r) => r,
        };
        let i = self.items.len();
        self.items.push(item);
        let (cs, rs) = self.cells(&r);
        for row in rs {
            for col in cs.clone() {
                self.grid[row * self.cols + col].push(i);
            }
        }
    }

    /// A polyline (screen points) labels should not cover.
    pub fn add_polyline(&mut self, pts: &[(f64, f64)]) {
        for w in pts.windows(2) {
            self.add(Item::Segment(w[0], w[1]));
        }
    }

    /// A mark (circle, square, dot: its bounding box) labels should not cover.
    pub fn add_mark(&mut self, r: Rect) {
        self.add(Item::Mark(r));
    }

    /// How much `r` covers: label and mark overlap areas plus segment lengths weighted.
    /// 0 when the spot is free.
    fn cost(&self, r: &Rect) -> f64 {
        let mut near: Vec<usize> = Vec::new();
        let (cs, rs) = self.cells(r);
        for row in rs {
            for col in cs.clone() {
                near.extend(&self.grid[row * self.cols + col]);
            }
        }
        near.sort_unstable();
        near.dedup();
        let mut cost = 0.0;
        for i in near {
            cost += match self.items[i] {
                Item::Segment(a, b) => SEGMENT_WEIGHT * r.clip_len(a, b),
                Item::Mark(m) | Item::Label(m) => r.overlap(&m),
            };
        }
        cost
    }

    /// Place `text` drawn in `style` near `anchor`, keeping `clear` px free around it
    /// (the radius of the mark there). See the module documentation.
    pub fn place(&mut self, anchor: (f64, f64), clear: f64, text: &str, style: Style) -> Placed {
        let (w, h) = text_size(text, style.size, style.bold);
        let (ax, ay) = anchor;
        let spot = |gap: f64, (ux, uy): (i8, i8)| {
            let d = clear + gap;
            let x = match ux {
                1 => ax + d,
                -1 => ax - d - w,
                _ => ax - w / 2.0,
            };
            let y = match uy {
                1 => ay + d,
                -1 => ay - d - h,
                _ => ay - h / 2.0,
            };
            Rect { x, y, w, h }.clamped(&self.bounds)
        };
        let mut best: Option<(f64, Rect, usize)> = None;
        'search: for (ring, gap) in GAPS.into_iter().enumerate() {
            for dir in DIRECTIONS {
                let r = spot(gap, dir);
                let c = self.cost(&r);
                if best.is_none_or(|(b, _, _)| c < b) {
                    best = Some((c, r, ring));
                    if c == 0.0 {
                        break 'search;
                    }
                }
            }
        }
        let (rect, ring) = best.map_or((spot(GAPS[0], DIRECTIONS[0]), 0), |(_, r, i)| (r, i));
        self.add(Item::Label(rect));
        // Far labels get a leader, which the labels placed later avoid too.
        let leader = leader(&rect, anchor, clear).filter(|_| style.leader && ring >= 2);
        if let Some((a, b)) = leader {
            self.add(Item::Segment(a, b));
        }
        Placed {
            x: rect.x + 1.5,
            y: rect.y + ascent(style.size),
            rect,
            leader,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TICK: Style = Style {
        size: 9.0,
        bold: false,
        leader: true,
    };
    const NAME: Style = Style {
        size: 12.0,
        bold: true,
        leader: false,
    };

    /// Whether `r` lies inside `b` (to rounding).
    fn inside(r: &Rect, b: &Rect) -> bool {
        let e = 1e-9;
        r.x >= b.x - e && r.y >= b.y - e && r.x + r.w <= b.x + b.w + e && r.y + r.h <= b.y + b.h + e
    }

    fn big() -> Rect {
        Rect {
            x: 0.0,
            y: 0.0,
            w: 900.0,
            h: 700.0,
        }
    }

    #[test]
    fn two_labels_at_one_anchor_get_disjoint_boxes() {
        let mut p = Placer::new(big());
        let a = p.place((300.0, 300.0), 3.0, "1:40", TICK);
        let b = p.place((300.0, 300.0), 3.0, "1:40", TICK);
        assert_eq!(a.rect.overlap(&b.rect), 0.0, "{a:?} {b:?}");
        assert_ne!(a, b);
    }

    #[test]
    fn a_label_on_a_segment_moves_off_it() {
        // A track going down-right through where the first spot (below right) would be.
        let mut p = Placer::new(big());
        let track = [(300.0, 300.0), (400.0, 340.0)];
        let mut q = Placer::new(big());
        let default = q.place((300.0, 300.0), 3.0, "1:40", TICK);
        assert!(
            default.rect.clip_len(track[0], track[1]) > 0.0,
            "the test's premise"
        );
        p.add_polyline(&track);
        let moved = p.place((300.0, 300.0), 3.0, "1:40", TICK);
        assert_eq!(moved.rect.clip_len(track[0], track[1]), 0.0, "{moved:?}");
    }

    #[test]
    fn labels_stay_inside_the_bounds() {
        let mut p = Placer::new(big());
        let l = p.place((895.0, 695.0), 3.0, "a long label", NAME);
        assert!(inside(&l.rect, &big()), "{l:?}");
    }

    #[test]
    fn placement_is_deterministic() {
        let run = || {
            let mut p = Placer::new(big());
            p.add_polyline(&[(100.0, 600.0), (300.0, 100.0), (500.0, 400.0)]);
            p.add_mark(Rect::around(300.0, 100.0, 8.0));
            (0..40)
                .map(|i| {
                    let t = i as f64 / 40.0;
                    p.place((100.0 + 400.0 * t, 600.0 - 300.0 * t), 3.0, "12:34", TICK)
                })
                .collect::<Vec<_>>()
        };
        assert_eq!(run(), run());
    }

    #[test]
    fn a_crowded_spot_keeps_every_label() {
        // Sixty labels on one anchor in a small box: no free spot for most of them, yet
        // each gets a spot, inside the bounds.
        let bounds = Rect {
            x: 0.0,
            y: 0.0,
            w: 200.0,
            h: 150.0,
        };
        let mut p = Placer::new(bounds);
        p.add_polyline(&[(0.0, 75.0), (200.0, 75.0)]);
        let placed: Vec<Placed> = (0..60)
            .map(|i| p.place((100.0, 75.0), 3.0, &format!("{i}:00"), TICK))
            .collect();
        assert_eq!(placed.len(), 60);
        assert!(placed.iter().all(|l| inside(&l.rect, &bounds)));
        // The first ones found free spots.
        for (i, a) in placed.iter().take(8).enumerate() {
            for b in &placed[..i] {
                assert_eq!(a.rect.overlap(&b.rect), 0.0);
            }
        }
    }

    #[test]
    fn clipping_measures_the_inside_part() {
        let r = Rect {
            x: 0.0,
            y: 0.0,
            w: 10.0,
            h: 10.0,
        };
        assert!((r.clip_len((-5.0, 5.0), (15.0, 5.0)) - 10.0).abs() < 1e-9);
        assert_eq!(r.clip_len((-5.0, 20.0), (15.0, 20.0)), 0.0);
        assert!((r.clip_len((5.0, 5.0), (5.0, 8.0)) - 3.0).abs() < 1e-9);
    }
}
