//! Point (sensor) mode's geometry (obstacles.md §3.6): a random point of an obstacle's
//! boundary as seen from a vehicle — a random integer bearing within the tangent arc,
//! then the distance along that ray to the polygon.

use geometry::{angle180, angle360, project_point, rel_ang, Polygon};

/// Distance from (px, py) along compass bearing `deg` to the segment a–b, if hit.
fn ray_to_seg(px: f64, py: f64, deg: f64, a: (f64, f64), b: (f64, f64)) -> Option<f64> {
    let (dx, dy) = (deg.to_radians().sin(), deg.to_radians().cos());
    let (ex, ey) = (b.0 - a.0, b.1 - a.1);
    let den = dx * ey - dy * ex;
    if den.abs() < 1e-12 {
        return None;
    }
    let (wx, wy) = (a.0 - px, a.1 - py);
    let t = (wx * ey - wy * ex) / den;
    let u = (wx * dy - wy * dx) / den;
    (t >= 0.0 && (-1e-9..=1.0 + 1e-9).contains(&u)).then_some(t)
}

/// Nearest boundary distance along the ray, if any edge is hit.
pub fn ray_dist_to_poly(poly: &Polygon, px: f64, py: f64, deg: f64) -> Option<f64> {
    let v = poly.vertices();
    let n = v.len();
    (0..n)
        .filter_map(|i| {
            let (a, b) = (v[i], v[(i + 1) % n]);
            ray_to_seg(px, py, deg, (a.x, a.y), (b.x, b.y))
        })
        .min_by(f64::total_cmp)
}

/// A random visible boundary point of `poly` from (x, y); `None` from inside, or when
/// the drawn ray misses (a bearing at the very edge of the arc).
pub fn sensor_point(
    poly: &Polygon,
    x: f64,
    y: f64,
    rand01: &mut dyn FnMut() -> f64,
) -> Option<(f64, f64)> {
    if poly.is_empty() || poly.contains(x, y) || !(x.is_finite() && y.is_finite()) {
        return None;
    }
    let (cx, cy) = poly.center();
    let mid = rel_ang(x, y, cx, cy);
    let (mut lo, mut hi) = (0.0f64, 0.0f64);
    for v in poly.vertices() {
        let d = angle180(rel_ang(x, y, v.x, v.y) - mid);
        lo = lo.min(d);
        hi = hi.max(d);
    }
    let (a, b) = (lo.ceil(), hi.floor());
    if !(a.is_finite() && b.is_finite()) || a > b {
        return None;
    }
    let k = (a + (rand01().clamp(0.0, 0.999_999) * (b - a + 1.0)).floor()).min(b);
    let deg = angle360(mid + k);
    let d = ray_dist_to_poly(poly, x, y, deg)?;
    Some(project_point(deg, d, x, y))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_lie_on_the_near_side() {
        let sq = Polygon::from_xy(&[(10.0, -5.0), (10.0, 5.0), (20.0, 5.0), (20.0, -5.0)]);
        assert!((ray_dist_to_poly(&sq, 0.0, 0.0, 90.0).unwrap() - 10.0).abs() < 1e-9);
        assert_eq!(ray_dist_to_poly(&sq, 0.0, 0.0, 270.0), None);
        for r in [0.0, 0.25, 0.5, 0.75, 0.9999] {
            let mut f = || r;
            let (px, py) = sensor_point(&sq, 0.0, 0.0, &mut f).unwrap();
            assert!(sq.dist_to_poly(px, py) < 1e-6, "({px},{py})");
            assert!(px <= 10.0 + 1e-6, "seen from the west: the west edge");
        }
        assert_eq!(sensor_point(&sq, 15.0, 0.0, &mut || 0.5), None, "inside");
    }
}
