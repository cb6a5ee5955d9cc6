//! ZAIC_PEAK (spec §3.1).

use super::shape::{dist_of, Component, Shape};
use super::{one_var, pieces_from_samples};
use crate::domain::Domain;
use crate::error::IvpError;
use crate::function::IvpFunction;

thread_local! {
    /// Components of dropped builders, for the next ones on this thread.
    static SPARE_COMPS: std::cell::RefCell<Vec<Vec<Component>>> = const { std::cell::RefCell::new(Vec::new()) };
}

thread_local! {
    static SCRATCH: std::cell::RefCell<Vec<f64>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// ZAIC_PEAK builder: one or more peak components, combined by max or sum.
#[derive(Debug, Clone)]
pub struct ZaicPeak {
    domain: Domain,
    pub(crate) comps: Vec<Component>,
    value_wrap: bool,
    summit_insist: bool,
    warnings: String,
    error: Option<IvpError>,
    /// The pieces' buffers, kept for the next [`ZaicPeak::try_extract_coupled`] of a
    /// builder kept across iterations.
    kept: super::Pieces1,
}

/// A builder's storage goes to the spares when it is dropped (one is made for every
/// ZAIC of every behavior every iteration).
impl Drop for ZaicPeak {
    fn drop(&mut self) {
        let mut comps = std::mem::take(&mut self.comps);
        if comps.capacity() > 0 {
            comps.clear();
            let _ = SPARE_COMPS.try_with(|s| super::spare::keep(&mut s.borrow_mut(), comps));
        }
        crate::domain::give_domain(std::mem::take(&mut self.domain));
        std::mem::take(&mut self.kept).give_back();
    }
}

impl ZaicPeak {
    /// Builder over variable `var` of `domain` (fails if `var` is missing).
    pub fn new(domain: &Domain, var: &str) -> Result<Self, IvpError> {
        Ok(ZaicPeak {
            domain: one_var(domain, var)?,
            comps: {
                let spare = SPARE_COMPS.try_with(|s| s.borrow_mut().pop());
                let mut comps = spare.ok().flatten().unwrap_or_default();
                comps.push(Component::default());
                comps
            },
            value_wrap: false,
            summit_insist: true,
            warnings: String::new(),
            error: None,
            kept: Default::default(),
        })
    }

    fn warn(&mut self, w: &str) {
        if !self.warnings.is_empty() {
            self.warnings.push_str(" # ");
        }
        self.warnings.push_str(w);
    }

    /// Fails (records the typed error, returns false) on a bad index or non-finite value.
    /// The passing test is inlined into the setters (every ZAIC of every behavior is set
    /// up every iteration); the failures are recorded out of line.
    #[inline]
    fn check(&mut self, idx: usize, param: &str, v: f64) -> bool {
        if idx < self.comps.len() && v.is_finite() {
            return true;
        }
        self.check_failed(idx, param, v)
    }

    /// [`ZaicPeak::check`]'s failures: the warning and the typed error.
    #[cold]
    #[inline(never)]
    fn check_failed(&mut self, idx: usize, param: &str, v: f64) -> bool {
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
        let mut p = super::Pieces1::default();
        self.pieces(maxval, &mut p)?;
        Ok(p.finish(crate::domain::domain_of(self.domain.vars())))
    }

    /// [`ZaicPeak::try_extract`] then [`crate::coupler::try_couple_normalized`] of that
    /// function (f1, weight `w1`) with `f2` (weight `w2`): the same function, bit for
    /// bit, without making the pieces a function in between (the Waypoint's course
    /// function, every iteration). The outer error is the extraction's, the inner one
    /// the coupler's.
    pub fn try_extract_coupled(
        &mut self,
        maxval: bool,
        f2: &IvpFunction,
        weights: (f64, f64),
        normalize: bool,
    ) -> Result<Result<IvpFunction, IvpError>, IvpError> {
        let mut p = std::mem::take(&mut self.kept);
        let done = self.pieces(maxval, &mut p);
        let out = done.map(|()| {
            let pieces = (&p.bounds[..], &mut p.weights[..]);
            crate::coupler::try_couple_line(self.domain.var(0), pieces, f2, weights, normalize)
        });
        self.kept = p;
        out
    }

    /// The pieces of the function, into `out` (its pieces replaced).
    fn pieces(&self, maxval: bool, out: &mut super::Pieces1) -> Result<(), IvpError> {
        if let Some(e) = &self.error {
            return Err(e.clone());
        }
        let var = self.domain.var(0);
        let grid = super::peak_scan::Grid {
            low: var.low,
            high: var.high,
            delta: var.delta(),
            points: var.points as usize,
            wrap: self.value_wrap,
        };
        if super::peak_scan::pieces(&self.comps, grid, maxval, out).is_some() {
            return Ok(());
        }
        let n = grid.points;
        // Sample buffers reused per thread: this runs for every ZAIC of every behavior
        // every iteration, and fresh zeroed vectors cost more than the sampling.
        SCRATCH.with_borrow_mut(|scratch| {
            scratch.resize(2 * n, 0.0);
            let (total, vals) = scratch.split_at_mut(n);
            self.sample_into(maxval, total, vals);
            std::mem::replace(out, pieces_from_samples(total)).give_back();
            Ok(())
        })
    }

    /// Sum (or max, `maxval`) of the components' samples into `total`; `vals` is scratch
    /// of the same length.
    pub(crate) fn sample_into(&self, maxval: bool, total: &mut [f64], vals: &mut [f64]) {
        let var = self.domain.var(0);
        let delta = var.delta();
        let n = var.points as usize;
        for (k, c) in self.comps.iter().enumerate() {
            let shape = Shape::of(c);
            // The first component's samples go straight into `total` (what the
            // combination below would copy there).
            let first = k == 0;
            let buf: &mut [f64] = if first { &mut *total } else { &mut *vals };
            shape.sample(c.summit, self.value_wrap, var.low, var.high, delta, buf);
            if self.summit_insist && buf.iter().all(|&v| v == c.minutil) && n > 0 {
                let ix = if c.summit < var.low {
                    0
                } else if c.summit > var.high {
                    n - 1
                } else {
                    let mut best = 0usize;
                    let mut bd = f64::INFINITY;
                    for i in 0..n {
                        let x = i as f64 * delta + var.low;
                        let d = dist_of(c.summit, x, self.value_wrap, var.low, var.high, delta);
                        if d < bd {
                            bd = d;
                            best = i;
                        }
                    }
                    best
                };
                buf[ix] = c.maxutil;
            }
            if first {
                continue;
            }
            for i in 0..n {
                if maxval {
                    if vals[i] > total[i] {
                        total[i] = vals[i];
                    }
                } else {
                    total[i] += vals[i];
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The distance as the spec states it, the short way round with `wrap`.
    fn dist(wrap: bool, summit: f64, x: f64, low: f64, high: f64, delta: f64) -> f64 {
        if !wrap {
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

    /// Extracted and coupled at once, the function is the one of extracting then
    /// coupling, bit for bit, on both paths (the skipping scan, and every point sampled:
    /// a max of two components), with the coupler's refusals the same.
    #[test]
    fn extract_coupled_is_extract_then_couple() {
        let d = Domain::parse("course:0:359:360,speed:0:4:41").unwrap();
        let mut s = ZaicPeak::new(&d, "speed").unwrap();
        s.set_params(1.5, 0.75, 1.6, 20.0, 0.0, 100.0, 0);
        let mut spd = s.extract(true).unwrap();
        spd.normalize(0.0, 40.0);
        let bits = |f: &IvpFunction| f.weights().iter().map(|w| w.to_bits()).collect::<Vec<_>>();
        for (wrap, maxval, summit) in [
            (true, false, 120.5),
            (false, true, 33.3),
            (true, false, 0.0),
        ] {
            let mut z = ZaicPeak::new(&d, "course").unwrap();
            z.set_value_wrap(wrap);
            z.set_params(summit, 0.0, 180.0, 50.0, 0.0, 100.0, 0);
            let k = z.add_component();
            z.set_params(10.0, 30.0, 180.0, 5.0, 0.0, 20.0, k);
            for (w1, norm) in [(60.0, true), (60.0, false), (0.0, true)] {
                let want = crate::coupler::try_couple_normalized(
                    z.try_extract(maxval).unwrap(),
                    &spd,
                    w1,
                    40.0,
                    norm,
                );
                let got = z
                    .try_extract_coupled(maxval, &spd, (w1, 40.0), norm)
                    .unwrap();
                let (Ok(want), Ok(got)) = (&want, &got) else {
                    assert_eq!(want.err(), got.err());
                    continue;
                };
                assert_eq!((got.bounds(), got.domain()), (want.bounds(), want.domain()));
                assert_eq!(bits(got), bits(want));
            }
        }
        // Its own failure comes first, the coupler's inside.
        let mut z = ZaicPeak::new(&d, "course").unwrap();
        z.set_min_max_util(5.0, 1.0, 0);
        assert!(z
            .try_extract_coupled(false, &spd, (50.0, 50.0), true)
            .is_err());
        let mut z = ZaicPeak::new(&d, "speed").unwrap();
        assert!(matches!(
            z.try_extract_coupled(false, &spd, (50.0, 50.0), true),
            Ok(Err(_))
        ));
    }

    /// The branch-free sampler gives, bit for bit, the utility of the distance.
    #[test]
    fn sample_is_bit_identical_to_utility_of_dist() {
        let d = Domain::parse("course:0:359:360").unwrap();
        let (low, high, delta) = (0.0, 359.0, 1.0);
        let comps = [
            (120.5, 0.0, 180.0, 50.0, 0.0, 100.0),
            (10.0, 30.0, 180.0, 5.0, 0.0, 20.0),
            (350.0, 0.0, 0.0, 0.0, 0.0, 100.0),
            (-20.0, 15.0, 40.0, 0.0, 10.0, 90.0),
            (200.0, 7.5, 0.25, 100.0, 0.0, 100.0),
        ];
        for wrap in [false, true] {
            for &(summit, pw, bw, dl, mn, mx) in &comps {
                let mut z = ZaicPeak::new(&d, "course").unwrap();
                z.set_value_wrap(wrap);
                z.set_params(summit, pw, bw, dl, mn, mx, 0);
                let c = z.comps[0];
                let shape = Shape::of(&c);
                let mut out = vec![0.0; 360];
                shape.sample(c.summit, wrap, low, high, delta, &mut out);
                for (i, &v) in out.iter().enumerate() {
                    let x = i as f64 * delta + low;
                    let want = shape.utility(dist(wrap, c.summit, x, low, high, delta));
                    assert_eq!(v.to_bits(), want.to_bits(), "{wrap} {summit} {i}");
                }
            }
        }
    }
}
