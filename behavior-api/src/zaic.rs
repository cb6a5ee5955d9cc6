//! Named ZAIC builders: the shapes of [`ivp::zaic`] described by a parameter struct,
//! so a call reads `Peak { summit: 1.5, base_width: 1.0, ..Peak::default() }` instead
//! of seven unnamed numbers. The positional `set_params` of [`ivp::zaic::ZaicPeak`] and
//! [`ivp::zaic::ZaicSpd`] stay as they are; these build the same functions.
//!
//! A course or heading is circular: set `value_wrap: true` so that a peak near 0°
//! reaches past 359° (and the other way round) instead of being cut at the domain's
//! ends. Speeds and depths are not circular (`value_wrap: false`, the default).
//!
//! ```
//! use behavior_api::ivp::Domain;
//! use behavior_api::zaic::Peak;
//!
//! let domain = Domain::parse("course:0:359:360").unwrap();
//! // Best at 350°, falling to 0 within 30° either side: 10° (grid index 10) is inside.
//! let f = Peak { summit: 350.0, base_width: 30.0, value_wrap: true, ..Peak::default() }
//!     .build(&domain, "course")
//!     .unwrap();
//! assert!(f.eval(&[10]).unwrap() > 0.0);
//! ```

use ivp::zaic::{ZaicPeak, ZaicSpd};
use ivp::{Domain, IvpError, IvpFunction};

/// A ZAIC_PEAK: utility `max_util` at `summit`, flat (or falling by `summit_delta`)
/// within `peak_width` of it, then falling linearly to `min_util` over `base_width`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Peak {
    /// The preferred value.
    pub summit: f64,
    /// Half-width of the top around the summit (0: a point).
    pub peak_width: f64,
    /// Width of the slope from the top's edge down to `min_util`.
    pub base_width: f64,
    /// How much the utility drops across the top (0: flat).
    pub summit_delta: f64,
    /// Utility far from the summit (default 0).
    pub min_util: f64,
    /// Utility at the summit (default 100).
    pub max_util: f64,
    /// A circular variable (course, heading): the shape wraps around the domain's ends.
    pub value_wrap: bool,
}

impl Default for Peak {
    fn default() -> Self {
        Peak {
            summit: 0.0,
            peak_width: 0.0,
            base_width: 0.0,
            summit_delta: 0.0,
            min_util: 0.0,
            max_util: 100.0,
            value_wrap: false,
        }
    }
}

impl Peak {
    /// The function over `var` of `domain` (its other variables are ignored).
    pub fn build(&self, domain: &Domain, var: &str) -> Result<IvpFunction, IvpError> {
        let mut z = ZaicPeak::new(domain, var)?;
        z.set_params(
            self.summit,
            self.peak_width,
            self.base_width,
            self.summit_delta,
            self.min_util,
            self.max_util,
            0,
        );
        z.set_value_wrap(self.value_wrap);
        z.try_extract(true)
    }
}

/// A ZAIC_SPD: a speed preference with utility `max_spd_util` at `med`, falling to
/// `low_util` at `low` and `high_util` at `high`, then to `min_util` at the domain's
/// ends; utilities within `[0, max_util]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Speed {
    pub med: f64,
    pub low: f64,
    pub high: f64,
    pub low_util: f64,
    pub high_util: f64,
    /// Utility at the domain's ends (default 0).
    pub min_util: f64,
    /// Utility at `med` (default 0: then `max_util`).
    pub max_spd_util: f64,
    /// The utilities' ceiling (default 100).
    pub max_util: f64,
}

impl Default for Speed {
    fn default() -> Self {
        Speed {
            med: 0.0,
            low: 0.0,
            high: 0.0,
            low_util: 0.0,
            high_util: 0.0,
            min_util: 0.0,
            max_spd_util: 0.0,
            max_util: 100.0,
        }
    }
}

impl Speed {
    /// The function over `var` of `domain`.
    pub fn build(&self, domain: &Domain, var: &str) -> Result<IvpFunction, IvpError> {
        let mut z = ZaicSpd::new(domain, var)?;
        z.set_params(
            self.med,
            self.low,
            self.high,
            self.low_util,
            self.high_util,
            self.min_util,
            self.max_spd_util,
            self.max_util,
        );
        z.try_extract()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn speed_domain() -> Domain {
        Domain::parse("speed:0:4:41").expect("domain")
    }

    /// The named builder makes exactly the function of the positional one.
    #[test]
    fn peak_is_the_positional_builder() {
        let d = speed_domain();
        let named = Peak {
            summit: 1.5,
            peak_width: 0.2,
            base_width: 1.0,
            summit_delta: 10.0,
            min_util: 5.0,
            max_util: 90.0,
            value_wrap: false,
        }
        .build(&d, "speed")
        .expect("built");
        let mut z = ZaicPeak::new(&d, "speed").expect("zaic");
        z.set_params(1.5, 0.2, 1.0, 10.0, 5.0, 90.0, 0);
        let positional = z.extract(true).expect("built");
        for i in 0..=40 {
            assert_eq!(named.eval(&[i]), positional.eval(&[i]), "at index {i}");
        }
    }

    #[test]
    fn value_wrap_reaches_past_the_domain_end() {
        let d = Domain::parse("course:0:359:360").expect("domain");
        let peak = Peak {
            summit: 355.0,
            base_width: 20.0,
            ..Peak::default()
        };
        let cut = peak.build(&d, "course").expect("built");
        let wrapped = Peak {
            value_wrap: true,
            ..peak
        }
        .build(&d, "course")
        .expect("built");
        assert_eq!(cut.eval(&[5]), Some(0.0));
        assert!(wrapped.eval(&[5]).is_some_and(|u| u > 0.0));
    }

    #[test]
    fn speed_is_the_positional_builder_and_bad_values_are_errors() {
        let d = speed_domain();
        let named = Speed {
            med: 2.0,
            low: 1.0,
            high: 3.0,
            low_util: 60.0,
            high_util: 40.0,
            ..Speed::default()
        }
        .build(&d, "speed")
        .expect("built");
        let mut z = ZaicSpd::new(&d, "speed").expect("zaic");
        z.set_params5(2.0, 1.0, 3.0, 60.0, 40.0);
        let positional = z.extract().expect("built");
        for i in 0..=40 {
            assert_eq!(named.eval(&[i]), positional.eval(&[i]), "at index {i}");
        }
        let bad = Peak {
            summit: f64::NAN,
            ..Peak::default()
        };
        assert!(bad.build(&d, "speed").is_err());
        assert!(
            Peak::default().build(&d, "course").is_err(),
            "no such variable"
        );
    }
}
