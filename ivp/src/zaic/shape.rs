//! A ZAIC_PEAK component and its utility shape, shared by the builder (`peak`) and
//! its skipping scan (`peak_scan`).

#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Component {
    pub(crate) summit: f64,
    pub(crate) pwidth: f64,
    pub(crate) bwidth: f64,
    pub(crate) delta: f64,
    pub(crate) minutil: f64,
    pub(crate) maxutil: f64,
}

/// A component's utility shape with its loop-invariant quotients computed once: the
/// same IEEE operations on the same operands as computing them per sample, so the
/// values are bit-identical, without two divisions per sample.
#[derive(Clone, Copy)]
pub(crate) struct Shape {
    pub(crate) pwidth: f64,
    pub(crate) reach: f64,
    pub(crate) sd: f64,
    peak_slope: f64,
    edge: f64,
    base_slope: f64,
    minutil: f64,
    maxutil: f64,
}

/// Distance from the summit to `x` on the grid `[low, high]` step `delta`, the short
/// way round when `wrap`: the sampler's expression (the skipping scan's `dist_to` is
/// the same with branches, so their values agree bit for bit).
#[inline(always)]
pub(crate) fn dist_of(summit: f64, x: f64, wrap: bool, low: f64, high: f64, delta: f64) -> f64 {
    if !wrap {
        return (summit - x).abs();
    }
    let above = summit > x;
    // `x - summit` is exactly `-(summit - x)` (and both +0.0 when equal): no select.
    let a = (summit - x).abs();
    let b = if above {
        (x - low) + (high - summit) + delta
    } else {
        (high - x) + (summit - low) + delta
    };
    if a < b {
        a
    } else {
        b
    }
}

impl Shape {
    pub(crate) fn of(c: &Component) -> Shape {
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

    /// `out[i]` = utility at grid value `i·delta + low`: [`Shape::utility`] of
    /// [`ZaicPeak::dist`], written without branches on the samples (selects of values
    /// computed with the very same operations) so the loop runs straight through 360
    /// headings several times per behavior per iteration.
    pub(crate) fn sample(
        &self,
        summit: f64,
        wrap: bool,
        low: f64,
        high: f64,
        delta: f64,
        out: &mut [f64],
    ) {
        // Two loops without a branch on `wrap` inside, every choice a select: the
        // compiler vectorizes them (this runs on every grid point of every ZAIC).
        if wrap {
            // `i as u32 as f64` is exact (grids are u32-sized) and vectorizes, where
            // a float counter is a chain the compiler must keep.
            for (i, v) in out.iter_mut().enumerate() {
                let x = f64::from(i as u32) * delta + low;
                *v = self.at(dist_of(summit, x, true, low, high, delta));
            }
        } else {
            for (i, v) in out.iter_mut().enumerate() {
                let x = f64::from(i as u32) * delta + low;
                *v = self.at(dist_of(summit, x, false, low, high, delta));
            }
        }
    }

    /// The utility at distance `dist` from the summit, as a chain of selects.
    #[inline(always)]
    pub(crate) fn at(&self, dist: f64) -> f64 {
        let peak = if self.sd <= 0.0 {
            self.maxutil
        } else {
            self.maxutil - self.peak_slope * dist
        };
        let base = self.edge - self.base_slope * (dist - self.pwidth);
        let val = if dist <= self.pwidth {
            peak
        } else if dist <= self.reach {
            base
        } else {
            self.minutil
        };
        if val > self.maxutil {
            self.maxutil
        } else {
            val
        }
    }

    /// [`Shape::at`] with branches for its selects: the same operations on the same
    /// operands where used, so the same value, computing only the branch taken (for the
    /// skipping scan, which looks at a few samples one at a time).
    #[inline(always)]
    pub(crate) fn utility(&self, dist: f64) -> f64 {
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
