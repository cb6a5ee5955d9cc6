//! The stand-on function (behaviors-contacts.md §5.4.1): hold the course and speed
//! ownship had when the stand-on situation began — a heading ZAIC around `hdg0`
//! coupled with a speed ZAIC around `spd0`.

use behavior_api::ivp::{couple, zaic, Domain, IvpFunction, ZaicSpd};

/// The heading ZAIC's shape: summit, deltas and utilities.
#[derive(Clone, Copy, Debug)]
pub struct HeadingZaic {
    pub summit: f64,
    pub ldelta: f64,
    pub hdelta: f64,
    pub ldelta_util: f64,
    pub hdelta_util: f64,
    pub lmin_util: f64,
    pub hmin_util: f64,
    pub max_util: f64,
}

impl HeadingZaic {
    /// The shape the stand-on function uses: deltas 20/20, utilities 25/25, 0/0, 100.
    pub fn standon(summit: f64) -> Self {
        HeadingZaic {
            summit,
            ldelta: 20.0,
            hdelta: 20.0,
            ldelta_util: 25.0,
            hdelta_util: 25.0,
            lmin_util: 0.0,
            hmin_util: 0.0,
            max_util: 100.0,
        }
    }

    /// Utility of course `x` (degrees).
    pub fn utility(&self, x: f64) -> f64 {
        if !(0.0..360.0).contains(&x) {
            return 0.0;
        }
        let s = self.summit;
        // Left: strictly less than 180° counter-clockwise of the summit.
        let left = if s < 180.0 {
            x < s || x > s + 180.0
        } else {
            x > s - 180.0 && x < s
        };
        if !left {
            let mut d = x - s;
            if d < 0.0 {
                d += 360.0;
            }
            if d == self.hdelta {
                return self.hdelta_util;
            }
            if d < self.hdelta {
                if self.hdelta == 0.0 {
                    return 0.0;
                }
                return self.max_util - (self.max_util - self.hdelta_util) * d / self.hdelta;
            }
            let mut k = s + self.hdelta;
            if k >= 360.0 {
                k -= 360.0;
            }
            let mut e = x - k;
            if e < 0.0 {
                e += 360.0;
            }
            let run = 180.0 - self.hdelta;
            if run == 0.0 {
                return 0.0;
            }
            return self.hdelta_util - (self.hdelta_util - self.hmin_util) * e / run;
        }
        let mut d = s - x;
        if d < 0.0 {
            d += 360.0;
        }
        if d == self.ldelta {
            return self.ldelta_util;
        }
        if d < self.ldelta {
            if self.ldelta == 0.0 {
                return 0.0;
            }
            return self.max_util - (self.max_util - self.ldelta_util) * d / self.ldelta;
        }
        let mut k = s - self.ldelta;
        if k < 0.0 {
            k += 360.0;
        }
        let mut e = k - x;
        if e < 0.0 {
            e += 360.0;
        } else if e >= 360.0 {
            e -= 360.0;
        }
        let run = 180.0 - self.ldelta;
        if run == 0.0 {
            return 0.0;
        }
        self.ldelta_util - (self.ldelta_util - self.lmin_util) * e / run
    }

    /// The function over `course` of `domain` (a `0:359:360` course when the domain's
    /// course cannot hold compass headings).
    pub fn extract(&self, domain: &Domain) -> Option<IvpFunction> {
        let ix = domain.index_of("course")?;
        let var = domain.var(ix);
        let own;
        let d = if var.low < 0.0 || var.high >= 360.0 || var.points < 4 {
            own = Domain::parse("course:0:359:360").ok()?;
            &own
        } else {
            domain
        };
        let var = d.var(d.index_of("course")?);
        let samples: Vec<f64> = (0..var.points)
            .map(|j| self.utility(var.value(j)))
            .collect();
        zaic::from_samples(d, "course", &samples).ok()
    }
}

/// Why the stand-on function could not be built (each a BHV_WARNING).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StandOnFail {
    Spd,
    Crs,
    Coupler,
}

impl StandOnFail {
    pub fn message(self) -> &'static str {
        match self {
            StandOnFail::Spd => "Failure on the SPD ZAIC",
            StandOnFail::Crs => "Failure on the CRS ZAIC",
            StandOnFail::Coupler => "Failure on the CRS_SPD COUPLER",
        }
    }
}

/// Course × speed, weights 0.5/0.5.
pub fn build(domain: &Domain, hdg0: f64, spd0: f64) -> Result<IvpFunction, StandOnFail> {
    let mut z = ZaicSpd::new(domain, "speed").map_err(|_| StandOnFail::Spd)?;
    z.set_params(spd0, 0.1, spd0 + 0.4, 50.0, 50.0, 0.0, 0.0, 100.0);
    let spd = z.extract().ok_or(StandOnFail::Spd)?;
    let crs = HeadingZaic::standon(hdg0)
        .extract(domain)
        .ok_or(StandOnFail::Crs)?;
    couple(crs, spd, 0.5, 0.5, true).ok_or(StandOnFail::Coupler)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn heading_zaic_by_hand() {
        let z = HeadingZaic::standon(10.0);
        assert_eq!(z.utility(10.0), 100.0);
        // 10° right of the summit: half way down to 25 over 20°.
        assert_eq!(z.utility(20.0), 62.5);
        assert_eq!(z.utility(30.0), 25.0);
        // Left side wraps through north: 350 is 20° left.
        assert_eq!(z.utility(350.0), 25.0);
        assert_eq!(z.utility(0.0), 62.5);
        // Opposite the summit (190, right side by the rule): 25 − 25·160/160 = 0.
        assert!(z.utility(190.0).abs() < 1e-12);
        // 100° right: 25 − 25·80/160.
        assert!((z.utility(110.0) - 12.5).abs() < 1e-12);
        assert_eq!(z.utility(360.0), 0.0);
    }

    #[test]
    fn coupled_function_peaks_at_the_held_course_and_speed() {
        let d = Domain::parse("course:0:359:360,speed:0:4:41").unwrap();
        let f = build(&d, 45.0, 2.0).unwrap();
        let best = f.eval(&[45, 20]).unwrap();
        assert!(best > f.eval(&[60, 20]).unwrap());
        assert!(best > f.eval(&[45, 30]).unwrap());
        assert!(best > f.eval(&[225, 20]).unwrap());
    }
}
