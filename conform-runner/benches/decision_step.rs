//! µs per decision iteration for each golden helm case (the measure of the C++ timings
//! in each case's `.timing.json`): `cargo bench -p helm-conform --bench decision_step`.
//!
//! Each sample replays the case through a fresh helm and counts only the decision steps
//! (modes, behaviors, solve), as the C++ figure does.

use std::path::PathBuf;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use helm_conform as conform;
use helm_engine::factory::BehaviorFactory;

fn cases() -> Vec<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../conformance/helm");
    conform::collect(&[dir]).unwrap_or_default()
}

fn helm_cases(c: &mut Criterion) {
    let factory = BehaviorFactory::with_builtins();
    let mut group = c.benchmark_group("decision_iteration");
    group.measurement_time(Duration::from_secs(3));
    group.warm_up_time(Duration::from_secs(1));
    for file in cases() {
        let Ok(case) = conform::load(&file) else {
            continue;
        };
        // Cases needing plugin behaviors are measured by `helm conform --bench` with
        // IVP_BEHAVIOR_DIRS set.
        if conform::build_helm(&case, &file, &factory).is_err() {
            continue;
        }
        group.bench_function(&case.name, |b| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                let mut done = 0u64;
                while done < iters {
                    let Ok(mut helm) = conform::build_helm(&case, &file, &factory) else {
                        break;
                    };
                    conform::replay(&case, &mut helm, false);
                    let (t, n) = helm.decision_timing();
                    let n = n.min(iters - done);
                    total += t.mul_f64(n as f64 / helm.decision_timing().1.max(1) as f64);
                    done += n.max(1);
                }
                total
            })
        });
    }
    group.finish();
}

criterion_group!(benches, helm_cases);
criterion_main!(benches);
