//! The golden helm cases recorded with a real contact manager beside the helm
//! (conformance/helm): every case whose helm posts a `BCM_ALERT_REQUEST` and whose mail
//! carries that alert's on-flag. Our manager is fed the case's own mail (ownship's
//! NAV_*, the NODE_REPORTs) and the helm's request, and iterated at each step; each
//! on-flag value the real manager delivered must come from ours first (same value),
//! no earlier than one step and no later than [`LATENCY`] before it arrived in the
//! recording (the real manager ticks on its own and the bus adds a delay).

use std::path::{Path, PathBuf};

use helm_conform::{Case, Step};

use contact_manager::{AlertSet, Config, ContactManager, MailValue};

/// Largest delay (s) accepted between our on-flag and the recorded arrival.
const LATENCY: f64 = 1.0;

/// The golden helm cases (read by the conformance runner's own reader).
fn cases() -> Vec<(PathBuf, Case)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../conformance/helm");
    helm_conform::load_all(&[dir]).expect("the golden cases in conformance/helm")
}

/// The helm's request posted at step `s`, if any.
fn request(s: &Step) -> Option<&str> {
    s.expect.get("BCM_ALERT_REQUEST").and_then(|r| r.as_str())
}

#[test]
fn on_flags_agree_with_the_recorded_contact_manager() {
    let mut checked = 0;
    for (path, case) in cases() {
        // A case whose description says its alerts came from a scripted stand-in with
        // its own rule (not the helm's request) says nothing about the manager.
        if case.description.contains("stand-in") {
            continue;
        }
        let steps = &case.step;
        let Some(req) = steps.iter().find_map(request) else {
            continue;
        };
        let mut set = AlertSet::default();
        let id = set.apply(req).expect("the case's request parses");
        let var = set.get(&id).expect("alert").on_flags[0].var.clone();
        // The recorded arrivals: (time, value) of each distinct value of the flag.
        let mut recorded: Vec<(f64, String)> = Vec::new();
        for s in steps {
            for (k, v) in &s.mail {
                if *k == var {
                    let v = v.as_str().unwrap_or_default().to_string();
                    if !recorded.iter().any(|(_, r)| *r == v) {
                        recorded.push((s.time, v));
                    }
                }
            }
        }
        if recorded.is_empty() {
            continue;
        }
        let mut m = ContactManager::new("ownship", Config::default(), None);
        let mut ours: Vec<(f64, String)> = Vec::new();
        for s in steps {
            let mut mail: Vec<(&str, MailValue<'_>)> = Vec::new();
            for (k, v) in &s.mail {
                let v = match v {
                    toml::Value::Float(f) => MailValue::Num(*f),
                    toml::Value::Integer(i) => MailValue::Num(*i as f64),
                    toml::Value::String(s) => MailValue::Str(s),
                    _ => continue,
                };
                mail.push((k.as_str(), v));
            }
            if let Some(r) = request(s) {
                mail.push(("BCM_ALERT_REQUEST", MailValue::Str(r)));
            }
            m.handle_mail(s.time, &mail);
            for p in m.iterate(s.time) {
                if p.var == var {
                    let v = p.val.to_string();
                    if !ours.iter().any(|(_, o)| *o == v) {
                        ours.push((s.time, v));
                    }
                }
            }
        }
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        for (t_rec, v) in &recorded {
            let Some((t_ours, _)) = ours.iter().find(|(_, o)| o == v) else {
                panic!("{name}: ours never posted {var} = {v} (recorded at {t_rec})");
            };
            println!("{name}: {var} = {v}: ours at {t_ours}, recorded arrival at {t_rec}");
            assert!(
                t_ours < t_rec && t_rec - t_ours <= LATENCY,
                "{name}: {var} = {v}: ours at {t_ours}, recorded arrival at {t_rec}"
            );
            checked += 1;
        }
    }
    assert!(checked >= 3, "only {checked} on-flags checked");
    println!("{checked} recorded on-flags matched");
}
