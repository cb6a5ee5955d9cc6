//! Ellipse polygons: `format=ellipse, …`, `ellipse:: …`, `ellipse: …` (§4.6). The
//! rotation is mathematical (counter-clockwise from +x), not a compass bearing.

use super::{failed, finish_convex, keyed_items, vertex, MAX_VERTICES};
use crate::angles::deg_to_radians;
use crate::polygon::Polygon;
use crate::spec::Attrs;
use crate::text::{atof, atoi, is_number};
use std::f64::consts::PI;

pub(crate) fn polygon(text: &str) -> Option<Polygon> {
    let (mut x, mut y, mut z) = (None, None, 0.0);
    let (mut major, mut minor, mut rads, mut degs) = (None, None, None, None);
    let (mut pts, mut snap) = (None, 0.0);
    let mut inactive = false;
    let mut attrs = Attrs::default();
    for (key, value) in keyed_items(text) {
        let num = is_number(value);
        let v = atof(value);
        match key.as_str() {
            "format" if value == "ellipse" => {}
            "format" => return failed(inactive),
            "active" if value.eq_ignore_ascii_case("false") => inactive = true,
            "x" if num => x = Some(v),
            "y" if num => y = Some(v),
            "z" if num => z = v,
            "major" if num => major = Some(v).filter(|m| *m > 0.0).or(major),
            "minor" if num => minor = Some(v).filter(|m| *m > 0.0).or(minor),
            "rads" if num => rads = Some(v),
            "degs" if num => degs = Some(v),
            "pts" if num => pts = Some(atoi(value)).filter(|n| *n >= 4).or(pts),
            "snap" | "snap_value" if num && v > 0.0 => snap = v,
            _ => {
                if !attrs.set_attr(&key, value) {
                    return failed(inactive);
                }
            }
        }
    }
    let (Some(x), Some(y), Some(major), Some(minor), Some(n)) = (x, y, major, minor, pts) else {
        return failed(inactive);
    };
    let Some(r) = rads.or_else(|| degs.map(deg_to_radians)) else {
        return failed(inactive);
    };
    if n > MAX_VERTICES as i64 {
        return failed(inactive);
    }
    let (h, k) = (major / 2.0, minor / 2.0);
    let step = (2.0 * PI) / n as f64;
    let verts = (0..n)
        .map(|i| {
            let a = -PI + i as f64 * step;
            let px = x + ((h * a.cos()) * r.cos()) - ((k * a.sin()) * r.sin());
            let py = y + ((k * a.sin()) * r.cos()) + ((h * a.cos()) * r.sin());
            vertex(px, py, z)
        })
        .collect();
    let mut poly = Polygon::new(verts);
    poly.attrs = attrs;
    if inactive {
        poly.attrs.active = Some(false);
    }
    finish_convex(poly, snap).or_else(|| failed(inactive))
}
