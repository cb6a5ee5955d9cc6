//! The course × speed function of BHV_Trail and BHV_Shadow: a wrapping course peak and a
//! speed peak, coupled 50/50 and normalized, built every running iteration. What does
//! not change between iterations is kept: the speed function while its parameters are
//! the same (a steady contact speed) and the course builder.

use behavior_api::ivp::{Domain, IvpFunction, ZaicPeak};
use behavior_api::kept::{self, Kept};

/// One ZAIC_PEAK component: summit, peak width, base width, summit delta (utilities
/// 0 to 100).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Peak {
    pub summit: f64,
    pub pwidth: f64,
    pub bwidth: f64,
    pub delta: f64,
}

impl Peak {
    /// The builder of this peak over `var` of `domain`, as the behaviors set it up.
    pub fn builder(&self, domain: &Domain, var: &str, wrap: bool) -> Option<ZaicPeak> {
        let mut z = ZaicPeak::new(domain, var).ok()?;
        z.set_params(
            self.summit,
            self.pwidth,
            self.bwidth,
            self.delta,
            0.0,
            100.0,
            0,
        );
        if wrap {
            z.set_value_wrap(true);
        }
        Some(z)
    }

    fn key(&self) -> [u64; 4] {
        [self.summit, self.pwidth, self.bwidth, self.delta].map(f64::to_bits)
    }
}

/// What one behavior keeps between its builds of the coupled function.
#[derive(Default)]
pub struct CoupledPeaks {
    /// The speed function, normalized to [0, 50] as the coupler normalizes it.
    speed: Kept<[u64; 4]>,
    /// The course builder; every parameter is set again each build (`set_params`
    /// overwrites them all), so it builds what a fresh one would.
    course: Option<ZaicPeak>,
}

impl CoupledPeaks {
    /// `couple(course peak (wrapping), speed peak, 50, 50, true)`, bit for bit, with
    /// the course pieces coupled straight from the builder. `None` when a builder or
    /// the coupler fails: the caller then takes the reference's path for its messages.
    pub fn build(&mut self, domain: &Domain, crs: Peak, spd: Peak) -> Option<IvpFunction> {
        let f2 = self
            .speed
            .get(spd.key(), || {
                let mut z = spd.builder(domain, "speed", false).ok_or(())?;
                let mut f = z.extract(true).ok_or(())?;
                f.normalize(0.0, 50.0);
                Ok::<_, ()>(f)
            })
            .ok()?;
        let z = kept::peak(&mut self.course, domain, "course", true, 1)?;
        let ok = z.set_params(crs.summit, crs.pwidth, crs.bwidth, crs.delta, 0.0, 100.0, 0);
        let f = z.try_extract_coupled(true, f2, (50.0, 50.0), true);
        // A builder that failed or warned carries that state: the next build starts
        // from a fresh one.
        let keep = ok && z.warnings().is_empty();
        kept::drop_on_failure(&mut self.course, keep);
        f.ok()?.ok()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use behavior_api::ivp::couple;
    use behavior_api::testing::function_bits;

    /// The reference: both peaks made afresh, then coupled.
    fn fresh(domain: &Domain, crs: Peak, spd: Peak) -> Option<IvpFunction> {
        let fc = crs.builder(domain, "course", true)?.extract(true)?;
        let fs = spd.builder(domain, "speed", false)?.extract(true)?;
        couple(fc, fs, 50.0, 50.0, true)
    }

    /// Over random summits and widths (some repeated, some refused), the kept path
    /// gives the fresh function bit for bit, or fails where it fails.
    #[test]
    fn kept_build_equals_a_fresh_one() {
        let domain = Domain::parse("course:0:359:360,speed:0:4:41").unwrap();
        let mut kept = CoupledPeaks::default();
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = |n: u64| {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (seed >> 33) % n
        };
        let pick = |k: u64, of: &[f64]| of[k as usize % of.len()];
        let (mut same, mut failed) = (0, 0);
        for _ in 0..400 {
            let crs = Peak {
                summit: pick(next(7), &[0.0, 45.5, 180.0, 359.0, 370.0, -10.0, f64::NAN]),
                pwidth: pick(next(3), &[20.0, 30.0, 0.0]),
                bwidth: pick(next(3), &[160.0, 150.0, 10.0]),
                delta: pick(next(3), &[50.0, 0.0, 150.0]),
            };
            let spd = Peak {
                summit: pick(
                    next(8),
                    &[1.5, 1.5, 1.5, 0.0, 2.25, 4.0, 6.0, f64::INFINITY],
                ),
                pwidth: pick(next(2), &[0.1, 0.0]),
                bwidth: 2.0,
                delta: pick(next(2), &[10.0, 50.0]),
            };
            let want = fresh(&domain, crs, spd);
            let got = kept.build(&domain, crs, spd);
            match (&want, &got) {
                (Some(w), Some(g)) => {
                    assert_eq!(function_bits(w), function_bits(g), "{crs:?} {spd:?}");
                    same += 1;
                }
                (None, None) => failed += 1,
                _ => panic!("{crs:?} {spd:?}: {} vs {}", want.is_some(), got.is_some()),
            }
        }
        assert!(same > 200 && failed > 20, "{same} {failed}");
    }
}
