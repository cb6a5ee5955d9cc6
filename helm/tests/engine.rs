//! Engine bookkeeping driven through the library API: IVPHELM_STATEVARS and the
//! standby helm's take-over.

use helm_conform::Case;
use helm_engine::posting::Value;
use helm_engine::{Helm, HelmState, Mail};

mod common;

fn case(config: &str) -> Case {
    let bhv = "initialize DEPLOY = true\nBehavior = BHV_Timer\n{\n  name = t\n  condition = DEPLOY = true\n  runflag = T_RUN = yes\n}\n";
    case_of("engine", bhv, config)
}

/// A case named `name` of the `.bhv` text `bhv`, with `config` as its `[config]`.
fn case_of(name: &str, bhv: &str, config: &str) -> Case {
    let text = format!(
        "name = \"{name}\"\ndomain = [\"course:0:359:360\", \"speed:0:4:41\"]\ncheck = []\nbhv = '''\n{bhv}'''\n[config]\n{config}\n[[step]]\ntime = 1000.0\n"
    );
    toml::from_str(&text).expect("case parses")
}

fn mail(var: &str, value: Value, time: f64, source: &str) -> Mail {
    Mail {
        var: var.into(),
        value,
        time,
        source: source.into(),
        source_aux: String::new(),
    }
}

fn nav(t: f64) -> Vec<Mail> {
    ["NAV_X", "NAV_Y", "NAV_HEADING", "NAV_SPEED"]
        .iter()
        .map(|v| mail(v, Value::Num(0.0), t, "uSimMarine"))
        .collect()
}

fn helm(config: &str) -> Helm {
    common::builtin_case_helm(&case(config), "engine.toml")
}

#[test]
fn statevars_are_posted_when_they_grow_not_every_iteration() {
    let mut h = helm("start_in_drive = \"true\"");
    h.startup(1000.0);
    let mut posted = Vec::new();
    for k in 0..12 {
        let t = 1000.0 + 0.25 * k as f64;
        h.handle_mail(t, &nav(t));
        for p in h.iterate(t) {
            if p.var == "IVPHELM_STATEVARS" {
                posted.push(p.value.clone());
            }
        }
    }
    assert_eq!(posted, vec![Value::Str("DEPLOY,T_RUN".into())]);
}

#[test]
fn a_standby_helm_takes_over_when_the_primary_goes_quiet() {
    let mut h = helm("start_in_drive = \"true\"\nstandby = \"2\"");
    h.startup(1000.0);
    assert_eq!(h.state(), HelmState::Standby);
    let primary = |t: f64| mail("IVPHELM_STATE", Value::Str("DRIVE".into()), t, "pHelmIvP_A");
    // Heartbeats every second: it stays in standby.
    for k in 0..4 {
        let t = 1000.0 + k as f64;
        h.handle_mail(t, &[primary(t)]);
        h.iterate(t);
        assert_eq!(h.state(), HelmState::Standby, "at {t}");
    }
    // Then silence for more than 2 s: it takes over.
    h.handle_mail(1005.5, &nav(1005.5));
    h.iterate(1005.5);
    assert_eq!(h.state(), HelmState::Drive);
}

#[test]
fn create_and_loop_times_are_measured_separately() {
    // IVPHELM_CREATE_CPU covers the behaviors, IVPHELM_LOOP_CPU also the solver: on every
    // decision the first is positive and not above the second; the appcast report gives
    // each active behavior its own step time.
    let bhv = "initialize DEPLOY = true\nBehavior = BHV_Waypoint\n{\n  name = w\n  condition = DEPLOY = true\n  speed = 2\n  points = 0,100 : 100,100\n}\n";
    let c = case_of("times", bhv, "start_in_drive = \"true\"");
    let mut h = common::builtin_case_helm(&c, "times.toml");
    h.startup(1000.0);
    let mut pairs = 0;
    let mut solver_seen = false;
    for k in 0..12 {
        let t = 1000.0 + 0.25 * k as f64;
        h.handle_mail(t, &nav(t));
        let posts = h.iterate(t);
        let num = |var: &str| {
            posts.iter().find(|p| p.var == var).map(|p| match p.value {
                Value::Num(x) => x,
                Value::Str(_) => panic!("{var} is a string"),
            })
        };
        if let (Some(create), Some(lp)) = (num("IVPHELM_CREATE_CPU"), num("IVPHELM_LOOP_CPU")) {
            assert!(create > 0.0 && create <= lp, "create {create} loop {lp}");
            solver_seen |= create < lp;
            pairs += 1;
        }
    }
    assert!(pairs >= 8, "only {pairs} decisions");
    assert!(solver_seen, "the loop time never exceeded the create time");
    let body = h.appcast_body(1003.0, "open");
    for l in ["SolveTime:", "CreateTime:", "LoopTime:"] {
        assert!(body.contains(l), "{body}");
    }
    let line = body
        .lines()
        .find(|l| l.trim_start().starts_with("w ["))
        .unwrap_or_else(|| panic!("no active line for w:\n{body}"));
    let cpu: f64 = line
        .split("(cpu=")
        .nth(1)
        .and_then(|r| r.split(')').next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no cpu in {line}"));
    assert!(cpu > 0.0, "{line}");
}

#[test]
fn the_appcast_lists_the_behaviors_postings_by_variable() {
    // Postings of two behaviors, made in no particular order: the report's table of
    // last postings gives each variable once, in the variables' order.
    let bhv = "initialize DEPLOY = true\nBehavior = BHV_Waypoint\n{\n  name = w\n  condition = DEPLOY = true\n  speed = 2\n  points = 0,100 : 100,100\n  runflag = ZULU = 1\n  runflag = ALPHA = 2\n}\nBehavior = BHV_Timer\n{\n  name = t\n  condition = DEPLOY = true\n  runflag = MIKE = yes\n}\n";
    let c = case_of("rows", bhv, "start_in_drive = \"true\"");
    let mut h = common::builtin_case_helm(&c, "rows.toml");
    h.startup(1000.0);
    for k in 0..12 {
        let t = 1000.0 + 0.25 * k as f64;
        h.handle_mail(t, &nav(t));
        h.iterate(t);
    }
    let body = h.appcast_body(1003.0, "open");
    let vars: Vec<&str> = body
        .lines()
        .skip_while(|l| !l.starts_with("Variable"))
        .skip(2) // the header and its rule
        .take_while(|l| !l.trim().is_empty())
        .filter_map(|l| l.split_whitespace().next())
        .collect();
    for v in ["ALPHA", "MIKE", "ZULU"] {
        assert!(vars.contains(&v), "{v} missing from {vars:?} in\n{body}");
    }
    let mut sorted = vars.clone();
    sorted.sort_unstable();
    sorted.dedup();
    assert_eq!(vars, sorted, "{body}");
}
