//! A behavior's last IvP function kept between builds: while the inputs it was built
//! from are the same (by their exact bits), it is lent again instead of built. Built-in
//! and plugin behaviors whose function seldom changes (a constant depth, a cruise speed)
//! share this one mechanism, and the ZAIC builders they set up again every iteration;
//! [`CoupledPeaks`] is both at once for two peaks coupled 50/50.

use ivp::zaic::ZaicPeak;
use ivp::{Domain, IvpFunction};

/// The last function built, with the key of the inputs it was built from.
pub struct Kept<K> {
    last: Option<(K, IvpFunction)>,
}

impl<K> Default for Kept<K> {
    fn default() -> Self {
        Kept { last: None }
    }
}

impl<K: PartialEq> Kept<K> {
    /// The kept function when `key` is its key, else `build()` (kept when it succeeds;
    /// failures are not kept, so they are met again with the same inputs). The function
    /// it replaces goes back to the spare storage.
    pub fn get<E>(
        &mut self,
        key: K,
        build: impl FnOnce() -> Result<IvpFunction, E>,
    ) -> Result<&IvpFunction, E> {
        let kept = match self.last.take() {
            Some((k, f)) if k == key => (k, f),
            old => {
                if let Some((_, f)) = old {
                    f.recycle();
                }
                (key, build()?)
            }
        };
        Ok(&self.last.insert(kept).1)
    }
}

/// The ZAIC_PEAK builder over `var` kept in `slot` (made, with value wrap `wrap` and
/// `comps` components, when there is none), its parameters to be set again by the
/// caller: every parameter the caller sets is overwritten, so it builds what a fresh
/// builder would. A builder whose setter failed carries that failure: the caller drops
/// it ([`drop_on_failure`]).
pub fn peak<'a>(
    slot: &'a mut Option<ZaicPeak>,
    domain: &Domain,
    var: &str,
    wrap: bool,
    comps: usize,
) -> Option<&'a mut ZaicPeak> {
    if slot.is_none() {
        let mut z = ZaicPeak::new(domain, var).ok()?;
        z.set_value_wrap(wrap);
        while z.components() < comps {
            z.add_component();
        }
        *slot = Some(z);
    }
    slot.as_mut()
}

/// Drop the kept builder unless `ok` (its setters succeeded; a caller may also ask for
/// no warnings): the next build starts from a fresh one, as the reference does every
/// iteration.
pub fn drop_on_failure(slot: &mut Option<ZaicPeak>, ok: bool) {
    if !ok {
        *slot = None;
    }
}

/// The key of a [`crate::zaic::Peak`]: its numbers by their bits, and its wrap.
fn peak_key(p: &crate::zaic::Peak) -> [u64; 7] {
    let b = f64::to_bits;
    [
        b(p.summit),
        b(p.peak_width),
        b(p.base_width),
        b(p.summit_delta),
        b(p.min_util),
        b(p.max_util),
        u64::from(p.value_wrap),
    ]
}

/// What a behavior keeps between its builds of two peaks coupled 50/50 (a course peak
/// with a speed peak in Trail, Shadow and StationKeep; speed with depth in
/// PeriodicSurface): the second peak's function while that peak is the same (a steady
/// speed, a fixed depth), and the first peak's builder.
pub struct CoupledPeaks {
    /// The variables of the first and the second peak.
    vars: (&'static str, &'static str),
    /// The second peak's function, normalized to [0, 50] as the coupler normalizes it.
    second: Kept<[u64; 7]>,
    /// The first peak's builder; every parameter is set again each build.
    first: Option<ZaicPeak>,
}

impl Default for CoupledPeaks {
    /// A course peak coupled with a speed peak.
    fn default() -> Self {
        CoupledPeaks::over("course", "speed")
    }
}

impl CoupledPeaks {
    /// A peak over `first` coupled with a peak over `second`.
    pub fn over(first: &'static str, second: &'static str) -> Self {
        CoupledPeaks {
            vars: (first, second),
            second: Kept::default(),
            first: None,
        }
    }

    /// `couple(p1 over the first variable, p2 over the second, 50, 50, true)` of two
    /// freshly built peaks, bit for bit, with the first one's pieces coupled straight
    /// from its builder. `None` when a builder or the coupler fails (a caller that
    /// reports failures then builds afresh for the messages).
    pub fn build(
        &mut self,
        domain: &Domain,
        p1: &crate::zaic::Peak,
        p2: &crate::zaic::Peak,
    ) -> Option<IvpFunction> {
        let (v1, v2) = self.vars;
        let f2 = self
            .second
            .get(peak_key(p2), || {
                let mut f = p2.build(domain, v2)?;
                f.normalize(0.0, 50.0);
                Ok::<_, ivp::IvpError>(f)
            })
            .ok()?;
        let z = peak(&mut self.first, domain, v1, p1.value_wrap, 1)?;
        z.set_value_wrap(p1.value_wrap);
        let ok = z.set_params(
            p1.summit,
            p1.peak_width,
            p1.base_width,
            p1.summit_delta,
            p1.min_util,
            p1.max_util,
            0,
        );
        let f = z.try_extract_coupled(true, f2, (50.0, 50.0), true);
        // A builder that failed or warned carries that state: the next build starts
        // from a fresh one.
        let keep = ok && z.warnings().is_empty();
        drop_on_failure(&mut self.first, keep);
        f.ok()?.ok()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::function_bits;
    use crate::zaic::Peak;

    fn one_piece(v: f64) -> IvpFunction {
        let d = ivp::Domain::parse("x:0:9:10").unwrap();
        IvpFunction::from_pieces(d, &[(vec![(0, 9)], vec![0.0, v])]).unwrap()
    }

    #[test]
    fn built_once_per_key_and_failures_not_kept() {
        let mut kept = Kept::default();
        let mut builds = 0;
        for (key, v) in [(1u64, 5.0), (1, 6.0), (2, 7.0), (2, 8.0), (1, 9.0)] {
            let f = kept
                .get(key, || {
                    builds += 1;
                    Ok::<_, ()>(one_piece(v))
                })
                .unwrap();
            // The function of the key's first build, lent while the key holds.
            let want = match (key, v) {
                (1, 6.0) => 5.0,
                (2, 8.0) => 7.0,
                _ => v,
            };
            assert_eq!(f.weights()[1], want);
        }
        assert_eq!(builds, 3);
        assert!(kept.get(3, || Err("no")).is_err());
        // The failure was not kept: the same key builds again.
        assert_eq!(
            kept.get(3, || Ok::<_, &str>(one_piece(1.0)))
                .unwrap()
                .weights()[1],
            1.0
        );
    }

    /// The reference: both peaks built afresh, then coupled.
    fn coupled_fresh(d: &Domain, crs: &Peak, spd: &Peak) -> Option<IvpFunction> {
        let fc = crs.build(d, "course").ok()?;
        let fs = spd.build(d, "speed").ok()?;
        ivp::coupler::couple(fc, fs, 50.0, 50.0, true)
    }

    /// Over random peaks (some repeated, some refused, utilities 0-100 and 0-25), the
    /// kept path gives the fresh function bit for bit, or fails where it fails.
    #[test]
    fn coupled_peaks_equal_fresh_ones() {
        let d = Domain::parse("course:0:359:360,speed:0:4:41").unwrap();
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
        for _ in 0..500 {
            let crs = Peak {
                summit: pick(next(7), &[0.0, 45.5, 180.0, 359.0, 370.0, -10.0, f64::NAN]),
                peak_width: pick(next(3), &[20.0, 30.0, 0.0]),
                base_width: pick(next(3), &[160.0, 180.0, 10.0]),
                summit_delta: pick(next(3), &[50.0, 0.0, 150.0]),
                value_wrap: next(5) != 0,
                ..Peak::default()
            };
            let spd = Peak {
                summit: pick(
                    next(8),
                    &[1.5, 1.5, 1.5, 0.0, 2.25, 4.0, 6.0, f64::INFINITY],
                ),
                peak_width: pick(next(2), &[0.1, 0.0]),
                base_width: pick(next(2), &[2.0, 0.4]),
                summit_delta: pick(next(3), &[10.0, 50.0, 0.0]),
                max_util: pick(next(3), &[100.0, 25.0, 100.0]),
                ..Peak::default()
            };
            let want = coupled_fresh(&d, &crs, &spd);
            let got = kept.build(&d, &crs, &spd);
            match (&want, &got) {
                (Some(w), Some(g)) => {
                    assert_eq!(function_bits(w), function_bits(g), "{crs:?} {spd:?}");
                    same += 1;
                }
                (None, None) => failed += 1,
                _ => panic!("{crs:?} {spd:?}: {} vs {}", want.is_some(), got.is_some()),
            }
        }
        assert!(same > 250 && failed > 20, "{same} {failed}");
    }
}
