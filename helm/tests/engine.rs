//! Engine bookkeeping driven through the library API: IVPHELM_STATEVARS and the
//! standby helm's take-over.

use helm::conform::{build_helm, Case};
use helm::factory::BehaviorFactory;
use helm::posting::Value;
use helm::{Helm, HelmState, Mail};

fn case(config: &str) -> Case {
    let bhv = "initialize DEPLOY = true\nBehavior = BHV_Timer\n{\n  name = t\n  condition = DEPLOY = true\n  runflag = T_RUN = yes\n}\n";
    let text = format!(
        "name = \"engine\"\ndomain = [\"course:0:359:360\", \"speed:0:4:41\"]\ncheck = []\nbhv = '''\n{bhv}'''\n[config]\n{config}\n[[step]]\ntime = 1000.0\n"
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
    let c = case(config);
    build_helm(
        &c,
        std::path::Path::new("engine.toml"),
        &BehaviorFactory::with_builtins(),
    )
    .expect("helm builds")
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
