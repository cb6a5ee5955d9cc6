//! The contact extrapolation rule with speed decay (contacts-appcast.md §3.2 `decay`,
//! §4.3 the contact manager's CPA test): the last reported position moved along the
//! reported heading for the time since the report, the speed falling linearly from the
//! reported value at `start` seconds to 0 at `end` seconds. The helm itself never
//! extrapolates (§2.4; the behaviors' `extrapolate`/`decay` are accepted and inert);
//! this is for a contact-manager stand-in and for behaviors that choose to.

use geometry::project_point;

/// `decay = start,end` (seconds, 0 ≤ start ≤ end). Default 15, 30.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Decay {
    pub start: f64,
    pub end: f64,
}

impl Default for Decay {
    fn default() -> Self {
        Decay {
            start: 15.0,
            end: 30.0,
        }
    }
}

/// A `decay` value that is not two numbers with 0 ≤ start ≤ end.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("decay must be start,end with 0 <= start <= end: {0}")]
pub struct DecayError(pub String);

impl Decay {
    /// ```
    /// let d = contacts::Decay::parse("30,60").unwrap();
    /// assert_eq!((d.start, d.end), (30.0, 60.0));
    /// assert!(contacts::Decay::parse("60,30").is_err());
    /// ```
    pub fn parse(s: &str) -> Result<Decay, DecayError> {
        let err = || DecayError(s.to_string());
        let (a, b) = s.split_once(',').ok_or_else(err)?;
        let start = mbutil::parse_number(a).ok_or_else(err)?;
        let end = mbutil::parse_number(b).ok_or_else(err)?;
        if !(0.0 <= start && start <= end) {
            return Err(err());
        }
        Ok(Decay { start, end })
    }

    /// Distance run in `dt` seconds from speed `spd`: full speed until `start`, then
    /// linearly slower until stopped at `end` (the integral of that speed).
    pub fn distance(&self, spd: f64, dt: f64) -> f64 {
        if dt.is_nan() || dt <= 0.0 || spd.is_nan() || spd <= 0.0 {
            return 0.0;
        }
        if dt <= self.start {
            return spd * dt;
        }
        let span = self.end - self.start;
        if span <= 0.0 {
            return spd * self.start;
        }
        let t = dt.min(self.end);
        let left = self.end - t;
        spd * self.start + spd * (span * span - left * left) / (2.0 * span)
    }

    /// Where a contact reported at (x, y) heading `hdg` at `spd` at time `utc` is at
    /// `now`.
    pub fn extrapolate(
        &self,
        x: f64,
        y: f64,
        hdg: f64,
        spd: f64,
        utc: f64,
        now: f64,
    ) -> (f64, f64) {
        let d = self.distance(spd, now - utc);
        if d == 0.0 {
            return (x, y);
        }
        project_point(crate::engine::angle360(hdg), d, x, y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decayed_distance_by_hand() {
        let d = Decay {
            start: 10.0,
            end: 30.0,
        };
        // Full speed 2 m/s for 5 s: 10 m.
        assert_eq!(d.distance(2.0, 5.0), 10.0);
        // 20 s: 10 s at 2 (20 m), then 10 s of the ramp from 2 to 1 (average 1.5: 15 m).
        assert_eq!(d.distance(2.0, 20.0), 35.0);
        // At and after 30 s: 20 m + the whole ramp 2 → 0 over 20 s (20 m) = 40 m.
        assert_eq!(d.distance(2.0, 30.0), 40.0);
        assert_eq!(d.distance(2.0, 300.0), 40.0);
        // No time, negative time, no speed: no motion.
        assert_eq!(d.distance(2.0, -1.0), 0.0);
        assert_eq!(d.distance(0.0, 10.0), 0.0);
        assert_eq!(d.distance(f64::NAN, 10.0), 0.0);
        // start = end: stops dead at start.
        assert_eq!(
            Decay {
                start: 5.0,
                end: 5.0
            }
            .distance(2.0, 9.0),
            10.0
        );
    }

    #[test]
    fn extrapolated_position() {
        let d = Decay::default();
        // Heading east at 1 m/s, 10 s old: 10 m east.
        let (x, y) = d.extrapolate(100.0, 50.0, 90.0, 1.0, 1000.0, 1010.0);
        assert!((x - 110.0).abs() < 1e-9 && (y - 50.0).abs() < 1e-9);
        assert_eq!(
            d.extrapolate(1.0, 2.0, 90.0, 1.0, 1000.0, 1000.0),
            (1.0, 2.0)
        );
    }

    #[test]
    fn parse_errors() {
        assert!(Decay::parse("a,b").is_err());
        assert!(Decay::parse("-1,3").is_err());
        assert!(Decay::parse("5").is_err());
        assert_eq!(
            Decay::parse(" 0 , 0 ").unwrap(),
            Decay {
                start: 0.0,
                end: 0.0
            }
        );
    }
}
