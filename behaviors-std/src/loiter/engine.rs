//! The loiter engine (behaviors-std.md §3.3): which polygon vertex to head for when
//! (re)acquiring the loiter polygon.

use geometry::{angle360, rel_ang, segment_angle, Polygon};

/// Default internal spiral factor.
pub const DEFAULT_SPIRAL: f64 = -2.0;

/// Internal spiral factor for the `spiral_factor` parameter value.
pub fn spiral_from_param(v: f64) -> f64 {
    -75.0 + (v / 100.0) * 74.0
}

/// Index of the acquire vertex, or `None` (-1) if the polygon is not convex.
pub fn acquire_vertex(
    poly: &Polygon,
    clockwise: bool,
    spiral: f64,
    osx: f64,
    osy: f64,
    osh: f64,
) -> Option<usize> {
    if !poly.is_convex() {
        return None;
    }
    let v = poly.vertices();
    let n = v.len();
    let next = |i: usize| v[(i + 1) % n];
    if poly.contains(osx, osy) {
        let h = angle360(osh);
        let mut head_to = 0;
        let mut best = f64::INFINITY;
        for (i, p) in v.iter().enumerate() {
            let d = (h - rel_ang(osx, osy, p.x, p.y)).abs();
            if d < best {
                best = d;
                head_to = i;
            }
        }
        let mut pick = 0;
        let mut best = f64::INFINITY;
        for (i, p) in v.iter().enumerate() {
            let q = next(i);
            let mut val = segment_angle(osx, osy, p.x, p.y, q.x, q.y).abs();
            if i == head_to {
                val += spiral;
            }
            if val < best {
                best = val;
                pick = i;
            }
        }
        return Some(pick);
    }
    let mut pick = 0;
    let mut best: Option<f64> = None;
    for (i, p) in v.iter().enumerate() {
        if !poly.vertex_is_viewable(i, osx, osy) {
            continue;
        }
        let q = next(i);
        let a = segment_angle(osx, osy, p.x, p.y, q.x, q.y);
        let better = match best {
            None => true,
            Some(b) => {
                if clockwise {
                    a > b
                } else {
                    a < b
                }
            }
        };
        if better {
            best = Some(a);
            pick = i;
        }
    }
    Some(pick)
}

/// Position relative to the polygon band.
pub fn loiter_mode(prev: &str, dist_to_poly: f64, acquire_dist: f64) -> &'static str {
    let stable_or = |side: &str| {
        let recovering = prev.strip_prefix("recovering_") == Some(side);
        if prev == "stable" || recovering {
            if side == "external" {
                "recovering_external"
            } else {
                "recovering_internal"
            }
        } else if side == "external" {
            "acquiring_external"
        } else {
            "acquiring_internal"
        }
    };
    if dist_to_poly > acquire_dist {
        stable_or("external")
    } else if dist_to_poly < -acquire_dist {
        stable_or("internal")
    } else {
        "stable"
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geometry::{parse_polygon, pts_spec};

    fn ccw_radial(spec: &str) -> Polygon {
        let mut p = parse_polygon(spec).unwrap();
        p.apply_snap(0.1);
        if p.is_clockwise() {
            p.reverse();
        }
        p
    }

    #[test]
    fn spec_example_acquire_vertex() {
        let p = ccw_radial("format=radial, x=50, y=-80, radius=20, pts=8, snap=1");
        assert_eq!(
            pts_spec(p.vertices(), 1),
            "pts={42,-62:32,-72:32,-88:42,-98:58,-98:68,-88:68,-72:58,-62}"
        );
        assert_eq!(
            acquire_vertex(&p, false, DEFAULT_SPIRAL, 0.0, -20.0, 0.0),
            Some(2)
        );
    }

    #[test]
    fn golden_case_first_vertex() {
        let p = ccw_radial("format=radial, x=60, y=-60, radius=25, pts=6");
        assert_eq!(
            acquire_vertex(&p, false, DEFAULT_SPIRAL, 0.0, 0.0, 90.0),
            Some(2)
        );
    }

    #[test]
    fn inside_and_nonconvex() {
        let p = Polygon::from_xy(&[(0.0, 0.0), (0.0, 100.0), (100.0, 100.0), (100.0, 0.0)]);
        let i = acquire_vertex(&p, true, DEFAULT_SPIRAL, 50.0, 50.0, 45.0).unwrap();
        assert!(i < 4);
        let c = Polygon::from_xy(&[(0.0, 0.0), (5.0, 2.0), (10.0, 0.0), (5.0, 10.0)]);
        assert_eq!(
            acquire_vertex(&c, true, DEFAULT_SPIRAL, 50.0, 50.0, 0.0),
            None
        );
        assert_eq!(spiral_from_param(100.0), -1.0);
    }

    #[test]
    fn modes() {
        assert_eq!(loiter_mode("idle", 50.0, 10.0), "acquiring_external");
        assert_eq!(loiter_mode("stable", 50.0, 10.0), "recovering_external");
        assert_eq!(
            loiter_mode("recovering_external", 50.0, 10.0),
            "recovering_external"
        );
        assert_eq!(loiter_mode("acquiring_external", 5.0, 10.0), "stable");
        assert_eq!(loiter_mode("stable", -50.0, 10.0), "recovering_internal");
        assert_eq!(loiter_mode("idle", -50.0, 10.0), "acquiring_internal");
    }
}
