//! The degree-1 fit of one box from its values (spec §8 step 3), shared by the
//! reflector's tile-by-tile path and the uniform tiling's grid path.

/// Boxes of up to this many dimensions are fitted without heap allocation.
pub(crate) const FIT_DIMS: usize = 4;

/// Whether the fit of box `b` takes its centre point too (some edge spans more than 2
/// grid points).
pub(crate) fn takes_centre(b: &[(u32, u32)]) -> bool {
    b.iter().any(|&(lo, hi)| hi - lo + 1 > 2)
}

/// The degree-1 fit of box `b` (1 to [`FIT_DIMS`] dimensions) from its values: `vals`
/// holds the corners (`vals[mask]`, bit d of `mask` set = dimension d at its high end)
/// and, when [`takes_centre`], the centre last. The n slopes then the intercept go to
/// `w`. Spec §8 step 3: slopes from the mean corner differences, intercept from the mean
/// residual, shifted into the values' range when `strict`.
pub(crate) fn fit_values(b: &[(u32, u32)], vals: &[f64], strict: bool, w: &mut [f64]) {
    match b.len() {
        1 => fit_values_n::<1>(b, vals, strict, w),
        2 => fit_values_n::<2>(b, vals, strict, w),
        3 => fit_values_n::<3>(b, vals, strict, w),
        _ => fit_values_n::<FIT_DIMS>(b, vals, strict, w),
    }
}

/// [`fit_values`] for `N` dimensions: [`fit_box`] on the box and values copied into
/// fixed-size arrays.
pub(crate) fn fit_values_n<const N: usize>(
    b: &[(u32, u32)],
    vals: &[f64],
    strict: bool,
    w: &mut [f64],
) {
    let ncorner = 1usize << N;
    let lo: [u32; N] = std::array::from_fn(|d| b[d].0);
    let hi: [u32; N] = std::array::from_fn(|d| b[d].1);
    let mut v = [0.0f64; (1 << FIT_DIMS) + 1];
    v[..vals.len()].copy_from_slice(vals);
    let mut out = [0.0f64; FIT_DIMS + 1];
    if vals.len() > ncorner {
        fit_box::<N, true>(&lo, &hi, &v, strict, &mut out);
    } else {
        fit_box::<N, false>(&lo, &hi, &v, strict, &mut out);
    }
    w[..=N].copy_from_slice(&out[..=N]);
}

/// `q / width` as an `f64` division, by a multiplication when `width` is a power of two:
/// `q · 2⁻ᵏ` and `q / 2ᵏ` are the same exact real number, rounded once the same way
/// (subnormal results included), so the same bits; the multiplication does not wait on
/// the divider. `width` is not 0 (a zero-width dimension has slope 0, not divided).
#[inline(always)]
pub(crate) fn div_by_width(q: f64, width: u32) -> f64 {
    if width.is_power_of_two() {
        // Exact: 1 / 2^k for k < 32.
        q * (1.0 / f64::from(width))
    } else {
        q / f64::from(width)
    }
}

/// The degree-1 fit of the box `lo..=hi` from `vals`: the corners (`vals[mask]`, bit d
/// of `mask` set = dimension d at its high end), then, when `CENTRE`, the centre at
/// `vals[2^N]`. The n slopes then the intercept go to `w[..=N]`. `N` and `CENTRE` are
/// constants, so every loop unrolls and the values stay in registers.
///
/// The arithmetic is [`crate::reflector::Reflector::fit`]'s, with two exact shortcuts: each point's plane
/// value is computed once and used for both the mean residual and the range check, and
/// the minima and maxima are taken by comparison. Those skip NaNs as `f64::min`/`max`
/// do (the running value starts infinite, never NaN) and may differ from them only in
/// the sign of a zero, which the shift (a difference of two values known to be unequal)
/// never shows.
#[inline(always)]
pub(crate) fn fit_box<const N: usize, const CENTRE: bool>(
    lo: &[u32; N],
    hi: &[u32; N],
    vals: &[f64; (1 << FIT_DIMS) + 1],
    strict: bool,
    w: &mut [f64; FIT_DIMS + 1],
) {
    let ncorner = 1usize << N;
    let m = ncorner + usize::from(CENTRE);
    let lof: [f64; N] = std::array::from_fn(|d| f64::from(lo[d]));
    let hif: [f64; N] = std::array::from_fn(|d| f64::from(hi[d]));
    for d in 0..N {
        let width = f64::from(hi[d] - lo[d]);
        if width == 0.0 {
            w[d] = 0.0;
            continue;
        }
        let mut sum = 0.0;
        let mut cnt = 0.0;
        for mask in 0..ncorner {
            if mask & (1 << d) == 0 {
                sum += vals[mask | (1 << d)] - vals[mask];
                cnt += 1.0;
            }
        }
        w[d] = div_by_width(sum / cnt, hi[d] - lo[d]);
    }
    // The plane (without intercept) at each corner, then at the centre.
    let mut plane = [0.0f64; (1 << FIT_DIMS) + 1];
    for (mask, p) in plane.iter_mut().enumerate().take(ncorner) {
        let mut acc = 0.0;
        for d in 0..N {
            acc += w[d] * if mask & (1 << d) != 0 { hif[d] } else { lof[d] };
        }
        *p = acc;
    }
    if CENTRE {
        let mut acc = 0.0;
        for d in 0..N {
            acc += w[d] * f64::from(lo[d] + (hi[d] - lo[d]) / 2);
        }
        plane[ncorner] = acc;
    }
    let mut isum = 0.0;
    for k in 0..m {
        isum += vals[k] - plane[k];
    }
    let mut icpt = isum / m as f64;
    if strict {
        let (mut vmin, mut vmax) = (f64::INFINITY, f64::NEG_INFINITY);
        let (mut pmin, mut pmax) = (f64::INFINITY, f64::NEG_INFINITY);
        for k in 0..m {
            let (v, p) = (vals[k], plane[k] + icpt);
            vmin = if v < vmin { v } else { vmin };
            vmax = if v > vmax { v } else { vmax };
            pmin = if p < pmin { p } else { pmin };
            pmax = if p > pmax { p } else { pmax };
        }
        if pmax > vmax {
            icpt -= pmax - vmax;
        } else if pmin < vmin {
            icpt += vmin - pmin;
        }
    }
    w[N] = icpt;
}
