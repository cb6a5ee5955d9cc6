//! ZAIC_SPD (spec §3.2): speed preference from five anchors.

use super::{one_var, pieces_from_anchors};
use crate::domain::Domain;
use crate::error::{invalid, IvpError};
use crate::function::IvpFunction;

/// ZAIC_SPD builder.
#[derive(Debug, Clone)]
pub struct ZaicSpd {
    domain: Domain,
    med: f64,
    low: f64,
    hgh: f64,
    low_util: f64,
    hgh_util: f64,
    min_util: f64,
    max_spd_util: f64,
    max_util: f64,
    warnings: String,
    error: Option<IvpError>,
}

impl ZaicSpd {
    /// Builder over variable `var` of `domain`.
    pub fn new(domain: &Domain, var: &str) -> Result<Self, IvpError> {
        let d = one_var(domain, var)?;
        let (lo, hi) = (d.var(0).low, d.var(0).high);
        Ok(ZaicSpd {
            domain: d,
            med: lo,
            low: lo,
            hgh: hi,
            low_util: 0.0,
            hgh_util: 0.0,
            min_util: 0.0,
            max_spd_util: 0.0,
            max_util: 100.0,
            warnings: String::new(),
            error: None,
        })
    }

    fn finite(&mut self, param: &str, v: f64) -> bool {
        if v.is_finite() {
            return true;
        }
        self.error.get_or_insert(IvpError::NotFinite {
            param: param.to_string(),
            value: v,
        });
        false
    }

    fn clip_speed(&self, v: f64) -> f64 {
        let var = self.domain.var(0);
        v.max(var.low).min(var.high)
    }

    fn clip_util(&self, v: f64) -> f64 {
        v.max(0.0).min(self.max_util)
    }

    /// `setParams(med, low, hgh, low_util, hgh_util, min_util, max_util, max_util_total)`.
    /// Speeds are clipped into the domain, utilities into `[0, max_util_total]`.
    /// Returns true exactly when the adjustment step changed something (the values
    /// clipped, or a low/high utility overridden at the domain's edge); false also when
    /// a value is not finite (nothing built then).
    #[allow(clippy::too_many_arguments)]
    pub fn set_params(
        &mut self,
        med: f64,
        low: f64,
        hgh: f64,
        low_util: f64,
        hgh_util: f64,
        min_util: f64,
        max_spd_util: f64,
        max_util: f64,
    ) -> bool {
        let names = [
            ("med_spd", med),
            ("low_spd", low),
            ("hgh_spd", hgh),
            ("low_spd_util", low_util),
            ("hgh_spd_util", hgh_util),
            ("min_spd_util", min_util),
            ("max_spd_util", max_spd_util),
            ("max_util", max_util),
        ];
        let mut all_finite = true;
        for (n, v) in names {
            all_finite = self.finite(n, v) && all_finite;
        }
        if !all_finite {
            return false;
        }
        self.max_util = max_util.max(0.0);
        self.med = self.clip_speed(med);
        self.low = self.clip_speed(low);
        self.hgh = self.clip_speed(hgh);
        self.low_util = self.clip_util(low_util);
        self.hgh_util = self.clip_util(hgh_util);
        self.min_util = self.clip_util(min_util);
        self.max_spd_util = self.clip_util(max_spd_util);
        self.adjust()
    }

    /// The adjustment step (spec §3.2), applied to the stored parameters: the median
    /// into the domain, low/high speeds on their side of it, utilities at most
    /// `max_util`, and the low (high) utility overridden by `min_spd_util`
    /// (`max_spd_util`) when the low (high) speed is the domain's edge. Returns whether
    /// it changed something, the override counting as a change even when the value
    /// stays: that is `setParams`' answer in the real builder.
    fn adjust(&mut self) -> bool {
        let var = self.domain.var(0);
        let (dlow, dhigh) = (var.low, var.high);
        let before = self.params();
        self.med = self.med.max(dlow).min(dhigh);
        self.low = self.low.max(dlow).min(self.med);
        self.hgh = self.hgh.max(self.med).min(dhigh);
        let mu = self.max_util;
        self.min_util = self.min_util.min(mu);
        self.low_util = self.low_util.min(mu);
        self.hgh_util = self.hgh_util.min(mu);
        self.max_spd_util = self.max_spd_util.min(mu);
        let mut overridden = false;
        if self.low == dlow {
            self.low_util = self.min_util;
            overridden = true;
        }
        if self.hgh == dhigh {
            self.hgh_util = self.max_spd_util;
            overridden = true;
        }
        overridden || before != self.params()
    }

    /// The parameters the adjustment may change, compared bit for bit.
    fn params(&self) -> [u64; 7] {
        [
            self.med,
            self.low,
            self.hgh,
            self.min_util,
            self.low_util,
            self.hgh_util,
            self.max_spd_util,
        ]
        .map(f64::to_bits)
    }

    /// `setParams` with the C++ defaults `min_util = 0, max_util = 0, max_util_total = 100`.
    pub fn set_params5(
        &mut self,
        med: f64,
        low: f64,
        hgh: f64,
        low_util: f64,
        hgh_util: f64,
    ) -> bool {
        self.set_params(med, low, hgh, low_util, hgh_util, 0.0, 0.0, 100.0)
    }

    pub fn set_med_speed(&mut self, v: f64) -> bool {
        if !self.finite("med_spd", v) {
            return false;
        }
        self.med = self.clip_speed(v);
        true
    }
    /// Always true for a finite value: the real setter fails only without a domain
    /// (the value is clipped to the domain; its side of the median is settled by the
    /// adjustment).
    pub fn set_low_speed(&mut self, v: f64) -> bool {
        if !self.finite("low_spd", v) {
            return false;
        }
        self.low = self.clip_speed(v);
        true
    }
    /// Always true for a finite value (as [`ZaicSpd::set_low_speed`]).
    pub fn set_hgh_speed(&mut self, v: f64) -> bool {
        if !self.finite("hgh_spd", v) {
            return false;
        }
        self.hgh = self.clip_speed(v);
        true
    }
    pub fn set_low_speed_util(&mut self, v: f64) -> bool {
        if !self.finite("low_spd_util", v) {
            return false;
        }
        self.low_util = self.clip_util(v);
        true
    }
    pub fn set_hgh_speed_util(&mut self, v: f64) -> bool {
        if !self.finite("hgh_spd_util", v) {
            return false;
        }
        self.hgh_util = self.clip_util(v);
        true
    }
    pub fn set_min_spd_util(&mut self, v: f64) -> bool {
        if !self.finite("min_spd_util", v) {
            return false;
        }
        self.min_util = self.clip_util(v);
        true
    }
    pub fn set_max_spd_util(&mut self, v: f64) -> bool {
        if !self.finite("max_spd_util", v) {
            return false;
        }
        self.max_spd_util = self.clip_util(v);
        true
    }
    /// Low speed := domain low (its utility becomes `min_spd_util`).
    pub fn disable_low_speed(&mut self) {
        self.low = self.domain.var(0).low;
    }
    /// High speed := domain high (its utility becomes `max_spd_util`).
    pub fn disable_high_speed(&mut self) {
        self.hgh = self.domain.var(0).high;
    }

    pub fn warnings(&self) -> &str {
        &self.warnings
    }

    pub fn extract(&mut self) -> Option<IvpFunction> {
        self.try_extract().ok()
    }

    pub fn try_extract(&mut self) -> Result<IvpFunction, IvpError> {
        if let Some(e) = &self.error {
            return Err(e.clone());
        }
        self.adjust();
        let var = self.domain.var(0);
        let dlow = var.low;
        let (med, low, hgh) = (self.med, self.low, self.hgh);
        let (mu, min_u, low_u) = (self.max_util, self.min_util, self.low_util);
        let (hgh_u, max_u) = (self.hgh_util, self.max_spd_util);
        let n = var.points as i32;
        let delta = var.delta();
        let idx = |s: f64| -> i32 {
            if delta <= 0.0 {
                return 0;
            }
            let t = ((s - dlow) / delta + 0.5).trunc();
            t.max(0.0).min(f64::from(n - 1)) as i32
        };
        let i2 = idx(med);
        let i1 = idx(low).min(i2);
        let i3 = idx(hgh).max(i2);
        let (mut d, mut r) = (Vec::with_capacity(5), Vec::with_capacity(5));
        if i2 != 0 {
            d.push(0);
            r.push(min_u);
        }
        if i1 != 0 && i1 != i2 {
            d.push(i1);
            r.push(low_u);
        }
        d.push(i2);
        r.push(mu);
        if i3 != i2 {
            d.push(i3);
            r.push(hgh_u);
        }
        if i3 != n - 1 {
            d.push(n - 1);
            r.push(max_u);
        }
        let p = pieces_from_anchors(&d, &r, n)
            .ok_or_else(|| invalid("anchors", "not strictly increasing from 0 to N-1"))?;
        Ok(p.finish(self.domain.clone()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn speed_domain() -> Domain {
        Domain::parse("speed:0:5:51").expect("domain")
    }

    #[test]
    fn set_params_reports_whether_the_adjustment_changed_something() {
        // hgh_spd at the domain's high edge: its utility is overridden (a change).
        let mut z = ZaicSpd::new(&speed_domain(), "speed").expect("builder");
        assert!(z.set_params5(4.9, 4.8, 5.0, 30.0, 30.0));
        assert!(z.extract().is_some());
        // Nothing to adjust: false, and the function is still built.
        let mut z = ZaicSpd::new(&speed_domain(), "speed").expect("builder");
        assert!(!z.set_params5(2.0, 1.0, 3.0, 50.0, 50.0));
        assert!(z.extract().is_some());
        // low_spd above the median is clipped to it: a change.
        let mut z = ZaicSpd::new(&speed_domain(), "speed").expect("builder");
        assert!(z.set_params5(2.0, 3.0, 4.0, 50.0, 50.0));
        // low_spd at the domain's low edge: overridden even though min_spd_util = 0
        // leaves the utility where a 0 argument put it.
        let mut z = ZaicSpd::new(&speed_domain(), "speed").expect("builder");
        assert!(z.set_params5(2.0, 0.0, 3.0, 0.0, 50.0));
    }

    #[test]
    fn setters_succeed_on_either_side_of_the_median() {
        let mut z = ZaicSpd::new(&speed_domain(), "speed").expect("builder");
        assert!(z.set_med_speed(2.0));
        assert!(z.set_low_speed(3.0));
        assert!(z.set_hgh_speed(1.0));
        assert!(!z.set_low_speed(f64::NAN));
    }
}
