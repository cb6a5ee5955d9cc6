//! The perimeter geometry both op-region behaviors share: the distance along a ray to
//! a polygon's edge (behaviors-more.md §0.1 `rayDistToSeg` / `rayDistToPoly`) and the
//! rounding the region postings use.

use behavior_api::geometry::{dist, project_point, segments_cross, Polygon};

/// Where the infinite lines through a-b and p-q meet (`None` when parallel), with the
/// vertical and horizontal special cases of the slope/intercept form.
fn line_intersection(
    a: (f64, f64),
    b: (f64, f64),
    p: (f64, f64),
    q: (f64, f64),
) -> Option<(f64, f64)> {
    let vert1 = a.0 == b.0;
    let vert2 = p.0 == q.0;
    if vert1 && vert2 {
        return None;
    }
    if vert1 {
        let m2 = (q.1 - p.1) / (q.0 - p.0);
        return Some((a.0, m2 * (a.0 - p.0) + p.1));
    }
    if vert2 {
        let m1 = (b.1 - a.1) / (b.0 - a.0);
        return Some((p.0, m1 * (p.0 - a.0) + a.1));
    }
    let m1 = (b.1 - a.1) / (b.0 - a.0);
    let m2 = (q.1 - p.1) / (q.0 - p.0);
    if m1 == m2 {
        return None;
    }
    if a.1 == b.1 {
        return Some(((a.1 - p.1) / m2 + p.0, a.1));
    }
    if p.1 == q.1 {
        return Some(((p.1 - a.1) / m1 + a.0, p.1));
    }
    let b1 = a.1 - m1 * a.0;
    let b2 = p.1 - m2 * p.0;
    let x = (b2 - b1) / (m1 - m2);
    Some((x, m1 * x + b1))
}

/// Distance from `p` along compass bearing `deg` to segment a-b, or -1 if the ray
/// misses it.
pub fn ray_dist_to_seg(a: (f64, f64), b: (f64, f64), p: (f64, f64), deg: f64) -> f64 {
    let reach = dist(a.0, a.1, p.0, p.1).max(dist(b.0, b.1, p.0, p.1));
    let q = project_point(deg, 2.0 * reach, p.0, p.1);
    if !segments_cross(a.0, a.1, b.0, b.1, p.0, p.1, q.0, q.1) {
        return -1.0;
    }
    match line_intersection(a, b, p, q) {
        Some(i) => dist(i.0, i.1, p.0, p.1),
        None => -1.0,
    }
}

/// Distance from `p` along bearing `deg` to the nearest edge of `poly` (closing edge
/// included), or -1 if no edge is hit.
pub fn ray_dist_to_poly(poly: &Polygon, p: (f64, f64), deg: f64) -> f64 {
    let v = poly.vertices();
    match v.len() {
        0 => -1.0,
        1 => ray_dist_to_seg((v[0].x, v[0].y), (v[0].x, v[0].y), p, deg),
        2 => ray_dist_to_seg((v[0].x, v[0].y), (v[1].x, v[1].y), p, deg),
        n => {
            let mut best = -1.0;
            for i in 0..n {
                let a = v[i];
                let b = v[(i + 1) % n];
                let d = ray_dist_to_seg((a.x, a.y), (b.x, b.y), p, deg);
                if d >= 0.0 && (best < 0.0 || d < best) {
                    best = d;
                }
            }
            best
        }
    }
}

/// `trunc(v + 0.5)`: the helm's integer posting.
pub fn int_post(v: f64) -> f64 {
    (v + 0.5).trunc()
}

/// A perimeter distance as posted: whole metres from 1 m up, the exact value below
/// (the golden case `opregion_breach` shows 0.97 and -1 posted as they are).
pub fn dist_post(v: f64) -> f64 {
    if v >= 1.0 {
        int_post(v)
    } else {
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> Polygon {
        Polygon::from_xy(&[(-20.0, 20.0), (60.0, 20.0), (60.0, -60.0), (-20.0, -60.0)])
    }

    #[test]
    fn rays_hit_the_nearest_edge() {
        let p = square();
        assert_eq!(ray_dist_to_poly(&p, (0.0, 0.0), 180.0), 60.0);
        assert_eq!(ray_dist_to_poly(&p, (0.0, 0.0), 90.0), 60.0);
        assert_eq!(ray_dist_to_poly(&p, (0.0, 0.0), 0.0), 20.0);
        let d = ray_dist_to_poly(&p, (0.0, 0.0), 45.0);
        assert!((d - 20.0 * 2f64.sqrt()).abs() < 1e-9, "{d}");
        // Outside and heading away: nothing ahead.
        assert_eq!(ray_dist_to_poly(&p, (70.0, 0.0), 90.0), -1.0);
        // Outside and heading back in: the near edge.
        assert!((ray_dist_to_poly(&p, (70.0, 0.0), 270.0) - 10.0).abs() < 1e-9);
        assert_eq!(ray_dist_to_poly(&Polygon::default(), (0.0, 0.0), 0.0), -1.0);
    }

    #[test]
    fn postings_round_from_one_metre() {
        assert_eq!(dist_post(60.4), 60.0);
        assert_eq!(dist_post(2.5), 3.0);
        assert_eq!(dist_post(0.97), 0.97);
        assert_eq!(dist_post(-1.0), -1.0);
        assert_eq!(int_post(-0.5), 0.0);
        assert_eq!(int_post(-1.745), -1.0);
    }
}
