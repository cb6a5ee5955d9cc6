use super::*;

#[test]
fn spawn_strings() {
    assert!(may_spawn("name=bob # contact=bob"));
    assert!(!may_spawn("contact=bob"));
    assert_eq!(spawn_name("name=bob # contact=bob"), "bob");
    assert_eq!(spawn_name(" name = Bob "), "Bob");
    // The contact manager's alert for an empty name: a valid pair with an empty value.
    assert_eq!(
        update_pairs("name= # contact=").unwrap(),
        [("name", ""), ("contact", "")]
    );
    assert_eq!(spawn_name("name= # contact="), "");
    // A field that is not exactly key=value spoils the lookup.
    assert_eq!(spawn_name("name=bob # x=a=b"), "");
    assert_eq!(spawn_name("name=bob # =3"), "");
    // Quotes protect '#' and '='.
    assert_eq!(
        update_pairs(r#"name=bob # msg="a#b=c""#).unwrap(),
        [("name", "bob"), ("msg", r#""a#b=c""#)]
    );
    assert!(matches!(update_pairs("junk"), Err(AlertError::NotAPair(_))));
}

#[test]
fn alert_requests_as_recorded() {
    let f = ContactFilter::default();
    // The cases' values (avd_spawn_*, colregs22_*, cutrange_spawn_pursuit).
    assert_eq!(
        alert_request("cut_", "CUT_INFO", 100.0, 101.0, &f),
        "id=cut_, on_flag=CUT_INFO=name=$[VNAME] # contact=$[VNAME],alert_range=100, cpa_range=101"
    );
    assert_eq!(
        alert_request("avd_", "CONTACT_INFO", 120.0, 400.0, &f),
        "id=avd_, on_flag=CONTACT_INFO=name=$[VNAME] # contact=$[VNAME],alert_range=120, cpa_range=400"
    );
    // One decimal at most; the filter summary follows a comma.
    let mut f = ContactFilter::default();
    f.set_param("match_type", "kayak").unwrap();
    assert_eq!(
        alert_request("ctmp_", "UPDATES_CUT", 100.0, 100.0 + 1.0, &f),
        "id=ctmp_, on_flag=UPDATES_CUT=name=$[VNAME] # contact=$[VNAME],alert_range=100, cpa_range=101,match_type=kayak"
    );
    assert!(
        alert_request("a", "V", 12.345, 0.05, &ContactFilter::default())
            .ends_with("alert_range=12.3, cpa_range=0.1")
    );
}

#[test]
fn able_filters() {
    let f = AbleFilter::parse(" Action = EXPUNGE , bhv_type=BHV_AvoidCollision").unwrap();
    assert_eq!(f.action, AbleAction::Expunge);
    assert_eq!(f.bhv_type.as_deref(), Some("bhv_avoidcollision"));
    assert!(f.applies_to("BHV_AvoidCollision", "anyone", ""));
    assert!(!f.applies_to("BHV_CutRange", "anyone", ""));
    let f = AbleFilter::parse("action=enable,contact=bob,vsource=ais").unwrap();
    assert!(f.applies_to("x", "Bob", "AIS"));
    assert!(!f.applies_to("x", "Bob", "radar"));
    for (s, e) in [
        ("contact=bob", AlertError::NoAction),
        ("action=disable", AlertError::NoTarget),
        (
            "action=able,contact=bob",
            AlertError::BadAction("able".into()),
        ),
        (
            "action=disable,contact=a,contact=b",
            AlertError::RepeatedKey("contact".into()),
        ),
        (
            "action=disable,action=enable,contact=a",
            AlertError::RepeatedKey("action".into()),
        ),
        (
            "action=disable,who=bob",
            AlertError::UnknownKey("who".into()),
        ),
        ("action=disable,bob", AlertError::NotAPair("bob".into())),
    ] {
        assert_eq!(AbleFilter::parse(s), Err(e), "{s}");
    }
}

#[test]
fn blacklist_quirks() {
    let mut b = AbleBlacklist::default();
    b.note("action=disable,contact=Bob");
    b.note("action=disable,contact=bob");
    assert_eq!(b.len(), 1);
    assert_eq!(b.seed("BOB").as_deref(), Some("action=disable,contact=bob"));
    // enable does not remove; able does.
    b.note("action=enable,contact=bob");
    assert!(b.contains("bob"));
    b.note("action=able,contact=bob");
    assert!(b.is_empty() && b.seed("bob").is_none());
    // Bounded.
    for i in 0..(BLACKLIST_MAX + 50) {
        b.note(&format!("action=disable,contact=c{i}"));
    }
    assert_eq!(b.len(), BLACKLIST_MAX);
}
