//! What a behavior keeps between its function builds: a function whose inputs (by their
//! exact bits) did not change (the SDK's [`Kept`]), and the ZAIC builders it sets up
//! again every iteration.

pub use behavior_api::kept::Kept;
use ivp::zaic::ZaicPeak;
use ivp::Domain;

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

/// Drop the kept builder after a failed setter (`ok` false): the next build starts
/// from a fresh one, as the reference does every iteration.
pub fn drop_on_failure(slot: &mut Option<ZaicPeak>, ok: bool) {
    if !ok {
        *slot = None;
    }
}

#[cfg(test)]
pub(crate) mod tests {
    pub use behavior_api::testing::function_bits as parts;

    /// A reproducible pick among `n`.
    pub fn picker(mut seed: u64) -> impl FnMut(u64) -> u64 {
        move |n| {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (seed >> 33) % n
        }
    }
}
