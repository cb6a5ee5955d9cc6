//! Oval (stadium) polygons `format=oval, …` / `oval: x=…, y=…, rad=…, len=…, ang=…`
//! (§4.10). Every other key is accepted and ignored: ovals carry no attributes.

use super::{project, vertex};
use crate::polygon::Polygon;
use crate::text::{atof, bite_x, split};

pub(crate) fn polygon(text: &str) -> Option<Polygon> {
    let (mut x, mut y, mut ang, mut rad, mut len) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for item in split(text, ',') {
        let (key, value) = bite_x(item, '=');
        let d = atof(value);
        match key.to_ascii_lowercase().as_str() {
            "x" => x = d,
            "y" => y = d,
            "ang" => ang = d,
            "rad" if d > 0.0 => rad = d,
            "len" if d > 0.0 => len = d,
            _ => {}
        }
    }
    if !(rad > 0.0 && len > 2.0 * rad) {
        return None;
    }
    let m = (len - 2.0 * rad) / 2.0;
    let (c1x, c1y) = project(ang, m, x, y);
    let (c2x, c2y) = project(ang - 180.0, m, x, y);
    let mut pts = Vec::with_capacity(26);
    for (base, cx, cy) in [(ang, c1x, c1y), (ang + 180.0, c2x, c2y)] {
        let mut d = -90.0;
        while d <= 90.0 {
            let (px, py) = project(base + d, rad, cx, cy);
            pts.push(vertex(px, py, 0.0));
            d += 15.0;
        }
    }
    Some(Polygon::new(pts))
}
