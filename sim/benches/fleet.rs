//! `helm sim` fleet speed: ten vehicles (missions/fleet's eight, four loitering and four
//! in transit, and two more loiterers) each with AvoidCollision spawned per contact,
//! ten simulated minutes (a sixth of the hour of issue 23, so that criterion's ten
//! samples fit in a few minutes; the run is in steady state after the first minute), no
//! `.alog`, on one core. Target: 500x real time, i.e. under 1.2 s per iteration. Needs
//! the contact plugin beside the workspace's release build:
//!
//!     cargo build --release -p bhv-contact
//!     cargo bench -p helm-sim --bench fleet

use std::path::{Path, PathBuf};

use criterion::{criterion_group, criterion_main, Criterion};
use helm_sim::fleet::{FleetOptions, FleetPlan};

/// missions/fleet with two more vehicles and ten minutes to run, in a temp folder.
fn ten_vehicles() -> PathBuf {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("../missions/fleet");
    let dir = std::env::temp_dir().join(format!("helm-sim-fleet-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    for e in std::fs::read_dir(&src).expect("missions/fleet") {
        let p = e.expect("entry").path();
        std::fs::copy(&p, dir.join(p.file_name().expect("name"))).expect("copy");
    }
    let text = std::fs::read_to_string(dir.join("scenario.toml"))
        .expect("scenario")
        .replace("max_time = 240", "max_time = 600")
        + "\n[[vehicle]]\nname = \"lia2\"\nmission = \"fleet.moos\"\nbhv = [\"lia.bhv\"]\nx = -100\ny = 0\nheading = 0\n\
           \n[[vehicle]]\nname = \"lou2\"\nmission = \"fleet.moos\"\nbhv = [\"lou.bhv\"]\nx = 40\ny = 0\nheading = 180\n";
    std::fs::write(dir.join("scenario.toml"), text).expect("write scenario");
    dir
}

fn bench(c: &mut Criterion) {
    if std::env::var_os("IVP_BEHAVIOR_DIRS").is_none() {
        let built = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/release");
        std::env::set_var("IVP_BEHAVIOR_DIRS", built);
    }
    let dir = ten_vehicles();
    let plan = FleetPlan::load(&dir.join("scenario.toml"))
        .expect("the fleet loads (cargo build --release -p bhv-contact first)");
    assert_eq!(plan.vehicles.len(), 10);
    let mut g = c.benchmark_group("fleet");
    g.sample_size(10);
    g.bench_function("ten_vehicles_ten_minutes", |b| {
        b.iter(|| {
            let o = plan.run(&[], &FleetOptions::default()).expect("runs");
            assert_eq!(o.end_reason, "max-time");
            o.vehicles.iter().map(|v| v.observer.spawns).sum::<u64>()
        })
    });
    g.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, bench);
criterion_main!(benches);
