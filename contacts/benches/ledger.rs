//! `cargo bench -p contacts`: the ledger's per-iteration work with 10 and 50 contacts.
//!
//! * `maintain/N`: stale check, snapshot rebuild, `IVPHELM_LEDGER_SUMMARY` and
//!   `IVPHELM_CONTACT_SUMMARY` — what the helm does every iteration;
//! * `batch/N`: one report per contact ingested first (every contact reporting in the
//!   same iteration, the worst case at 4 Hz with 1 Hz reports), then the above;
//! * `engine/N`: a CPA engine reset per contact plus one CPA — what each contact
//!   behavior adds per iteration before building its function.

use std::hint::black_box;

use contacts::{CpaEngine, Ledger};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};

fn reports(n: usize, t: f64) -> Vec<String> {
    (0..n)
        .map(|i| {
            let k = i as f64;
            format!(
                "NAME=c{i:02},X={},Y={},SPD=1.8,HDG={},DEP=0,LAT=43.8263968,LON=-70.32899417,\
                 TYPE=kayak,COLOR=yellow,MODE=DRIVE,ALLSTOP=clear,INDEX=1,YAW=-3.14,TIME={t},LENGTH=4",
                100.0 + k,
                -50.0 + 3.0 * k,
                (k * 7.0) % 360.0
            )
        })
        .collect()
}

fn ledger_with(n: usize) -> (Ledger, Vec<String>, Vec<String>) {
    let mut l = Ledger::new(Some((43.8253, -70.3304)));
    let r = reports(n, 1000.0);
    for s in &r {
        l.ingest(s, 1000.0).expect("bench report");
    }
    l.maintain(1000.0);
    let keep: Vec<String> = (0..n).step_by(2).map(|i| format!("c{i:02}")).collect();
    (l, r, keep)
}

fn bench(c: &mut Criterion) {
    for n in [10usize, 50] {
        let (mut l, r, keep) = ledger_with(n);
        c.bench_with_input(BenchmarkId::new("maintain", n), &n, |b, _| {
            b.iter(|| {
                l.maintain(black_box(1000.25));
                let k = l
                    .contact_summary(keep.iter().map(String::as_str))
                    .map_or(0, str::len);
                black_box((l.summary().len(), k))
            })
        });
        c.bench_with_input(BenchmarkId::new("batch", n), &n, |b, _| {
            b.iter(|| {
                for s in &r {
                    let _ = black_box(l.ingest(s, 1000.25).is_ok());
                }
                l.maintain(black_box(1000.25));
                let k = l
                    .contact_summary(keep.iter().map(String::as_str))
                    .map_or(0, str::len);
                black_box((l.summary().len(), k))
            })
        });
        c.bench_with_input(BenchmarkId::new("engine", n), &n, |b, _| {
            b.iter(|| {
                let mut sum = 0.0;
                for ct in l.snapshot().contacts() {
                    let e = CpaEngine::new(ct.x, ct.y, ct.hdg, ct.spd, 0.0, 0.0);
                    sum += e.cpa(black_box(45.0), 2.0, 120.0);
                }
                black_box(sum)
            })
        });
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
