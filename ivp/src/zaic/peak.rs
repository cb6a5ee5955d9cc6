//! ZAIC_PEAK (spec §3.1).

use super::{one_var, pieces_from_samples};
use crate::domain::Domain;
use crate::error::IvpError;
use crate::function::IvpFunction;

#[derive(Debug, Clone, Copy, PartialEq)]
struct Component {
    summit: f64,
    pwidth: f64,
    bwidth: f64,
    delta: f64,
    minutil: f64,
    maxutil: f64,
}

/// A component's utility shape with its loop-invariant quotients computed once: the
/// same IEEE operations on the same operands as computing them per sample, so the
/// values are bit-identical, without two divisions per sample.
struct Shape {
    pwidth: f64,
    reach: f64,
    sd: f64,
    peak_slope: f64,
    edge: f64,
    base_slope: f64,
    minutil: f64,
    maxutil: f64,
}

impl Shape {
    fn of(c: &Component) -> Shape {
        let sd = if c.pwidth > 0.0 { c.delta } else { 0.0 };
        let edge = c.maxutil - sd;
        Shape {
            pwidth: c.pwidth,
            reach: c.pwidth + c.bwidth,
            sd,
            peak_slope: sd / c.pwidth,
            edge,
            base_slope: (edge - c.minutil) / c.bwidth,
            minutil: c.minutil,
            maxutil: c.maxutil,
        }
    }

    /// Utility at distance `dist` from the summit (spec §3.1).
    fn utility(&self, dist: f64) -> f64 {
        let val = if dist <= self.pwidth {
            if self.sd <= 0.0 {
                self.maxutil
            } else {
                self.maxutil - self.peak_slope * dist
            }
        } else if dist <= self.reach {
            self.edge - self.base_slope * (dist - self.pwidth)
        } else {
            self.minutil
        };
        if val > self.maxutil {
            self.maxutil
        } else {
            val
        }
    }
}

impl Default for Component {
    fn default() -> Self {
        Component {
            summit: 0.0,
            pwidth: 0.0,
            bwidth: 0.0,
            delta: 0.0,
            minutil: 0.0,
            maxutil: 100.0,
        }
    }
}

/// ZAIC_PEAK builder: one or more peak components, combined by max or sum.
#[derive(Debug, Clone)]
pub struct ZaicPeak {
    domain: Domain,
    comps: Vec<Component>,
    value_wrap: bool,
    summit_insist: bool,
    warnings: String,
    error: Option<IvpError>,
}

impl ZaicPeak {
    /// Builder over variable `var` of `domain` (fails if `var` is missing).
    pub fn new(domain: &Domain, var: &str) -> Result<Self, IvpError> {
        Ok(ZaicPeak {
            domain: one_var(domain, var)?,
            comps: vec![Component::default()],
            value_wrap: false,
            summit_insist: true,
            warnings: String::new(),
            error: None,
        })
    }

    fn warn(&mut self, w: &str) {
        if !self.warnings.is_empty() {
            self.warnings.push_str(" # ");
        }
        self.warnings.push_str(w);
    }

    /// Fails (records the typed error, returns false) on a bad index or non-finite value.
    fn check(&mut self, idx: usize, param: &str, v: f64) -> bool {
        if idx >= self.comps.len() {
            self.warn(&format!("{param}:index out of range"));
            self.error.get_or_insert(IvpError::BadComponent {
                index: idx,
                count: self.comps.len(),
            });
            return false;
        }
        if !v.is_finite() {
            self.warn(&format!("{param}:not a finite number"));
            self.error.get_or_insert(IvpError::NotFinite {
                param: param.to_string(),
                value: v,
            });
            return false;
        }
        true
    }

    pub fn set_summit(&mut self, v: f64, idx: usize) -> bool {
        if !self.check(idx, "summit", v) {
            return false;
        }
        self.comps[idx].summit = v;
        true
    }

    /// Negative widths become 0.
    pub fn set_peak_width(&mut self, v: f64, idx: usize) -> bool {
        if !self.check(idx, "peakwidth", v) {
            return false;
        }
        self.comps[idx].pwidth = v.max(0.0);
        true
    }

    /// Negative widths become 0.
    pub fn set_base_width(&mut self, v: f64, idx: usize) -> bool {
        if !self.check(idx, "basewidth", v) {
            return false;
        }
        self.comps[idx].bwidth = v.max(0.0);
        true
    }

    /// Negative becomes 0; clipped to `maxutil - minutil` (with a warning).
    pub fn set_summit_delta(&mut self, v: f64, idx: usize) -> bool {
        if !self.check(idx, "summitdelta", v) {
            return false;
        }
        let c = &mut self.comps[idx];
        let mut d = v.max(0.0);
        let range = c.maxutil - c.minutil;
        let clipped = d > range;
        if clipped {
            d = range;
        }
        c.delta = d;
        if clipped {
            self.warn("setSummitDelta:delta greater than util range");
        }
        true
    }

    /// `min >= max` makes the builder state bad (no function) and returns false.
    pub fn set_min_max_util(&mut self, min: f64, max: f64, idx: usize) -> bool {
        if !self.check(idx, "minutil", min) || !self.check(idx, "maxutil", max) {
            return false;
        }
        if min >= max {
            self.warn("setMinMaxUtil:min>=max:");
            self.error
                .get_or_insert(IvpError::MinNotBelowMax { min, max });
            return false;
        }
        let c = &mut self.comps[idx];
        c.minutil = min;
        c.maxutil = max;
        if c.delta > max - min {
            c.delta = max - min;
        }
        true
    }

    /// summit, basewidth, peakwidth, then min/max util, then summit delta.
    #[allow(clippy::too_many_arguments)]
    pub fn set_params(
        &mut self,
        summit: f64,
        pwidth: f64,
        bwidth: f64,
        delta: f64,
        minutil: f64,
        maxutil: f64,
        idx: usize,
    ) -> bool {
        let mut ok = self.set_summit(summit, idx);
        ok = self.set_base_width(bwidth, idx) && ok;
        ok = self.set_peak_width(pwidth, idx) && ok;
        ok = self.set_min_max_util(minutil, maxutil, idx) && ok;
        ok = self.set_summit_delta(delta, idx) && ok;
        ok
    }

    /// Add a default component; returns its index.
    pub fn add_component(&mut self) -> usize {
        self.comps.push(Component::default());
        self.comps.len() - 1
    }

    pub fn set_value_wrap(&mut self, v: bool) {
        self.value_wrap = v;
    }

    pub fn set_summit_insist(&mut self, v: bool) {
        self.summit_insist = v;
    }

    /// Number of components.
    pub fn components(&self) -> usize {
        self.comps.len()
    }

    /// Warnings collected so far (C++ `getWarnings`).
    pub fn warnings(&self) -> &str {
        &self.warnings
    }

    /// Build the function (`maxval`: max over components, else the sum); `None` on bad state.
    pub fn extract(&mut self, maxval: bool) -> Option<IvpFunction> {
        self.try_extract(maxval).ok()
    }

    /// As [`ZaicPeak::extract`] with the typed reason of a failure.
    pub fn try_extract(&mut self, maxval: bool) -> Result<IvpFunction, IvpError> {
        if let Some(e) = &self.error {
            return Err(e.clone());
        }
        let var = self.domain.var(0).clone();
        let n = var.points as usize;
        let delta = var.delta();
        let mut total = vec![0.0f64; n];
        let mut vals = vec![0.0f64; n];
        for (k, c) in self.comps.iter().enumerate() {
            let shape = Shape::of(c);
            for (i, v) in vals.iter_mut().enumerate() {
                let x = i as f64 * delta + var.low;
                *v = shape.utility(self.dist(c.summit, x, var.low, var.high, delta));
            }
            if self.summit_insist && vals.iter().all(|&v| v == c.minutil) && n > 0 {
                let ix = if c.summit < var.low {
                    0
                } else if c.summit > var.high {
                    n - 1
                } else {
                    let mut best = 0usize;
                    let mut bd = f64::INFINITY;
                    for i in 0..n {
                        let x = i as f64 * delta + var.low;
                        let d = self.dist(c.summit, x, var.low, var.high, delta);
                        if d < bd {
                            bd = d;
                            best = i;
                        }
                    }
                    best
                };
                vals[ix] = c.maxutil;
            }
            for i in 0..n {
                if k == 0 {
                    total[i] = vals[i];
                } else if maxval {
                    if vals[i] > total[i] {
                        total[i] = vals[i];
                    }
                } else {
                    total[i] += vals[i];
                }
            }
        }
        Ok(pieces_from_samples(&total).finish(self.domain.clone()))
    }

    fn dist(&self, summit: f64, x: f64, low: f64, high: f64, delta: f64) -> f64 {
        if !self.value_wrap {
            return (summit - x).abs();
        }
        let (a, b) = if summit > x {
            (summit - x, (x - low) + (high - summit) + delta)
        } else {
            (x - summit, (high - x) + (summit - low) + delta)
        };
        if a < b {
            a
        } else {
            b
        }
    }
}
