//! The least and greatest rate of closure of [`CpaEngine::min_max_roc_with`] from four
//! cosines instead of the table of 360 (an objective function that needs the range of
//! the rate of closure but not each heading's cosine).

use super::{cos_or_zero, CpaEngine};

impl CpaEngine {
    /// `min_max_roc_with(&roc_cosines(), vmax)`, bit for bit, from the four cosines that
    /// can be the table's extremes; `None` (ask the table) unless the bearing is in
    /// [0, 360), `cn_to_os` finite and `vmax` in [1e-100, 1e100].
    ///
    /// Why four: the table's angles are `b − i` (plus 360 below 0), i.e. `f + k` for
    /// k = 0..=359 with `f` the bearing's fraction (exactly, or within 1e-13 for a
    /// bearing below 1). Only k = 0 and 359 lie within 1° of 0/360 (one of them within
    /// 0.5°), only k = 179 and 180 within 1° of 180; every other cosine is at least
    /// cos(1°) − cos(0.5°) > 1e-4 from the extreme, far beyond libm's error (under an
    /// ulp). At a positive `vmax` the rate `vmax·c + cn_to_os` is monotone in `c` (each
    /// rounded step is), so the extreme rates are those of the extreme cosines; they are
    /// finite and never −0 here (no product underflows: |c| > 1e-17), so the fold's
    /// picks among equal values cannot differ in bits.
    pub fn min_max_roc_fast(&self, vmax: f64) -> Option<(f64, f64)> {
        let b = self.abs_os_cn;
        let usable = (0.0..360.0).contains(&b)
            && self.cn_to_os.is_finite()
            && (1e-100..=1e100).contains(&vmax);
        if !usable {
            return None;
        }
        // roc_cosines' entry i.
        let entry = |i: usize| {
            let a = b - i as f64;
            cos_or_zero(if a < 0.0 { a + 360.0 } else { a })
        };
        // k ↦ i = (⌊b⌋ − k) mod 360.
        let fb = b as usize;
        let hi = entry(fb).max(entry((fb + 1) % 360));
        let lo = entry((fb + 180) % 360).min(entry((fb + 181) % 360));
        Some((self.roc_of_cosine(lo, vmax), self.roc_of_cosine(hi, vmax)))
    }
}
