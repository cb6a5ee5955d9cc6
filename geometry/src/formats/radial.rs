//! Radial polygons: the keyed `format=radial, …` / `radial:: …` form (§4.4) and the
//! short `radial: x, y, radius, pts[, snap[, label]]` form (§4.5).

use super::{failed, finish_convex, keyed_items, project, vertex, MAX_VERTICES};
use crate::polygon::Polygon;
use crate::spec::{Attrs, Vertex};
use crate::text::{atof, atoi, is_number, split, trim};

/// Vertices at bearings `delta/2`, `delta/2 + delta`, … (accumulated) below 360;
/// `None` beyond [`MAX_VERTICES`].
fn ring(cx: f64, cy: f64, z: f64, radius: f64, delta: f64) -> Option<Vec<Vertex>> {
    let mut pts = Vec::new();
    let mut b = delta / 2.0;
    while b < 360.0 {
        if pts.len() >= MAX_VERTICES {
            return None;
        }
        let (x, y) = project(b, radius, cx, cy);
        pts.push(vertex(x, y, z));
        b += delta;
    }
    Some(pts)
}

/// §4.4. Any item that is not accepted makes the string invalid; an `active=false`
/// item seen before the failure makes the invalid result an empty inactive polygon.
pub(crate) fn keyed(text: &str) -> Option<Polygon> {
    let (mut x, mut y, mut z, mut sx, mut sy) = (None, None, 0.0, 0.0, 0.0);
    let (mut radius, mut pts, mut snap) = (None, None, 0.0);
    let mut inactive = false;
    let mut attrs = Attrs::default();
    for (key, value) in keyed_items(text) {
        let num = is_number(value);
        match key.as_str() {
            "format" if value == "radial" => {}
            "format" => return failed(inactive),
            "x" if num => x = Some(atof(value)),
            "y" if num => y = Some(atof(value)),
            "z" if num => z = atof(value),
            "shiftx" if num => sx = atof(value),
            "shifty" if num => sy = atof(value),
            "active" if value.eq_ignore_ascii_case("false") => inactive = true,
            "radius" if num => radius = Some(atof(value)).filter(|r| *r > 0.0).or(radius),
            "pts" if num => pts = Some(atoi(value)).filter(|n| *n >= 3).or(pts),
            "snap" if num && atof(value) > 0.0 => snap = atof(value),
            _ => {
                if !attrs.set_attr(&key, value) {
                    return failed(inactive);
                }
            }
        }
    }
    let (Some(x), Some(y), Some(radius), Some(n)) = (x, y, radius, pts) else {
        return failed(inactive);
    };
    let Some(pts) = ring(x + sx, y + sy, z, radius, 360.0 / n as f64) else {
        return failed(inactive);
    };
    let mut poly = Polygon::new(pts);
    poly.attrs = attrs;
    if inactive {
        poly.attrs.active = Some(false);
    }
    finish_convex(poly, snap).or_else(|| failed(inactive))
}

/// §4.5: no number checks (`atof`), a real-valued point count; a count that is not a
/// finite number > 0 is invalid (the C++ loops forever on a negative one).
pub(crate) fn short(text: &str) -> Option<Polygon> {
    let text = text.strip_prefix("radial:").unwrap_or(text);
    let f: Vec<&str> = split(text, ',').into_iter().map(trim).collect();
    if !(4..=6).contains(&f.len()) {
        return None;
    }
    let (x, y, radius, n) = (atof(f[0]), atof(f[1]), atof(f[2]), atof(f[3]));
    let snap = f.get(4).map_or(0.0, |s| atof(s).max(0.0));
    if radius <= 0.0 || !(n.is_finite() && n > 0.0) {
        return None;
    }
    let mut poly = Polygon::new(ring(x, y, 0.0, radius, 360.0 / n)?);
    if let Some(label) = f.get(5) {
        poly.attrs.label = label.to_string();
    }
    finish_convex(poly, snap)
}
