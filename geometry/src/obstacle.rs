//! Geometry of polygon obstacles (obstacles.md §1.4.2, §1.7, §1.8): the buffer polygon
//! (XYPolyExpander), the tangent bearings from a point to a polygon, and the closest
//! approach of a ray to a polygon (`polyRayCPA`).

use crate::angles::{angle360, angle_diff, rel_ang};
use crate::points::{dist, perp_seg_int_pt, project_point};
use crate::polygon::Polygon;
use crate::spec::Vertex;

/// The convex polygon `p` grown by `buffer`, corners rounded in steps of `step_deg`
/// degrees (obstacles.md §1.4.2). A result that cannot be made convex is `p` itself.
///
/// ```
/// use geometry::{obstacle::buffer_polygon, Polygon};
/// let p = Polygon::from_xy(&[(60.0, -12.0), (60.0, 6.0), (80.0, 6.0), (80.0, -12.0)]);
/// let b = buffer_polygon(&p, 5.0, 30.0);
/// assert_eq!(b.size(), 16); // 4 edge ends × 2 + 2 arc points per corner
/// assert_eq!((b.vx(0), b.vy(0)), (60.0, -17.0));
/// ```
pub fn buffer_polygon(p: &Polygon, buffer: f64, step_deg: f64) -> Polygon {
    let v = p.vertices();
    let n = v.len();
    if n < 3 || step_deg <= 0.0 || !buffer.is_finite() {
        return p.clone();
    }
    let gx = v.iter().map(|q| q.x).sum::<f64>() / n as f64;
    let gy = v.iter().map(|q| q.y).sum::<f64>() / n as f64;
    // Both ends of every edge pushed out by the buffer along the edge's outward normal.
    let mut ends = Vec::with_capacity(n);
    for i in 0..n {
        let (a, b) = (v[i], v[(i + 1) % n]);
        let ang = rel_ang(a.x, a.y, b.x, b.y);
        let n1 = angle360(ang - 90.0);
        let n2 = angle360(ang + 90.0);
        let to_g = rel_ang(a.x, a.y, gx, gy);
        let out = if angle_diff(n2, to_g) > angle_diff(n1, to_g) {
            n2
        } else {
            n1
        };
        ends.push((
            project_point(out, buffer, a.x, a.y),
            project_point(out, buffer, b.x, b.y),
        ));
    }
    let sign = if p.is_clockwise() { 1.0 } else { -1.0 };
    let mut out: Vec<Vertex> = Vec::new();
    for i in 0..n {
        let p1 = ends[(i + n - 1) % n].1;
        let p2 = ends[i].0;
        let a1 = rel_ang(v[i].x, v[i].y, p1.0, p1.1);
        let a2 = rel_ang(v[i].x, v[i].y, p2.0, p2.1);
        let steps = (angle_diff(a1, a2) / step_deg).trunc() as i64;
        out.push(Vertex::new(p1.0, p1.1));
        for j in 1..steps.max(1) {
            let (x, y) = project_point(
                angle360(a1 + sign * j as f64 * step_deg),
                buffer,
                v[i].x,
                v[i].y,
            );
            out.push(Vertex::new(x, y));
        }
        let near_last = out.len() >= 2
            && out
                .last()
                .is_some_and(|l| dist(l.x, l.y, p2.0, p2.1) <= 1.0);
        if !near_last {
            out.push(Vertex::new(p2.0, p2.1));
        }
    }
    let mut poly = Polygon::new(out);
    while !poly.is_convex() && poly.size() >= 3 {
        poly = Polygon::new(drop_flattest(poly.vertices()));
    }
    if poly.is_convex() {
        poly
    } else {
        p.clone()
    }
}

/// The vertices without the one of smallest |(v − prev) × (next − prev)| (first wins).
fn drop_flattest(v: &[Vertex]) -> Vec<Vertex> {
    let n = v.len();
    let mut best = 0;
    let mut best_val = f64::INFINITY;
    for i in 0..n {
        let pv = v[(i + n - 1) % n];
        let nx = v[(i + 1) % n];
        let c = ((v[i].x - pv.x) * (nx.y - pv.y) - (v[i].y - pv.y) * (nx.x - pv.x)).abs();
        if c < best_val {
            best_val = c;
            best = i;
        }
    }
    let mut out = v.to_vec();
    out.remove(best);
    out
}

/// The point of the polygon's boundary closest to (x, y) (first edge wins ties).
pub fn closest_point(p: &Polygon, x: f64, y: f64) -> Option<(f64, f64)> {
    let v = p.vertices();
    let n = v.len();
    if n == 0 {
        return None;
    }
    if n == 1 {
        return Some((v[0].x, v[0].y));
    }
    let mut best = None;
    let mut best_d = f64::INFINITY;
    for i in 0..n {
        let (a, b) = (v[i], v[(i + 1) % n]);
        let q = perp_seg_int_pt(a.x, a.y, b.x, b.y, x, y);
        let d = dist(q.0, q.1, x, y);
        if d < best_d {
            best_d = d;
            best = Some(q);
        }
    }
    best
}

/// The tangent bearings (`bmin`, `bmax`) from (x, y) to the polygon's vertices
/// (obstacles.md §1.7, `bearingMinMaxToPoly`); `bmin > bmax` when the polygon straddles
/// north. `None` for an empty polygon or a point inside it.
///
/// ```
/// use geometry::{obstacle::bearing_min_max, Polygon};
/// let p = Polygon::from_xy(&[(-1.0, 10.0), (1.0, 10.0), (1.0, 12.0), (-1.0, 12.0)]);
/// let (lo, hi) = bearing_min_max(&p, 0.0, 0.0).unwrap();
/// assert!(lo > 270.0 && hi < 90.0); // wraps through north
/// ```
pub fn bearing_min_max(p: &Polygon, x: f64, y: f64) -> Option<(f64, f64)> {
    if p.is_empty() || p.contains(x, y) {
        return None;
    }
    // Each bearing computed again where it is read (same arithmetic, same bits): no list
    // per call, and an obstacle behavior asks every iteration.
    let bngs = || p.vertices().iter().map(move |v| rel_ang(x, y, v.x, v.y));
    let mut quad = [false; 4];
    for b in bngs() {
        quad[((b / 90.0).floor() as usize).min(3)] = true;
    }
    let closest_bng = || {
        closest_point(p, x, y)
            .map(|(cx, cy)| rel_ang(x, y, cx, cy))
            .unwrap_or(0.0)
    };
    let wraps = match quad {
        [true, false, false, true] | [true, false, true, true] | [true, true, false, true] => true,
        [true, false, true, false] => {
            let b = closest_bng();
            !(b > 45.0 && b <= 225.0)
        }
        [false, true, false, true] => {
            let b = closest_bng();
            !(b > 135.0 && b <= 315.0)
        }
        _ => false,
    };
    if wraps {
        let bmin = bngs().filter(|b| *b > 180.0).fold(360.0, f64::min);
        let bmax = bngs().filter(|b| *b <= 180.0).fold(0.0, f64::max);
        Some((bmin, bmax))
    } else {
        let bmin = bngs().fold(f64::INFINITY, f64::min);
        let bmax = bngs().fold(f64::NEG_INFINITY, f64::max);
        Some((bmin, bmax))
    }
}

/// Unit direction of compass course `c`, exact at 0/90/180/270.
fn course_dir(c: f64) -> (f64, f64) {
    let c = angle360(c);
    if c == 0.0 {
        (0.0, 1.0)
    } else if c == 90.0 {
        (1.0, 0.0)
    } else if c == 180.0 {
        (0.0, -1.0)
    } else if c == 270.0 {
        (-1.0, 0.0)
    } else {
        let r = c.to_radians();
        (r.sin(), r.cos())
    }
}

/// Whether the ray from (bx, by) along unit `d` crosses the segment a–b (obstacles.md
/// §1.8): the lines meet ahead of (or at) the base, within the edge's x- and y-ranges.
fn ray_crosses(bx: f64, by: f64, d: (f64, f64), a: Vertex, b: Vertex) -> bool {
    let e = (b.x - a.x, b.y - a.y);
    let den = d.0 * e.1 - d.1 * e.0;
    let w = (a.x - bx, a.y - by);
    if den == 0.0 {
        // Parallel: only identical lines cross.
        return w.0 * d.1 - w.1 * d.0 == 0.0;
    }
    let t = (w.0 * e.1 - w.1 * e.0) / den;
    if t < 0.0 {
        return false;
    }
    // A vertical edge meets at its own x, a horizontal one at its own y (no rounding).
    let ix = if e.0 == 0.0 { a.x } else { bx + t * d.0 };
    let iy = if e.1 == 0.0 { a.y } else { by + t * d.1 };
    let x_ok = (a.x - b.x).abs() <= 1e-6 || (ix >= a.x.min(b.x) && ix <= a.x.max(b.x));
    let y_ok = (a.y - b.y).abs() <= 1e-6 || (iy >= a.y.min(b.y) && iy <= a.y.max(b.y));
    x_ok && y_ok
}

/// Distance from (px, py) to the ray: perpendicular if the foot lies ahead, else to the base.
fn dist_to_ray(bx: f64, by: f64, d: (f64, f64), px: f64, py: f64) -> f64 {
    let w = (px - bx, py - by);
    let along = w.0 * d.0 + w.1 * d.1;
    if along > 0.0 {
        (w.0 * d.1 - w.1 * d.0).abs()
    } else {
        dist(px, py, bx, by)
    }
}

/// Closest approach of the ray from (x, y) along compass course `c` to the polygon's
/// edges (`polyRayCPA`, obstacles.md §1.8): 0 if it crosses an edge.
///
/// ```
/// use geometry::{obstacle::poly_ray_cpa, Polygon};
/// let p = Polygon::from_xy(&[(10.0, -1.0), (10.0, 1.0), (12.0, 1.0), (12.0, -1.0)]);
/// assert_eq!(poly_ray_cpa(&p, 0.0, 0.0, 90.0), 0.0); // straight through
/// assert_eq!(poly_ray_cpa(&p, 0.0, 5.0, 90.0), 4.0); // passes 4 north of the top edge
/// ```
pub fn poly_ray_cpa(p: &Polygon, x: f64, y: f64, c: f64) -> f64 {
    let v = p.vertices();
    let n = v.len();
    if n == 0 {
        return f64::INFINITY;
    }
    let d = course_dir(c);
    let edges = if n == 1 { 1 } else { n };
    let mut best = f64::INFINITY;
    for i in 0..edges {
        let (a, b) = (v[i], v[(i + 1) % n]);
        if n > 1 && ray_crosses(x, y, d, a, b) {
            return 0.0;
        }
        let da = dist_to_ray(x, y, d, a.x, a.y);
        let db = dist_to_ray(x, y, d, b.x, b.y);
        let q = perp_seg_int_pt(a.x, a.y, b.x, b.y, x, y);
        let ds = dist(q.0, q.1, x, y);
        best = best.min(da.min(db).min(ds));
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect() -> Polygon {
        Polygon::from_xy(&[(60.0, -12.0), (60.0, 6.0), (80.0, 6.0), (80.0, -12.0)])
    }

    /// The bearings listed once, as the function did before it computed them where they
    /// are read: the reference for [`bearing_min_max`].
    fn bearing_min_max_listed(p: &Polygon, x: f64, y: f64) -> Option<(f64, f64)> {
        if p.is_empty() || p.contains(x, y) {
            return None;
        }
        let bngs: Vec<f64> = p
            .vertices()
            .iter()
            .map(|v| rel_ang(x, y, v.x, v.y))
            .collect();
        let mut quad = [false; 4];
        for &b in &bngs {
            quad[((b / 90.0).floor() as usize).min(3)] = true;
        }
        let closest = || closest_point(p, x, y).map_or(0.0, |(cx, cy)| rel_ang(x, y, cx, cy));
        let wraps = match quad {
            [true, false, false, true] | [true, false, true, true] | [true, true, false, true] => {
                true
            }
            [true, false, true, false] => !(closest() > 45.0 && closest() <= 225.0),
            [false, true, false, true] => !(closest() > 135.0 && closest() <= 315.0),
            _ => false,
        };
        let it = bngs.iter().copied();
        Some(if wraps {
            (
                it.clone().filter(|b| *b > 180.0).fold(360.0, f64::min),
                it.filter(|b| *b <= 180.0).fold(0.0, f64::max),
            )
        } else {
            (
                it.clone().fold(f64::INFINITY, f64::min),
                it.fold(f64::NEG_INFINITY, f64::max),
            )
        })
    }

    /// Bit for bit the listed reference all around two obstacles (north-straddling and
    /// not) and inside them.
    #[test]
    fn bearing_range_is_the_listed_one() {
        let tri = Polygon::from_xy(&[(-1.0, 10.0), (1.0, 10.0), (0.0, 12.0)]);
        let bits = |r: Option<(f64, f64)>| r.map(|(a, b)| (a.to_bits(), b.to_bits()));
        let mut some = 0;
        for poly in [rect(), tri] {
            for i in 0..40 {
                for j in 0..40 {
                    let (x, y) = (-20.0 + 2.7 * f64::from(i), -30.0 + 1.9 * f64::from(j));
                    let got = bearing_min_max(&poly, x, y);
                    some += usize::from(got.is_some());
                    assert_eq!(
                        bits(got),
                        bits(bearing_min_max_listed(&poly, x, y)),
                        "({x}, {y})"
                    );
                }
            }
        }
        assert!(some > 3000, "{some}");
    }

    #[test]
    fn buffer_of_the_recorded_rectangle() {
        // obstacles.md §1.4.2 run R1, b = 5, printed at precision 5.
        let b = buffer_polygon(&rect(), 5.0, 30.0);
        assert_eq!(
            crate::pts_spec(b.vertices(), 5),
            "pts={60,-17:57.5,-16.33013:55.66987,-14.5:55,-12:55,6:55.66987,8.5:57.5,10.33013:60,11:80,11:82.5,10.33013:84.33013,8.5:85,6:85,-12:84.33013,-14.5:82.5,-16.33013:80,-17}"
        );
    }

    #[test]
    fn zero_buffer_is_the_polygon_again() {
        // Every p2 coincides with p1 (within 1), the duplicate first vertex is the
        // flattest and is dropped: the rectangle comes back.
        let b = buffer_polygon(&rect(), 0.0, 30.0);
        assert!(b.is_convex());
        assert_eq!(b.size(), 4);
    }

    #[test]
    fn ray_cpa_misses_and_hits() {
        let p = rect();
        // Along 90 from (0,10): passes 4 north of the top edge y = 6.
        assert_eq!(poly_ray_cpa(&p, 0.0, 10.0, 90.0), 4.0);
        // Heading away (270): the nearest vertex (60,6) is behind: distance to the base.
        let d = poly_ray_cpa(&p, 0.0, 10.0, 270.0);
        assert!((d - (3600.0f64 + 16.0).sqrt()).abs() < 1e-9);
        assert_eq!(poly_ray_cpa(&p, 0.0, 0.0, 90.0), 0.0);
    }
}
