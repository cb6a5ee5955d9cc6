//! What a behavior keeps between its function builds: a function whose inputs (by their
//! exact bits) did not change (the SDK's [`Kept`]), and the ZAIC builders it sets up
//! again every iteration.

pub use behavior_api::kept::{drop_on_failure, peak, Kept};

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
