//! The golden contact cases (conformance/helm), replayed through the ledger alone:
//! every `NODE_REPORT` of a step is ingested at the step's time, then the ledger is
//! maintained, and its `IVPHELM_LEDGER_SUMMARY` must equal what the real helm posted at
//! that step. Also checks the geodesy against the reports' LAT/LON (pNodeReporter
//! converts its X/Y with the mission's origin, LatOrigin 43.8253, LongOrigin -70.3304).

use std::path::{Path, PathBuf};

use contacts::{Geodesy, Ledger, NodeReport};

const ORIGIN: (f64, f64) = (43.8253, -70.3304);

struct Step {
    time: f64,
    reports: Vec<String>,
    summary: Option<String>,
}

fn cases() -> Vec<(String, Vec<Step>)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../conformance/helm");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("conformance/helm")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    let mut out = Vec::new();
    for f in files {
        let text = std::fs::read_to_string(&f).expect("case file");
        let doc: toml::Table = text.parse().expect("case toml");
        let steps = doc
            .get("step")
            .and_then(|s| s.as_array())
            .expect("steps")
            .iter()
            .map(|s| {
                let time = s["time"].as_float().expect("time");
                let reports = s
                    .get("mail")
                    .and_then(|m| m.as_array())
                    .into_iter()
                    .flatten()
                    .filter_map(|m| {
                        let m = m.as_array()?;
                        (m[0].as_str()? == "NODE_REPORT")
                            .then(|| m[1].as_str().map(String::from))?
                    })
                    .collect();
                let summary = s
                    .get("expect")
                    .and_then(|e| e.get("IVPHELM_LEDGER_SUMMARY"))
                    .and_then(|v| v.as_str())
                    .map(String::from);
                Step {
                    time,
                    reports,
                    summary,
                }
            })
            .collect::<Vec<_>>();
        if steps.iter().any(|s| !s.reports.is_empty()) {
            let name = f.file_stem().unwrap().to_string_lossy().into_owned();
            out.push((name, steps));
        }
    }
    out
}

#[test]
fn ledger_summary_matches_every_step_of_every_contact_case() {
    let cases = cases();
    assert!(cases.len() >= 6, "contact cases missing: {}", cases.len());
    let mut compared = 0;
    for (name, steps) in &cases {
        let mut ledger = Ledger::new(Some(ORIGIN));
        for (i, step) in steps.iter().enumerate() {
            for r in &step.reports {
                if let Err(e) = ledger.ingest(r, step.time) {
                    panic!("{name} step {i}: {r}: {e}");
                }
            }
            ledger.maintain(step.time);
            if let Some(want) = &step.summary {
                assert_eq!(
                    ledger.summary(),
                    want,
                    "{name} step {i} (time {})",
                    step.time
                );
                compared += 1;
            }
        }
    }
    println!(
        "{} cases, {compared} ledger summaries compared",
        cases.len()
    );
    assert!(compared > 1000);
}

#[test]
fn lat_lon_of_the_reports_convert_to_their_x_y() {
    let g = Geodesy::new(ORIGIN.0, ORIGIN.1);
    let (mut n, mut worst, mut worst_inv) = (0, 0.0f64, 0.0f64);
    for (_, steps) in cases() {
        for r in steps.iter().flat_map(|s| &s.reports) {
            let p = NodeReport::parse(r);
            let (x, y, lat, lon) = (p.x.unwrap(), p.y.unwrap(), p.lat.unwrap(), p.lon.unwrap());
            let (cx, cy) = g.to_local(lat, lon);
            worst = worst.max((cx - x).abs()).max((cy - y).abs());
            let (ilat, ilon) = g.to_latlon(x, y);
            worst_inv = worst_inv.max((ilat - lat).abs()).max((ilon - lon).abs());
            n += 1;
        }
    }
    println!("{n} reports: worst x/y error {worst:.4} m, worst lat/lon error {worst_inv:e} deg");
    assert!(n > 1000);
    // LAT is printed with 7 decimals (1.1 cm of latitude); pNodeReporter's own inverse
    // stops within a couple of centimetres.
    assert!(worst < 0.025, "{worst}");
    assert!(worst_inv < 3e-7, "{worst_inv}");
}
