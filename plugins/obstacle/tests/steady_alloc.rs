//! BHV_AvoidObstacleV24 allocates nothing per iteration in steady state (issue 19): the
//! buffer polygons are kept while what they are made of holds, the function is built in
//! kept storage. Counted as the helm drives it (`on_every_state` then `on_run`, the
//! function handed back afterwards), less the mock helm's own copies of the postings.

use behavior_api::sdk::{HelmDomain, IvpBehavior};
use behavior_api::testing::{allocations, CountingAlloc, MockHelm};
use bhv_obstacle::AvoidObstacleV24;

#[global_allocator]
static GLOBAL: CountingAlloc = CountingAlloc;

/// The lib.rs example's obstacle and parameters.
fn behavior() -> (AvoidObstacleV24, MockHelm) {
    let mut b = AvoidObstacleV24::new(&HelmDomain::new("course,0,359,360:speed,0,4,21"));
    let mut helm = MockHelm::new("avd_ob_oba");
    for (p, v) in bhv_obstacle::EXAMPLE_PARAMS {
        assert!(helm.with(|ctx| b.set_param(ctx, p, v)), "{p}");
    }
    helm.with(|ctx| b.on_params_complete(ctx));
    (b, helm)
}

/// One iteration at ownship `(x, y)` heading north: the allocations it made (less the
/// mock's) and whether it built a function.
fn iteration(b: &mut AvoidObstacleV24, helm: &mut MockHelm, x: f64, y: f64) -> (usize, bool) {
    helm.nav(x, y, 0.0, 2.0);
    helm.time += 0.25;
    helm.clear();
    let before = allocations();
    helm.with(|ctx| b.on_every_state(ctx));
    let f = helm.with(|ctx| b.on_run(ctx));
    let n = allocations() - before;
    let built = f.is_some();
    // As the helm does once it has copied the function: its buffers come back.
    if let Some(f) = f {
        f.give_back();
    }
    (n.saturating_sub(helm.recording_allocations()), built)
}

/// Ownship runs north 10 m west of the obstacle's west edge: the range (10) stays above
/// both CPA distances + 1, so the buffer polygons never change.
#[test]
fn steady_range_allocates_nothing() {
    let (mut b, mut helm) = behavior();
    let rounds = 200;
    let mut made = 0;
    for k in 0..rounds {
        let (n, built) = iteration(&mut b, &mut helm, 50.0, -8.0 + 0.04 * k as f64);
        assert!(built, "round {k}: no function");
        if k >= rounds / 2 {
            made += n;
        }
    }
    assert_eq!(made, 0, "allocations in {} steady iterations", rounds / 2);
}

/// Every tenth iteration ownship is 6 m off (the rim's distance flexes to 5), then back
/// at 10 m: the polygons change then and back, and the iterations between allocate
/// nothing.
#[test]
fn changing_range_allocates_only_when_the_polygons_change() {
    let (mut b, mut helm) = behavior();
    let (mut between, mut at_changes) = (0, 0);
    let mut last_x = f64::NAN;
    for k in 0..300 {
        let x = if k % 10 == 5 { 54.0 } else { 50.0 };
        let (n, built) = iteration(&mut b, &mut helm, x, -8.0 + 0.03 * k as f64);
        assert!(built, "round {k}: no function");
        if k >= 100 {
            if x == last_x {
                between += n;
            } else {
                at_changes += n;
            }
        }
        last_x = x;
    }
    println!("{at_changes} allocations at 40 changes of the polygons");
    assert_eq!(between, 0, "allocations between the changes");
}

/// With a range flag and a CPA flag holding macros, ownship swings between 12 m and
/// 10 m off the obstacle (above both CPA distances + 1, so the polygons hold): the range
/// flag is posted every iteration and the CPA event fires every other one, and the
/// macro expansion allocates nothing either (only the mock's copies of the flags).
#[test]
fn flags_with_macros_allocate_nothing() {
    let (mut b, mut helm) = behavior();
    for (p, v) in [
        ("rng_flag", "<20 RNGF = $[OID]:$[RNG]"),
        (
            "cpa_flag",
            "CPAF = $[OID],cpa=$[CPA],bng=$[BNG],side=$[SIDE],min=$[MINU_CPA]",
        ),
    ] {
        assert!(helm.with(|ctx| b.set_param(ctx, p, v)), "{p}");
    }
    let rounds = 200;
    let (mut made, mut cpa_posts) = (0, 0);
    for k in 0..rounds {
        let x = if k % 2 == 0 { 48.0 } else { 50.0 };
        let (n, built) = iteration(&mut b, &mut helm, x, -8.0 + 0.04 * k as f64);
        assert!(built, "round {k}: no function");
        let rng = if k % 2 == 0 { "12" } else { "10" };
        assert_eq!(helm.flags[0].0, format!("RNGF = oba:{rng}"), "round {k}");
        if k >= rounds / 2 {
            made += n;
            cpa_posts += helm.flags.len() - 1;
        }
    }
    assert_eq!(cpa_posts, rounds / 4, "one CPA flag every other iteration");
    assert_eq!(made, 0, "allocations in {} steady iterations", rounds / 2);
}
