//! The decision step with BHV_OpRegion, BHV_OpRegionV24, BHV_PModelView and BHV_Convoy,
//! each loaded from its release library as the helm loads it:
//! `cargo bench -p helm-conform --bench region_behaviors`.
//!
//! µs per decision iteration (modes, behaviors, solve), as the C++ figure of each golden
//! case's `.timing-O2.json`. `opregion_breach` is the golden case itself (checked to pass
//! first; its C++ ratio is printed after criterion's report). The other three have no
//! golden case: each replays the mail of a recorded case (`opregion_breach`'s vehicle,
//! `trail_contact`'s vehicle and contact) with a `.bhv` naming the type beside a
//! BHV_Waypoint, so the figure is that behavior's share of a realistic iteration.
//!
//! Its own file rather than a group in `decision_step.rs`, whose cases need no plugin.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, Criterion};
use helm_conform::{self as conform, Case};
use helm_engine::factory::BehaviorFactory;

const PACKAGES: [&str; 3] = ["bhv-region", "bhv-visuals", "bhv-convoy"];

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

/// Release builds of the three libraries, alone in a folder.
fn library_dir() -> PathBuf {
    let tmp = Path::new(env!("CARGO_TARGET_TMPDIR"));
    let target = tmp.join("bench-plugins-target");
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let mut cmd = Command::new(cargo);
    cmd.current_dir(workspace())
        .args(["build", "--release", "--quiet"])
        .env("CARGO_TARGET_DIR", &target);
    for p in PACKAGES {
        cmd.args(["-p", p]);
    }
    assert!(
        cmd.status().expect("run cargo build").success(),
        "build failed"
    );
    let dir = tmp.join("bench-region-lib");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for p in PACKAGES {
        let name = format!("lib{}.so", p.replace('-', "_"));
        std::fs::copy(target.join("release").join(&name), dir.join(&name)).unwrap();
    }
    dir
}

/// The C++ mean (µs per decision iteration) recorded beside a case.
fn cpp_mean(case: &str) -> Option<f64> {
    let p = workspace().join(format!("conformance/helm/{case}.timing-O2.json"));
    let text = std::fs::read_to_string(p).ok()?;
    let key = "\"mean_us_per_iteration\":";
    let rest = &text[text.find(key)? + key.len()..];
    rest.split(',').next()?.trim().parse().ok()
}

const WAYPOINT: &str = "\nBehavior = BHV_Waypoint\n{\n  name = survey\n  pwt = 100\n  condition = DEPLOY = true\n  speed = 2\n  capture_radius = 4\n  points = 40,-40 : 40,0 : 90,0\n}\n";

/// (bench name, recorded case whose mail is replayed, the `.bhv` or `None` for the
/// case's own).
fn variants() -> Vec<(&'static str, &'static str, Option<String>)> {
    let v24 = "initialize DEPLOY = true\n\nBehavior = BHV_OpRegionV24\n{\n  name = opregx\n  pwt = 100\n  condition = DEPLOY = true\n  core_poly = -20,20 : 60,20 : 60,-60 : -20,-60\n  save_dist = 2\n  halt_dist = 10\n}\n";
    let pmv = "initialize DEPLOY = true\n\nBehavior = BHV_PModelView\n{\n  name = pmv\n  pwt = 100\n  condition = DEPLOY = true\n}\n";
    let convoy = "initialize DEPLOY = true\n\nBehavior = BHV_Convoy\n{\n  name = convoy\n  pwt = 100\n  condition = DEPLOY = true\n  contact = abe\n  radius = 8\n  inter_mark_range = 5\n  max_mark_range = 80\n}\n";
    vec![
        ("OpRegion/opregion_breach", "opregion_breach", None),
        (
            "OpRegionV24",
            "opregion_breach",
            Some(format!("{v24}{WAYPOINT}")),
        ),
        (
            "PModelView",
            "opregion_breach",
            Some(format!("{pmv}{WAYPOINT}")),
        ),
        ("Convoy", "trail_contact", Some(convoy.to_string())),
    ]
}

fn decision_steps(c: &mut Criterion) {
    let dir = library_dir();
    let (factory, _) = helm_mission::factory_for(std::slice::from_ref(&dir));
    for t in [
        "BHV_OpRegion",
        "BHV_OpRegionV24",
        "BHV_PModelView",
        "BHV_Convoy",
    ] {
        assert!(factory.knows(t), "{t} not loaded");
    }
    let mut group = c.benchmark_group("region_behaviors");
    group.measurement_time(Duration::from_secs(3));
    group.warm_up_time(Duration::from_secs(1));
    let mut summary = Vec::new();
    for (name, base, bhv) in variants() {
        let file = workspace().join(format!("conformance/helm/{base}.toml"));
        let mut case: Case = conform::load(&file).expect("case");
        let golden = bhv.is_none();
        if let Some(b) = bhv {
            case.bhv = b;
        }
        let mut helm = conform::build_helm(&case, &file, &factory).expect("helm builds");
        let mismatches = conform::replay(&case, &mut helm, golden);
        assert!(!golden || mismatches.is_empty(), "{name}: {mismatches:?}");
        let run = |factory: &BehaviorFactory| {
            let mut helm = conform::build_helm(&case, &file, factory).expect("helm builds");
            conform::replay(&case, &mut helm, false);
            helm.decision_timing()
        };
        group.bench_function(name, |b| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                let mut done = 0u64;
                while done < iters {
                    let (t, n) = run(&factory);
                    let n = n.max(1);
                    let take = n.min(iters - done);
                    total += t.mul_f64(take as f64 / n as f64);
                    done += take;
                }
                total
            })
        });
        // A plain mean over 2 s for the summary line.
        let (mut t, mut n) = (Duration::ZERO, 0u64);
        let t0 = Instant::now();
        while t0.elapsed() < Duration::from_secs(2) {
            let (dt, dn) = run(&factory);
            t += dt;
            n += dn;
        }
        let ours = t.as_secs_f64() * 1e6 / n.max(1) as f64;
        let cpp = if golden { cpp_mean(base) } else { None };
        summary.push(match cpp {
            Some(cpp) => format!(
                "{name}: {ours:.2} µs per decision iteration; C++ {cpp:.2} µs; ratio {:.3}",
                ours / cpp
            ),
            None => format!("{name}: {ours:.2} µs per decision iteration ({base}'s mail)"),
        });
    }
    group.finish();
    for line in summary {
        println!("{line}");
    }
}

criterion_group!(benches, decision_steps);
criterion_main!(benches);
