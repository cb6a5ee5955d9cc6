//! The row kernels compiled for AVX2 against their baseline compilation, bit for bit.

use super::*;

fn rng(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*seed >> 11) as f64 / (1u64 << 53) as f64
}

/// Ordinary values mostly; ties, signed zeros, NaN, infinities and subnormals now and
/// then.
fn value(seed: &mut u64) -> f64 {
    let odd = [
        0.0,
        -0.0,
        f64::NAN,
        f64::INFINITY,
        -f64::INFINITY,
        1e-310,
        7.0,
    ];
    if rng(seed) < 0.15 {
        odd[(rng(seed) * odd.len() as f64) as usize % odd.len()]
    } else {
        (rng(seed) - 0.5) * 200.0
    }
}

fn bits(v: &[f64]) -> Vec<u64> {
    // NaN as the one canonical NaN: its sign is no property of the code.
    v.iter()
        .map(|&x| {
            if x.is_nan() {
                f64::NAN.to_bits()
            } else {
                x.to_bits()
            }
        })
        .collect()
}

/// [`fit_run_avx2`] is [`fit_run_plain`] bit for bit, over runs of 0 to 40 tiles (the
/// vector loops' tails), every kind of width (0, powers of two, others), with and
/// without centre, strict or not, on awkward values.
#[cfg(target_arch = "x86_64")]
#[test]
fn fit_run_avx2_is_the_plain_fit() {
    if !std::arch::is_x86_feature_detected!("avx2") {
        return;
    }
    let mut seed = 11u64;
    for case in 0..4000 {
        let n = case % 41;
        let list = |seed: &mut u64| (0..n).map(|_| value(seed)).collect::<Vec<f64>>();
        let vals: Vec<Vec<f64>> = (0..5).map(|_| list(&mut seed)).collect();
        let widths = (
            [0, 1, 2, 3, 4, 5, 8][case % 7],
            [0, 1, 2, 6, 16][(case / 7) % 5],
        );
        let xl: Vec<f64> = (0..n).map(|k| (k as u32 * (widths.0 + 1)) as f64).collect();
        let xh: Vec<f64> = xl.iter().map(|x| x + f64::from(widths.0)).collect();
        let xm: Vec<f64> = xl.iter().map(|x| x + f64::from(widths.0 / 2)).collect();
        let y0 = (rng(&mut seed) * 30.0).floor();
        let y = [y0, y0 + f64::from(widths.1), y0 + f64::from(widths.1 / 2)];
        let run = Run {
            x: [&xl, &xh, &xm],
            y,
            widths,
            vals: [&vals[0], &vals[1], &vals[2], &vals[3], &vals[4]],
            strict: case % 3 != 0,
            centre: case % 2 == 0 || widths.0 > 1 || widths.1 > 1,
        };
        let mut got: Vec<Vec<f64>> = vec![vec![-3.25; n]; 5];
        let mut want: Vec<Vec<f64>> = vec![vec![9.5; n]; 5];
        for (lists, wide) in [(&mut got, true), (&mut want, false)] {
            let [a, b, c, d, e] = &mut lists[..] else {
                unreachable!()
            };
            let mut out = RunOut {
                w: [a, b, c],
                min: d,
                max: e,
            };
            if wide {
                // SAFETY: AVX2 is present (checked above).
                unsafe { fit_run_avx2(&run, &mut out) };
            } else {
                fit_run_plain(&run, &mut out);
            }
        }
        for (g, w) in got.iter().zip(&want) {
            assert_eq!(bits(g), bits(w), "case {case}");
        }
    }
}

/// The normalizing row compiled for AVX2 is its baseline compilation bit for bit, on awkward weights, shifts and scales.
#[cfg(target_arch = "x86_64")]
#[test]
fn normalize_avx2_is_the_plain_normalize() {
    if !std::arch::is_x86_feature_detected!("avx2") {
        return;
    }
    let mut seed = 17u64;
    for case in 0..4000 {
        let n = case % 41;
        let xl: Vec<f64> = (0..n).map(|k| (3 * k) as f64).collect();
        let xh: Vec<f64> = xl.iter().map(|x| x + 2.0).collect();
        let w: Vec<Vec<f64>> = (0..3)
            .map(|_| (0..n).map(|_| value(&mut seed)).collect())
            .collect();
        let (shift, scale) = (value(&mut seed), value(&mut seed));
        let y = [(case % 13) as f64, (case % 13 + 2) as f64];
        let mut results = vec![];
        for wide in [true, false] {
            let (mut w0, mut w1, mut w2) = (w[0].clone(), w[1].clone(), w[2].clone());
            let (mut lo, mut hi) = (vec![0.0; n], vec![0.0; n]);
            let row = NormRow {
                x: [&xl, &xh],
                y,
                w: [&mut w0, &mut w1, &mut w2],
                min: &mut lo,
                max: &mut hi,
            };
            if wide {
                // SAFETY: AVX2 is present (checked above).
                unsafe { normalize_row_avx2(row, shift, scale) };
            } else {
                normalize_row_body(row, shift, scale);
            }
            results.push([w0, w1, w2, lo, hi].map(|v| bits(&v)));
        }
        assert_eq!(results[0], results[1], "case {case}");
    }
}
