//! The perimeter geometry both op-region behaviors share: the distance along a ray to
//! a polygon's edge (behaviors-more.md §0.1 `rayDistToSeg` / `rayDistToPoly`) and the
//! rounding the region postings use.

use behavior_api::geometry::angles::{angle360, deg_to_radians};
use behavior_api::geometry::{dist, segments_cross, Polygon};

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

/// A compass bearing's direction, worked out once for every edge a ray is tested
/// against: `project_point`'s cases and its sine and cosine, so that
/// [`Bearing::project`] gives `project_point`'s point, bit for bit, without them.
#[derive(Clone, Copy)]
enum Bearing {
    North,
    East,
    South,
    West,
    /// The sine and cosine of the bearing in radians.
    Other(f64, f64),
}

impl Bearing {
    fn of(deg: f64) -> Bearing {
        let deg = angle360(deg);
        if deg == 0.0 {
            Bearing::North
        } else if deg == 90.0 {
            Bearing::East
        } else if deg == 180.0 {
            Bearing::South
        } else if deg == 270.0 {
            Bearing::West
        } else {
            let rad = deg_to_radians(deg);
            Bearing::Other(rad.sin(), rad.cos())
        }
    }

    /// `project_point(deg, dist, cx, cy)`: the same operations on the same numbers.
    fn project(self, dist: f64, cx: f64, cy: f64) -> (f64, f64) {
        match self {
            Bearing::North => (cx, cy + dist),
            Bearing::East => (cx + dist, cy),
            Bearing::South => (cx, cy - dist),
            Bearing::West => (cx - dist, cy),
            Bearing::Other(sin, cos) => (cx + sin * dist, cy + cos * dist),
        }
    }
}

/// Distance from `p` along compass bearing `deg` to segment a-b, or -1 if the ray
/// misses it.
pub fn ray_dist_to_seg(a: (f64, f64), b: (f64, f64), p: (f64, f64), deg: f64) -> f64 {
    let (da, db) = (dist(a.0, a.1, p.0, p.1), dist(b.0, b.1, p.0, p.1));
    ray_to_seg(a, b, (da, db), p, Bearing::of(deg))
}

/// [`ray_dist_to_seg`] with the ends' distances to `p` (`da`, `db`) and the bearing
/// given: a polygon's edges share their ends and their ray.
fn ray_to_seg(
    a: (f64, f64),
    b: (f64, f64),
    (da, db): (f64, f64),
    p: (f64, f64),
    bearing: Bearing,
) -> f64 {
    let reach = da.max(db);
    let q = bearing.project(2.0 * reach, p.0, p.1);
    if !segments_cross(a.0, a.1, b.0, b.1, p.0, p.1, q.0, q.1) {
        return -1.0;
    }
    match line_intersection(a, b, p, q) {
        Some(i) => dist(i.0, i.1, p.0, p.1),
        None => -1.0,
    }
}

/// Distance from `p` along bearing `deg` to the nearest edge of `poly` (closing edge
/// included), or -1 if no edge is hit. The bearing's sine and cosine are taken once,
/// and each vertex's distance to `p` once (each is the end of two edges).
pub fn ray_dist_to_poly(poly: &Polygon, p: (f64, f64), deg: f64) -> f64 {
    let v = poly.vertices();
    match v.len() {
        0 => -1.0,
        1 => ray_dist_to_seg((v[0].x, v[0].y), (v[0].x, v[0].y), p, deg),
        2 => ray_dist_to_seg((v[0].x, v[0].y), (v[1].x, v[1].y), p, deg),
        n => {
            let bearing = Bearing::of(deg);
            let to_p = |i: usize| dist(v[i].x, v[i].y, p.0, p.1);
            let first = to_p(0);
            let mut da = first;
            let mut best = -1.0;
            for i in 0..n {
                let a = v[i];
                let (b, db) = if i + 1 < n {
                    (v[i + 1], to_p(i + 1))
                } else {
                    (v[0], first)
                };
                let d = ray_to_seg((a.x, a.y), (b.x, b.y), (da, db), p, bearing);
                if d >= 0.0 && (best < 0.0 || d < best) {
                    best = d;
                }
                da = db;
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

    /// The first form: each edge on its own, `project_point` for each.
    fn ray_dist_reference(poly: &Polygon, p: (f64, f64), deg: f64) -> f64 {
        let v = poly.vertices();
        let n = v.len();
        let mut best = -1.0;
        for i in 0..n {
            let (a, b) = ((v[i].x, v[i].y), (v[(i + 1) % n].x, v[(i + 1) % n].y));
            let reach = dist(a.0, a.1, p.0, p.1).max(dist(b.0, b.1, p.0, p.1));
            let q = behavior_api::geometry::project_point(deg, 2.0 * reach, p.0, p.1);
            if !segments_cross(a.0, a.1, b.0, b.1, p.0, p.1, q.0, q.1) {
                continue;
            }
            if let Some(x) = line_intersection(a, b, p, q) {
                let d = dist(x.0, x.1, p.0, p.1);
                if d >= 0.0 && (best < 0.0 || d < best) {
                    best = d;
                }
            }
        }
        best
    }

    /// Bearings taken once and shared vertex distances give the first form's bits.
    #[test]
    fn shared_bearing_and_distances_give_the_same_bits() {
        let polys = [
            square(),
            Polygon::from_xy(&[
                (0.0, 0.0),
                (50.0, 10.0),
                (40.0, 70.0),
                (-5.5, 33.3),
                (-20.0, 5.0),
            ]),
        ];
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = |span: f64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * span
        };
        for poly in &polys {
            for k in 0..2000 {
                let p = (next(140.0) - 40.0, next(140.0) - 70.0);
                let deg = match k % 5 {
                    0 => [0.0, 90.0, 180.0, 270.0, 360.0, -90.0][k % 6],
                    _ => next(800.0) - 400.0,
                };
                let (got, want) = (
                    ray_dist_to_poly(poly, p, deg),
                    ray_dist_reference(poly, p, deg),
                );
                assert_eq!(got.to_bits(), want.to_bits(), "{p:?} {deg}");
            }
        }
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
