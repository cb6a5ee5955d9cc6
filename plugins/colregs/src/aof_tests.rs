//! Objective function values at chosen points, worked out by hand.

use super::*;

fn scene(cn: (f64, f64, f64, f64), osh: f64) -> Scene {
    Scene {
        cnx: cn.0,
        cny: cn.1,
        cnh: cn.2,
        cnv: cn.3,
        osx: 0.0,
        osy: 0.0,
        osh,
    }
}

#[test]
fn cpa_function_by_hand() {
    // Contact 100 m north heading south at 2; collision distance 10, all-clear 30.
    let a = CpaAof::new(&scene((0.0, 100.0, 180.0, 2.0), 0.0), 120.0, 10.0, 30.0).unwrap();
    assert_eq!(a.utility(0.0, 2.0), 0.0); // straight at it: CPA 0
                                          // East at 2: relative velocity (2, 2) from (0, −100): CPA 100/√2 = 70.7 > 30.
    assert_eq!(a.utility(90.0, 2.0), 100.0);
    // East at 0.4: CPA 100·0.4/√(0.16 + 4) = 19.61, in between.
    let p = 40.0 / 4.16f64.sqrt();
    let want = 25.0 + 75.0 * (p - 10.0) / 20.0;
    assert!((a.utility(90.0, 0.4) - want).abs() < 1e-9);
    assert!(CpaAof::new(&scene((0.0, 100.0, 180.0, 2.0), 0.0), 120.0, 31.0, 30.0).is_none());
}

#[test]
fn r13_refuses_the_wrong_side() {
    // Overtaking a contact 40 m ahead, 2 m to port (heading north at 1), at 3, on its
    // port side. (Dead astern would be both port and starboard of it: avoided.)
    let s = scene((-2.0, 40.0, 0.0, 1.0), 0.0);
    let a = R13Aof::new(&s, 120.0, 10.0, 18.0, Some(Side::Port)).unwrap();
    // 10° right passes it to starboard: refused.
    assert_eq!(a.utility(10.0, 3.0), 0.0);
    // 345° passes to port: relative velocity (3 sin 345°, 3 cos 345° − 1) from
    // (2, −40): CPA |px·vy − py·vx| / |v| = 13.3: 15 + 85·(p − 10)/8.
    let (vx, vy) = (
        3.0 * 345f64.to_radians().sin(),
        3.0 * 345f64.to_radians().cos() - 1.0,
    );
    let p = (2.0 * vy + 40.0 * vx).abs() / vx.hypot(vy);
    assert!(p > 10.0 && p < 18.0);
    let want = 15.0 + 85.0 * (p - 10.0) / 8.0;
    assert!((a.utility(345.0, 3.0) - want).abs() < 1e-6);
    assert!(R13Aof::new(&s, 120.0, 10.0, 18.0, None).is_none());
}

#[test]
fn r14_rewards_a_port_to_port_pass() {
    // Head-on at 100 m, contact south at 2. b0: contact turned to 270 and ownship to
    // 90, both at 2: (−2·1 + 2·cos 180°)·360/(2·100·π) = −4·1.8/π.
    let a = R14Aof::new(&scene((0.0, 100.0, 180.0, 2.0), 0.0), 120.0, 10.0, 18.0).unwrap();
    // The engine's 12-digit π, not f64's (behaviors-contacts.md §1.3).
    #[allow(clippy::approx_constant)]
    let pi12 = 3.14159265359;
    let k = 360.0 / (2.0 * 100.0 * pi12);
    assert!((a.b0 + 4.0 * k).abs() < 1e-9);
    // East at 2: bearing rate −2·k (half of b0) → m3 = 50; CPA 70.7 → m1 = 100.
    assert!((a.utility(90.0, 2.0) - 150.0).abs() < 1e-9);
    // West at 2 passes it to starboard: refused.
    assert_eq!(a.utility(270.0, 2.0), 0.0);
}

#[test]
fn r16_astern_only_with_a_starboard_turn() {
    // Contact at (60, 20) heading west at 2, ownship heading north: give way astern.
    let s = scene((60.0, 20.0, 270.0, 2.0), 0.0);
    let a = R16Aof::new(&s, 10.0, 30.0, Some(Pass::Stern), true).unwrap();
    // East at 2 (a starboard turn) runs parallel to it: CPA 20 at t = 15 s:
    // 25 + 75·(20 − 10)/20.
    assert!((a.utility(90.0, 2.0) - 62.5).abs() < 1e-9);
    // A port turn that crosses ahead of it: refused.
    assert_eq!(a.utility(330.0, 2.0), 0.0);
    // Without port turns allowed, a port turn is refused whatever it crosses.
    let b = R16Aof::new(&s, 10.0, 30.0, Some(Pass::Stern), false).unwrap();
    assert_eq!(b.utility(200.0, 2.0), 0.0);
    assert!(R16Aof::new(&s, 10.0, 30.0, None, true).is_err());
    assert!(R16Aof::new(&s, 40.0, 30.0, Some(Pass::Bow), true).is_err());
}

/// Every AOF's grid evaluation gives what `eval` gives at every grid point, bit for
/// bit, over random scenes (a still contact, ownship on the contact, on its bow line)
/// and settings (equal, zero and crossed-in-range distances, every side and pass).
#[test]
fn grid_rows_equal_pointwise() {
    let mut seed = 21u64;
    let mut rng = move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let d = Domain::parse("course:0:359:360,speed:0:4:41").unwrap();
    let xs: Vec<u32> = (0..360).collect();
    let ys: Vec<u32> = (0..41).collect();
    let mut grid = vec![0.0; 360 * 41];
    let bits = |v: f64| {
        if v.is_nan() {
            f64::NAN.to_bits()
        } else {
            v.to_bits()
        }
    };
    for case in 0..120 {
        let cn = (
            ((rng() - 0.5) * 300.0).round(),
            if case % 9 == 0 {
                0.0
            } else {
                ((rng() - 0.5) * 300.0).round()
            },
            (rng() * 720.0).round() / 2.0,
            if case % 5 == 0 { 0.0 } else { rng() * 4.0 },
        );
        let mut s = scene(cn, (rng() * 720.0).round() / 2.0);
        if case % 11 == 0 {
            (s.osx, s.osy) = (cn.0, cn.1);
        }
        let (mu, big) = match case % 3 {
            0 => (10.0, 10.0),
            1 => (0.0, 25.0),
            _ => (rng() * 20.0, 20.0 + rng() * 60.0),
        };
        let tol = [60.0, 120.0, 300.0][case % 3];
        let mut aofs: Vec<Box<dyn Aof>> = vec![];
        aofs.extend(CpaAof::new(&s, tol, mu, big).map(|a| Box::new(a) as Box<dyn Aof>));
        for side in [Side::Port, Side::Starboard] {
            aofs.extend(
                R13Aof::new(&s, tol, mu, big, Some(side)).map(|a| Box::new(a) as Box<dyn Aof>),
            );
        }
        aofs.extend(R14Aof::new(&s, tol, mu, big).map(|a| Box::new(a) as Box<dyn Aof>));
        for pass in [Pass::Stern, Pass::Bow] {
            aofs.extend(
                R16Aof::new(&s, mu, big, Some(pass), case % 2 == 0)
                    .ok()
                    .map(|a| Box::new(a) as Box<dyn Aof>),
            );
        }
        for aof in &aofs {
            // Said to fill every slot: a slot left alone would keep the sentinel.
            assert!(aof.eval_grid_fills());
            grid.fill(-1234.5678);
            aof.eval_grid(&d, &[&xs, &ys], &mut grid);
            for j in 0..41u32 {
                for i in 0..360u32 {
                    let got = grid[(i + 360 * j) as usize];
                    let want = aof.eval(&d, &[i, j]);
                    assert_eq!(bits(got), bits(want), "case {case} at ({i}, {j})");
                }
            }
        }
    }
}

/// The row evaluation keeps its course lists (and R13's headings) on the thread from
/// one grid to the next: grids of other sizes and orders, one after the other, give
/// what the pointwise evaluation gives, bit for bit (a kept list longer or shorter
/// than the next grid's courses must not show through).
#[test]
fn kept_lists_serve_grids_of_any_size() {
    let mut seed = 77u64;
    let mut rng = move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let d = Domain::parse("course:0:359:360,speed:0:4:41").unwrap();
    for case in 0..60 {
        let s = scene(
            (
                ((rng() - 0.5) * 300.0).round(),
                ((rng() - 0.5) * 300.0).round(),
                (rng() * 720.0).round() / 2.0,
                rng() * 4.0,
            ),
            (rng() * 720.0).round() / 2.0,
        );
        // Some courses and speeds, in any order, as many as the case says.
        let n = [360, 1, 7, 200, 359, 45][case % 6];
        let xs: Vec<u32> = (0..n).map(|_| (rng() * 360.0) as u32 % 360).collect();
        let ys: Vec<u32> = (0..1 + case % 5)
            .map(|_| (rng() * 41.0) as u32 % 41)
            .collect();
        let (mu, big) = (rng() * 20.0, 20.0 + rng() * 40.0);
        let mut aofs: Vec<Box<dyn Aof>> = vec![];
        aofs.extend(CpaAof::new(&s, 120.0, mu, big).map(|a| Box::new(a) as Box<dyn Aof>));
        aofs.extend(
            R13Aof::new(&s, 120.0, mu, big, Some(Side::Port)).map(|a| Box::new(a) as Box<dyn Aof>),
        );
        aofs.extend(R14Aof::new(&s, 120.0, mu, big).map(|a| Box::new(a) as Box<dyn Aof>));
        aofs.extend(
            R16Aof::new(&s, mu, big, Some(Pass::Stern), case % 2 == 0)
                .ok()
                .map(|a| Box::new(a) as Box<dyn Aof>),
        );
        for aof in &aofs {
            let mut grid = vec![-1234.5678; xs.len() * ys.len()];
            aof.eval_grid(&d, &[&xs, &ys], &mut grid);
            for (j, &y) in ys.iter().enumerate() {
                for (k, &x) in xs.iter().enumerate() {
                    let got = grid[k + xs.len() * j];
                    let want = aof.eval(&d, &[x, y]);
                    assert_eq!(got.to_bits(), want.to_bits(), "case {case} at ({x}, {y})");
                }
            }
        }
    }
}

/// The baseline-instruction R14 row (what a CPU without AVX2 runs: the refusal rules
/// written out, not `BowStarRate::of`) gives the bits the dispatched row gives, over
/// every side and pass of random scenes: on an AVX2 machine the pointwise tests above
/// reach it only in a row's last few candidates.
#[test]
fn r14_plain_row_equals_the_dispatched_row() {
    let mut seed = 5u64;
    let mut rng = move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let d = Domain::parse("course:0:359:360,speed:0:4:41").unwrap();
    let xs: Vec<u32> = (0..360).collect();
    let mut checked = 0;
    for case in 0..200 {
        let cn = (
            ((rng() - 0.5) * 300.0).round(),
            ((rng() - 0.5) * 300.0).round(),
            (rng() * 720.0).round() / 2.0,
            if case % 7 == 0 { 0.0 } else { rng() * 4.0 },
        );
        let s = scene(cn, (rng() * 720.0).round() / 2.0);
        let (mu, big) = match case % 3 {
            0 => (10.0, 10.0),
            1 => (0.0, 25.0),
            _ => (rng() * 20.0, 20.0 + rng() * 60.0),
        };
        let Some(a) = R14Aof::new(&s, 120.0, mu, big) else {
            continue;
        };
        let c = rows::Courses::of(&a.engine, &d, &xs, None);
        for j in 0..41u32 {
            let v = d.value(1, j);
            let r = rows::R14Row {
                sides: a.engine.sides(),
                consts: a.engine.row_consts(),
                metric: a.metric,
                b0: a.b0,
                v,
            };
            let mut dists = vec![0.0; xs.len()];
            a.engine.cpa_dists((&c.sins, &c.coss), v, a.tol, &mut dists);
            let (mut got, mut want) = (dists.clone(), dists);
            rows::r14_row_plain(&r, &c, &mut got);
            rows::r14_row(&r, &c, &mut want);
            for k in 0..xs.len() {
                assert_eq!(
                    got[k].to_bits(),
                    want[k].to_bits(),
                    "case {case} speed {j} course {k}"
                );
            }
            checked += 1;
        }
        c.give_back();
    }
    assert!(checked > 1000, "only {checked} rows compared");
}
