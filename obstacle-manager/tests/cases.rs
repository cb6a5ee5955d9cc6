//! The golden helm cases whose helm asks the obstacle manager for alerts
//! (conformance/helm: `OBM_ALERT_REQUEST` in a step's expect) and whose mail carries
//! the manager's updates on the requested variable. Our manager is given each
//! recorded obstacle (the polygon of its update), fed the case's own NAV_X/NAV_Y and
//! the helm's request, and iterated at each step; each recorded update must come from
//! ours first, with the same value, at most [`LATENCY`] before it arrived in the
//! recording (the manager ticks on its own and the bus adds a delay), and not again.

use std::path::{Path, PathBuf};

use helm_conform::{Case, Step};

use obstacle_manager::{AlertRequest, Config, MailValue, ObstacleManager};

/// Largest delay (s) accepted between our update and the recorded arrival.
const LATENCY: f64 = 1.0;

/// The golden helm cases (read by the conformance runner's own reader).
fn cases() -> Vec<(PathBuf, Case)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../conformance/helm");
    helm_conform::load_all(&[dir]).expect("the golden cases in conformance/helm")
}

/// The helm's request posted at step `s`, if any.
fn request(s: &Step) -> Option<&str> {
    s.expect.get("OBM_ALERT_REQUEST").and_then(|r| r.as_str())
}

/// The polygon part of an update: `name=..#poly=<this>#id=..`.
fn poly_of(update: &str) -> Option<&str> {
    update.split('#').find_map(|p| p.strip_prefix("poly="))
}

#[test]
fn updates_agree_with_the_recorded_obstacle_manager() {
    let mut checked = 0;
    for (path, case) in cases() {
        let steps = &case.step;
        let Some(req) = steps.iter().find_map(request) else {
            continue;
        };
        let req = AlertRequest::parse(req).expect("the helm's request parses");
        // The recorded updates, with their arrival times.
        let recorded: Vec<(f64, String)> = steps
            .iter()
            .flat_map(|s| {
                s.mail
                    .iter()
                    .filter(|(k, _)| *k == req.update_var)
                    .filter_map(|(_, v)| v.as_str().map(|v| (s.time, v.to_string())))
            })
            .collect();
        if recorded.is_empty() {
            continue;
        }
        let mut cfg = Config::default();
        for (_, u) in &recorded {
            let poly = poly_of(u).expect("update has a polygon");
            cfg.set("given_obstacle", poly).expect("recorded polygon");
        }
        let mut m = ObstacleManager::new(cfg, steps[0].time);
        let mut ours: Vec<(f64, String)> = Vec::new();
        let mut requested = false;
        for s in steps {
            let mut mail: Vec<(&str, MailValue<'_>)> = s
                .mail
                .iter()
                .filter(|(k, _)| k == "NAV_X" || k == "NAV_Y")
                .filter_map(|(k, v)| v.as_float().map(|f| (k.as_str(), MailValue::Num(f))))
                .collect();
            // The helm's request reaches the manager the step after it was posted.
            if requested {
                if let Some(r) = steps.iter().find_map(request) {
                    mail.push(("OBM_ALERT_REQUEST", MailValue::Str(r)));
                }
                requested = false;
            }
            if request(s).is_some() {
                requested = true;
            }
            m.handle_mail(s.time, &mail);
            for p in m.iterate(s.time) {
                if p.var == req.update_var {
                    ours.push((s.time, p.val.to_string()));
                }
            }
        }
        let name = path.display();
        for (t, val) in &recorded {
            let first = ours
                .iter()
                .find(|(_, v)| v == val)
                .unwrap_or_else(|| panic!("{name}: ours never posted {val}: {ours:?}"));
            assert!(
                first.0 < *t && *t - first.0 <= LATENCY,
                "{name}: ours at {}, recorded arrival at {t}",
                first.0
            );
            println!("{name}: {val}: ours at {}, recorded at {t}", first.0);
            checked += 1;
        }
        assert_eq!(ours.len(), recorded.len(), "{name}: {ours:?}");
    }
    assert!(checked >= 1, "no case checked");
    println!("{checked} recorded obstacle updates matched");
}
