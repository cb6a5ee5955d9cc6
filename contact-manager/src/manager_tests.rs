use super::*;
use crate::value::MailValue::{Num, Str};
use crate::value::Value;

const AVD: &str =
    "id=avd_, on_flag=CONTACT_INFO=name=$[VNAME] # contact=$[VNAME],alert_range=50, cpa_range=75";

fn manager(lines: &[(&str, &str)]) -> ContactManager {
    let mut cfg = Config::default();
    for (p, v) in lines {
        cfg.set(p, v).unwrap();
    }
    ContactManager::new("alpha", cfg, None)
}

fn nav(m: &mut ContactManager, t: f64, x: f64, y: f64, h: f64, v: f64) {
    m.handle_mail(
        t,
        &[
            ("NAV_X", Num(x)),
            ("NAV_Y", Num(y)),
            ("NAV_HEADING", Num(h)),
            ("NAV_SPEED", Num(v)),
        ],
    );
}

fn report(m: &mut ContactManager, t: f64, name: &str, x: f64, y: f64, h: f64, v: f64) {
    let r = format!("NAME={name},X={x},Y={y},HDG={h},SPD={v},TIME={t},TYPE=kayak");
    m.handle_mail(t, &[("NODE_REPORT", Str(&r))]);
}

fn vals<'a>(p: &'a [Posting], var: &str) -> Vec<&'a Value> {
    p.iter().filter(|p| p.var == var).map(|p| &p.val).collect()
}

/// Head-on, worked by hand: ownship at the origin heading north at 2 m/s, bob on the
/// y axis heading south at 3 m/s (CPA 0 while closing). Alert 50, CPA range 75.
#[test]
fn head_on_alert_turns_on_inside_the_cpa_range_and_off_when_opening() {
    let mut m = manager(&[("alert", AVD), ("alert_verbose", "true")]);
    nav(&mut m, 10.0, 0.0, 0.0, 0.0, 2.0);
    // Range 80 > 75: nothing, although the CPA is 0.
    report(&mut m, 10.0, "bob", 0.0, 80.0, 180.0, 3.0);
    let p = m.iterate(10.0);
    assert!(vals(p, "CONTACT_INFO").is_empty());
    assert_eq!(
        vals(p, "ALERT_VERBOSE"),
        [&Value::Str("new_contact=bob".into())]
    );
    // Range 74 <= 75 and CPA 0 <= 50: on, once.
    report(&mut m, 11.0, "bob", 0.0, 74.0, 180.0, 3.0);
    let p = m.iterate(11.0);
    assert_eq!(
        vals(p, "CONTACT_INFO"),
        [&Value::Str("name=bob # contact=bob".into())]
    );
    assert_eq!(
        vals(p, "ALERT_VERBOSE"),
        [&Value::Str(
            "contact=bob,alert_id=avd_,off-->alerted,alert_range=50,alert_range_cpa=75,range_actual=74.0,range_cpa=0.0"
                .into()
        )]
    );
    assert_eq!(
        vals(p, "CONTACTS_ALERTED"),
        [&Value::Str("(bob,avd_)".into())]
    );
    assert_eq!(vals(p, "CONTACTS_COUNT"), [&Value::Num(1.0)]);
    report(&mut m, 12.0, "bob", 0.0, 30.0, 180.0, 3.0);
    assert!(
        vals(m.iterate(12.0), "CONTACT_INFO").is_empty(),
        "no repeat"
    );
    // Passed: 40 m astern and opening: range 40 <= 50, still alerted.
    report(&mut m, 13.0, "bob", 0.0, -40.0, 180.0, 3.0);
    assert!(vals(m.iterate(13.0), "ALERT_VERBOSE").is_empty());
    // 60 m astern, opening: range > 50 and CPA (= range, opening) 60 > 50: off.
    report(&mut m, 14.0, "bob", 0.0, -60.0, 180.0, 3.0);
    let p = m.iterate(14.0);
    assert_eq!(
        vals(p, "ALERT_VERBOSE"),
        [&Value::Str(
            "contact=bob,alert_id=avd_,alerted-->off,alert_range=50,alert_range_cpa=75,range_actual=60.0".into()
        )]
    );
    assert_eq!(vals(p, "CONTACTS_ALERTED"), [&Value::Str(String::new())]);
    assert_eq!(vals(p, "CONTACTS_COUNT"), [&Value::Num(0.0)]);
    assert_eq!(m.alerted().count(), 0);
}

/// A crossing worked by hand: ownship north at 1 m/s from the origin; the contact
/// heads west at 2 m/s. Relative position p = os − cn, relative velocity
/// w = (0,1) − (−2,0) = (2,1); t* = −p·w / |w|², CPA = |p + w t*|.
#[test]
fn crossing_alert_follows_range_and_cpa() {
    let mut m = manager(&[("alert", AVD)]);
    nav(&mut m, 0.0, 0.0, 0.0, 0.0, 1.0);
    // From (60, 50): p = (−60, −50), t* = 34, miss (8, −16) → CPA 17.9, but range
    // 78.1 > 75: off.
    report(&mut m, 0.0, "cal", 60.0, 50.0, 270.0, 2.0);
    let c = m.table().get("cal").unwrap().clone();
    let g = m.geometry(&c, 0.0);
    assert!((g.cpa - (8.0f64).hypot(16.0)).abs() < 1e-9, "{g:?}");
    assert!(vals(m.iterate(0.0), "CONTACT_INFO").is_empty());
    // From (60, 30): p = (−60, −30), t* = 30, miss (0, 0): CPA 0, range 67.1: on.
    report(&mut m, 1.0, "cal", 60.0, 30.0, 270.0, 2.0);
    let c = m.table().get("cal").unwrap().clone();
    assert!(m.geometry(&c, 1.0).cpa < 1e-9);
    assert_eq!(vals(m.iterate(1.0), "CONTACT_INFO").len(), 1);
    // The same contact heading east (opening): CPA = range 67.1 > 50: off.
    report(&mut m, 2.0, "cal", 60.0, 30.0, 90.0, 2.0);
    m.iterate(2.0);
    assert_eq!(m.alerted().count(), 0);
}

#[test]
fn stale_contact_resolves_then_retires_and_comes_back() {
    let mut m = manager(&[
        ("alert", AVD),
        ("alert", "id=avd_, off_flag=CONTACT_RESOLVED=$[VNAME]"),
        ("contact_max_age", "35"),
    ]);
    nav(&mut m, 100.0, 0.0, 0.0, 0.0, 0.0);
    report(&mut m, 100.0, "bob", 0.0, 40.0, 0.0, 0.0);
    let p = m.iterate(100.0);
    assert_eq!(vals(p, "CONTACTS_LIST"), [&Value::Str("bob".into())]);
    assert_eq!(vals(p, "CONTACT_INFO").len(), 1);
    // 35 s old: still there.
    assert!(vals(m.iterate(135.0), "CONTACT_RESOLVED").is_empty());
    // 35.5 s old: the alert no longer applies (off-flag), the contact is retired.
    let p = m.iterate(135.5);
    assert_eq!(vals(p, "CONTACT_RESOLVED"), [&Value::Str("bob".into())]);
    assert_eq!(vals(p, "CONTACTS_RETIRED"), [&Value::Str("bob".into())]);
    assert_eq!(vals(p, "CONTACTS_LIST"), [&Value::Str(String::new())]);
    assert!(m.table().is_empty());
    // A new report brings it back and the alert fires again.
    report(&mut m, 140.0, "bob", 0.0, 40.0, 0.0, 0.0);
    assert_eq!(vals(m.iterate(140.0), "CONTACT_INFO").len(), 1);
}

#[test]
fn reject_range_retires_with_the_off_flag() {
    let mut m = manager(&[
        (
            "alert",
            "id=far, on_flag=FAR=on, off_flag=FAR=off, alert_range=5000",
        ),
        ("reject_range", "1000"),
    ]);
    nav(&mut m, 0.0, 0.0, 0.0, 0.0, 0.0);
    report(&mut m, 0.0, "x", 0.0, 1099.0, 0.0, 0.0);
    assert_eq!(vals(m.iterate(0.0), "FAR"), [&Value::Str("on".into())]);
    report(&mut m, 1.0, "x", 0.0, 1101.0, 0.0, 0.0);
    let p = m.iterate(1.0);
    assert_eq!(vals(p, "FAR"), [&Value::Str("off".into())]);
    assert_eq!(vals(p, "CONTACTS_RETIRED"), [&Value::Str("x".into())]);
}

#[test]
fn ownship_reports_are_ignored_and_bad_ones_warned() {
    let mut m = manager(&[("alert", AVD)]);
    m.handle_mail(
        0.0,
        &[
            ("NODE_REPORT", Str("NAME=Alpha,X=0,Y=1,TIME=0")),
            ("NODE_REPORT", Str("NAME=sub,X=0,Y=1,TIME=0,TYPE=uuv")),
            ("NODE_REPORT", Str("X=0,Y=1")),
        ],
    );
    m.iterate(0.0);
    assert!(m.table().is_empty());
    let w: Vec<(&str, u64)> = m.warnings().run_warnings().collect();
    assert_eq!(
        w,
        [
            ("Bad Mail: NODE_REPORT:Missing vname.", 1),
            (
                "Bad Mail: NODE_REPORT:underwater vehicle type with no depth reported",
                1
            )
        ]
    );
}

#[test]
fn hold_alerts_for_helm_waits_for_drive() {
    let mut m = manager(&[("alert", AVD), ("hold_alerts_for_helm", "true")]);
    nav(&mut m, 0.0, 0.0, 0.0, 0.0, 0.0);
    report(&mut m, 0.0, "bob", 0.0, 10.0, 0.0, 0.0);
    assert!(vals(m.iterate(0.0), "CONTACT_INFO").is_empty());
    m.handle_mail(1.0, &[("IVPHELM_STATE", Str("PARK"))]);
    assert!(vals(m.iterate(1.0), "CONTACT_INFO").is_empty());
    m.handle_mail(2.0, &[("IVPHELM_STATE", Str("DRIVE"))]);
    report(&mut m, 2.0, "bob", 0.0, 10.0, 0.0, 0.0);
    assert_eq!(vals(m.iterate(2.0), "CONTACT_INFO").len(), 1);
}

#[test]
fn alert_requests_at_run_time() {
    let mut m = manager(&[]);
    nav(&mut m, 0.0, 0.0, 0.0, 0.0, 0.0);
    report(&mut m, 0.0, "bob", 0.0, 10.0, 0.0, 0.0);
    assert!(vals(m.iterate(0.0), "CONTACT_INFO").is_empty());
    m.handle_mail(
        1.0,
        &[
            ("BCM_ALERT_REQUEST", Str(AVD)),
            ("BCM_ALERT_REQUEST", Str("id=bad, match_colour=red")),
        ],
    );
    report(&mut m, 1.0, "bob", 0.0, 10.0, 0.0, 0.0);
    assert_eq!(vals(m.iterate(1.0), "CONTACT_INFO").len(), 1);
    assert_eq!(m.received().0, 2);
    assert!(m
        .warnings()
        .run_warnings()
        .any(|(t, _)| t == "Unhandled Alert Request: id=bad, match_colour=red"));
    // action=disable turns the alert off: the off transition happens.
    m.handle_mail(
        2.0,
        &[("BCM_ALERT_REQUEST", Str("id=avd_, action=disable"))],
    );
    report(&mut m, 2.0, "bob", 0.0, 10.0, 0.0, 0.0);
    m.iterate(2.0);
    assert_eq!(m.alerted().count(), 0);
}

#[test]
fn alert_filters_and_numeric_flags() {
    let mut m = manager(&[(
        "alert",
        "id=k, on_flag=SEEN=$[X], alert_range=100, match_type=ship",
    )]);
    nav(&mut m, 0.0, 0.0, 0.0, 0.0, 0.0);
    report(&mut m, 0.0, "kay", 3.5, 10.0, 0.0, 0.0);
    m.handle_mail(
        0.0,
        &[("NODE_REPORT", Str("NAME=big,X=7.25,Y=1,TIME=0,TYPE=tanker"))],
    );
    let p = m.iterate(0.0);
    // Only the ship (the unknown type "tanker" is fixed to ship); the value is a number.
    assert_eq!(vals(p, "SEEN"), [&Value::Num(7.25)]);
    assert_eq!(
        vals(p, "CONTACTS_UNALERTED"),
        [&Value::Str("(kay,k)".into())]
    );
}

#[test]
fn status_postings_only_on_change_and_recap_by_interval() {
    let mut m = manager(&[("alert", AVD), ("post_closest_range", "true")]);
    nav(&mut m, 0.0, 0.0, 0.0, 0.0, 0.0);
    report(&mut m, 0.0, "bob", 30.0, 40.0, 0.0, 0.0);
    report(&mut m, 0.0, "abe", 300.0, 400.0, 0.0, 0.0);
    let p = m.iterate(0.0);
    assert_eq!(vals(p, "CONTACTS_LIST"), [&Value::Str("abe,bob".into())]);
    assert_eq!(vals(p, "CONTACT_CLOSEST"), [&Value::Str("bob".into())]);
    assert_eq!(vals(p, "CONTACT_CLOSEST_RANGE"), [&Value::Num(50.0)]);
    assert_eq!(
        vals(p, "CONTACTS_RECAP"),
        [&Value::Str(
            "vname=abe,range=500.00,age=0.00 # vname=bob,range=50.00,age=0.00".into()
        )]
    );
    let p = m.iterate(0.5);
    assert!(vals(p, "CONTACTS_LIST").is_empty());
    assert!(vals(p, "CONTACT_CLOSEST").is_empty());
    assert!(vals(p, "CONTACTS_RECAP").is_empty(), "recap every 1 s");
    assert_eq!(vals(m.iterate(1.0), "CONTACTS_RECAP").len(), 1);
}

#[test]
fn range_reports_use_the_extrapolated_position() {
    let mut m = manager(&[]);
    nav(&mut m, 100.0, 0.0, 0.0, 0.0, 0.0);
    // Reported at (60, 0) 20 s ago heading west at 1 m/s. Default decay 15..30 s:
    // 15 m at full speed + the ramp from 1 to 2/3 m/s over 5 s (25/6 m) = 19.17 m,
    // so it is at x = 40.83: inside 50 m, though its last report is 60 m away.
    m.handle_mail(
        100.0,
        &[
            ("NODE_REPORT", Str("NAME=e,X=60,Y=0,HDG=270,SPD=1,TIME=80")),
            ("BCM_REPORT_REQUEST", Str("var=NEAR_ME,range=50")),
            (
                "BCM_REPORT_REQUEST",
                Str("var=NEAR_SHIPS,range=50,type=ship,refresh=true"),
            ),
            (
                "BCM_REPORT_REQUEST",
                Str("var=NEAR_KAYAKS,range=50,type=kayak"),
            ),
        ],
    );
    let p = m.iterate(100.0).to_vec();
    assert_eq!(vals(&p, "NEAR_ME"), [&Value::Str("e".into())]);
    assert_eq!(vals(&p, "NEAR_SHIPS"), [&Value::Str("e".into())]);
    assert_eq!(vals(&p, "NEAR_KAYAKS"), [&Value::Str(String::new())]);
    // Unchanged: not posted again, unless refreshed.
    assert!(vals(m.iterate(100.5), "NEAR_ME").is_empty());
    m.handle_mail(
        101.0,
        &[(
            "BCM_REPORT_REQUEST",
            Str("var=NEAR_ME,range=50,refresh=true"),
        )],
    );
    assert_eq!(vals(m.iterate(101.0), "NEAR_ME").len(), 1);
    let c = m.table().get("e").unwrap().clone();
    let g = m.geometry(&c, 100.0);
    assert!(
        (g.range_extrap - (60.0 - 15.0 - 25.0 / 6.0)).abs() < 1e-9,
        "{g:?}"
    );
}

#[test]
fn able_variables_post_bhv_able_filter() {
    let mut m = manager(&[
        ("disable_var", "XYZ_DISABLE_TARGET"),
        ("enable_var", "XYZ_REENABLE_TARGET"),
    ]);
    assert!(m
        .subscriptions()
        .contains(&"XYZ_DISABLE_TARGET".to_string()));
    m.handle_mail(
        0.0,
        &[
            ("XYZ_DISABLE_TARGET", Str("bob")),
            ("XYZ_REENABLE_TARGET", Str("contact=bob")),
            ("XYZ_REENABLE_TARGET", Str("colour=red")),
        ],
    );
    let p = m.iterate(0.0);
    assert_eq!(
        vals(p, "BHV_ABLE_FILTER"),
        [
            &Value::Str("contact=bob,action=disable".into()),
            &Value::Str("contact=bob,action=enable".into())
        ]
    );
    assert_eq!(m.warnings().run_total(), 1);
}

#[test]
fn display_radii_draws_the_largest_cpa_range() {
    let mut m = manager(&[
        ("alert", AVD),
        ("alert", "id=b, on_flag=B=1, alert_range=20, cpa_range=30"),
    ]);
    assert!(vals(m.iterate(0.0), "VIEW_CIRCLE").is_empty());
    m.handle_mail(1.0, &[("BCM_DISPLAY_RADII", Str("true"))]);
    let p = m.iterate(1.0);
    let v = vals(p, "VIEW_CIRCLE");
    assert_eq!(v.len(), 1);
    let s = v[0].as_str().unwrap();
    assert!(
        s.contains("radius=75") && s.contains("label=alert_alpha"),
        "{s}"
    );
}

#[test]
fn parsed_reports_act_as_their_text() {
    // Good, ownship's, malformed, filtered-by-depth and numeric reports, mixed with
    // other mail: reading the reports beforehand changes nothing.
    let texts = [
        "NAME=bob,X=0,Y=74,HDG=180,SPD=3,TIME=11,TYPE=kayak",
        "NAME=alpha,X=1,Y=1,TIME=11",
        "TYPE=kayak,X=1",
        "NAME=gus,X=5,Y=5,TIME=11,TYPE=uuv",
        "NAME=cal,LAT=43.8,LON=-70.3,TIME=11",
    ];
    let mut mail: Vec<(&str, MailValue<'_>)> = vec![("NAV_X", Num(0.0)), ("NODE_REPORT", Num(7.0))];
    mail.extend(texts.iter().map(|t| ("NODE_REPORT", Str(t))));
    let parsed: Vec<(usize, NodeReport<'_>)> = mail
        .iter()
        .enumerate()
        .filter_map(|(k, (_, v))| match v {
            Str(t) => Some((k, NodeReport::parse(t))),
            Num(_) => None,
        })
        .collect();
    let (mut text, mut read) = (manager(&[("alert", AVD)]), manager(&[("alert", AVD)]));
    text.handle_mail(11.0, &mail);
    read.handle_mail_parsed(11.0, &mail, &parsed);
    let (a, b) = (text.iterate(11.0).to_vec(), read.iterate(11.0).to_vec());
    assert_eq!(a, b);
    assert_eq!(text.received(), read.received());
    assert_eq!(text.malformed_reports(), read.malformed_reports());
    assert_eq!(text.malformed_reports(), 1);
    assert!(text.table().contacts().eq(read.table().contacts()));
    assert!(text
        .warnings()
        .run_warnings()
        .eq(read.warnings().run_warnings()));
    assert!(
        text.warnings().run_total() > 0,
        "the uuv without depth warns"
    );
}
