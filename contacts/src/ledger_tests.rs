use super::*;

const ORIGIN: Option<(f64, f64)> = Some((43.8253, -70.3304));

fn rep(name: &str, time: f64) -> String {
    format!("NAME={name},X=10,Y=20,SPD=1,HDG=90,DEP=0,TYPE=kayak,TIME={time}")
}

#[test]
fn summary_format_and_order() {
    let mut l = Ledger::new(ORIGIN);
    l.maintain(1000.0);
    assert_eq!(l.summary(), "now:0, reps:0, who:");
    for n in ["bob", "cal", "GUS", "fay"] {
        l.ingest(&rep(n, 1000.0), 1000.0).unwrap();
    }
    l.ingest(&rep("bob", 1001.0), 1001.0).unwrap();
    l.maintain(1001.0);
    // Byte order: upper case first.
    assert_eq!(l.summary(), "now:4, reps:5, who:GUS,bob,cal,fay");
    assert_eq!(l.snapshot().get("bob").unwrap().reports, 2);
}

#[test]
fn who_lists_twenty_names_at_most() {
    let mut l = Ledger::new(ORIGIN);
    for i in 0..25 {
        l.ingest(&rep(&format!("v{i:02}"), 5.0), 5.0).unwrap();
    }
    l.maintain(5.0);
    let who = l.summary().split("who:").nth(1).unwrap();
    assert_eq!(who.split(',').count(), 20);
    assert!(l.summary().starts_with("now:25, reps:25, who:v00,v01,"));
    assert!(who.ends_with("v19"));
}

#[test]
fn missing_fields_are_refused_uncounted_with_the_reference_text() {
    let mut l = Ledger::new(ORIGIN);
    let e = l.ingest("TYPE=kayak", 1.0).unwrap_err();
    assert_eq!(
        e.to_string(),
        "Missing vname.Missing timestamp.Missing both x/y and lat/lon."
    );
    assert_eq!(
        e.run_warnings("TYPE=kayak"),
        [
            "Bad NodeReport: TYPE=kayak".to_string(),
            "The issue: Missing vname.Missing timestamp.Missing both x/y and lat/lon.".to_string()
        ]
    );
    // X without Y is no position; a non-numeric TIME is no time.
    let e = l.ingest("NAME=a,X=1,TIME=now", 1.0).unwrap_err();
    assert_eq!(
        e.to_string(),
        "Missing timestamp.Missing both x/y and lat/lon."
    );
    assert!(!e.counted());
    assert_eq!((l.reps(), l.refused(), l.len()), (0, 2, 0));
}

#[test]
fn underwater_types_need_a_depth_and_are_counted() {
    let mut l = Ledger::new(ORIGIN);
    let e = l.ingest("NAME=u,X=1,Y=1,TIME=3,TYPE=uuv", 3.0).unwrap_err();
    assert_eq!(e, IngestError::NoDepth);
    assert_eq!(
        e.to_string(),
        "underwater vehicle type with no depth reported"
    );
    assert_eq!((l.reps(), l.len()), (1, 0));
    // Upper-case GLIDER is known but not "glider": no depth needed.
    let a = l.ingest("NAME=g,X=1,Y=1,TIME=3,TYPE=GLIDER", 3.0).unwrap();
    assert_eq!(a.vtype, "GLIDER");
    let a = l
        .ingest("NAME=u,X=1,Y=1,TIME=3,TYPE=uuv,DEPTH=4", 3.0)
        .unwrap();
    assert_eq!((a.name, a.vtype, a.new), ("u", "auv", true));
    l.maintain(3.0);
    let u = l.snapshot().get("u").unwrap();
    assert_eq!((u.dep, u.length), (4.0, 3.0)); // auv default length 3
    assert_eq!(l.snapshot().get("g").unwrap().length, 0.0); // GLIDER: no default
}

#[test]
fn latlon_only_reports_are_converted_and_xy_only_get_latlon() {
    let mut l = Ledger::new(ORIGIN);
    // bob's first report of avd_spawn_crossing without its X/Y.
    l.ingest("NAME=bob,LAT=43.8263968,LON=-70.32899417,TIME=1000", 1000.0)
        .unwrap();
    // LON alone counts as "lat/lon present" (latitude 0): far away, but accepted.
    l.ingest("NAME=eq,LON=-70.3304,TIME=1000", 1000.0).unwrap();
    l.ingest("NAME=xy,X=115,Y=120,TIME=1000", 1000.0).unwrap();
    l.maintain(1000.0);
    let s = l.snapshot();
    let bob = s.get("bob").unwrap();
    assert!((bob.x - 115.0).abs() < 0.03 && (bob.y - 120.0).abs() < 0.03);
    let eq = s.get("eq").unwrap();
    assert!(eq.y < -4.8e6, "{eq:?}");
    let xy = s.get("xy").unwrap();
    assert!((xy.lat - 43.8263968).abs() < 1e-6 && (xy.lon + 70.32899417).abs() < 1e-6);
    // Both given: kept verbatim, even when they disagree.
    l.ingest("NAME=both,X=1,Y=2,LAT=10,LON=20,TIME=1000", 1000.0)
        .unwrap();
    l.maintain(1000.0);
    let b = l.snapshot().get("both").unwrap();
    assert_eq!((b.x, b.y, b.lat, b.lon), (1.0, 2.0, 10.0, 20.0));
    // Without an origin a lat/lon-only report cannot be placed.
    let mut l = Ledger::new(None);
    assert_eq!(
        l.ingest("NAME=bob,LAT=43.8,LON=-70.3,TIME=1", 1.0),
        Err(IngestError::NoOrigin)
    );
}

#[test]
fn stale_contacts_go_after_twice_the_max_age_by_report_time() {
    let mut l = Ledger::new(ORIGIN);
    assert_eq!(l.set_max_age(1.0), 10.0); // clipped
    assert_eq!(l.set_max_age(1e9), 1800.0);
    assert_eq!(l.set_max_age(f64::NAN), DEFAULT_MAX_AGE);
    l.set_max_age(10.0);
    l.ingest(&rep("bob", 1000.0), 1000.0).unwrap();
    // Received late, but age counts from the report's TIME.
    l.ingest(&rep("cal", 995.0), 1010.0).unwrap();
    l.ingest(&rep("zero", 0.0), 1000.0).unwrap();
    assert_eq!(l.maintain(1015.0), 0);
    assert_eq!(l.maintain(1015.1), 1); // cal: 20.1 > 2 × 10
    assert_eq!(l.snapshot().len(), 2);
    assert_eq!(l.maintain(1020.0), 0); // bob: exactly 20, not more
    assert_eq!(l.maintain(1020.01), 1);
    l.maintain(1e9);
    assert_eq!(l.summary(), "now:1, reps:3, who:zero"); // TIME 0 never goes stale
}

#[test]
fn the_cap_refuses_new_names_only() {
    let mut l = Ledger::new(ORIGIN);
    l.set_max_contacts(2);
    l.ingest(&rep("a", 1.0), 1.0).unwrap();
    l.ingest(&rep("b", 1.0), 1.0).unwrap();
    assert_eq!(
        l.ingest(&rep("c", 1.0), 1.0),
        Err(IngestError::Full { cap: 2 })
    );
    assert!(l.ingest(&rep("a", 2.0), 2.0).is_ok());
    assert_eq!((l.len(), l.refused_full(), l.reps()), (2, 1, 3));
}

#[test]
fn overlong_text_fields_are_refused() {
    let mut l = Ledger::new(ORIGIN);
    let long = "n".repeat(MAX_TEXT_FIELD + 1);
    let e = l.ingest(&rep(&long, 1.0), 1.0).unwrap_err();
    assert!(matches!(e, IngestError::FieldTooLong { field: "NAME", .. }));
    assert!(l.ingest(&rep(&long[1..], 1.0), 1.0).is_ok());
}

#[test]
fn snapshot_fields() {
    let mut l = Ledger::new(ORIGIN);
    l.ingest(
        "NAME=bob,X=1,Y=2,SPD=3,HDG=4,DEP=5,LAT=6,LON=7,TYPE=KAYAK,GROUP=red,VSOURCE=ais,TIME=990",
        995.0,
    )
    .unwrap();
    // Not in the snapshot until maintained.
    assert!(!l.snapshot().has("bob"));
    l.maintain(1000.0);
    let s = l.snapshot();
    assert_eq!(s.now(), 1000.0);
    let nums: Vec<f64> = [
        "x", "y", "hdg", "spd", "dep", "lat", "lon", "utc", "utc_age",
    ]
    .iter()
    .map(|f| s.num("bob", f).unwrap())
    .collect();
    assert_eq!(nums, [1.0, 2.0, 4.0, 3.0, 5.0, 6.0, 7.0, 990.0, 10.0]);
    assert_eq!(s.num("bob", "utc_received"), Some(995.0));
    assert_eq!(s.num("bob", "utc_age_received"), Some(5.0));
    assert_eq!(s.text("bob", "type"), Some("KAYAK"));
    assert_eq!(s.text("bob", "group"), Some("red"));
    assert_eq!(s.text("bob", "vsource"), Some("ais"));
    // The contact base's "grp" is unknown to the snapshot (group always "").
    assert_eq!(s.text("bob", crate::CONTACT_BASE_GROUP_FIELD), None);
    assert_eq!(s.num("bob", "group"), None);
    assert_eq!(s.num("BOB", "x"), None); // names are case-sensitive
    assert_eq!(s.names().collect::<Vec<_>>(), ["bob"]);
}

#[test]
fn contact_summary_distinct_in_set_order() {
    let mut l = Ledger::new(ORIGIN);
    assert_eq!(l.contact_summary(["", ""]), None);
    assert_eq!(
        l.contact_summary(["bob", "", "al", "bob", "bo"]),
        Some("bob,al,bo")
    );
    assert_eq!(l.contact_summary(std::iter::empty()), None);
}

#[test]
fn routing() {
    assert!(feeds_ledger("NODE_REPORT") && feeds_ledger("AIS_REPORT_LOCAL"));
    assert!(!feeds_ledger("NODE_REPORT_LOCAL") && !feeds_ledger("node_report"));
}

#[test]
fn ingest_parsed_is_ingest_of_the_text() {
    // Accepted, updated, refused (missing fields, depth, full) and malformed reports:
    // the text path and the parsed path give the same results, counters and snapshot.
    let reports = [
        rep("bob", 10.0),
        rep("bob", 11.0),
        "NAME=cal,LAT=43.826,LON=-70.33,TIME=12,TYPE=glider".to_string(),
        "NAME=cal,LAT=43.826,LON=-70.33,TIME=12,TYPE=glider,DEP=3".to_string(),
        "TYPE=kayak".to_string(),
        "{\"NAME\":\"dee\",\"X\":\"1\",\"Y\":\"2\",\"TIME\":\"13\",\"GROUP\":\"g\"}".to_string(),
        "NAME=eve,X=1,Y=2,TIME=14,TYPE=uuv".to_string(),
        rep("fay", 15.0),
    ];
    let (mut text, mut parsed) = (Ledger::new(ORIGIN), Ledger::new(ORIGIN));
    text.set_max_contacts(3);
    parsed.set_max_contacts(3);
    for (k, r) in reports.iter().enumerate() {
        let now = 20.0 + k as f64;
        let a = text.ingest(r, now).map(|a| format!("{a:?}"));
        let b = parsed
            .ingest_parsed(&NodeReport::parse(r), now)
            .map(|a| format!("{a:?}"));
        assert_eq!(a, b, "{r}");
    }
    assert_eq!(
        (text.reps(), text.refused(), text.refused_full()),
        (parsed.reps(), parsed.refused(), parsed.refused_full())
    );
    assert_eq!(text.refused_full(), 2, "eve and fay found the ledger full");
    text.maintain(30.0);
    parsed.maintain(30.0);
    assert_eq!(text.summary(), parsed.summary());
    assert_eq!(text.snapshot(), parsed.snapshot());
}

#[test]
fn feeds_ledger_is_the_list() {
    for v in LEDGER_VARS {
        assert!(feeds_ledger(v), "{v}");
    }
    for v in ["NODE_REPORT_LOCAL", "AIS_REPORTS", "", "node_report"] {
        assert!(!feeds_ledger(v), "{v}");
    }
}
