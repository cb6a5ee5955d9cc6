//! Whether a function's weights hold a NaN: the helm checks every function a behavior
//! returns before it trusts it, thousands of weights a contact's function, each
//! iteration. AVX2 reads 16 a step where it is there.

/// Whether any of `xs` is NaN (of any sign or payload).
pub fn any_nan(xs: &[f64]) -> bool {
    #[cfg(target_arch = "x86_64")]
    if xs.len() >= 16 && std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: AVX2 is there (checked just above).
        return unsafe { any_nan_avx2(xs) };
    }
    any_nan_plain(xs)
}

/// [`any_nan`] without SIMD of its own. Not short-circuited: the whole scan vectorizes.
fn any_nan_plain(xs: &[f64]) -> bool {
    xs.iter().fold(false, |nan, w| nan | w.is_nan())
}

/// [`any_nan`] 16 values a step: an unordered comparison of two values is true where
/// either is NaN, so one compare covers 8 values.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn any_nan_avx2(xs: &[f64]) -> bool {
    use std::arch::x86_64::*;
    let (groups, rest) = xs.as_chunks::<16>();
    let mut acc = _mm256_setzero_pd();
    for g in groups {
        let p = g.as_ptr();
        // SAFETY: `g` holds 16 `f64`s, read at p .. p + 16.
        let [a, b, c, d] = unsafe {
            [
                _mm256_loadu_pd(p),
                _mm256_loadu_pd(p.add(4)),
                _mm256_loadu_pd(p.add(8)),
                _mm256_loadu_pd(p.add(12)),
            ]
        };
        let x = _mm256_cmp_pd::<_CMP_UNORD_Q>(a, b);
        let y = _mm256_cmp_pd::<_CMP_UNORD_Q>(c, d);
        acc = _mm256_or_pd(acc, _mm256_or_pd(x, y));
    }
    _mm256_movemask_pd(acc) != 0 || any_nan_plain(rest)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every length up to 70, a NaN (quiet or signalling, either sign) at every place,
    /// or none among infinities and zeros of both signs.
    #[test]
    fn any_nan_finds_every_nan_and_only_nan() {
        let nans = [
            f64::NAN,
            -f64::NAN,
            f64::from_bits(0x7ff0_0000_0000_0001),
            f64::from_bits(0xfff0_0000_dead_beef),
        ];
        let plain = [
            1.5,
            -0.0,
            0.0,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::MAX,
            1e-310,
        ];
        for n in 0..70 {
            let base: Vec<f64> = (0..n).map(|i| plain[i % plain.len()]).collect();
            assert!(!any_nan(&base), "{n}");
            for at in 0..n {
                for &x in &nans {
                    let mut v = base.clone();
                    v[at] = x;
                    assert!(any_nan(&v), "{n} {at}");
                    assert!(any_nan_plain(&v));
                }
            }
        }
    }
}
