//! The polygon of a point cluster (obstacles.md §2.5.1): pObstacleMgr's convex hull
//! (a Graham scan from the lowest point, with its one- and two-point hulls), the lasso
//! pseudo hull, and the radial placeholder for a hull that failed.

use geometry::{angle180, angle360, dist, parse_polygon, project_point, rel_ang, Polygon};
use moos_mission::text::format_g;

/// `(p2 − p0) × (p1 − p0) < −0.01`.
fn left_turn(p0: (f64, f64), p1: (f64, f64), p2: (f64, f64)) -> bool {
    let (ax, ay) = (p2.0 - p0.0, p2.1 - p0.1);
    let (bx, by) = (p1.0 - p0.0, p1.1 - p0.1);
    ax * by - bx * ay < -0.01
}

fn one_point(a: (f64, f64)) -> Polygon {
    let v: Vec<(f64, f64)> = [30.0, 150.0, 270.0]
        .iter()
        .map(|&h| project_point(h, 0.1, a.0, a.1))
        .collect();
    Polygon::from_xy(&v)
}

fn two_point(a: (f64, f64), b: (f64, f64)) -> Polygon {
    let d = dist(a.0, a.1, b.0, b.1);
    if d < 0.001 {
        return one_point(a);
    }
    let w = d / 10.0;
    let g = rel_ang(a.0, a.1, b.0, b.1);
    let p = |c: (f64, f64), h: f64| project_point(angle360(h), w, c.0, c.1);
    Polygon::from_xy(&[
        p(a, g + 90.0),
        p(a, g + 270.0),
        p(b, g + 270.0),
        p(b, g + 90.0),
    ])
}

/// Delete the vertex with the smallest |(v − prev) × (next − prev)| (first index wins
/// ties) until convex or fewer than 3 vertices are left (obstacles.md §1.4.2 step 5).
fn settle(mut pts: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    while pts.len() >= 3 && !Polygon::from_xy(&pts).is_convex() {
        let n = pts.len();
        let mut best = (0, f64::INFINITY);
        for i in 0..n {
            let (p, v, q) = (pts[(i + n - 1) % n], pts[i], pts[(i + 1) % n]);
            let c = ((v.0 - p.0) * (q.1 - p.1) - (q.0 - p.0) * (v.1 - p.1)).abs();
            if c < best.1 {
                best = (i, c);
            }
        }
        pts.remove(best.0);
    }
    pts
}

/// The convex hull of `pts` (most recent first). May be non-convex in degenerate
/// cases; the caller then uses [`placeholder`].
///
/// ```
/// use obstacle_manager::hull::convex_hull;
/// let h = convex_hull(&[(63.0, 5.0), (70.0, 3.0), (66.0, -6.0), (60.0, -4.0)]);
/// assert_eq!(h.spec(5), "pts={60,-4:63,5:70,3:66,-6}");
/// ```
pub fn convex_hull(pts: &[(f64, f64)]) -> Polygon {
    let Some(&first) = pts.first() else {
        return Polygon::default();
    };
    let mut root = first;
    for &p in pts {
        if p.1 < root.1 || (p.1 == root.1 && p.0 < root.0) {
            root = p;
        }
    }
    let mut others: Vec<((f64, f64), f64)> = pts
        .iter()
        .filter(|&&p| p != root)
        .map(|&p| (p, angle180(rel_ang(root.0, root.1, p.0, p.1))))
        .collect();
    // Stable: equal angles keep their order.
    others.sort_by(|a, b| b.1.total_cmp(&a.1));
    let mut sorted: Vec<(f64, f64)> = Vec::with_capacity(others.len());
    let mut cand: Option<((f64, f64), f64)> = None;
    for b in others {
        cand = Some(match cand {
            None => b,
            Some(a) if (a.1 - b.1).abs() > 0.1 => {
                sorted.push(a.0);
                b
            }
            Some(a) => {
                let far = |p: (f64, f64)| dist(root.0, root.1, p.0, p.1);
                if far(b.0) > far(a.0) {
                    b
                } else {
                    a
                }
            }
        });
    }
    if let Some(a) = cand {
        sorted.push(a.0);
    }
    match sorted.len() {
        0 => return one_point(root),
        1 => return two_point(root, sorted[0]),
        _ => {}
    }
    let mut stack = vec![root, sorted[0]];
    for &s in &sorted[1..] {
        while stack.len() >= 2 {
            let (t0, t1) = (stack[stack.len() - 2], stack[stack.len() - 1]);
            if left_turn(t0, t1, s) {
                break;
            }
            stack.pop();
        }
        stack.push(s);
    }
    match stack.len() {
        1 => one_point(stack[0]),
        2 => two_point(stack[1], stack[0]),
        _ => {
            stack.reverse();
            let poly = Polygon::from_xy(&stack);
            if poly.is_convex() {
                return poly;
            }
            let settled = settle(stack);
            if settled.len() == 2 {
                two_point(settled[0], settled[1])
            } else {
                Polygon::from_xy(&settled)
            }
        }
    }
}

/// The lasso pseudo hull: a radial polygon round the mean of the points
/// (`x=%.2f,y=%.2f,radius=%.2f,pts=n,snap=0.01`). `None` when the string is refused
/// (e.g. non-finite points).
pub fn lasso(pts: &[(f64, f64)], radius: f64, n: usize) -> Option<Polygon> {
    let (cx, cy) = centroid(pts)?;
    parse_polygon(&format!(
        "format=radial, x={cx:.2},y={cy:.2},radius={radius:.2},pts={n},snap=0.01"
    ))
}

fn centroid(pts: &[(f64, f64)]) -> Option<(f64, f64)> {
    if pts.is_empty() {
        return None;
    }
    let n = pts.len() as f64;
    let sx: f64 = pts.iter().map(|p| p.0).sum();
    let sy: f64 = pts.iter().map(|p| p.1).sum();
    Some((sx / n, sy / n))
}

/// The placeholder for a failed hull: a radial octagon round the centroid with the
/// largest point distance as radius (at least 0.5), numbers in C++ stream format.
pub fn placeholder(pts: &[(f64, f64)]) -> Option<Polygon> {
    let (cx, cy) = centroid(pts)?;
    let r = pts
        .iter()
        .map(|p| dist(cx, cy, p.0, p.1))
        .fold(0.5, f64::max);
    parse_polygon(&format!(
        "format=radial, x={},y={},radius={},pts=8",
        format_g(cx),
        format_g(cy),
        format_g(r)
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(pts: &[(f64, f64)]) -> String {
        convex_hull(pts).spec(5)
    }

    /// The hulls pObstacleMgr posted in run R3 (obstacles.md §2.5.1), points most
    /// recent first.
    #[test]
    fn the_recorded_hulls() {
        assert_eq!(
            spec(&[(60.0, -4.0)]),
            "pts={60.05,-3.9134:60.05,-4.0866:59.9,-4}"
        );
        assert_eq!(
            spec(&[(66.0, -6.0), (60.0, -4.0)]),
            "pts={66.2,-5.4:65.8,-6.6:59.8,-4.6:60.2,-3.4}"
        );
        assert_eq!(
            spec(&[(70.0, 3.0), (66.0, -6.0), (60.0, -4.0)]),
            "pts={60,-4:70,3:66,-6}"
        );
        // The same four points three times over: duplicates collapse.
        let four = [(63.0, 5.0), (70.0, 3.0), (66.0, -6.0), (60.0, -4.0)];
        let mut twelve = Vec::new();
        for _ in 0..3 {
            twelve.extend_from_slice(&four);
        }
        assert_eq!(spec(&twelve), "pts={60,-4:63,5:70,3:66,-6}");
        assert_eq!(
            spec(&[(130.0, 40.0), (120.0, 40.0)]),
            "pts={120,39:120,41:130,41:130,39}"
        );
    }

    #[test]
    fn degenerate_clusters() {
        // All in one place: a one-point hull; on a line: the two ends.
        assert_eq!(convex_hull(&[(1.0, 1.0); 5]).size(), 3);
        let line = convex_hull(&[(0.0, 0.0), (5.0, 5.0), (10.0, 10.0), (2.0, 2.0)]);
        assert_eq!(line.size(), 4);
        assert!(line.is_convex());
        assert!(line.dist_to_poly(10.0, 10.0) < 1.5);
        assert!(convex_hull(&[]).is_empty());
        // An interior point is not a vertex.
        let h = convex_hull(&[
            (5.0, 5.0),
            (0.0, 0.0),
            (10.0, 0.0),
            (10.0, 10.0),
            (0.0, 10.0),
        ]);
        assert_eq!(h.size(), 4);
        assert!(h.is_convex());
    }

    #[test]
    fn lasso_and_placeholder() {
        let l = lasso(&[(0.0, 0.0), (10.0, 0.0)], 6.0, 8).unwrap();
        assert_eq!(l.size(), 8);
        assert!(l.is_convex());
        assert!((l.dist_to_poly(5.0, 0.0) - 6.0 * (22.5f64).to_radians().cos()).abs() < 0.02);
        let p = placeholder(&[(0.0, 0.0), (2.0, 0.0)]).unwrap();
        assert_eq!(p.size(), 8);
        assert!(p.contains(1.0, 0.0));
        assert!(lasso(&[], 6.0, 8).is_none());
    }
}
