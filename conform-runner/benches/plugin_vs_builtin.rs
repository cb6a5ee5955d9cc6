//! The same behavior called built-in and through a loaded library:
//! `cargo bench -p helm-conform --bench plugin_vs_builtin`.
//!
//! The case is `conformance/helm/plugin_constant_speed.toml` (a BHV_Waypoint and a
//! BHV_ConstantSpeed, 400 iterations). `builtin` runs it as recorded: BHV_Waypoint is the
//! helm's own (behaviors-std, compiled in). `library` runs it with the waypoint block's type
//! renamed `BHV_WaypointLib`: the very same `behaviors_std::BhvWaypoint` code, served from
//! `libbhv_test_failure.so` through the stable ABI. BHV_ConstantSpeed comes from its
//! library in both. Both variants must still reproduce the golden case exactly.
//!
//! The measure is µs per decision iteration (modes, behaviors, solve), as in
//! `helm_iteration`. After criterion's report, an interleaved A/B run prints both means
//! and the ratio (goal: library at most 2% slower).

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, Criterion};
use helm_conform::{self as conform, Case};
use helm_engine::factory::BehaviorFactory;

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

/// Release builds of the two libraries, alone in a folder.
fn library_dir() -> PathBuf {
    let tmp = Path::new(env!("CARGO_TARGET_TMPDIR"));
    let target = tmp.join("bench-plugins-target");
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let status = Command::new(cargo)
        .current_dir(workspace())
        .args(["build", "--release", "--quiet"])
        .args(["-p", "bhv-constant-speed", "-p", "bhv-test-failure"])
        .env("CARGO_TARGET_DIR", &target)
        .status()
        .expect("run cargo build");
    assert!(status.success(), "building the bench libraries failed");
    let dir = tmp.join("bench-plugins-lib");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for name in ["libbhv_constant_speed.so", "libbhv_test_failure.so"] {
        std::fs::copy(target.join("release").join(name), dir.join(name)).unwrap();
    }
    dir
}

struct Variant {
    name: &'static str,
    case: Case,
}

fn variants(file: &Path, factory: &BehaviorFactory) -> Vec<Variant> {
    let builtin = conform::load(file).expect("case");
    let mut library = conform::load(file).expect("case");
    let renamed = library
        .bhv
        .replace("Behavior = BHV_Waypoint\n", "Behavior = BHV_WaypointLib\n");
    assert_ne!(renamed, library.bhv, "the case has no BHV_Waypoint block");
    library.bhv = renamed;
    let out = vec![
        Variant {
            name: "builtin",
            case: builtin,
        },
        Variant {
            name: "library",
            case: library,
        },
    ];
    for v in &out {
        let mut helm = conform::build_helm(&v.case, file, factory).expect("helm builds");
        let mismatches = conform::replay(&v.case, &mut helm, true);
        assert!(
            mismatches.is_empty(),
            "{}: {} mismatches, first {:?}",
            v.name,
            mismatches.len(),
            mismatches.first()
        );
    }
    out
}

/// One replay through a fresh helm: (decision time, decisions).
fn run_once(v: &Variant, file: &Path, factory: &BehaviorFactory) -> (Duration, u64) {
    let mut helm = conform::build_helm(&v.case, file, factory).expect("helm builds");
    conform::replay(&v.case, &mut helm, false);
    helm.decision_timing()
}

fn plugin_vs_builtin(c: &mut Criterion) {
    let file = workspace().join("conformance/helm/plugin_constant_speed.toml");
    let dir = library_dir();
    let (factory, _) = helm_mission::factory_for(std::slice::from_ref(&dir));
    assert!(factory.knows("BHV_WaypointLib") && factory.knows("BHV_ConstantSpeed"));
    let variants = variants(&file, &factory);

    // PLUGIN_BENCH_REVERSE=1 measures `library` first (to see an order effect).
    let mut order: Vec<&Variant> = variants.iter().collect();
    if std::env::var_os("PLUGIN_BENCH_REVERSE").is_some() {
        order.reverse();
    }
    let mut group = c.benchmark_group("plugin_vs_builtin");
    group.measurement_time(Duration::from_secs(5));
    group.warm_up_time(Duration::from_secs(1));
    for v in order {
        group.bench_function(v.name, |b| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                let mut done = 0u64;
                while done < iters {
                    let (t, n) = run_once(v, &file, &factory);
                    let n = n.max(1);
                    let take = n.min(iters - done);
                    total += t.mul_f64(take as f64 / n as f64);
                    done += take;
                }
                total
            })
        });
    }
    group.finish();

    // Interleaved A/B: alternate the variants so drift and noise hit both alike.
    let secs: f64 = std::env::var("PLUGIN_BENCH_SECS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(10.0);
    let mut sums = [(Duration::ZERO, 0u64); 2];
    let wall = Instant::now();
    while wall.elapsed().as_secs_f64() < secs {
        for (k, v) in variants.iter().enumerate() {
            let (t, n) = run_once(v, &file, &factory);
            sums[k].0 += t;
            sums[k].1 += n;
        }
    }
    let us = |k: usize| sums[k].0.as_secs_f64() / sums[k].1.max(1) as f64 * 1e6;
    let (b, l) = (us(0), us(1));
    println!(
        "plugin_vs_builtin interleaved ({} decisions each): builtin {b:.2} µs, \
         library {l:.2} µs per decision iteration; library/builtin = {:.4} ({:+.2}%)",
        sums[0].1,
        l / b,
        (l / b - 1.0) * 100.0
    );
}

criterion_group!(benches, plugin_vs_builtin);
criterion_main!(benches);
