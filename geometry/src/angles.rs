//! Angles on the compass (0 = north/+y, 90 = east/+x, clockwise), behaviors-std.md §1.1.

/// Add/subtract 360 until `0 <= a < 360` (loops, as specified, not fmod).
pub fn angle360(a: f64) -> f64 {
    if !a.is_finite() {
        return a;
    }
    let mut a = a;
    while a >= 360.0 {
        a -= 360.0;
    }
    while a < 0.0 {
        a += 360.0;
    }
    a
}

/// `angle360`, then minus 360 when above 180: range (-180, 180].
pub fn angle180(a: f64) -> f64 {
    let a = angle360(a);
    if a > 180.0 {
        a - 360.0
    } else {
        a
    }
}

/// Unsigned difference between two headings, in [0, 180].
pub fn angle_diff(a: f64, b: f64) -> f64 {
    let a = angle360(a);
    let b = angle360(b);
    let d = (a - b).abs();
    if d >= 180.0 {
        360.0 - d
    } else {
        d
    }
}

/// Compass bearing from A to B, computed exactly as the reference (bit-exact).
pub fn rel_ang(ax: f64, ay: f64, bx: f64, by: f64) -> f64 {
    if ax == bx && ay == by {
        return 0.0;
    }
    let mut w = 0.0;
    let mut sop = 0.0;
    if ax < bx {
        if ay == by {
            return 90.0;
        }
        w = 90.0;
    } else if ax > bx {
        if ay == by {
            return 270.0;
        }
        w = 270.0;
    }
    if ay < by {
        if ax == bx {
            return 0.0;
        }
        sop = if bx > ax { -1.0 } else { 1.0 };
    } else if by < ay {
        if ax == bx {
            return 180.0;
        }
        sop = if bx > ax { 1.0 } else { -1.0 };
    }
    let t = ((by - ay).abs() / (bx - ax).abs()).atan();
    let t_deg = (t / std::f64::consts::PI) * 180.0;
    angle360(t_deg * sop + w)
}

/// `(d / 180) * pi`.
pub fn deg_to_radians(d: f64) -> f64 {
    (d / 180.0) * std::f64::consts::PI
}

/// Turn angle at p2 when going p1 -> p2 -> p3, in (-180, 180].
pub fn segment_angle(p1x: f64, p1y: f64, p2x: f64, p2y: f64, p3x: f64, p3y: f64) -> f64 {
    if (p1x == p2x && p1y == p2y) || (p2x == p3x && p2y == p3y) {
        return 0.0;
    }
    let mut a1 = rel_ang(p1x, p1y, p2x, p2y);
    let mut a2 = rel_ang(p2x, p2y, p3x, p3y);
    if a1 > 180.0 {
        a1 -= 360.0;
    }
    if a2 > 180.0 {
        a2 -= 360.0;
    }
    let mut r = a2 - a1;
    if r > 180.0 {
        r -= 360.0;
    }
    if r <= -180.0 {
        r += 360.0;
    }
    r
}

/// Angle at vertex 1 (degrees) of the triangle P1 P2 P3, by the law of cosines.
pub fn angle_from_three_points(x1: f64, y1: f64, x2: f64, y2: f64, x3: f64, y3: f64) -> f64 {
    let a = (x2 - x3).hypot(y2 - y3);
    let b = (x1 - x3).hypot(y1 - y3);
    let c = (x1 - x2).hypot(y1 - y2);
    let den = 2.0 * b * c;
    if den == 0.0 {
        return 0.0;
    }
    let r = ((b * b + c * c - a * a) / den).acos();
    (r / std::f64::consts::PI) * 180.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap() {
        assert_eq!(angle360(-90.0), 270.0);
        assert_eq!(angle360(720.0), 0.0);
        assert_eq!(angle180(270.0), -90.0);
        assert_eq!(angle180(180.0), 180.0);
        assert_eq!(angle_diff(350.0, 10.0), 20.0);
        assert_eq!(angle_diff(0.0, 180.0), 180.0);
    }

    #[test]
    fn rel_ang_cardinal_and_example() {
        assert_eq!(rel_ang(0.0, 0.0, 0.0, 10.0), 0.0);
        assert_eq!(rel_ang(0.0, 0.0, 10.0, 0.0), 90.0);
        assert_eq!(rel_ang(0.0, 0.0, 0.0, -10.0), 180.0);
        assert_eq!(rel_ang(0.0, 0.0, -10.0, 0.0), 270.0);
        assert_eq!(rel_ang(1.0, 1.0, 1.0, 1.0), 0.0);
        let r = rel_ang(0.0, 0.0, 100.0, 50.0);
        assert!((r - 63.4349488229).abs() < 1e-9, "{r}");
        assert!((rel_ang(0.0, 0.0, 10.0, 10.0) - 45.0).abs() < 1e-12);
        assert!((rel_ang(0.0, 0.0, -10.0, -10.0) - 225.0).abs() < 1e-12);
        assert!((rel_ang(0.0, 0.0, -10.0, 10.0) - 315.0).abs() < 1e-12);
        assert!((rel_ang(0.0, 0.0, 10.0, -10.0) - 135.0).abs() < 1e-12);
    }

    #[test]
    fn segment_and_three_points() {
        // Heading north then turning east: +90.
        assert_eq!(segment_angle(0.0, 0.0, 0.0, 10.0, 10.0, 10.0), 90.0);
        assert_eq!(segment_angle(0.0, 0.0, 0.0, 10.0, -10.0, 10.0), -90.0);
        assert_eq!(segment_angle(0.0, 0.0, 0.0, 0.0, 1.0, 1.0), 0.0);
        let a = angle_from_three_points(0.0, 0.0, 10.0, 0.0, 0.0, 10.0);
        assert!((a - 90.0).abs() < 1e-9);
        assert_eq!(angle_from_three_points(0.0, 0.0, 0.0, 0.0, 1.0, 1.0), 0.0);
        assert!((deg_to_radians(180.0) - std::f64::consts::PI).abs() < 1e-15);
    }
}
