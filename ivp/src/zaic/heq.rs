//! ZAIC_HEQ / ZAIC_LEQ (spec §3.4): "higher (lower) or equal is good".

use super::{one_var, Pieces1};
use crate::domain::Domain;
use crate::error::IvpError;
use crate::function::IvpFunction;

#[derive(Debug, Clone)]
struct Params {
    domain: Domain,
    summit: f64,
    basewidth: f64,
    summit_delta: f64,
    minutil: f64,
    maxutil: f64,
    warnings: String,
    error: Option<IvpError>,
}

impl Params {
    fn new(domain: &Domain, var: &str) -> Result<Self, IvpError> {
        Ok(Params {
            domain: one_var(domain, var)?,
            summit: 0.0,
            basewidth: 0.0,
            summit_delta: 0.0,
            minutil: 0.0,
            maxutil: 100.0,
            warnings: String::new(),
            error: None,
        })
    }
    fn bad(&mut self, e: IvpError, warning: &str) -> bool {
        if !self.warnings.is_empty() {
            self.warnings.push_str(" # ");
        }
        self.warnings.push_str(warning);
        self.error.get_or_insert(e);
        false
    }
    fn set_summit(&mut self, v: f64) -> bool {
        if !v.is_finite() {
            return self.bad(
                IvpError::NotFinite {
                    param: "summit".into(),
                    value: v,
                },
                "setSummit:not finite",
            );
        }
        self.summit = v;
        true
    }
    fn set_base_width(&mut self, v: f64) -> bool {
        if !v.is_finite() {
            return self.bad(
                IvpError::NotFinite {
                    param: "basewidth".into(),
                    value: v,
                },
                "setBaseWidth:not finite",
            );
        }
        if v < 0.0 {
            return self.bad(
                IvpError::Negative {
                    param: "basewidth".into(),
                    value: v,
                },
                "setBaseWidth:negative",
            );
        }
        self.basewidth = v;
        true
    }
    fn set_summit_delta(&mut self, v: f64) -> bool {
        if !v.is_finite() {
            return self.bad(
                IvpError::NotFinite {
                    param: "summit_delta".into(),
                    value: v,
                },
                "setSummitDelta:not finite",
            );
        }
        if v < 0.0 {
            return self.bad(
                IvpError::Negative {
                    param: "summit_delta".into(),
                    value: v,
                },
                "setSummitDelta:negative",
            );
        }
        self.summit_delta = v;
        true
    }
    fn set_min_max_util(&mut self, min: f64, max: f64) -> bool {
        if !min.is_finite() || !max.is_finite() {
            let (p, v) = if min.is_finite() {
                ("maxutil", max)
            } else {
                ("minutil", min)
            };
            return self.bad(
                IvpError::NotFinite {
                    param: p.into(),
                    value: v,
                },
                "setMinMaxUtil:not finite",
            );
        }
        if min >= max {
            return self.bad(
                IvpError::MinNotBelowMax { min, max },
                "setMinMaxUtil:min>=max:",
            );
        }
        self.minutil = min;
        self.maxutil = max;
        true
    }
    /// (delta, N, ib, round) with the index math that ignores the domain low.
    fn setup(&self) -> Result<(f64, i32, f64), IvpError> {
        if let Some(e) = &self.error {
            return Err(e.clone());
        }
        let var = self.domain.var(0);
        let delta = var.delta();
        if delta <= 0.0 {
            return Err(IvpError::ZeroDelta(var.name.clone()));
        }
        let ib = ((self.basewidth + delta / 2.0) / delta).trunc();
        Ok((delta, var.points as i32, ib))
    }
}

fn round_ix(v: f64, delta: f64, n: i32) -> i32 {
    let t = (v / delta + 0.5).trunc();
    t.max(0.0).min(f64::from(n - 1)) as i32
}

macro_rules! common_setters {
    () => {
        pub fn set_summit(&mut self, v: f64) -> bool {
            self.p.set_summit(v)
        }
        /// Negative is an error (returns false, no function).
        pub fn set_base_width(&mut self, v: f64) -> bool {
            self.p.set_base_width(v)
        }
        /// Negative is an error (returns false, no function).
        pub fn set_summit_delta(&mut self, v: f64) -> bool {
            self.p.set_summit_delta(v)
        }
        /// `min >= max` is an error (returns false, no function).
        pub fn set_min_max_util(&mut self, min: f64, max: f64) -> bool {
            self.p.set_min_max_util(min, max)
        }
        pub fn warnings(&self) -> &str {
            &self.p.warnings
        }
        pub fn extract(&mut self) -> Option<IvpFunction> {
            self.try_extract().ok()
        }
    };
}

/// ZAIC_HEQ builder (values at or above the summit are good).
#[derive(Debug, Clone)]
pub struct ZaicHeq {
    p: Params,
}

impl ZaicHeq {
    pub fn new(domain: &Domain, var: &str) -> Result<Self, IvpError> {
        Ok(ZaicHeq {
            p: Params::new(domain, var)?,
        })
    }
    common_setters!();

    pub fn try_extract(&mut self) -> Result<IvpFunction, IvpError> {
        let (delta, n, ib) = self.p.setup()?;
        let p = &self.p;
        let tb = -0.00001;
        let i2 = round_ix(p.summit, delta, n);
        let i1 = round_ix(p.summit - p.basewidth, delta, n).min(i2);
        let mut out = Pieces1::default();
        if i2 < n - 1 {
            if p.summit_delta > 0.0 && i2 < n - 2 {
                out.push(i2 + 1, n - 1, tb, p.maxutil);
                out.push(i2, i2, 0.0, p.maxutil + p.summit_delta);
            } else {
                out.push(i2, n - 1, tb, p.maxutil);
            }
        }
        if i1 < i2 {
            let s = (p.maxutil - p.minutil) / ib;
            let b = if i1 > 0 {
                p.minutil - s * f64::from(i1)
            } else {
                p.maxutil - s * f64::from(i2)
            };
            out.push(i1, i2 - 1, s, b);
        }
        if i1 > 0 {
            out.push(0, i1 - 1, -tb, p.minutil);
        }
        Ok(out.finish(p.domain.clone()))
    }
}

/// ZAIC_LEQ builder (values at or below the summit are good).
#[derive(Debug, Clone)]
pub struct ZaicLeq {
    p: Params,
}

impl ZaicLeq {
    pub fn new(domain: &Domain, var: &str) -> Result<Self, IvpError> {
        Ok(ZaicLeq {
            p: Params::new(domain, var)?,
        })
    }
    common_setters!();

    pub fn try_extract(&mut self) -> Result<IvpFunction, IvpError> {
        let (delta, n, ib) = self.p.setup()?;
        let p = &self.p;
        let tb = 0.00001;
        let i1 = round_ix(p.summit, delta, n);
        let i2 = round_ix(p.summit + p.basewidth, delta, n).max(i1);
        let mut out = Pieces1::default();
        if p.summit_delta > 0.0 && i1 > 1 {
            out.push(0, i1 - 1, tb, p.maxutil);
            out.push(i1, i1, 0.0, p.maxutil + p.summit_delta);
        } else {
            out.push(0, i1, tb, p.maxutil);
        }
        if i1 < i2 {
            let s = -(p.maxutil - p.minutil) / ib;
            let b = if i1 > 0 {
                p.maxutil - s * f64::from(i1)
            } else {
                p.minutil - s * f64::from(i2)
            };
            out.push(i1 + 1, i2, s, b);
        }
        if i2 < n - 1 {
            out.push(i2 + 1, n - 1, -tb, p.minutil);
        }
        Ok(out.finish(p.domain.clone()))
    }
}
