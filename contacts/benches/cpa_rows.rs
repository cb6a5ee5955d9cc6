//! `cargo bench -p contacts --bench cpa_rows`: the CPA rows of an avoidance function's
//! grid (every second course, 21 speeds from 0 to 4 m/s, an 8/25 m utility taken in the
//! row), for contacts 20 to 50 m off at several bearings and courses: the kernel that
//! takes most of a fleet's time. `plain` is the row of distances, `metric` the row with
//! the utility, `flat` the same with the utility's flat ends given.

use std::hint::black_box;

use contacts::engine::AvoidRamp;
use contacts::CpaEngine;
use criterion::{criterion_group, criterion_main, Criterion};

fn engines() -> Vec<CpaEngine> {
    let mut out = Vec::new();
    for (k, range) in [20.0, 35.0, 50.0].into_iter().enumerate() {
        for b in 0..8 {
            let a = f64::from(b * 45 + 10 * k as i32).to_radians();
            let (x, y) = (range * a.sin(), range * a.cos());
            let cn_hdg = f64::from((b * 77) % 360);
            out.push(CpaEngine::new(x, y, cn_hdg, 1.5, 0.0, 0.0));
        }
    }
    out
}

fn bench(c: &mut Criterion) {
    let es = engines();
    let (sins, coss): (Vec<f64>, Vec<f64>) = (0..180)
        .map(|h| f64::from(2 * h).to_radians().sin_cos())
        .unzip();
    let speeds: Vec<f64> = (0..21).map(|j| 0.2 * f64::from(j)).collect();
    let mut row = vec![0.0; sins.len()];
    // AvoidCollision's 8/25 m utility.
    let ramp = AvoidRamp { cd: 8.0, acd: 25.0 };
    let metric = move |d: f64| ramp.at(d);
    let mut g = c.benchmark_group("cpa_rows");
    g.bench_function("plain", |b| {
        b.iter(|| {
            for e in &es {
                for &v in &speeds {
                    e.cpa_dists((&sins, &coss), v, 60.0, &mut row);
                    black_box(&row);
                }
            }
        })
    });
    g.bench_function("metric", |b| {
        b.iter(|| {
            for e in &es {
                for &v in &speeds {
                    e.cpa_dists_map((&sins, &coss), (v, 60.0), &mut row, metric);
                    black_box(&row);
                }
            }
        })
    });
    let flat = ramp.flat_ends();
    g.bench_function("flat", |b| {
        b.iter(|| {
            for e in &es {
                for &v in &speeds {
                    e.cpa_dists_flat((&sins, &coss), (v, 60.0), &mut row, metric, flat);
                    black_box(&row);
                }
            }
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
