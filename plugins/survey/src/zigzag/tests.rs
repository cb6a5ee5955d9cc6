use super::*;
use behavior_api::testing::MockHelm;

fn zig(params: &[(&str, &str)]) -> (ZigZag, MockHelm) {
    let mut b = ZigZag::new(&HelmDomain::new("course,0,359,360:speed,0,4,41"));
    let mut helm = MockHelm::new("zig");
    for (p, v) in params {
        assert!(helm.with(|ctx| b.set_param(ctx, p, v)), "{p}={v}");
    }
    (b, helm)
}

#[test]
fn angles_and_lines() {
    assert!(contains_angle(10.0, 50.0, 30.0));
    assert!(!contains_angle(10.0, 50.0, 60.0));
    assert!(contains_angle(350.0, 20.0, 355.0));
    assert!(contains_angle(0.0, 180.0, 270.0));
    assert!(contains_angle(40.0, 40.0, 40.0));
    assert_eq!(dist_to_line(5.0, 3.0, 0.0, 0.0, 0.0, 10.0), 5.0);
    assert_eq!(dist_to_line(5.0, 3.0, 0.0, 1.0, 10.0, 1.0), 2.0);
    assert!((dist_to_line(0.0, 2.0, 0.0, 0.0, 2.0, 2.0) - 2f64.sqrt()).abs() < 1e-12);
}

#[test]
fn parameters_and_refusals() {
    let (mut b, mut helm) = zig(&[
        ("max_zig_zags", "1.7"),
        ("zig_first", "Right"),
        ("stem_hdg", "-90"),
        ("visual_hints", "draw_req_hdg=false, set_hdg_color=off"),
        ("speed", "5"),
    ]);
    assert_eq!(b.default_name(), "???");
    assert_eq!(
        (b.max_zig_legs, b.zig_first, b.stem_hdg),
        (2, Side::Star, 270.0)
    );
    assert_eq!(
        (b.draw_req, b.set_color.as_str(), b.speed),
        (false, "off", 5.0)
    );
    helm.with(|ctx| {
        for (p, v) in [
            ("zig_angle", "0.5"),
            ("zig_angle", "76"),
            ("zig_first", "up"),
            ("max_zig_zags", "0"),
            ("max_stem_odo", "0"),
            ("hdg_thresh", "-1"),
            ("speed", "-1"),
            ("zigflag", "ZIG ="),
            ("visual_hints", "bogus=1"),
            ("visual_hints", "req_hdg_color=notacolor"),
            ("fierce_zigging", "sometimes"),
        ] {
            assert!(!b.set_param(ctx, p, v), "{p}={v}");
        }
        assert!(b.set_param(ctx, "mod_speed", "-7"));
        assert_eq!(b.speed, 0.0);
        assert!(b.set_param(ctx, "mod_speed", "9"));
        assert_eq!(b.speed, 4.0);
        assert!(b.set_param(ctx, "mod_speed", "RESET"));
        assert_eq!(b.speed, 0.0);
    });
}

#[test]
fn zigs_count_turns_post_flags_and_complete() {
    let (mut b, mut helm) = zig(&[
        ("speed", "2"),
        ("zig_angle", "55"),
        ("zig_first", "star"),
        ("max_zig_zags", "1"),
        ("hdg_thresh", "2"),
        ("zigflag", "ZIGF = $[ZIGS]:$[ZAGS]:$[ZIG_SIDE]:$[ZIGS_TOGO]"),
        ("zagflag", "ZAGF = $[ZAGS]"),
        ("starflag", "STARF = $[ZIGS]"),
        ("portflagx", "PORTX = $[ZIGS]"),
    ]);
    helm.nav(0.0, 0.0, 0.0, 2.0);
    let f = helm.with(|ctx| b.on_run(ctx));
    assert!(f.is_some());
    assert_eq!(b.set_hdg, 55.0);
    assert_eq!(helm.flags, vec![("STARF = 0".to_string(), false)]);
    assert_eq!(
        helm.posted("VIEW_SEGLIST")[0],
        "pts={0,0:16.4,11.5},label=zig_set_abe,label_color=invisible,edge_color=white,\
         vertex_color=white,duration=5,vertex_size=2,edge_size=1"
    );
    // A new colour reaches the kept line attributes.
    helm.with(|ctx| assert!(b.set_param(ctx, "visual_hints", "set_hdg_color=off")));
    helm.clear();
    helm.with(|ctx| b.on_run(ctx));
    assert_eq!(
        helm.posted("VIEW_SEGLIST")[0],
        "pts={0,0:16.4,11.5},label=zig_set_abe,label_color=invisible,edge_color=invisible,\
         vertex_color=invisible,duration=5,vertex_size=2,edge_size=1"
    );
    helm.flags.clear();
    // Within hdg_thresh of 55: the first turn is done.
    helm.nav(5.0, 5.0, 54.0, 2.0);
    helm.with(|ctx| b.on_run(ctx)).unwrap();
    assert_eq!(helm.flags[0].0, "ZIGF = 1:0:star:1");
    assert_eq!(b.side, Side::Port);
    assert_eq!(b.set_hdg, 305.0);
    helm.flags.clear();
    helm.nav(6.0, 9.0, 306.0, 2.0);
    helm.with(|ctx| b.on_run(ctx)).unwrap();
    let texts: Vec<&str> = helm.flags.iter().map(|f| f.0.as_str()).collect();
    assert_eq!(
        texts,
        vec!["ZIGF = 2:1:port:0", "ZAGF = 1", "PORTX = 2", "STARF = 2"]
    );
    helm.nav(9.0, 12.0, 54.0, 2.0);
    assert!(helm.with(|ctx| b.on_run(ctx)).is_none());
    assert_eq!(helm.completes, 1);
    assert!(b.expand("$[ODO]").parse::<f64>().unwrap() > 15.0);
}

#[test]
fn stale_or_missing_nav_is_an_error() {
    let (mut b, mut helm) = zig(&[("zig_angle", "30")]);
    helm.set("NAV_X", 1.0);
    assert!(helm.with(|ctx| b.on_run(ctx)).is_none());
    assert_eq!(
        helm.last("BHV_ERROR").as_deref(),
        Some("zig: ownship NAV_X/Y not found or stale.")
    );
    helm.set("NAV_Y", 1.0);
    assert!(helm.with(|ctx| b.on_run(ctx)).is_none());
    assert_eq!(
        helm.last("BHV_ERROR").as_deref(),
        Some("zig: ownship NAV_HEADING not found or stale.")
    );
}

#[test]
fn idle_to_run_takes_the_stem_and_run_to_idle_erases() {
    let (mut b, mut helm) = zig(&[("stem_on_active", "true"), ("speed_on_active", "true")]);
    helm.nav(10.0, 0.0, 30.0, 1.5);
    helm.with(|ctx| b.on_idle_to_run(ctx));
    assert_eq!((b.stem_hdg, b.speed, b.orig_speed), (30.0, 1.5, 1.5));
    assert_eq!(b.stem.unwrap().0, (10.0, 0.0));
    helm.with(|ctx| b.on_run_to_idle(ctx));
    assert_eq!(
        helm.posted("VIEW_SEGLIST"),
        vec![
            "pts={0,0:9,0:0,9},active=false,label=zig_set_abe",
            "pts={0,0:9,0:0,9},active=false,label=zig_req_abe"
        ]
    );
}
