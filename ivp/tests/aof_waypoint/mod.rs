//! AOF_Waypoint (behaviors-std.md §2.4 `roc`): the analytical function the golden
//! reflector cases were built from. It belongs to the Waypoint behavior, not to the
//! solver crate, so it lives with the tests that need it; the angles come from
//! `geometry`, the one place the compass arithmetic is written.

use geometry::{angle180, angle360, rel_ang};
use ivp::Domain;
use ivp_reflector::Aof;

/// Rate of closure toward a point, at (course, speed).
pub struct AofWaypoint {
    course_dim: usize,
    speed_dim: usize,
    bearing: f64,
    desired_speed: f64,
    /// The speed variable's high.
    vmax: f64,
}

impl AofWaypoint {
    pub fn new(
        domain: &Domain,
        osx: f64,
        osy: f64,
        ptx: f64,
        pty: f64,
        desired_speed: f64,
    ) -> Result<Self, String> {
        let course_dim = domain.index_of("course").ok_or("no course variable")?;
        let speed_dim = domain.index_of("speed").ok_or("no speed variable")?;
        let vmax = domain.var(speed_dim).high;
        if vmax <= 0.0 {
            return Err("speed.high must be > 0".into());
        }
        Ok(AofWaypoint {
            course_dim,
            speed_dim,
            bearing: rel_ang(osx, osy, ptx, pty),
            desired_speed,
            vmax,
        })
    }
}

impl Aof for AofWaypoint {
    fn eval(&self, domain: &Domain, index: &[u32]) -> f64 {
        let c = domain.value(self.course_dim, index[self.course_dim]);
        let v = domain.value(self.speed_dim, index[self.speed_dim]);
        let a = angle360(c - self.bearing);
        let roc = (a / 180.0 * std::f64::consts::PI).cos() * v;
        let mut diff = self.desired_speed - roc;
        if diff < 0.0 {
            diff *= -0.5;
        }
        if diff > 2.0 * self.vmax {
            diff = 2.0 * self.vmax;
        }
        let s1 = (1.0 - diff / (2.0 * self.vmax)) * 100.0;
        let s2 = (1.0 - (angle180(a).abs() * v.max(0.0)) / (self.vmax * 180.0)) * 100.0;
        0.8 * s1 + 0.2 * s2
    }
}
