//! Points and segments (behaviors-std.md §1.2).

use crate::angles::{angle360, deg_to_radians};

/// Euclidean distance.
pub fn dist(px: f64, py: f64, qx: f64, qy: f64) -> f64 {
    (px - qx).hypot(py - qy)
}

/// The point `dist` away from (cx, cy) at compass bearing `deg`.
pub fn project_point(deg: f64, dist: f64, cx: f64, cy: f64) -> (f64, f64) {
    let deg = angle360(deg);
    if deg == 0.0 {
        return (cx, cy + dist);
    }
    if deg == 90.0 {
        return (cx + dist, cy);
    }
    if deg == 180.0 {
        return (cx, cy - dist);
    }
    if deg == 270.0 {
        return (cx - dist, cy);
    }
    let rad = deg_to_radians(deg);
    (cx + rad.sin() * dist, cy + rad.cos() * dist)
}

fn clamp_range(v: f64, a: f64, b: f64) -> f64 {
    let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
    if v < lo {
        lo
    } else if v > hi {
        hi
    } else {
        v
    }
}

/// The point of segment (x1,y1)-(x2,y2) "closest" to Q, with the reference clamping
/// (x and y clamped to the segment's ranges independently).
pub fn perp_seg_int_pt(x1: f64, y1: f64, x2: f64, y2: f64, qx: f64, qy: f64) -> (f64, f64) {
    if (x1 - x2).abs() < 1e-7 {
        return (x1, clamp_range(qy, y1, y2));
    }
    if (y1 - y2).abs() < 1e-7 {
        return (clamp_range(qx, x1, x2), y1);
    }
    let m = (y2 - y1) / (x2 - x1);
    let b = y1 - m * x1;
    let om = -1.0 / m;
    let ob = qy - om * qx;
    let ix = (ob - b) / (m - om);
    let iy = om * ix + ob;
    (clamp_range(ix, x1, x2), clamp_range(iy, y1, y2))
}

/// Distance from Q to [`perp_seg_int_pt`].
pub fn dist_point_to_seg(x1: f64, y1: f64, x2: f64, y2: f64, qx: f64, qy: f64) -> f64 {
    let (ix, iy) = perp_seg_int_pt(x1, y1, x2, y2, qx, qy);
    dist(ix, iy, qx, qy)
}

fn orient(ax: f64, ay: f64, bx: f64, by: f64, cx: f64, cy: f64) -> f64 {
    (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
}

fn on_seg(ax: f64, ay: f64, bx: f64, by: f64, px: f64, py: f64) -> bool {
    px >= ax.min(bx) && px <= ax.max(bx) && py >= ay.min(by) && py <= ay.max(by)
}

/// True if the two segments touch or cross (sharing an endpoint counts).
#[allow(clippy::too_many_arguments)]
pub fn segments_cross(
    x1: f64,
    y1: f64,
    x2: f64,
    y2: f64,
    x3: f64,
    y3: f64,
    x4: f64,
    y4: f64,
) -> bool {
    if (x1 == x3 && y1 == y3)
        || (x1 == x4 && y1 == y4)
        || (x2 == x3 && y2 == y3)
        || (x2 == x4 && y2 == y4)
    {
        return true;
    }
    let d1 = orient(x3, y3, x4, y4, x1, y1);
    let d2 = orient(x3, y3, x4, y4, x2, y2);
    let d3 = orient(x1, y1, x2, y2, x3, y3);
    let d4 = orient(x1, y1, x2, y2, x4, y4);
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    (d1 == 0.0 && on_seg(x3, y3, x4, y4, x1, y1))
        || (d2 == 0.0 && on_seg(x3, y3, x4, y4, x2, y2))
        || (d3 == 0.0 && on_seg(x1, y1, x2, y2, x3, y3))
        || (d4 == 0.0 && on_seg(x1, y1, x2, y2, x4, y4))
}

/// `snap` of §2.5: nearest multiple of `s`, halves away from zero; `s <= 0` is none.
pub(crate) fn snap(v: f64, s: f64) -> f64 {
    if s <= 0.0 {
        return v;
    }
    let q = v / s;
    let n = if q >= 0.0 {
        (q + 0.5) as i64
    } else {
        (q - 0.5) as i64
    };
    n as f64 * s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projection() {
        assert_eq!(project_point(0.0, 10.0, 1.0, 2.0), (1.0, 12.0));
        assert_eq!(project_point(90.0, 10.0, 1.0, 2.0), (11.0, 2.0));
        assert_eq!(project_point(-180.0, 10.0, 1.0, 2.0), (1.0, -8.0));
        assert_eq!(project_point(270.0, 10.0, 1.0, 2.0), (-9.0, 2.0));
        let (x, y) = project_point(45.0, 2f64.sqrt(), 0.0, 0.0);
        assert!((x - 1.0).abs() < 1e-12 && (y - 1.0).abs() < 1e-12);
    }

    #[test]
    fn perpendicular() {
        assert_eq!(perp_seg_int_pt(0.0, 0.0, 0.0, 10.0, 5.0, 20.0), (0.0, 10.0));
        assert_eq!(perp_seg_int_pt(0.0, 0.0, 10.0, 0.0, 5.0, 3.0), (5.0, 0.0));
        let (x, y) = perp_seg_int_pt(0.0, 0.0, 10.0, 10.0, 10.0, 0.0);
        assert!((x - 5.0).abs() < 1e-12 && (y - 5.0).abs() < 1e-12);
        // beyond the end: clamped independently
        let (x, y) = perp_seg_int_pt(0.0, 0.0, 10.0, 10.0, 30.0, 0.0);
        assert_eq!((x, y), (10.0, 10.0));
        assert!((dist_point_to_seg(0.0, 0.0, 10.0, 0.0, 5.0, 3.0) - 3.0).abs() < 1e-12);
        assert_eq!(dist(0.0, 0.0, 3.0, 4.0), 5.0);
    }

    #[test]
    fn crossing() {
        assert!(segments_cross(0.0, 0.0, 10.0, 10.0, 0.0, 10.0, 10.0, 0.0));
        assert!(!segments_cross(0.0, 0.0, 1.0, 1.0, 5.0, 0.0, 6.0, 0.0));
        assert!(segments_cross(0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 2.0, 0.0));
    }
}
