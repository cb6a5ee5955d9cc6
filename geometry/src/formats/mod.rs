//! Every geometry string format of geometry-formats.md §4–§6, one module per format.
//! The entry points (`parse_polygon`, `parse_seglist`, `parse_point`) dispatch here.

pub(crate) mod abbreviated;
pub(crate) mod attr;
pub(crate) mod bowtie;
pub(crate) mod ellipse;
pub(crate) mod lawnmower;
pub(crate) mod oval;
pub(crate) mod point;
pub(crate) mod pylon;
pub(crate) mod radial;
pub(crate) mod standard;
pub(crate) mod wedge;
pub(crate) mod zigzag;

use crate::angles::{angle360, deg_to_radians};
use crate::polygon::Polygon;
use crate::spec::Vertex;
use crate::text::{bite_x, split_q};

/// The most vertices a generator may produce; more makes the string invalid. The C++
/// generators have no limit and, with counts this large, effectively hang (an O(n²)
/// convexity test, or an accumulated bearing that stops advancing).
pub(crate) const MAX_VERTICES: usize = 10_000;

/// A vertex with z stored only when it is not 0 (z = 0 is never printed).
pub(crate) fn vertex(x: f64, y: f64, z: f64) -> Vertex {
    Vertex {
        x,
        y,
        z: (z != 0.0).then_some(z),
    }
}

/// `project` of §2.4: compass bearing, exact on the four axes.
pub(crate) fn project(deg: f64, dist: f64, cx: f64, cy: f64) -> (f64, f64) {
    crate::points::project_point(deg, dist, cx, cy)
}

/// `projectRaw` of §2.4: like [`project`] without the axis special cases.
pub(crate) fn project_raw(deg: f64, dist: f64, cx: f64, cy: f64) -> (f64, f64) {
    let deg = if !(0.0..360.0).contains(&deg) {
        angle360(deg)
    } else {
        deg
    };
    let r = deg_to_radians(deg);
    (cx + r.sin() * dist, cy + r.cos() * dist)
}

pub(crate) use crate::points::snap;

/// The `key=value` items of the keyed generators: quote/brace-aware split on commas,
/// keys lower-cased and trimmed, values trimmed.
pub(crate) fn keyed_items(text: &str) -> impl Iterator<Item = (String, &str)> {
    split_q(text, ',').into_iter().map(|item| {
        let (k, v) = bite_x(item, '=');
        (k.to_ascii_lowercase(), v)
    })
}

/// A generated polygon: convexity computed, the snap applied with undo (§3.5); `None`
/// unless convex.
pub(crate) fn finish_convex(mut poly: Polygon, snap_value: f64) -> Option<Polygon> {
    poly.apply_snap(snap_value);
    poly.is_convex().then_some(poly)
}

/// What a keyed generator returns on failure: nothing, or the empty inactive polygon
/// when an `active=false` item was seen (radial and ellipse, §4.4).
pub(crate) fn failed(inactive: bool) -> Option<Polygon> {
    inactive.then(|| {
        let mut p = Polygon::new(Vec::new());
        p.attrs.active = Some(false);
        p
    })
}
