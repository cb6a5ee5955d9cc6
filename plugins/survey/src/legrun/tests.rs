use super::*;
use behavior_api::testing::MockHelm;

fn legrun(params: &[(&str, &str)]) -> (LegRun, MockHelm) {
    let mut b = LegRun::new(&HelmDomain::new("course,0,359,360:speed,0,4,41"));
    let mut helm = MockHelm::new("legs");
    for (p, v) in params {
        assert!(helm.with(|ctx| b.set_param(ctx, p, v)), "{p}={v}");
    }
    helm.with(|ctx| b.on_params_complete(ctx));
    (b, helm)
}

#[test]
fn parameters_and_refusals() {
    let (mut b, mut helm) = legrun(&[("leg_spds", "2, 2:1.5"), ("capture_radius", "abc")]);
    assert_eq!(b.default_name(), "legrun");
    assert_eq!(b.spds, vec![2.0, 1.5, 1.5]);
    assert_eq!(b.leg_engine.capture_radius, 0.0);
    assert!(helm.perpetual);
    assert_eq!(
        helm.last("BHV_WARNING").as_deref(),
        Some("legs: Invalid or unset legrun")
    );
    helm.with(|ctx| {
        for (p, v) in [
            ("speed", "5"),
            ("capture_radius", "-1"),
            ("repeat", "-2"),
            ("init_leg_mode", "FIXED"),
            ("leg_spds", "1,9"),
            ("mid_leg_pct", "101"),
            ("leg_endflag", "X ="),
            ("visual_hints", "vertex_color=nocolor"),
            ("nonsense", "1"),
        ] {
            assert!(!b.set_param(ctx, p, v), "{p}={v}");
        }
        assert!(b.set_param(ctx, "repeat", "sometimes"));
        assert!(b.set_param(ctx, "leg_spds", "replace,3"));
        assert!(b.set_param(ctx, "patience", "150"));
    });
    // `speed = 5` was clipped to the domain (and refused).
    assert_eq!(
        (b.speed, b.spds.clone(), b.patience),
        (4.0, vec![3.0], 99.0)
    );
}

#[test]
fn first_leg_then_turn() {
    let (mut b, mut helm) = legrun(&[
        ("vx1", "0,100"),
        ("vx2", "0,0"),
        ("turn_rad", "10"),
        ("speed", "2"),
        ("leg_endflag", "LEG_END = $[LEG_ID]"),
    ]);
    assert_eq!(helm.last("LR_MODE").as_deref(), Some("init"));
    assert_eq!(helm.last("BHV_SETTINGS").as_deref(), Some(
        "type=BHV_LegRun,name=legs,speed=2,currix=0,capture_radius=3,slip_radius=15,patience=50"
    ));
    helm.nav(0.0, 50.0, 0.0, 2.0);
    let f = helm.with(|ctx| b.on_run(ctx)).unwrap();
    assert_eq!(f.var_names().collect::<Vec<_>>(), vec!["course", "speed"]);
    assert_eq!(b.mode(), Mode::Leg1);
    assert_eq!(helm.last("LR_NOW_SPD").as_deref(), Some("2"));
    assert_eq!(helm.posted("VIEW_SEGLIST").len(), 3);
    // Capture of P1: the leg ends, the turn starts next iteration.
    helm.nav(0.0, 98.0, 0.0, 2.0);
    helm.with(|ctx| b.on_run(ctx)).unwrap();
    assert_eq!(helm.flags.last().unwrap().0, "LEG_END = 0");
    helm.with(|ctx| b.on_run(ctx)).unwrap();
    assert_eq!(b.mode(), Mode::Turn1);
    assert_eq!(b.expand("$[LEG_ID]:$[NY]"), "1:$[NY]");
    assert!(b.turn_engine.pts.len() > 5);
}

#[test]
fn resume_mode_is_an_error() {
    let (mut b, mut helm) = legrun(&[
        ("p1", "0,100"),
        ("p2", "0,0"),
        ("turn_rad", "10"),
        ("init_leg_mode", "resume"),
    ]);
    helm.nav(0.0, 50.0, 0.0, 2.0);
    assert!(helm.with(|ctx| b.on_run(ctx)).is_none());
    assert_eq!(
        helm.last("BHV_ERROR").as_deref(),
        Some("legs: Bad init leg direction, check init_leg_mode param.")
    );
}
