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

/// Most tiles of `vals` (per tile `k`, the values `vals[j][k]`) given one value at all
/// their points, or all but one, or zeros of either sign: ordinary values, zeros, values
/// about the filled steps' limit 2^1020, the greatest, subnormals, infinities, NaN.
fn flatten(vals: &mut [Vec<f64>], seed: &mut u64) {
    let limit = f64::from_bits(0x7fb0_0000_0000_0000);
    let below = f64::from_bits(limit.to_bits() - 1);
    let flat = [
        100.0,
        -100.0,
        0.1,
        1.0 / 3.0,
        0.0,
        limit,
        -limit,
        below,
        -below,
        f64::MAX,
        1e-310,
        -5e-324,
        f64::INFINITY,
        -f64::INFINITY,
        f64::NAN,
    ];
    for k in 0..vals[0].len() {
        if rng(seed) < 0.3 {
            continue;
        }
        let v = if rng(seed) < 0.2 {
            (rng(seed) - 0.5) * 1e3
        } else {
            flat[(rng(seed) * flat.len() as f64) as usize % flat.len()]
        };
        for list in vals.iter_mut() {
            // Zeros of either sign.
            list[k] = if v == 0.0 && rng(seed) < 0.5 { -v } else { v };
        }
        if rng(seed) < 0.1 {
            let j = (rng(seed) * 5.0) as usize % 5;
            vals[j][k] = value(seed);
        }
    }
}

/// [`fit_run_avx2`] is [`fit_run_plain`] bit for bit, over runs of 0 to 40 tiles (the
/// vector loops' tails), every kind of width (0, powers of two, others), with and
/// without centre, strict or not, on awkward values and on tiles of one value (the
/// filled steps).
#[cfg(target_arch = "x86_64")]
#[test]
fn fit_run_avx2_is_the_plain_fit() {
    if !std::arch::is_x86_feature_detected!("avx2") {
        return;
    }
    let mut seed = 11u64;
    for case in 0..16000 {
        let n = case % 41;
        let list = |seed: &mut u64| (0..n).map(|_| value(seed)).collect::<Vec<f64>>();
        let mut vals: Vec<Vec<f64>> = (0..5).map(|_| list(&mut seed)).collect();
        if case % 4 != 3 {
            flatten(&mut vals, &mut seed);
        }
        if case % 5 == 4 {
            // Zeros and the least subnormals only: zero planes and intercepts of either
            // sign, residual sums rounding to zero.
            let tiny = [0.0, -0.0, 5e-324, -5e-324, 1e-323, -1.5e-323, 3e-323];
            for v in vals.iter_mut().flat_map(|l| l.iter_mut()) {
                *v = tiny[(rng(&mut seed) * tiny.len() as f64) as usize % tiny.len()];
            }
        }
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

/// The normalizing row before the edges were picked arithmetically (the oracle): the
/// same weights and ranges bit for bit, on awkward weights and random integer edges.
#[test]
fn normalize_row_equals_the_pick_of_edges() {
    let mut seed = 29u64;
    for case in 0..4000 {
        let n = case % 41;
        let xl: Vec<f64> = (0..n).map(|_| (rng(&mut seed) * 400.0).floor()).collect();
        let xh: Vec<f64> = xl
            .iter()
            .map(|x| x + (rng(&mut seed) * 9.0).floor())
            .collect();
        let w: Vec<Vec<f64>> = (0..3)
            .map(|_| (0..n).map(|_| value(&mut seed)).collect())
            .collect();
        let (shift, scale) = (value(&mut seed), value(&mut seed));
        let y = [(case % 13) as f64, (case % 13 + 2) as f64];
        let (mut w0, mut w1, mut w2) = (w[0].clone(), w[1].clone(), w[2].clone());
        let (mut lo, mut hi) = (vec![0.0; n], vec![0.0; n]);
        let row = NormRow {
            x: [&xl, &xh],
            y,
            w: [&mut w0, &mut w1, &mut w2],
            min: &mut lo,
            max: &mut hi,
        };
        normalize_row(row, shift, scale);
        let mut want = [w[0].clone(), w[1].clone(), w[2].clone(), vec![], vec![]];
        for k in 0..n {
            let (a, b) = (w[0][k] * scale, w[1][k] * scale);
            let c = (w[2][k] + shift) * scale;
            let (mut lo, mut hi) = (c, c);
            hi += a * if a < 0.0 { xl[k] } else { xh[k] };
            lo += a * if a < 0.0 { xh[k] } else { xl[k] };
            hi += b * if b < 0.0 { y[0] } else { y[1] };
            lo += b * if b < 0.0 { y[1] } else { y[0] };
            (want[0][k], want[1][k], want[2][k]) = (a, b, c);
            want[3].push(lo);
            want[4].push(hi);
        }
        let got = [w0, w1, w2, lo, hi].map(|v| bits(&v));
        assert_eq!(got, want.map(|v| bits(&v)), "case {case}");
    }
}

/// [`fold_range`] (four lanes, the fold in order only for zeros of both signs) is the
/// reflector's fold as it was written (the oracle: min_max_wt's comparisons, the last
/// piece first), on awkward values with ties of signed zeros, a NaN last piece, and
/// lists of zeros of one sign or both with values above or below them.
#[test]
fn fold_range_equals_the_fold_in_order() {
    let mut seed = 31u64;
    for case in 1..12000 {
        let n = 1 + case % 75;
        let zeros = [0.0, -0.0];
        let zeros_of = [&zeros[..], &zeros[..1], &zeros[1..]][(case / 7) % 3];
        let pick = |seed: &mut u64| {
            if case % 5 == 1 && rng(seed) < 0.8 {
                // Zeros (of one sign or both) the extreme, or not.
                let z = zeros_of[(rng(seed) * 2.0) as usize % zeros_of.len()];
                [z, z, z, 5.0, -5.0][(case / 3) % 5]
            } else if case % 3 == 0 && rng(seed) < 0.5 {
                zeros[(rng(seed) * 2.0) as usize % 2]
            } else {
                value(seed)
            }
        };
        let lo: Vec<f64> = (0..n).map(|_| pick(&mut seed)).collect();
        let hi: Vec<f64> = (0..n).map(|_| pick(&mut seed)).collect();
        let (mut mn, mut mx) = (lo[n - 1], hi[n - 1]);
        for k in (0..n - 1).rev() {
            if lo[k] < mn {
                mn = lo[k];
            }
            if hi[k] > mx {
                mx = hi[k];
            }
        }
        let got = fold_range(&lo, &hi);
        assert_eq!(bits(&[got.0, got.1]), bits(&[mn, mx]), "case {case}");
    }
}

/// [`write_reversed`] (four pieces at a time by shuffles where AVX2 is at hand) is the
/// piece-by-piece write in reverse, normalized or not, bit for bit, after any prefix
/// already in the weights, over lists of 0 to 40 pieces of awkward values.
#[test]
fn write_reversed_is_the_reversed_write() {
    let mut seed = 43u64;
    for case in 0..3000 {
        let n = case % 41;
        let w: Vec<Vec<f64>> = (0..3)
            .map(|_| (0..n).map(|_| value(&mut seed)).collect())
            .collect();
        let scale = (case % 3 != 0).then(|| (value(&mut seed), value(&mut seed)));
        let prefix: Vec<f64> = (0..case % 5).map(|_| value(&mut seed)).collect();
        let mut want = prefix.clone();
        for k in (0..n).rev() {
            let p = [w[0][k], w[1][k], w[2][k]];
            want.extend(match scale {
                Some((shift, s)) => [p[0] * s, p[1] * s, (p[2] + shift) * s],
                None => p,
            });
        }
        let mut got = prefix;
        write_reversed([&w[0], &w[1], &w[2]], [scale, None], &mut got);
        assert_eq!(bits(&got), bits(&want), "case {case}");
    }
}

/// [`normalized_range`] (the range of the normalized pieces without writing them) is
/// [`fold_range`] of the ranges [`normalize_row`] writes, bit for bit, or `None` only for
/// an extreme of zeros; over grids of 1 to 9 rows of 0 to 40 pieces of awkward weights,
/// some all zero (zeros of both signs at the extremes), many flat (slopes +0, taken the
/// shorter way) with ordinary, zero, huge and awkward intercepts, under ordinary and
/// awkward shifts and scales (infinite, NaN, zero, negative, tiny, huge).
#[test]
fn normalized_range_is_the_fold_of_normalized_rows() {
    let mut seed = 53u64;
    let mut answered = 0;
    for case in 0..12000 {
        let (nx, ny) = (case % 41, 1 + case % 9);
        let n = nx * ny;
        let xl: Vec<f64> = (0..nx).map(|k| (3 * k) as f64).collect();
        let xh: Vec<f64> = xl.iter().map(|x| x + (case % 3) as f64).collect();
        let yl: Vec<f64> = (0..ny).map(|k| (2 * k) as f64).collect();
        let yh: Vec<f64> = yl.iter().map(|y| y + 1.0).collect();
        let zero = case % 7 == 0;
        let mut w: Vec<Vec<f64>> = (0..3)
            .map(|_| {
                (0..n)
                    .map(|_| if zero { 0.0 } else { value(&mut seed) })
                    .collect()
            })
            .collect();
        // Flat pieces (slopes +0; or −0, not flat) of any intercept, most of the time.
        let share = [0.0, 0.5, 0.95][case % 3];
        for k in 0..n {
            if !zero && rng(&mut seed) < share {
                let slope = |seed: &mut u64| if rng(seed) < 0.9 { 0.0 } else { -0.0 };
                (w[0][k], w[1][k]) = (slope(&mut seed), slope(&mut seed));
                let c = [100.0, 0.0, -0.0, 1e300, -1e300, 5e-324][case / 3 % 6];
                w[2][k] = if rng(&mut seed) < 0.7 {
                    c
                } else {
                    value(&mut seed)
                };
            }
        }
        let odd = [
            f64::INFINITY,
            -f64::INFINITY,
            f64::NAN,
            0.0,
            -0.0,
            -2.5,
            1e-300,
            1e300,
        ];
        let (shift, scale) = if zero {
            ([0.0, -0.0][case % 2], 1.0)
        } else if case % 5 < 2 {
            (value(&mut seed), value(&mut seed))
        } else if case % 5 == 2 {
            let s = odd[(rng(&mut seed) * 8.0) as usize % 8];
            ((rng(&mut seed) - 0.5) * 300.0, s)
        } else {
            ((rng(&mut seed) - 0.5) * 300.0, rng(&mut seed) * 3.0)
        };
        let got = normalized_range((&xl, &xh, &yl, &yh, [&w[0], &w[1], &w[2]]), shift, scale);
        if n == 0 {
            assert!(got.is_none(), "case {case}");
            continue;
        }
        let (mut w0, mut w1, mut w2) = (w[0].clone(), w[1].clone(), w[2].clone());
        let (mut lo, mut hi) = (vec![0.0; n], vec![0.0; n]);
        for cy in 0..ny {
            let (i, j) = (cy * nx, (cy + 1) * nx);
            let row = NormRow {
                x: [&xl, &xh],
                y: [yl[cy], yh[cy]],
                w: [&mut w0[i..j], &mut w1[i..j], &mut w2[i..j]],
                min: &mut lo[i..j],
                max: &mut hi[i..j],
            };
            normalize_row(row, shift, scale);
        }
        let want = fold_range(&lo, &hi);
        match got {
            Some(got) => {
                answered += 1;
                assert_eq!(
                    bits(&[got.0, got.1]),
                    bits(&[want.0, want.1]),
                    "case {case}"
                );
            }
            None => assert!(want.0 == 0.0 || want.1 == 0.0, "case {case}"),
        }
    }
    assert!(answered > 6000, "{answered}");
}

/// Two scalings written at once are the first written then the second applied to it.
#[test]
fn write_reversed_twice_is_once_then_again() {
    let mut seed = 61u64;
    for case in 0..2000 {
        let n = case % 41;
        let w: Vec<Vec<f64>> = (0..3)
            .map(|_| (0..n).map(|_| value(&mut seed)).collect())
            .collect();
        let s1 = Some((value(&mut seed), value(&mut seed)));
        let s2 = (case % 4 != 0).then(|| (value(&mut seed), value(&mut seed)));
        let mut once = vec![];
        write_reversed([&w[0], &w[1], &w[2]], [s1, None], &mut once);
        // Back in the lists' order, then written again with the second scaling.
        let back: Vec<Vec<f64>> = (0..3)
            .map(|d| (0..n).map(|k| once[3 * (n - 1 - k) + d]).collect())
            .collect();
        let mut want = vec![];
        write_reversed([&back[0], &back[1], &back[2]], [s2, None], &mut want);
        let mut got = vec![];
        write_reversed([&w[0], &w[1], &w[2]], [s1, s2], &mut got);
        assert_eq!(bits(&got), bits(&want), "case {case}");
    }
}

/// Raising a row's cells four at a time ([`avx2::raise_cells`]) is raising them tile by
/// tile in the reflector's order (build_grid's step), bit for bit: rows of 0 to 40 tiles,
/// 1 to 5 tiles a cell, cells starting at -inf or not, awkward values (NaN, infinities,
/// zeros of both signs: the bits tell them apart).
#[cfg(target_arch = "x86_64")]
#[test]
fn raise_cells_of_row_is_the_raise_tile_by_tile() {
    if !std::arch::is_x86_feature_detected!("avx2") {
        return;
    }
    let mut seed = 23u64;
    for case in 0..6000usize {
        let (n, per_cell) = (case % 41, 1 + (case / 41) % 5);
        let row: Vec<f64> = (0..n).map(|_| value(&mut seed)).collect();
        let ncells = n.div_ceil(per_cell);
        let start: Vec<f64> = (0..ncells)
            .map(|_| match case % 3 {
                0 => f64::NEG_INFINITY,
                1 if rng(&mut seed) < 0.5 => f64::NEG_INFINITY,
                _ => value(&mut seed),
            })
            .collect();
        let mut want = start.clone();
        for cx in (0..n).rev() {
            let g = &mut want[cx / per_cell];
            if *g == f64::NEG_INFINITY || row[cx] > *g {
                *g = row[cx];
            }
        }
        let mut got = start.clone();
        raise_cells_of_row(&mut got, &row, per_cell);
        assert_eq!(bits(&got), bits(&want), "case {case}");
    }
}
