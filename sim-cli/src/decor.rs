//! Layers of the one-vehicle picture (`picture.rs`): the metre grid with the
//! origin, heading arrows, and the Monte-Carlo start and end clouds. (Its labels are
//! placed by `labels.rs`.)

use std::fmt::Write as _;

use super::canvas::{nice_length, View, H, MARGIN, W};

const GRID: &str = "#e8e8e8";
const GRID_TEXT: &str = "#9a9a9a";

/// Grid lines every round number of metres over the drawing area, labelled along the
/// bottom and left edges, and the origin marked when it is in view.
pub(crate) fn grid(o: &mut String, v: &View) {
    let (left, right, top, bottom) = (MARGIN, W - MARGIN - 170.0, MARGIN, H - MARGIN);
    let (x0, y1) = v.world(left, top);
    let (x1, y0) = v.world(right, bottom);
    let step = nice_length(x1 - x0);
    // Multiples of the step from integers (no summed rounding in the labels); `+ 0.0`
    // turns a -0 into 0.
    let mut k = (x0 / step).ceil();
    while k * step <= x1 {
        let x = k * step + 0.0;
        k += 1.0;
        let (px, _) = v.p(x, 0.0);
        let _ = writeln!(
            o,
            r#"<path d="M{px:.1},{top:.1} V{bottom:.1}" stroke="{GRID}" stroke-width="1"/><text x="{px:.1}" y="{:.1}" font-size="9" fill="{GRID_TEXT}" text-anchor="middle">{x}</text>"#,
            bottom + 12.0
        );
    }
    let mut k = (y0 / step).ceil();
    while k * step <= y1 {
        let y = k * step + 0.0;
        k += 1.0;
        let (_, py) = v.p(0.0, y);
        let _ = writeln!(
            o,
            r#"<path d="M{left:.1},{py:.1} H{right:.1}" stroke="{GRID}" stroke-width="1"/><text x="{:.1}" y="{:.1}" font-size="9" fill="{GRID_TEXT}" text-anchor="end">{y}</text>"#,
            left - 4.0,
            py + 3.0
        );
    }
    if (x0..=x1).contains(&0.0) && (y0..=y1).contains(&0.0) {
        let (px, py) = v.p(0.0, 0.0);
        let _ = writeln!(
            o,
            r#"<path d="M{:.1},{py:.1} h12 M{px:.1},{:.1} v12" stroke="{GRID_TEXT}" stroke-width="1.5"/><text x="{:.1}" y="{:.1}" font-size="9" fill="{GRID_TEXT}">0,0</text>"#,
            px - 6.0,
            py - 6.0,
            px + 3.0,
            py + 11.0
        );
    }
    let _ = writeln!(
        o,
        r#"<text x="{right:.1}" y="{:.1}" font-size="9" fill="{GRID_TEXT}" text-anchor="end">m</text>"#,
        bottom + 24.0
    );
}

/// An arrow from `at` along compass `heading` (degrees).
pub(crate) fn heading_arrow(o: &mut String, v: &View, at: (f64, f64), heading: f64, color: &str) {
    let (px, py) = v.p(at.0, at.1);
    let h = heading.to_radians();
    let (dx, dy) = (h.sin(), -h.cos());
    let (tx, ty) = (px + dx * 24.0, py + dy * 24.0);
    // The head: two points 7 px back from the tip, 4 px either side.
    let (bx, by) = (tx - dx * 7.0, ty - dy * 7.0);
    let (nx, ny) = (-dy * 4.0, dx * 4.0);
    let _ = writeln!(
        o,
        r#"<path d="M{px:.1},{py:.1} L{tx:.1},{ty:.1}" stroke="{color}" stroke-width="2"/><path d="M{tx:.1},{ty:.1} L{:.1},{:.1} L{:.1},{:.1} Z" fill="{color}"/>"#,
        bx + nx,
        by + ny,
        bx - nx,
        by - ny
    );
}

/// At most about `keep` points of `t`, its last point kept.
pub(crate) fn thin(t: &[(f64, f64)], keep: usize) -> Vec<(f64, f64)> {
    let step = t.len().div_ceil(keep.max(2)).max(1);
    let mut v: Vec<(f64, f64)> = t.iter().copied().step_by(step).collect();
    if let Some(&l) = t.last() {
        if v.last() != Some(&l) {
            v.push(l);
        }
    }
    v
}

/// Every run's start and end as small dots (Monte Carlo).
pub(crate) fn clouds(o: &mut String, v: &View, tracks: &[Vec<(f64, f64)>], start: &str, end: &str) {
    for (pick, color) in [(true, start), (false, end)] {
        for t in tracks {
            let p = if pick { t.first() } else { t.last() };
            if let Some(&(x, y)) = p {
                let (px, py) = v.p(x, y);
                let _ = write!(
                    o,
                    r#"<circle cx="{px:.1}" cy="{py:.1}" r="1.8" fill="{color}" fill-opacity="0.45"/>"#
                );
            }
        }
        o.push('\n');
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thinning_keeps_the_ends() {
        let t: Vec<(f64, f64)> = (0..1000).map(|i| (i as f64, 0.0)).collect();
        let k = thin(&t, 50);
        assert!(k.len() <= 52);
        assert_eq!((k[0], *k.last().unwrap()), ((0.0, 0.0), (999.0, 0.0)));
    }
}
