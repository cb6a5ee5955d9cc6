//! ZAIC_SPD (spec §3.2): speed preference from five anchors.

use super::{one_var, pieces_from_anchors};
use crate::domain::Domain;
use crate::error::IvpError;
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
    /// Returns false when `low` is above or `hgh` below the median speed in force
    /// *before* the call (what the reference reports; the values are still used).
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
        let old_med = self.med;
        self.max_util = max_util.max(0.0);
        self.med = self.clip_speed(med);
        self.low = self.clip_speed(low);
        self.hgh = self.clip_speed(hgh);
        self.low_util = self.clip_util(low_util);
        self.hgh_util = self.clip_util(hgh_util);
        self.min_util = self.clip_util(min_util);
        self.max_spd_util = self.clip_util(max_spd_util);
        self.low <= old_med && self.hgh >= old_med
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
    /// Returns false if `v` is above the median speed (value still stored, clipped to the domain).
    pub fn set_low_speed(&mut self, v: f64) -> bool {
        if !self.finite("low_spd", v) {
            return false;
        }
        self.low = self.clip_speed(v);
        self.low <= self.med
    }
    /// Returns false if `v` is below the median speed (value still stored, clipped to the domain).
    pub fn set_hgh_speed(&mut self, v: f64) -> bool {
        if !self.finite("hgh_spd", v) {
            return false;
        }
        self.hgh = self.clip_speed(v);
        self.hgh >= self.med
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
        let var = self.domain.var(0).clone();
        let (dlow, dhigh) = (var.low, var.high);
        // Adjustment.
        let med = self.med.max(dlow).min(dhigh);
        let low = self.low.max(dlow).min(med);
        let hgh = self.hgh.max(med).min(dhigh);
        let mu = self.max_util;
        let min_u = self.min_util.min(mu);
        let mut low_u = self.low_util.min(mu);
        let mut hgh_u = self.hgh_util.min(mu);
        let max_u = self.max_spd_util.min(mu);
        if low == dlow {
            low_u = min_u;
        }
        if hgh == dhigh {
            hgh_u = max_u;
        }
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
        let p = pieces_from_anchors(&d, &r, n).ok_or_else(|| IvpError::Invalid {
            param: "anchors".into(),
            reason: "not strictly increasing from 0 to N-1".into(),
        })?;
        Ok(p.finish(self.domain.clone()))
    }
}
