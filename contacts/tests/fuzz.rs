//! Fuzz harnesses of what the `contacts` crate reads from outside (issue 18), run by
//! `cargo test` on a bounded budget (`FUZZ_CASES`, `FUZZ_SECS`; see `fuzzkit`): the
//! `NODE_REPORT` parser and ledger, and the alert strings (spawn/update strings,
//! `BHV_ABLE_FILTER`, `cnflag`, filter and decay parameters). Seeds are the repo's
//! files: the `NODE_REPORT`s and alert mail of the golden cases in conformance/helm.
//!
//! Invariants: no panic, no hang, bounded memory (fuzzkit); the ledger never holds more
//! contacts than its cap; an accepted report's name is in the next snapshot; a refusal
//! has a reason text; what the alert readers return comes from the input.

use std::path::Path;

use contacts::{AbleBlacklist, AbleFilter, CnFlag, ContactFilter, Decay, Ledger};

/// The string values of the named variables in the cases' mail and expectations.
fn case_strings(vars: &[&str]) -> Vec<Vec<u8>> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../conformance/helm");
    let mut out = Vec::new();
    for text in fuzzkit::seed_files(&dir, "toml") {
        let text = String::from_utf8_lossy(&text);
        for line in text.lines() {
            for var in vars {
                // Mail pairs: ["VAR", "value"]; expectations: VAR = "value".
                for pat in [format!("[\"{var}\", \""), format!("{var} = \"")] {
                    let mut rest = line;
                    while let Some(i) = rest.find(&pat) {
                        rest = &rest[i + pat.len()..];
                        if let Some(j) = rest.find('"') {
                            out.push(rest.as_bytes()[..j].to_vec());
                        }
                    }
                }
            }
        }
    }
    out.sort();
    out.dedup();
    out
}

fn report_seeds() -> Vec<Vec<u8>> {
    let all = case_strings(&["NODE_REPORT"]);
    assert!(all.len() > 1000, "too few NODE_REPORT seeds: {}", all.len());
    // Every 40th of the recorded reports (they differ only in numbers), plus other forms.
    let mut v: Vec<Vec<u8>> = all.into_iter().step_by(40).collect();
    v.push(br#"{"NAME":"alpha","X":"1","Y":"2","TIME":"3","TYPE":"uuv","DEP":"4"}"#.to_vec());
    v.push(b"NAME=g,LAT=43.8,LON=-70.3,TIME=5,TYPE=glider".to_vec());
    v.push(b"NAME=a\nNAME=b,X=1,Y=2,TIME=0\nX=1".to_vec());
    v
}

const REPORT_DICT: &[&[u8]] = &[
    b",",
    b"=",
    b"{",
    b"}",
    b"\"",
    b":",
    b"\n",
    b"NAME=",
    b"X=",
    b"Y=",
    b"LAT=",
    b"LON=",
    b"TIME=",
    b"UTC_TIME=",
    b"TYPE=uuv",
    b"TYPE=glider",
    b"DEP=",
    b"nan",
    b"-",
    b".",
    b"999999999999999999999999999999999999999999",
    b"1e308",
    b"HDG=1000000000000000000000000000000000000000000000000000000000000",
    b"LENGTH=-1",
    b"GROUP=",
    b"\xff",
];

fn check_reports(data: &[u8]) {
    const CAP: usize = 8;
    let text = String::from_utf8_lossy(data);
    let mut l = Ledger::new(Some((43.8253, -70.3304)));
    l.set_max_contacts(CAP);
    // The whole input as one report, then each line as one (several contacts).
    for r in std::iter::once(text.as_ref()).chain(text.lines()) {
        let p = contacts::NodeReport::parse(r);
        let now = p.time.unwrap_or(0.0);
        match l.ingest(r, now) {
            Ok(a) => {
                let name = a.name.to_string();
                assert!(!name.is_empty());
                l.maintain(now);
                assert!(l.snapshot().has(&name), "accepted {name:?} missing");
                // Whatever numbers got in, the geometry behaviors run on them ends.
                for c in l.snapshot().contacts() {
                    let e = contacts::CpaEngine::new(c.x, c.y, c.hdg, c.spd, 0.0, 0.0);
                    let _ = e.cpa(c.hdg, c.spd, 120.0);
                    let _ = (e.crosses_bow_dist(c.hdg, 2.0), e.passes_port(c.lat, 1.0));
                    let _ = contacts::cpa(0.0, 0.0, c.lon, 2.0, c.x, c.y, c.hdg, c.spd, 120.0);
                    let _ = contacts::rel_bearing(0.0, 0.0, c.hdg, c.x, c.y);
                    let _ = Decay::default().extrapolate(c.x, c.y, c.hdg, c.spd, c.utc, 1e9);
                }
            }
            Err(e) => {
                assert!(!e.to_string().is_empty());
                l.maintain(now);
            }
        }
        assert!(l.len() <= CAP);
        assert!(l.summary().starts_with("now:"));
        let _ = contacts::local_nav_vars(r);
    }
}

#[test]
fn fuzz_node_reports() {
    fuzzkit::fuzz(
        "node_report",
        3000,
        &report_seeds(),
        REPORT_DICT,
        check_reports,
    );
}

fn alert_seeds() -> Vec<Vec<u8>> {
    let mut v = case_strings(&["CONTACT_INFO", "CUT_INFO", "BCM_ALERT_REQUEST"]);
    assert!(v.len() >= 5, "too few alert seeds: {}", v.len());
    for s in [
        "action=disable,contact=bob",
        "action=expunge,bhv_type=BHV_AvoidCollision,vsource=ais",
        "action=able,contact=bob",
        "@<20 CLOSE=$[CN_NAME]",
        "@cpa CPA=$[CPA]",
        "30,60",
        "{kayak,usv}",
        "pts={0,0:100,0:100,100:0,100}",
        r#"name=bob # msg="a#b=c""#,
    ] {
        v.push(s.as_bytes().to_vec());
    }
    v
}

const ALERT_DICT: &[&[u8]] = &[
    b"#",
    b"=",
    b",",
    b"\"",
    b"name=",
    b"contact=",
    b"action=",
    b"disable",
    b"enable",
    b"expunge",
    b"able",
    b"bhv_type=",
    b"vsource=",
    b"@<",
    b"@>",
    b"<",
    b">",
    b"{",
    b"}",
    b"pts=",
    b":",
    b"\xff",
];

fn check_alerts(data: &[u8]) {
    let s = String::from_utf8_lossy(data);
    let s = s.as_ref();
    if let Ok(pairs) = contacts::update_pairs(s) {
        for (k, v) in pairs {
            assert!(s.contains(k) && s.contains(v));
        }
    }
    let n = contacts::spawn_name(s);
    assert!(s.contains(n));
    let _ = contacts::may_spawn(s);
    if let Ok(f) = AbleFilter::parse(s) {
        assert!(f.contact.is_some() || f.bhv_type.is_some() || f.vsource.is_some());
        let _ = f.applies_to("BHV_AvoidCollision", "bob", "");
    }
    let mut b = AbleBlacklist::default();
    for line in s.lines() {
        b.note(line);
    }
    assert!(b.len() <= contacts::alert::BLACKLIST_MAX);
    if let Ok(f) = CnFlag::parse(s) {
        assert!(!f.var.is_empty());
        let _ = f.tag.fires_on_range(Some(10.0), 5.0);
    }
    let mut f = ContactFilter::default();
    for p in ["match_name", "ignore_type", "match_region", "strict_ignore"] {
        let _ = f.set_param(p, s);
    }
    let _ = f.check("bob", "", "kayak", 1.0, 2.0);
    let _ = contacts::alert_request("avd_", "CONTACT_INFO", 50.0, 75.0, &f);
    if let Ok(d) = Decay::parse(s) {
        assert!(0.0 <= d.start && d.start <= d.end);
        let _ = d.extrapolate(0.0, 0.0, 90.0, 2.0, 0.0, 1e9);
    }
}

#[test]
fn fuzz_alert_strings() {
    fuzzkit::fuzz(
        "alert_strings",
        3000,
        &alert_seeds(),
        ALERT_DICT,
        check_alerts,
    );
}
