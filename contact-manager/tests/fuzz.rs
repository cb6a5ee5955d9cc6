//! Fuzz harnesses (fuzzkit, bounded by `FUZZ_CASES` / `FUZZ_SECS`) of what the contact
//! manager reads from outside: configuration lines and the run-time request strings
//! (`BCM_ALERT_REQUEST`, `BCM_REPORT_REQUEST`, the able variables, `NODE_REPORT`).
//! Seeds: the alert requests and node reports of the golden cases, and lines in the
//! form the distribution's missions write.
//!
//! Invariants: no panic, no hang, bounded memory; a refused line changes nothing; the
//! alert set never passes its cap; every posting has a variable name.

use std::path::Path;

use contact_manager::{alert::MAX_ALERTS, Config, ContactManager, MailValue};

fn case_strings(vars: &[&str]) -> Vec<Vec<u8>> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../conformance/helm");
    let mut out = Vec::new();
    for text in fuzzkit::seed_files(&dir, "toml") {
        let text = String::from_utf8_lossy(&text);
        for line in text.lines() {
            for var in vars {
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

fn seeds() -> Vec<Vec<u8>> {
    let mut v = case_strings(&["BCM_ALERT_REQUEST"]);
    assert!(!v.is_empty(), "no alert request seeds");
    let reports = case_strings(&["NODE_REPORT"]);
    v.extend(reports.into_iter().step_by(200));
    for s in [
        "alert = id=avd, var=CONTACT_INFO, val=\"name=$[VNAME] # contact=$[VNAME]\"",
        "alert = id=say, off_flag=SAY_MOOS=bye # B=2, alert_range=80, cpa_range=100",
        "alert = id=r, on_flag=X=1, alert_range=5, match_region=pts={0,0:10,0:10,10}",
        "decay = 30,60",
        "contact_local_coords = force_lat_lon",
        "ignore_group = {red,blue}",
        "BCM_REPORT_REQUEST = var=NEAR,range=100,group=a,type=kayak,refresh=true",
        "CMGR_DISABLE = contact=bob",
        "CMGR_EXPUNGE = vsource=ais",
        "action=disable,id=avd",
    ] {
        v.push(s.as_bytes().to_vec());
    }
    v
}

const DICT: &[&[u8]] = &[
    b",",
    b"=",
    b"#",
    b"\"",
    b"{",
    b"}",
    b":",
    b"\n",
    b"id=",
    b"on_flag=",
    b"off_flag=",
    b"alert_range=",
    b"cpa_range=",
    b"var=",
    b"val=",
    b"range=",
    b"refresh=",
    b"action=",
    b"match_region=pts={",
    b"$[VNAME]",
    b"$[UTC]",
    b"NAME=",
    b"TIME=",
    b"nan",
    b"-1",
    b"1e308",
    b"99999999999999999999999",
    b"\xff",
];

const PARAMS: &[&str] = &[
    "alert",
    "decay",
    "contact_max_age",
    "reject_range",
    "max_contacts",
    "ignore_group",
    "match_region",
    "disable_var",
    "able_flag",
    "contact_local_coords",
    "post_closest_range",
];

fn check(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let text = text.as_ref();
    // As configuration: the whole input as the value of each parameter, and each line
    // as `param = value`.
    let mut cfg = Config::default();
    cfg.set("disable_var", "CMGR_DISABLE").expect("seed config");
    cfg.set("expunge_var", "CMGR_EXPUNGE").expect("seed config");
    for p in PARAMS {
        let before = cfg.clone();
        if cfg.set(p, text).is_err() {
            assert_eq!(cfg, before, "a refused {p} line changed the config");
        }
    }
    for line in text.lines() {
        if let Some((p, v)) = line.split_once('=') {
            let _ = cfg.set(p, v);
        }
    }
    assert!(cfg.alerts.len() <= MAX_ALERTS);
    // As mail: every line of the input under each request variable, then iterations.
    let mut m = ContactManager::new("alpha", cfg, Some((43.8253, -70.3304)));
    let vars = [
        "BCM_ALERT_REQUEST",
        "BCM_REPORT_REQUEST",
        "NODE_REPORT",
        "CMGR_DISABLE",
        "CMGR_EXPUNGE",
        "BCM_DISPLAY_RADII",
    ];
    for (k, line) in std::iter::once(text).chain(text.lines()).enumerate() {
        let mail: Vec<(&str, MailValue<'_>)> =
            vars.iter().map(|v| (*v, MailValue::Str(line))).collect();
        let now = 1000.0 + k as f64;
        m.handle_mail(now, &mail);
        m.handle_mail(
            now,
            &[
                ("NAV_X", MailValue::Num(f64::NAN)),
                ("NAV_Y", MailValue::Str(line)),
            ],
        );
        for p in m.iterate(now) {
            assert!(!p.var.is_empty());
        }
        if k > 50 {
            break;
        }
    }
    assert!(m.alerts().len() <= MAX_ALERTS);
    let _ = contact_manager::appcast::body(&m, 2000.0);
}

#[test]
fn fuzz_config_and_requests() {
    fuzzkit::fuzz("contact_manager", 1500, &seeds(), DICT, check);
}
