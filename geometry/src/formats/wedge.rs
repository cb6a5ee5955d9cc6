//! Pie wedges (`format=wedge|piewedge`, `wedge:`, `piewedge:`, §4.7) and range wedges
//! (`format=rangewedge`, `rangewedge:`, §4.8). Arcs run clockwise from `lang` to `rang`.

use super::{finish_convex, keyed_items, project, vertex, MAX_VERTICES};
use crate::angles::angle360;
use crate::polygon::Polygon;
use crate::spec::{Attrs, Vertex};
use crate::text::{atof, atoi, is_number};

/// The items both wedges share.
#[derive(Default)]
struct WedgeItems {
    x: Option<f64>,
    y: Option<f64>,
    lang: Option<f64>,
    rang: Option<f64>,
    range: Option<f64>,
    range_min: f64,
    range_max: Option<f64>,
    pts: i64,
    snap: f64,
    attrs: Attrs,
}

/// `formats` are the accepted `format=` values; `ranged` selects the range-wedge keys.
fn items(text: &str, formats: &[&str], ranged: bool) -> Option<WedgeItems> {
    let mut w = WedgeItems::default();
    for (key, value) in keyed_items(text) {
        let num = is_number(value);
        let v = atof(value);
        match key.as_str() {
            "format" if formats.contains(&value) => {}
            "format" => return None,
            "x" if num => w.x = Some(v),
            "y" if num => w.y = Some(v),
            "lang" if num => w.lang = Some(v),
            "rang" if num => w.rang = Some(v),
            "range" if num && !ranged => w.range = Some(v),
            "range_min" if num && ranged => w.range_min = v,
            "range_max" if num && ranged => w.range_max = Some(v),
            "pts" if num => {
                let n = atoi(value);
                if n >= 0 {
                    w.pts = n;
                }
            }
            "snap" | "snap_value" if num && v > 0.0 => w.snap = v,
            _ => {
                if !w.attrs.set_attr(&key, value) {
                    return None;
                }
            }
        }
    }
    Some(w)
}

/// `(L, R, delta)`: R unwrapped past L, the arc divided into `pts` steps.
fn arc(lang: f64, rang: f64, pts: i64) -> (f64, f64, f64) {
    let l = angle360(lang);
    let mut r = angle360(rang);
    if r < l {
        r += 360.0;
    }
    let delta = if r > l { (r - l) / pts as f64 } else { 0.0 };
    (l, r, delta)
}

/// Points of the arc from L to R at `range`, after the first one (accumulated bearing).
fn arc_forward(pts: &mut Vec<Vertex>, (l, r, delta): (f64, f64, f64), range: f64, x: f64, y: f64) {
    let mut b = l;
    while b < r && pts.len() <= MAX_VERTICES {
        b += delta;
        if b > r {
            b = r;
        }
        let (px, py) = project(b, range, x, y);
        pts.push(vertex(px, py, 0.0));
    }
}

/// §4.7.
pub(crate) fn pie(text: &str) -> Option<Polygon> {
    let w = items(text, &["wedge", "piewedge"], false)?;
    let (x, y, lang, rang, range) = (w.x?, w.y?, w.lang?, w.rang?, w.range?);
    let a = arc(lang, rang, w.pts);
    let mut pts = vec![vertex(x, y, 0.0)];
    let (px, py) = project(a.0, range, x, y);
    pts.push(vertex(px, py, 0.0));
    arc_forward(&mut pts, a, range, x, y);
    if pts.len() > MAX_VERTICES {
        return None;
    }
    let mut poly = Polygon::new(pts);
    poly.attrs = w.attrs;
    finish_convex(poly, w.snap)
}

/// §4.8.
pub(crate) fn range(text: &str) -> Option<Polygon> {
    let w = items(text, &["rangewedge"], true)?;
    let (x, y, lang, rang, range_max) = (w.x?, w.y?, w.lang?, w.rang?, w.range_max?);
    if w.range_min >= range_max {
        return None;
    }
    let (l, r, delta) = arc(lang, rang, w.pts);
    let mut pts = Vec::new();
    let (px, py) = project(l, range_max, x, y);
    pts.push(vertex(px, py, 0.0));
    arc_forward(&mut pts, (l, r, delta), range_max, x, y);
    let (px, py) = project(r, w.range_min, x, y);
    pts.push(vertex(px, py, 0.0));
    let mut b = r;
    while b > l && pts.len() <= MAX_VERTICES {
        b -= delta;
        if b < l {
            b = l;
        }
        let (px, py) = project(b, w.range_min, x, y);
        pts.push(vertex(px, py, 0.0));
    }
    if pts.len() > MAX_VERTICES {
        return None;
    }
    let mut poly = Polygon::new(pts);
    poly.attrs = w.attrs;
    finish_convex(poly, w.snap)
}
