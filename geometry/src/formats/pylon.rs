//! Pylon polygons `pylon: x1=…, y1=…, x2=…, y2=…, axis_pad=…, perp_pad=…` (§4.9): a
//! rectangle around a segment. `format` is not a key, so `format=pylon` never works.

use super::{finish_convex, keyed_items, project, vertex};
use crate::angles::rel_ang;
use crate::polygon::Polygon;
use crate::spec::Attrs;
use crate::text::{atof, is_number};

pub(crate) fn polygon(text: &str) -> Option<Polygon> {
    let (mut x1, mut y1, mut x2, mut y2, mut z) = (None, None, None, None, 0.0);
    let (mut axis_pad, mut perp_pad, mut snap) = (None, None, 0.0);
    let mut attrs = Attrs::default();
    for (key, value) in keyed_items(text) {
        let num = is_number(value);
        let v = atof(value);
        match key.as_str() {
            "x1" if num => x1 = Some(v),
            "y1" if num => y1 = Some(v),
            "x2" if num => x2 = Some(v),
            "y2" if num => y2 = Some(v),
            "z" if num => z = v,
            "axis_pad" if num => axis_pad = Some(v).filter(|p| *p >= 0.0).or(axis_pad),
            "perp_pad" if num => perp_pad = Some(v).filter(|p| *p >= 0.0).or(perp_pad),
            "snap" | "snap_value" if num && v > 0.0 => snap = v,
            _ => {
                if !attrs.set_attr(&key, value) {
                    return None;
                }
            }
        }
    }
    let (x1, y1, x2, y2, axis, perp) = (x1?, y1?, x2?, y2?, axis_pad?, perp_pad?);
    let a = rel_ang(x1, y1, x2, y2);
    let (bx, by) = project(a - 180.0, axis, x1, y1);
    let (fx, fy) = project(a, axis, x2, y2);
    let corners = [
        project(a - 90.0, perp, bx, by),
        project(a + 90.0, perp, bx, by),
        project(a + 90.0, perp, fx, fy),
        project(a - 90.0, perp, fx, fy),
    ];
    let mut poly = Polygon::new(corners.iter().map(|&(x, y)| vertex(x, y, z)).collect());
    poly.attrs = attrs;
    finish_convex(poly, snap)
}
