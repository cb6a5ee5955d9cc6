//! Depth over time as a run records it (when the helm's domain has `depth`), with each
//! surfacing: what the picture's depth strip draws.

/// Samples kept at most; older ones are thinned two to one (first and latest kept).
const CAP: usize = 4_000;
/// A vehicle shallower than this is at the surface.
const SURFACE: f64 = 0.2;

/// Depth over time, and whether to draw it.
#[derive(Clone, Debug, Default)]
pub struct DepthTrace {
    /// Set when the helm's domain has a `depth` variable (its `IVPHELM_DOMAIN`).
    pub enabled: bool,
    /// (seconds from the start, depth).
    samples: Vec<(f64, f64)>,
    /// Times a dive came back to the surface.
    surfacings: Vec<f64>,
    submerged: bool,
}

impl DepthTrace {
    pub fn push(&mut self, t: f64, depth: f64) {
        if !depth.is_finite() {
            return;
        }
        if depth > SURFACE {
            self.submerged = true;
        } else if self.submerged {
            self.submerged = false;
            if self.surfacings.len() < CAP {
                self.surfacings.push(t);
            }
        }
        if self.samples.len() >= CAP {
            let last = self.samples.pop();
            let mut i = 0;
            self.samples.retain(|_| {
                i += 1;
                i % 2 == 1
            });
            self.samples.extend(last);
        }
        self.samples.push((t, depth));
    }

    pub fn samples(&self) -> &[(f64, f64)] {
        &self.samples
    }

    /// When each dive ended at the surface (seconds from the start).
    pub fn surfacings(&self) -> &[f64] {
        &self.surfacings
    }

    pub fn max_depth(&self) -> f64 {
        self.samples.iter().map(|s| s.1).fold(0.0, f64::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thinning_keeps_the_ends() {
        let mut t = DepthTrace::default();
        for i in 0..(3 * CAP) {
            t.push(i as f64, 1.0);
        }
        assert!(t.samples().len() <= CAP);
        assert_eq!(t.samples()[0].0, 0.0);
        assert_eq!(t.samples().last().map(|s| s.0), Some((3 * CAP - 1) as f64));
    }
}
