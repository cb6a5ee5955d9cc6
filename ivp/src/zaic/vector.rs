//! ZAIC_Vector (spec §3.5): explicit value → utility table.

use super::{one_var, Pieces1};
use crate::domain::{Domain, Snap};
use crate::error::{invalid, IvpError};
use crate::function::IvpFunction;

/// ZAIC_Vector builder.
#[derive(Debug, Clone)]
pub struct ZaicVector {
    domain: Domain,
    values: Vec<f64>,
    utils: Vec<f64>,
    warnings: String,
}

impl ZaicVector {
    pub fn new(domain: &Domain, var: &str) -> Result<Self, IvpError> {
        Ok(ZaicVector {
            domain: one_var(domain, var)?,
            values: vec![],
            utils: vec![],
            warnings: String::new(),
        })
    }

    /// Domain values `x[k]`.
    pub fn set_domain_vals(&mut self, v: &[f64]) -> bool {
        self.values = v.to_vec();
        v.iter().all(|x| x.is_finite())
    }

    /// Utilities `u[k]`.
    pub fn set_range_vals(&mut self, u: &[f64]) -> bool {
        self.utils = u.to_vec();
        u.iter().all(|x| x.is_finite())
    }

    pub fn warnings(&self) -> &str {
        &self.warnings
    }

    /// Lowest utility given.
    pub fn min_util(&self) -> f64 {
        self.utils.iter().copied().fold(f64::INFINITY, f64::min)
    }
    /// Highest utility given.
    pub fn max_util(&self) -> f64 {
        self.utils.iter().copied().fold(f64::NEG_INFINITY, f64::max)
    }

    pub fn extract(&mut self) -> Option<IvpFunction> {
        self.try_extract().ok()
    }

    pub fn try_extract(&mut self) -> Result<IvpFunction, IvpError> {
        if self.values.len() != self.utils.len() {
            return Err(invalid("range_vals", "length differs from domain_vals"));
        }
        for (k, (&x, &u)) in self.values.iter().zip(&self.utils).enumerate() {
            crate::error::finite(&format!("domain_vals[{k}]"), x)?;
            crate::error::finite(&format!("range_vals[{k}]"), u)?;
        }
        let var = self.domain.var(0).clone();
        if self.values.is_empty() || self.values[0] < var.low || self.values[0] > var.high {
            return Err(invalid(
                "domain_vals",
                "first value outside the domain range",
            ));
        }
        if self
            .values
            .iter()
            .skip(1)
            .any(|&x| x < var.low || x > var.high)
        {
            self.warnings = "domain values outside the domain range".into();
        }
        // Stable selection sort when not non-decreasing.
        let (mut xs, mut us) = (self.values.clone(), self.utils.clone());
        if xs.windows(2).any(|w| w[1] < w[0]) {
            let mut used = vec![false; xs.len()];
            let (mut nx, mut nu) = (vec![], vec![]);
            for _ in 0..xs.len() {
                let mut best: Option<usize> = None;
                for j in 0..xs.len() {
                    if !used[j] && best.is_none_or(|b| xs[j] < xs[b]) {
                        best = Some(j);
                    }
                }
                if let Some(b) = best {
                    used[b] = true;
                    nx.push(xs[b]);
                    nu.push(us[b]);
                }
            }
            xs = nx;
            us = nu;
        }
        let n = var.points as i32;
        let mut entries: Vec<(i32, f64)> = xs
            .iter()
            .zip(&us)
            .map(|(&x, &u)| (self.domain.snap(0, x, Snap::Nearest) as i32, u))
            .collect();
        if let Some(&(i0, u0)) = entries.first() {
            if i0 != 0 {
                entries.insert(0, (0, u0));
            }
        }
        if let Some(&(il, ul)) = entries.last() {
            if il != n - 1 {
                entries.push((n - 1, ul));
            }
        }
        let mut d: Vec<i32> = vec![];
        let mut r: Vec<f64> = vec![];
        let mut i = 0;
        while i < entries.len() {
            let (ix, mut sum) = entries[i];
            let mut cnt = 1.0;
            let mut j = i + 1;
            while j < entries.len() && entries[j].0 == ix {
                sum += entries[j].1;
                cnt += 1.0;
                j += 1;
            }
            d.push(ix);
            r.push(sum / cnt);
            i = j;
        }
        if d.len() < 2 {
            return Err(invalid("domain_vals", "need at least 2 distinct indices"));
        }
        let mut out = Pieces1::default();
        for k in 0..d.len() - 1 {
            let lo = if k == 0 { d[0] } else { d[k] + 1 };
            out.push_anchor(lo, d[k], r[k], d[k + 1], r[k + 1]);
        }
        Ok(out.finish(self.domain.clone()))
    }
}
