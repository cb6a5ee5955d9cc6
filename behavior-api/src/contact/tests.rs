use super::*;
use crate::testing::MockHelm;

fn base_with(contact: &str) -> ContactBase {
    let mut b = ContactBase::new(120.0);
    assert_eq!(b.set_param("contact", contact), Some(true));
    b
}

#[test]
fn missing_contact_warns_then_retracts() {
    let mut b = base_with("bob");
    let mut helm = MockHelm::new("avd_bob");
    helm.nav(0.0, 0.0, 0.0, 2.0);
    assert!(!helm.with(|ctx| b.every_state(ctx)));
    assert_eq!(
        helm.last("BHV_WARNING").as_deref(),
        Some("avd_bob: bob x/y/heading/speed info not found")
    );
    assert_eq!(helm.contact_set, "bob");
    helm.contact("bob", 30.0, 40.0, 90.0, 1.0, "kayak");
    helm.clear();
    assert!(helm.with(|ctx| b.every_state(ctx)));
    // The retraction posts the same text once more.
    assert_eq!(helm.posted("BHV_WARNING").len(), 1);
    assert_eq!(b.range(), 50.0);
    assert_eq!(b.cn_type, "kayak");
}

#[test]
fn not_ok_missing_contact_is_an_error() {
    let mut b = base_with("bob");
    assert_eq!(b.set_param("on_no_contact_ok", "false"), Some(true));
    let mut helm = MockHelm::new("t");
    helm.nav(0.0, 0.0, 0.0, 2.0);
    assert!(!helm.with(|ctx| b.every_state(ctx)));
    assert!(helm.last("BHV_ERROR").is_some());
}

#[test]
fn spawned_behavior_completes_when_its_contact_is_gone() {
    let mut b = base_with("bob");
    b.spawned();
    let mut helm = MockHelm::new("avd_bob");
    helm.nav(0.0, 0.0, 0.0, 2.0);
    assert!(!helm.with(|ctx| b.every_state(ctx)));
    assert_eq!(helm.completes, 1);
    assert!(helm.posted("BHV_WARNING").is_empty());
}

#[test]
fn alert_request_only_for_templates_with_updates() {
    let mut b = ContactBase::new(120.0);
    assert_eq!(b.alert_request("avd_", 50.0, 75.0), None);
    b.set_param("helm_templating", "spawn");
    b.set_param("helm_updates", "CONTACT_INFO");
    assert_eq!(
        b.alert_request("avd_", 50.0, 75.0).as_deref(),
        Some("id=avd_, on_flag=CONTACT_INFO=name=$[VNAME] # contact=$[VNAME],alert_range=50, cpa_range=75")
    );
    b.set_param("match_name", "abe");
    assert!(b
        .alert_request("avd_", 20.0, 40.0)
        .unwrap()
        .ends_with("alert_range=20, cpa_range=40,match_name=abe"));
    b.no_alert_request = true;
    assert_eq!(b.alert_request("avd_", 50.0, 75.0), None);
}

#[test]
fn macros_and_post_mortem() {
    let mut b = base_with("bob");
    let mut helm = MockHelm::new("avd_bob");
    helm.nav(0.0, 0.0, 0.0, 2.0);
    // Contact 3-4-5 to the south-west of ownship: bearing 180 + atan(3/4) = 216.87.
    helm.contact("bob", -30.0, -40.0, 0.0, 1.0, "kayak");
    helm.with(|ctx| b.every_state(ctx));
    assert_eq!(b.post_mortem(), "rng=50#bng=216.9");
    assert_eq!(
        b.expand_macros(POST_MORTEM_MACRO).as_deref(),
        Some("rng=50#bng=216.9")
    );
    assert_eq!(
        b.expand_macros("$[CN_NAME]:$[CNX]:$[CN_VTYPE]:$[OS_FORE_OF_CN]")
            .as_deref(),
        Some("bob:-30:kayak:true")
    );
    assert_eq!(b.expand_macros("plain"), None);
    assert_eq!(b.condition_text("T_$[CONTACT]=$[contact]"), "T_BOB=bob");
}

#[test]
fn range_cnflags_fire_on_edges() {
    let mut b = base_with("bob");
    assert_eq!(b.set_param("cnflag", "@<20 CLOSE=$[CN_NAME]"), Some(true));
    assert_eq!(b.set_param("cnflag", "<30 NEAR=$[RANGE]"), Some(true));
    assert_eq!(b.set_param("cnflag", "@nonsense X=1"), Some(false));
    let mut helm = MockHelm::new("avd_bob");
    helm.nav(0.0, 0.0, 0.0, 0.0);
    for (y, close, near) in [(25.0, 0, 1), (19.0, 1, 2), (18.0, 1, 3)] {
        helm.contact("bob", 0.0, y, 0.0, 0.0, "kayak");
        helm.with(|ctx| {
            b.every_state(ctx);
            b.handle_cnflags(ctx);
        });
        assert_eq!(helm.posted("CLOSE").len(), close, "y={y}");
        assert_eq!(helm.posted("NEAR").len(), near, "y={y}");
    }
    assert_eq!(helm.last("CLOSE").as_deref(), Some("bob"));
    assert_eq!(helm.last("NEAR").as_deref(), Some("18"));
}

#[test]
fn able_filter_disables_and_expunges() {
    let mut b = base_with("bob");
    b.can_disable = true;
    let mut helm = MockHelm::new("avd_bob");
    helm.strs.insert(
        "BHV_ABLE_FILTER".into(),
        "action=disable,contact=BOB".into(),
    );
    let out = helm.with(|ctx| b.able_filter(ctx, "BHV_AvoidCollision"));
    assert!(b.disabled && !out.expunge);
    helm.strs.insert(
        "BHV_ABLE_FILTER".into(),
        "action=expunge,bhv_type=bhv_avoidcollision".into(),
    );
    assert!(
        helm.with(|ctx| b.able_filter(ctx, "BHV_AvoidCollision"))
            .expunge
    );
    helm.strs
        .insert("BHV_ABLE_FILTER".into(), "action=able".into());
    assert_eq!(
        helm.with(|ctx| b.able_filter(ctx, "BHV_AvoidCollision"))
            .malformed,
        1
    );
}

#[test]
fn bearing_line_colour_by_relevance() {
    let mut b = base_with("bob");
    assert_eq!(
        b.set_param(
            "bearing_line_config",
            "white:0, green:0.65, yellow:0.8, red:1.0"
        ),
        Some(true)
    );
    let mut helm = MockHelm::new("avd_bob");
    helm.nav(0.0, 99.8, 0.0, 2.0);
    helm.contact("bob", 5.0, 149.0, 180.0, 2.0, "kayak");
    helm.with(|ctx| {
        b.every_state(ctx);
        b.post_bearing_line(ctx, 0.5);
    });
    let line = helm.last("VIEW_SEGLIST").unwrap();
    assert!(line.starts_with("pts={0,99.8:5,149},label="), "{line}");
    assert!(line.contains("edge_color=green"), "{line}");
    helm.with(|ctx| b.post_bearing_line(ctx, 2.0));
    assert!(helm
        .last("VIEW_SEGLIST")
        .unwrap()
        .contains("edge_color=blank"));
}
