//! The shape of a one-component ZAIC_PEAK and its three `.bhv` parameters, as the
//! Constant* behaviors take them (behaviors-plugins.md §2-§4).

use behavior_api::ivp::{Domain, IvpFunction, ZaicPeak};
use behavior_api::parse_number;

/// Peak width, base width and summit delta of a ZAIC_PEAK.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PeakShape {
    pub peakwidth: f64,
    pub basewidth: f64,
    pub summitdelta: f64,
}

impl PeakShape {
    pub const fn new(peakwidth: f64, basewidth: f64, summitdelta: f64) -> Self {
        PeakShape {
            peakwidth,
            basewidth,
            summitdelta,
        }
    }

    /// Handles `peakwidth`, `basewidth` (negative becomes 0) and `summitdelta` (clipped to
    /// [0, 100]): `None` for any other parameter, else whether the value was a number.
    pub fn set_param(&mut self, param: &str, value: &str) -> Option<bool> {
        let field = match param {
            "peakwidth" => &mut self.peakwidth,
            "basewidth" => &mut self.basewidth,
            "summitdelta" => &mut self.summitdelta,
            _ => return None,
        };
        let Some(v) = parse_number(value) else {
            return Some(false);
        };
        *field = if param == "summitdelta" {
            v.clamp(0.0, 100.0)
        } else {
            v.max(0.0)
        };
        Some(true)
    }

    /// The peak over `var` of `domain` with its summit at `summit`, wrapping around the
    /// ends of the variable's range when `wrap` (headings); without pwt. `None` when
    /// `var` is not in `domain` or the builder refuses a value.
    pub fn function(
        &self,
        domain: &Domain,
        var: &str,
        summit: f64,
        wrap: bool,
    ) -> Option<IvpFunction> {
        let mut z = ZaicPeak::new(domain, var).ok()?;
        z.set_summit(summit, 0);
        z.set_base_width(self.basewidth, 0);
        z.set_peak_width(self.peakwidth, 0);
        z.set_summit_delta(self.summitdelta, 0);
        if wrap {
            z.set_value_wrap(true);
        }
        z.extract(true)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use behavior_api::sdk::HelmDomain;

    fn shape() -> PeakShape {
        PeakShape::new(1.0, 2.0, 3.0)
    }

    #[test]
    fn parameters_are_clipped_and_others_left_alone() {
        let mut s = shape();
        assert_eq!(s.set_param("peakwidth", "-3"), Some(true));
        assert_eq!(s.set_param("basewidth", " 4.5 "), Some(true));
        assert_eq!(s.set_param("summitdelta", "150"), Some(true));
        assert_eq!(s, PeakShape::new(0.0, 4.5, 100.0));
        assert_eq!(s.set_param("summitdelta", "-1"), Some(true));
        assert_eq!(s.summitdelta, 0.0);
        assert_eq!(s.set_param("peakwidth", "wide"), Some(false));
        assert_eq!(s.set_param("basewidth", "1e3"), Some(false));
        assert_eq!(s.set_param("PeakWidth", "1"), None);
        assert_eq!(s.set_param("speed", "1"), None);
        assert_eq!((s.peakwidth, s.basewidth), (0.0, 4.5));
    }

    #[test]
    fn function_over_the_named_variable_only() {
        let helm = HelmDomain::new("course,0,359,360:speed,0,2,21");
        let dom = helm.ivp_domain(&["course", "speed"]).unwrap();
        let s = PeakShape::new(0.0, 0.2, 0.0);
        let f = s.function(&dom, "speed", 1.0, false).unwrap();
        assert_eq!(
            (f.domain().size(), f.domain().var(0).name.as_str()),
            (1, "speed")
        );
        assert!(s.function(&dom, "depth", 1.0, false).is_none());
    }
}
