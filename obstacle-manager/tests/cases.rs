//! The golden helm cases whose helm asks the obstacle manager for alerts
//! (conformance/helm: `OBM_ALERT_REQUEST` in a step's expect) and whose mail carries
//! the manager's updates on the requested variable. Our manager is given each
//! recorded obstacle (the polygon of its update), fed the case's own NAV_X/NAV_Y and
//! the helm's request, and iterated at each step; each recorded update must come from
//! ours first, with the same value, at most [`LATENCY`] before it arrived in the
//! recording (the manager ticks on its own and the bus adds a delay), and not again.

use std::path::{Path, PathBuf};

use obstacle_manager::{AlertRequest, Config, MailValue, ObstacleManager};

/// Largest delay (s) accepted between our update and the recorded arrival.
const LATENCY: f64 = 1.0;

fn cases() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../conformance/helm");
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("conformance/helm")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    v.sort();
    v
}

struct Step {
    time: f64,
    mail: Vec<(String, toml::Value)>,
    request: Option<String>,
}

fn steps(doc: &toml::Value) -> Vec<Step> {
    let mut out = Vec::new();
    for s in doc
        .get("step")
        .and_then(|s| s.as_array())
        .into_iter()
        .flatten()
    {
        let time = s.get("time").and_then(|t| t.as_float()).unwrap_or(0.0);
        let mut mail = Vec::new();
        for m in s
            .get("mail")
            .and_then(|m| m.as_array())
            .into_iter()
            .flatten()
        {
            if let Some([k, v]) = m.as_array().map(|a| a.as_slice()) {
                if let Some(k) = k.as_str() {
                    mail.push((k.to_string(), v.clone()));
                }
            }
        }
        let request = s
            .get("expect")
            .and_then(|e| e.get("OBM_ALERT_REQUEST"))
            .and_then(|r| r.as_str())
            .map(str::to_string);
        out.push(Step {
            time,
            mail,
            request,
        });
    }
    out
}

/// The polygon part of an update: `name=..#poly=<this>#id=..`.
fn poly_of(update: &str) -> Option<&str> {
    update.split('#').find_map(|p| p.strip_prefix("poly="))
}

#[test]
fn updates_agree_with_the_recorded_obstacle_manager() {
    let mut checked = 0;
    for path in cases() {
        let text = std::fs::read_to_string(&path).expect("read case");
        if !text.contains("OBM_ALERT_REQUEST") {
            continue;
        }
        let doc: toml::Value = toml::from_str(&text).expect("case toml");
        let steps = steps(&doc);
        let Some(req) = steps.iter().find_map(|s| s.request.clone()) else {
            continue;
        };
        let req = AlertRequest::parse(&req).expect("the helm's request parses");
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
        for s in &steps {
            let mut mail: Vec<(&str, MailValue<'_>)> = s
                .mail
                .iter()
                .filter(|(k, _)| k == "NAV_X" || k == "NAV_Y")
                .filter_map(|(k, v)| v.as_float().map(|f| (k.as_str(), MailValue::Num(f))))
                .collect();
            // The helm's request reaches the manager the step after it was posted.
            if requested {
                if let Some(r) = steps.iter().find_map(|s| s.request.as_deref()) {
                    mail.push(("OBM_ALERT_REQUEST", MailValue::Str(r)));
                }
                requested = false;
            }
            if s.request.is_some() {
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
