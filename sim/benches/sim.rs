//! `helm sim` speed: one whole simulated alpha mission (≈285 s of MOOS time, 1136 helm
//! iterations, 2843 simulator steps), the mission read once; with and without the
//! `.alog`. Target: under 0.1 s wall on one core.
//!
//!     cargo bench -p helm-sim --bench sim

use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion};
use helm_sim::{Prepared, RunOptions, StartShift};

fn alpha() -> Prepared {
    let m = Path::new(env!("CARGO_MANIFEST_DIR")).join("../missions/alpha");
    Prepared::load(&m, &[], None).expect("alpha loads")
}

fn bench(c: &mut Criterion) {
    let prep = alpha();
    let mut g = c.benchmark_group("sim");
    g.sample_size(20);
    g.bench_function("alpha_whole_mission", |b| {
        b.iter(|| {
            let o = prep
                .run(StartShift::default(), &RunOptions::default())
                .expect("runs");
            assert_eq!(o.end_reason, "mission-over");
            o.iterations
        })
    });
    let dir = std::env::temp_dir().join(format!("helm-sim-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let alog = dir.join("alpha.alog");
    g.bench_function("alpha_whole_mission_with_alog", |b| {
        b.iter(|| {
            prep.run(
                StartShift::default(),
                &RunOptions {
                    alog: Some(alog.clone()),
                    ..RunOptions::default()
                },
            )
            .expect("runs")
            .iterations
        })
    });
    g.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, bench);
criterion_main!(benches);
