//! Behavior-level tests of both op-region types on the SDK's mock helm.

use behavior_api::sdk::{HelmDomain, IvpBehavior};
use behavior_api::testing::MockHelm;

use crate::{Breach, OpRegion, OpRegionV24};

const DOMAIN: &str = "course,0,359,360:speed,0,4,41";
const SQUARE: &str = "0,0 : 100,0 : 100,-100 : 0,-100";

fn configured<B: IvpBehavior>(b: &mut B, helm: &mut MockHelm, params: &[(&str, &str)]) {
    for (p, v) in params {
        assert!(helm.with(|ctx| b.set_param(ctx, p, v)), "{p} = {v}");
    }
    helm.with(|ctx| b.on_params_complete(ctx));
}

fn run_at<B: IvpBehavior>(b: &mut B, helm: &mut MockHelm, t: f64, x: f64, y: f64) -> bool {
    helm.time = t;
    helm.nav(x, y, 90.0, 2.0);
    helm.with(|ctx| b.on_run(ctx)).is_some()
}

#[test]
fn opregion_refuses_bad_values() {
    let mut b = OpRegion::new(&HelmDomain::new(DOMAIN));
    let mut helm = MockHelm::new("op");
    for (p, v) in [
        ("polygon", "0,0 : 10,0 : 5,5 : 10,10 : 0,10"), // not convex
        ("polygon", "nonsense"),
        ("max_time", "-1"),
        ("max_depth", "deep"),
        ("min_altitude", "-2"),
        ("trigger_entry_time", "-0.5"),
        ("breached_poly_flag", "NOEQUALS"),
        ("reset_var", "TWO WORDS"),
        ("visual_hints", "edge_colour=red"),
        ("trigger_on_poly_entry", "perhaps"),
        ("no_such_param", "1"),
    ] {
        assert!(
            !helm.with(|ctx| b.set_param(ctx, p, v)),
            "{p} = {v} accepted"
        );
    }
}

#[test]
fn opregion_times_out_and_depth_breaches_and_resets() {
    let mut b = OpRegion::new(&HelmDomain::new(DOMAIN));
    let mut helm = MockHelm::new("op");
    configured(
        &mut b,
        &mut helm,
        &[
            ("polygon", SQUARE),
            ("max_time", "10"),
            ("max_depth", "20"),
            ("breached_time_flag", "LATE = yes"),
            ("time_remaining_var", "LEFT"),
            ("reset_var", "OP_RESET"),
        ],
    );
    assert!(!run_at(&mut b, &mut helm, 100.0, 50.0, -50.0));
    assert_eq!(helm.last("LEFT").as_deref(), Some("10"));
    run_at(&mut b, &mut helm, 109.6, 50.0, -50.0);
    assert_eq!(helm.last("LEFT").as_deref(), Some("0"));
    assert!(b.breach().is_none());
    run_at(&mut b, &mut helm, 110.5, 50.0, -50.0);
    assert_eq!(b.breach(), Some(Breach::Time));
    assert_eq!(helm.flags, [("LATE = yes".to_string(), false)]);
    assert!(helm.last("BHV_ERROR").unwrap().contains("Max Time failure"));
    // Latched until the reset variable says true; then the clock starts again.
    helm.strs.insert("OP_RESET".into(), "true".into());
    run_at(&mut b, &mut helm, 111.0, 50.0, -50.0);
    assert!(b.breach().is_none());
    helm.strs.remove("OP_RESET");
    helm.set("NAV_DEPTH", 25.0);
    helm.clear();
    run_at(&mut b, &mut helm, 112.0, 50.0, -50.0);
    assert_eq!(b.breach(), Some(Breach::Depth));
    assert_eq!(
        helm.last("BHV_ERROR").as_deref(),
        Some("op: BHV_OpRegion Max Depth failure: depth=25.0 max_depth=20")
    );
}

#[test]
fn opregion_start_outside_is_no_breach_until_entered_unless_told() {
    for (entry, breach) in [("true", false), ("false", true)] {
        let mut b = OpRegion::new(&HelmDomain::new(DOMAIN));
        let mut helm = MockHelm::new("op");
        configured(
            &mut b,
            &mut helm,
            &[
                ("polygon", SQUARE),
                ("trigger_on_poly_entry", entry),
                ("trigger_exit_time", "0"),
            ],
        );
        run_at(&mut b, &mut helm, 100.0, 150.0, -50.0);
        assert_eq!(
            b.breach().is_some(),
            breach,
            "trigger_on_poly_entry = {entry}"
        );
        assert_eq!(
            helm.last("OPREG_TRAJECTORY_PERIM_DIST").as_deref(),
            Some("-1")
        );
    }
}

#[test]
fn v24_recovers_outside_save_and_halts_outside_halt() {
    let mut b = OpRegionV24::new(&HelmDomain::new(DOMAIN));
    let mut helm = MockHelm::new("opx");
    assert_eq!(b.default_name(), "opregx");
    assert_eq!(b.domain(), DOMAIN);
    configured(
        &mut b,
        &mut helm,
        &[
            ("core_poly", SQUARE),
            ("save_dist", "10"),
            ("halt_dist", "10"),
            ("recover_spd", "1.5"),
            ("trigger_exit_time", "0"),
            ("save_flag", "SAVING = true"),
            ("savex_flag", "SAVING = false"),
            ("breached_poly_flag", "HALTED = poly"),
        ],
    );
    let (save, halt) = b.regions();
    assert!(save.unwrap().contains(-9.0, 5.0) && !save.unwrap().contains(-11.0, 5.0));
    assert!(halt.unwrap().contains(-19.0, 5.0) && !halt.unwrap().contains(-21.0, 5.0));
    assert!(
        !run_at(&mut b, &mut helm, 100.0, 50.0, -50.0),
        "inside: no function"
    );
    assert_eq!(
        helm.posted("VIEW_POLYGON").len(),
        3,
        "core, save and halt drawn"
    );
    run_at(&mut b, &mut helm, 102.0, 105.0, -50.0);
    assert!(
        run_at(&mut b, &mut helm, 103.0, 115.0, -50.0),
        "outside save: recovery"
    );
    assert_eq!(helm.flags[0].0, "SAVING = true");
    assert!(!run_at(&mut b, &mut helm, 104.0, 95.0, -50.0));
    assert_eq!(helm.flags[1].0, "SAVING = false");
    assert!(
        !run_at(&mut b, &mut helm, 105.0, 125.0, -50.0),
        "outside halt: no function"
    );
    assert!(helm
        .last("BHV_ERROR")
        .unwrap()
        .contains("Halt region breach"));
    assert!(helm.flags.iter().any(|f| f.0 == "HALTED = poly"));
    // reset (an update) forgets the breach.
    assert!(helm.with(|ctx| b.set_param(ctx, "reset", "true")));
    helm.clear();
    run_at(&mut b, &mut helm, 106.0, 50.0, -50.0);
    assert!(helm.posted("BHV_ERROR").is_empty());
}

#[test]
fn v24_refuses_bad_values_and_needs_a_region() {
    let mut b = OpRegionV24::new(&HelmDomain::new(DOMAIN));
    let mut helm = MockHelm::new("opx");
    for (p, v) in [
        ("save_dist", "-1"),
        ("halt_dist", "-1"),
        ("max_depth", "-1"),
        ("min_altitude", "-1"),
        ("recover_spd", "0"),
        ("trigger_on_poly_entry", "sometimes"),
        ("trigger_entry_time", "-1"),
        ("trigger_exit_time", "-1"),
        ("core_poly", "0,0 : 10,0 : 5,5 : 10,10 : 0,10"),
    ] {
        assert!(
            !helm.with(|ctx| b.set_param(ctx, p, v)),
            "{p} = {v} accepted"
        );
    }
    assert!(!b.collective_check().is_empty());
    assert!(helm.with(|ctx| b.set_param(ctx, "halt_poly", SQUARE)));
    assert!(b.collective_check().is_empty());
}
