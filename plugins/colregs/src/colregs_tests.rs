//! The behavior's flow and postings through the SDK's mock helm.

use super::*;
use behavior_api::testing::MockHelm;

fn make(version: Version, extra: &[(&str, &str)]) -> (Colregs, MockHelm) {
    let mut b = Colregs::new(&HelmDomain::new("course,0,359,360:speed,0,4,41"), version);
    let mut helm = MockHelm::new("col_bob");
    helm.priority = 150.0;
    let base = [
        ("contact", "bob"),
        ("pwt_outer_dist", "80"),
        ("pwt_inner_dist", "50"),
        ("completed_dist", "85"),
        ("min_util_cpa_dist", "10"),
        ("max_util_cpa_dist", "18"),
    ];
    for (p, v) in base.iter().chain(extra) {
        assert!(helm.with(|ctx| b.set_param(ctx, p, v)), "{p} = {v}");
    }
    (b, helm)
}

fn iterate(b: &mut Colregs, helm: &mut MockHelm) -> Option<FunctionData> {
    helm.with(|ctx| b.on_every_state(ctx));
    helm.with(|ctx| b.on_run(ctx))
}

#[test]
fn v22_head_on_postings_and_weight() {
    let (mut b, mut helm) = make(Version::V22, &[("post_per_contact_info", "true")]);
    helm.nav(0.0, 0.0, 0.0, 2.0);
    helm.contact("bob", 0.0, 65.0, 180.0, 2.0, "kayak");
    let f = iterate(&mut b, &mut helm).unwrap();
    // Relevance (80 − 65)/(80 − 50) = 0.5 of pwt 150.
    assert_eq!(f.pwt, 75.0);
    assert_eq!(f.piece_count(), Some(1680));
    assert_eq!(helm.last("COL22_RELEVANCE_BOB").as_deref(), Some("0.5"));
    assert_eq!(helm.last("COL22_AVOID_MODE_BOB").as_deref(), Some("headon"));
    assert_eq!(
        helm.last("COLREGS_SUMMARY_BOB").as_deref(),
        Some("mode=headon:none")
    );
    assert_eq!(helm.last("COLREGS_AVOID_IX_BOB").as_deref(), Some("10"));
    assert_eq!(helm.last("COLREGS_AVOID_PWT_BOB").as_deref(), Some("75"));
    assert_eq!(helm.last("CN_PORT_OF_OS__BOB").as_deref(), Some("0"));
    // Named after ownship (the mock's is `abe`).
    assert_eq!(
        helm.last("HEADON_DEBUG_ABE").as_deref(),
        Some("contact=bob,entered head-on mode")
    );
    assert_eq!(
        b.expand_macros("$[AVD_MODE]/$[APWT]/$[MODE_ID]/$[CONTACT]")
            .as_deref(),
        Some("headon/75/10/bob")
    );
}

#[test]
fn v22_completes_past_one_point_one_completed_dist_with_its_reason() {
    let (mut b, mut helm) = make(Version::V22, &[]);
    helm.nav(0.0, 0.0, 0.0, 2.0);
    helm.contact("bob", 0.0, -93.4, 180.0, 2.0, "kayak");
    assert!(iterate(&mut b, &mut helm).is_none()); // 93.4 < 1.1 × 85 (93.5000…01): not yet
    assert_eq!(helm.completes, 0);
    helm.contact("bob", 0.0, -93.6, 180.0, 2.0, "kayak");
    assert!(iterate(&mut b, &mut helm).is_none());
    assert_eq!(helm.completes, 1);
    assert_eq!(
        b.expand_macros(POST_MORTEM_MACRO).as_deref(),
        Some("rng1p1c#rng=93.6#bng=180")
    );
}

#[test]
fn v19_posts_its_info_and_no_reason() {
    let (mut b, mut helm) = make(Version::V19, &[]);
    helm.nav(0.0, 0.0, 0.0, 2.0);
    helm.contact("bob", 0.0, 65.0, 180.0, 2.0, "kayak");
    assert!(iterate(&mut b, &mut helm).is_some());
    assert_eq!(helm.last("COL19_RELEVANCE").as_deref(), Some("0.5"));
    assert_eq!(
        helm.last("AVD_INFO").as_deref(),
        Some("V19 CN:bob  Mode:headon:none")
    );
    // Posted without post_per_contact_info in V19.
    assert_eq!(
        helm.last("HEADON_DEBUG_ABE").as_deref(),
        Some("contact=bob,entered head-on mode")
    );
    let seg = helm.last("VIEW_SEGLIST").unwrap();
    assert!(
        seg.contains("msg=headon") && !seg.contains("active=false"),
        "{seg}"
    );
    assert!(helm.last("COL22_RELEVANCE_BOB").is_none());
    helm.contact("bob", 0.0, -93.6, 180.0, 2.0, "kayak");
    assert!(iterate(&mut b, &mut helm).is_none());
    assert_eq!(
        b.expand_macros(POST_MORTEM_MACRO).as_deref(),
        Some("rng=93.6#bng=180")
    );
    assert_eq!(b.expand_macros("$[AVD_MODE]"), None);
}

#[test]
fn v17_give_way_fails_as_the_reference_does() {
    let (mut b, mut helm) = make(Version::V17, &[]);
    helm.nav(0.0, 0.0, 0.0, 2.0);
    helm.contact("bob", 30.0, 30.0, 270.0, 2.0, "kayak");
    assert!(iterate(&mut b, &mut helm).is_none());
    let e = helm.last("BHV_ERROR").unwrap();
    assert!(
        e.ends_with("Unable to init AOF_R16:bad param[osh], value[0]"),
        "{e}"
    );
    assert_eq!(helm.last("COL17_RELEVANCE").as_deref(), Some("1"));
}

#[test]
fn version_refusals() {
    let d = HelmDomain::new("course,0,359,360:speed,0,4,41");
    let mut helm = MockHelm::new("c");
    let mut v19 = Colregs::v19(&d);
    let mut v17 = Colregs::v17(&d);
    let mut v22 = Colregs::v22(&d);
    assert!(!helm.with(|ctx| v19.set_param(ctx, "velocity_filter", "min_spd=1,max_spd=2,pct=5")));
    assert!(helm.with(|ctx| v22.set_param(ctx, "velocity_filter", "min_spd=1,max_spd=2,pct=5")));
    assert!(!helm.with(|ctx| v17.set_param(ctx, "can_disable", "true")));
    assert!(helm.with(|ctx| v19.set_param(ctx, "can_disable", "true")));
    assert!(!helm.with(|ctx| v17.set_param(ctx, "use_refinery", "true")));
    assert!(helm.with(|ctx| v19.set_param(ctx, "use_refinery", "true")));
    assert!(!helm.with(|ctx| v22.set_param(ctx, "pwt_grade", "steep")));
    assert!(!helm.with(|ctx| v22.set_param(ctx, "no_such_thing", "1")));
    assert!(helm.with(|ctx| v22.set_param(ctx, "eval_tol", "60")));
    assert_eq!(v22.base.time_on_leg, 60.0);
}

#[test]
fn stand_on_holds_course_and_speed_at_entry() {
    let (mut b, mut helm) = make(
        Version::V22,
        &[("pwt_outer_dist", "150"), ("completed_dist", "160")],
    );
    // Contact from port (see modes_tests): stand-on, unsure bow without a turn rate.
    helm.nav(0.0, 0.0, 10.0, 1.5);
    helm.contact("bob", -80.0, 100.0, 90.0, 2.0, "kayak");
    let f = iterate(&mut b, &mut helm).unwrap();
    assert_eq!(b.machine.mode, Mode::StandOn);
    assert_eq!((b.hdg0, b.spd0), (10.0, 1.5));
    // The stand-on function is the coupled ZAICs, not the 1680-piece tiling.
    assert_ne!(f.piece_count(), Some(1680));
}
