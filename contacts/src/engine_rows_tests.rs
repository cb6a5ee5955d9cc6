//! The AVX2 row with [`FlatEnds`] is the formula, bit for bit, at the ends' borders,
//! and skips the formula where it can (awkward numbers with the ends given:
//! engine_tests.rs's `cpa_row_chunks_are_cpa_entry`).

use std::cell::Cell;

use super::*;
use crate::engine::tests::rng;

/// An avoidance utility ([`AvoidRamp`]): 0 below `cd`, 100 above `acd`, a ramp between
/// (with its division), flat at both ends as [`FlatEnds`] says.
fn metric(cd: f64, acd: f64) -> impl Fn(f64) -> f64 + Copy {
    let ramp = AvoidRamp { cd, acd };
    move |d: f64| ramp.at(d)
}

fn units() -> (Vec<f64>, Vec<f64>) {
    (0..360)
        .map(|h| f64::from(h).to_radians().sin_cos())
        .unzip()
}

fn same(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

/// The row with the ends on, against `cpa_entry` per candidate.
fn check(row: &CpaRow, (sins, coss): (&[f64], &[f64]), cd: f64, acd: f64, what: &str) {
    let f = metric(cd, acd);
    let flat = Some(FlatEnds {
        below: cd,
        above: acd,
    });
    let mut wide = vec![-7.0; sins.len()];
    // SAFETY: the callers checked that the CPU has AVX2.
    unsafe { cpa_row_avx2(row, (sins, coss), &mut wide, f, Ends::of(row, flat, &f)) };
    for (k, ((&s, &c), &w)) in sins.iter().zip(coss).zip(&wide).enumerate() {
        let want = cpa_entry(row, (s, c), &f);
        assert!(same(want, w), "{what} [{k}]: want {want} got {w}");
    }
}

/// Random scenes of every scale (ranges of a metre to kilometres, contacts still to
/// fast, horizons short and long) and, for each, ends placed on the exact distance of
/// one of the row's candidates and a few units of the last place either side of it, so
/// that the tests' slack is what decides: every answer is the formula's.
#[test]
fn flat_rows_are_the_formula_at_the_borders() {
    if !std::arch::is_x86_feature_detected!("avx2") {
        return;
    }
    let (sins, coss) = units();
    let mut seed = 5u64;
    for case in 0..4000 {
        let scale = [1.0, 30.0, 200.0, 5000.0][case % 4];
        let row = CpaRow {
            v: rng(&mut seed) * 4.0,
            px: (rng(&mut seed) - 0.5) * scale,
            py: (rng(&mut seed) - 0.5) * scale,
            cn_vx: (rng(&mut seed) - 0.5) * 6.0,
            cn_vy: (rng(&mut seed) - 0.5) * 6.0,
            now: 0.0,
            tol: [1.0, 20.0, 60.0, 1e6][(case / 4) % 4],
        };
        let row = CpaRow {
            now: row.px.hypot(row.py),
            ..row
        };
        // A distance of the row (identity f), and ends on and around it.
        let k = (rng(&mut seed) * 360.0) as usize % 360;
        let d = cpa_entry(&row, (sins[k], coss[k]), &|d| d);
        let nudge = |x: f64, ulps: i64| f64::from_bits((x.to_bits() as i64 + ulps) as u64);
        for ulps in [-3i64, -1, 0, 1, 3] {
            let e = nudge(d, ulps);
            check(
                &row,
                (&sins, &coss),
                e,
                e + 10.0,
                &format!("case {case} cd {e}"),
            );
            check(
                &row,
                (&sins, &coss),
                e * 0.5,
                e,
                &format!("case {case} acd {e}"),
            );
            check(
                &row,
                (&sins, &coss),
                e,
                e,
                &format!("case {case} cd=acd {e}"),
            );
        }
        check(
            &row,
            (&sins, &coss),
            8.0,
            25.0,
            &format!("case {case} 8..25"),
        );
    }
}

/// The ends do save the formula: a contact far off the line of every course (every
/// candidate's CPA above `above`, or not closing) takes `f` only for the row's two ends
/// and its range now, and one that will pass within `below` on every closing course
/// likewise; with the ends off, `f` runs for every candidate of a closing vector.
#[test]
fn flat_rows_skip_the_formula() {
    if !std::arch::is_x86_feature_detected!("avx2") {
        return;
    }
    let (sins, coss) = units();
    let calls = Cell::new(0usize);
    let m = metric(8.0, 25.0);
    let f = |d: f64| {
        calls.set(calls.get() + 1);
        m(d)
    };
    let run = |row: &CpaRow, flat: Option<FlatEnds>| {
        calls.set(0);
        let mut out = vec![0.0; 360];
        // SAFETY: AVX2 checked above.
        unsafe { cpa_row_avx2(row, (&sins, &coss), &mut out, f, Ends::of(row, flat, &f)) };
        calls.get()
    };
    let ends = Some(FlatEnds {
        below: 8.0,
        above: 25.0,
    });
    // 400 m off, a contact crossing ahead fast: every CPA above 25 m.
    let far = CpaRow {
        v: 2.0,
        px: 0.0,
        py: -400.0,
        cn_vx: 3.0,
        cn_vy: 0.0,
        now: 400.0,
        tol: 60.0,
    };
    // 1 m off, still contact, ownship slow: every closing course passes within 8 m.
    let near = CpaRow {
        v: 0.5,
        px: 0.0,
        py: -1.0,
        cn_vx: 0.0,
        cn_vy: 0.0,
        now: 1.0,
        tol: 60.0,
    };
    for row in [far, near] {
        assert!(run(&row, None) >= 100, "{}", run(&row, None));
        assert!(run(&row, ends) <= 3, "{}", run(&row, ends));
    }
}

/// [`AvoidRamp::flat_ends`] keeps [`FlatEnds`]' promise (the value at 0 below `below`,
/// the value at `f64::MAX` above `above`) for ramps either way round, and gives none
/// for ends that are not finite.
#[test]
fn avoid_ramp_is_flat_where_it_says() {
    for (cd, acd) in [
        (8.0, 25.0),
        (10.0, 40.0),
        (3.5, 3.5),
        (25.0, 8.0),
        (0.0, 1e-300),
    ] {
        let ramp = AvoidRamp { cd, acd };
        let ends = ramp.flat_ends().expect("finite ends");
        let (low, high) = (ramp.at(0.0), ramp.at(f64::MAX));
        for k in 0..=1000 {
            let d = ends.below * f64::from(k) / 1000.0;
            if d < ends.below {
                assert!(same(ramp.at(d), low), "{cd}/{acd} below at {d}");
            }
            let d = ends.above * (1.0 + f64::from(k) / 100.0) + f64::from(k);
            if d > ends.above {
                assert!(same(ramp.at(d), high), "{cd}/{acd} above at {d}");
            }
        }
    }
    for (cd, acd) in [(f64::NAN, 25.0), (8.0, f64::INFINITY)] {
        assert_eq!(AvoidRamp { cd, acd }.flat_ends(), None);
    }
}
