//! A behavior's last IvP function kept between builds: while the inputs it was built
//! from are the same (by their exact bits), it is lent again instead of built. Built-in
//! and plugin behaviors whose function seldom changes (a constant depth, a cruise speed)
//! share this one mechanism, and the ZAIC builders they set up again every iteration.

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

#[cfg(test)]
mod tests {
    use super::*;

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
}
