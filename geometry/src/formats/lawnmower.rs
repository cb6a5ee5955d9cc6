//! Lawnmower seglists `format=lawnmower, …` / `lawnmower: …` (§5.5): parallel lanes
//! over a rotated block, entered at the lane end nearest the start point and driven
//! back and forth; each lane is tagged `lane`. Unusable items are silently ignored.

use super::{keyed_items, project, project_raw, snap, vertex, MAX_VERTICES};
use crate::angles::angle360;
use crate::objects::Seglist;
use crate::spec::{Attrs, EdgeTag};
use crate::text::{atof, is_number};

pub(crate) fn seglist(text: &str) -> Option<Seglist> {
    let (mut x, mut y, mut height, mut width, mut lane) = (None, None, None, None, None);
    let (mut degs, mut ns, mut startx, mut starty, mut snap_value) =
        (0.0, false, 0.0, 0.0, 0.00001);
    let mut attrs = Attrs::default();
    for (key, value) in keyed_items(text) {
        let num = is_number(value);
        let v = atof(value);
        match key.as_str() {
            "x" if num => x = Some(v),
            "y" if num => y = Some(v),
            "height" if num => height = Some(v),
            "width" if num => width = Some(v),
            "lane_width" | "swath" if num => lane = Some(v),
            "degs" if num => degs = v,
            "rows" => {
                let r = value.to_ascii_lowercase();
                ns = r == "ns" || r == "north-south";
            }
            "startx" if num => startx = v,
            "starty" if num => starty = v,
            "snap" if num && v >= 0.0 => snap_value = v,
            "label" | "msg" | "edge_color" | "vertex_color" => {
                attrs.set_attr(&key, value);
            }
            "edge_size" | "vertex_size" if num && v >= 0.0 => {
                attrs.set_attr(&key, value);
            }
            "active" => {
                attrs.set_attr(&key, value);
            }
            _ => {}
        }
    }
    let (cx, cy, mut height, mut width, lane) = (x?, y?, height?, width?, lane?);
    if !ns {
        std::mem::swap(&mut width, &mut height);
        degs += 90.0;
    }
    let w = if width > 0.0 { width } else { 40.0 };
    let h = if height > 0.0 { height } else { 80.0 };
    let s = if lane > 0.0 { lane } else { 10.0 };
    let a = if degs >= 1.0 { degs } else { 0.0 };

    let lanes = ((w / s) + 1.0) + 0.99999;
    if lanes.is_nan() || lanes >= (MAX_VERTICES / 2) as f64 {
        return None;
    }
    let n = lanes as usize;
    let (p, q) = (angle360(a - 90.0), angle360(a + 90.0));
    let (e1, e2) = (angle360(a), angle360(a - 180.0));
    // Each lane's two ends: (end1, end2).
    let lanes: Vec<[(f64, f64); 2]> = (0..n)
        .map(|i| {
            let mut off = w / 2.0 - i as f64 * s;
            let mut bearing = p;
            if off < 0.0 {
                bearing = q;
                off = -off;
            }
            let (lx, ly) = if off == 0.0 {
                (cx, cy)
            } else {
                project(bearing, off, cx, cy)
            };
            [
                project_raw(e1, h / 2.0, lx, ly),
                project_raw(e2, h / 2.0, lx, ly),
            ]
        })
        .collect();
    if lanes.is_empty() {
        return None;
    }
    // Entry: the nearest of the first and last lanes' ends, earlier wins ties.
    let candidates = [
        (lanes[0][0], false, 0),
        (lanes[0][1], false, 1),
        (lanes[n - 1][0], true, 0),
        (lanes[n - 1][1], true, 1),
    ];
    let (mut best, mut best_d) = (0, f64::INFINITY);
    for (i, ((ex, ey), _, _)) in candidates.iter().enumerate() {
        let d = (ex - startx).hypot(ey - starty);
        if d < best_d {
            best = i;
            best_d = d;
        }
    }
    let (_, reversed, mut kind) = candidates[best];
    let mut out = Seglist {
        attrs,
        ..Seglist::default()
    };
    let order: Box<dyn Iterator<Item = &[(f64, f64); 2]>> = if reversed {
        Box::new(lanes.iter().rev())
    } else {
        Box::new(lanes.iter())
    };
    for (k, ends) in order.enumerate() {
        for end in [ends[kind], ends[1 - kind]] {
            let (ex, ey) = (snap(end.0, snap_value), snap(end.1, snap_value));
            out.push(vertex(ex, ey, 0.0), "");
        }
        out.tags.push(EdgeTag {
            from: 2 * k,
            to: 2 * k + 1,
            tag: "lane".to_string(),
        });
        kind = 1 - kind;
    }
    Some(out)
}
