#![no_main]
//! Arbitrary bytes as point, seglist, polygon and colour strings: never panics; a
//! parsed polygon's methods never panic either.

use geometry::{is_color, parse_point, parse_polygon, parse_seglist, point_spec, seglist_spec};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let _ = is_color(&text);
    if let Some(sl) = parse_seglist(&text) {
        let _ = parse_seglist(&seglist_spec(&sl.pts, 3, &sl.attrs));
    }
    if let Some(mut poly) = parse_polygon(&text) {
        let _ = parse_polygon(&poly.spec(3));
        let _ = poly.is_convex();
        let (cx, cy) = poly.center();
        let _ = poly.contains(cx, cy);
        let _ = poly.dist_to_poly(cx + 1.0, cy - 1.0);
        for i in 0..poly.size() {
            let _ = poly.vertex_is_viewable(i, cx, cy);
        }
        poly.grow_radius(1.0);
        poly.apply_snap(0.5);
        poly.reverse();
    }
    if let Some(p) = parse_point(&text) {
        let _ = parse_point(&point_spec(p.x, p.y, p.z, &p.attrs));
    }
});
