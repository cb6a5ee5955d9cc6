//! Zigzag seglists `zigzag: startx, starty, angle, length, period, amplitude[, snap]`
//! (§5.4). `format=zigzag, …` is always invalid: its `format` field is not a number.

use super::{project, snap, vertex, MAX_VERTICES};
use crate::objects::Seglist;
use crate::text::{atof, is_number, split};

pub(crate) fn seglist(text: &str) -> Option<Seglist> {
    let text = text.strip_prefix("zigzag:").unwrap_or(text);
    let f = split(text, ',');
    if !(6..=7).contains(&f.len()) || !f.iter().all(|v| is_number(v)) {
        return None;
    }
    let v: Vec<f64> = f.iter().map(|s| atof(s)).collect();
    let (sx, sy, angle, length, period, amplitude) = (v[0], v[1], v[2], v[3], v[4], v[5]);
    let snap_value = v.get(6).copied().unwrap_or(0.0001);
    if period <= 0.0 || amplitude <= 0.0 || length <= 0.0 || snap_value < 0.0 {
        return None;
    }
    let mut out = Seglist::default();
    out.push(vertex(sx, sy, 0.0), "");
    let (mut side, mut d) = (-90.0, period / 4.0);
    while d < length {
        if out.pts.len() >= MAX_VERTICES {
            return None;
        }
        let (ax, ay) = project(angle, d, sx, sy);
        let (px, py) = project(angle + side, amplitude, ax, ay);
        out.push(vertex(px, py, 0.0), "");
        side = -side;
        d += period / 2.0;
    }
    for p in &mut out.pts {
        p.x = snap(p.x, snap_value);
        p.y = snap(p.y, snap_value);
    }
    Some(out)
}
