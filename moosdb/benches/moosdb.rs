//! `cargo bench -p moosdb`: codec cost per message (criterion), then the DB's delivered
//! notifications per second and p50/p99 latency with 4 publishers and 4 subscribers over
//! loopback (bounded in time, printed).

use std::hint::black_box;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use criterion::{criterion_group, Criterion};
use moos::client::{Client, ClientConfig};
use moos::wire::{self, Message, MsgView};
use moosdb::{Db, DbConfig};

fn codec(c: &mut Criterion) {
    let mut d = Message::notify_double("NAV_X", 12.5, 1700000000.25);
    d.source = "uSimMarine".into();
    d.community = "alpha".into();
    let mut s = Message::notify_string("IVPHELM_STATE", "DRIVE", 1700000000.25);
    s.source = "pHelmIvP".into();
    let mut buf = Vec::with_capacity(256);
    c.bench_function("encode_notify_double", |b| {
        b.iter(|| {
            buf.clear();
            black_box(&d).encode_into(&mut buf).expect("encode");
        })
    });
    let enc = d.encode().expect("encode");
    c.bench_function("decode_notify_double", |b| {
        b.iter(|| Message::decode(black_box(&enc)).expect("decode"))
    });
    let enc_s = s.encode().expect("encode");
    c.bench_function("decode_notify_string", |b| {
        b.iter(|| Message::decode(black_box(&enc_s)).expect("decode"))
    });
    // The DB's path: decoded in place, no allocation.
    c.bench_function("decode_view_notify_double", |b| {
        b.iter(|| MsgView::parse(black_box(&enc)).expect("decode"))
    });
    let batch: Vec<Message> = (0..100).map(|_| d.clone()).collect();
    let mut pkt = Vec::new();
    wire::encode_packet(&batch, &mut pkt).expect("encode");
    c.bench_function("decode_packet_100_msgs", |b| {
        b.iter(|| wire::decode_packet(black_box(&pkt), 1 << 24).expect("decode"))
    });
    let mut views = Vec::with_capacity(100);
    c.bench_function("decode_packet_views_100_msgs", |b| {
        b.iter(|| {
            views.clear();
            wire::decode_packet_views(black_box(&pkt), 1 << 24, &mut views).expect("decode")
        })
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1))
        .sample_size(20);
    targets = codec
}

fn cfg(port: u16, name: &str) -> ClientConfig {
    ClientConfig::new("127.0.0.1", port, name)
}

/// Subscribers that count what they receive (and record latencies from dval = send wall time).
fn subscribers(
    port: u16,
    n: usize,
    stop: &Arc<AtomicBool>,
    count: &Arc<AtomicU64>,
    lat: bool,
) -> Vec<std::thread::JoinHandle<Vec<f64>>> {
    (0..n)
        .map(|i| {
            let c = Client::connect(cfg(port, &format!("sub{i}"))).expect("sub");
            for p in 0..4 {
                c.register(&format!("P{p}"), 0.0).expect("register");
            }
            let (stop, count) = (stop.clone(), count.clone());
            std::thread::spawn(move || {
                let mut mail = Vec::new();
                let mut lats = Vec::new();
                while !stop.load(Ordering::Relaxed) {
                    c.wait_for_mail(Duration::from_millis(20));
                    mail.clear();
                    c.fetch(&mut mail);
                    if lat {
                        let now = moos::time::wall_time();
                        lats.extend(mail.iter().map(|m| (now - m.dval) * 1e6));
                    }
                    count.fetch_add(mail.len() as u64, Ordering::Relaxed);
                }
                lats
            })
        })
        .collect()
}

/// CPU seconds used so far by this process's live threads whose name starts with
/// `prefix` (Linux only; 0 elsewhere). Used to report the DB's own CPU per delivery,
/// which is far less noisy than the rate on a shared machine.
fn thread_cpu(prefix: &str) -> f64 {
    let (u, s) = thread_cpu_split(prefix);
    u + s
}

/// [`thread_cpu`] as (user, system) seconds.
fn thread_cpu_split(prefix: &str) -> (f64, f64) {
    let Ok(dir) = std::fs::read_dir("/proc/self/task") else {
        return (0.0, 0.0);
    };
    let tick = 100.0; // USER_HZ
    let (mut user, mut sys) = (0.0, 0.0);
    for e in dir.flatten() {
        let p = e.path();
        let name = std::fs::read_to_string(p.join("comm")).unwrap_or_default();
        if !name.starts_with(prefix) {
            continue;
        }
        let stat = std::fs::read_to_string(p.join("stat")).unwrap_or_default();
        // Fields after the ")" that closes the name: state is field 3, utime 14, stime 15.
        let Some(rest) = stat.rsplit_once(')').map(|(_, r)| r) else {
            continue;
        };
        let f: Vec<&str> = rest.split_whitespace().collect();
        let ut: f64 = f.get(11).and_then(|v| v.parse().ok()).unwrap_or(0.0);
        let st: f64 = f.get(12).and_then(|v| v.parse().ok()).unwrap_or(0.0);
        user += ut / tick;
        sys += st / tick;
    }
    (user, sys)
}

/// Delivered/s, then CPU ns per delivery: DB user, DB system, whole process.
fn throughput(port: u16, secs: f64) -> (f64, f64, f64, f64) {
    let stop = Arc::new(AtomicBool::new(false));
    let count = Arc::new(AtomicU64::new(0));
    let subs = subscribers(port, 4, &stop, &count, false);
    std::thread::sleep(Duration::from_millis(300));
    let published = Arc::new(AtomicU64::new(0));
    let pubs: Vec<_> = (0..4)
        .map(|p| {
            let c = Client::connect(cfg(port, &format!("pub{p}"))).expect("pub");
            let (stop, count, published) = (stop.clone(), count.clone(), published.clone());
            std::thread::spawn(move || {
                let var = format!("P{p}");
                while !stop.load(Ordering::Relaxed) {
                    // Flow control: keep at most ~200k deliveries outstanding.
                    if published.load(Ordering::Relaxed) * 4
                        > count.load(Ordering::Relaxed) + 200_000
                    {
                        std::thread::sleep(Duration::from_micros(200));
                        continue;
                    }
                    for i in 0..500 {
                        let _ = c.notify_double(&var, i as f64, Some(0.0));
                    }
                    published.fetch_add(500, Ordering::Relaxed);
                }
            })
        })
        .collect();
    std::thread::sleep(Duration::from_millis(500));
    let c0 = count.load(Ordering::Relaxed);
    let (db0, all0) = (thread_cpu_split("moosdb-"), thread_cpu(""));
    let t0 = Instant::now();
    std::thread::sleep(Duration::from_secs_f64(secs));
    let c1 = count.load(Ordering::Relaxed);
    let (db1, all1) = (thread_cpu_split("moosdb-"), thread_cpu(""));
    let n = (c1 - c0) as f64;
    let rate = n / t0.elapsed().as_secs_f64();
    stop.store(true, Ordering::Relaxed);
    for h in pubs {
        let _ = h.join();
    }
    for h in subs {
        let _ = h.join();
    }
    let ns = |a: f64, b: f64| (b - a) / n * 1e9;
    (rate, ns(db0.0, db1.0), ns(db0.1, db1.1), ns(all0, all1))
}

fn latency(port: u16, secs: f64) -> (f64, f64, usize) {
    let stop = Arc::new(AtomicBool::new(false));
    let count = Arc::new(AtomicU64::new(0));
    let subs = subscribers(port, 4, &stop, &count, true);
    std::thread::sleep(Duration::from_millis(300));
    let pstop = Arc::new(AtomicBool::new(false));
    let pubs: Vec<_> = (0..4)
        .map(|p| {
            let c = Client::connect(cfg(port, &format!("lpub{p}"))).expect("pub");
            let pstop = pstop.clone();
            std::thread::spawn(move || {
                let var = format!("P{p}");
                let mut next = Instant::now();
                while !pstop.load(Ordering::Relaxed) {
                    let _ = c.notify_double(&var, moos::time::wall_time(), None);
                    next += Duration::from_millis(10); // 100 Hz
                    if let Some(d) = next.checked_duration_since(Instant::now()) {
                        std::thread::sleep(d);
                    }
                }
            })
        })
        .collect();
    std::thread::sleep(Duration::from_secs_f64(secs));
    pstop.store(true, Ordering::Relaxed);
    for h in pubs {
        let _ = h.join();
    }
    std::thread::sleep(Duration::from_millis(200));
    stop.store(true, Ordering::Relaxed);
    let mut all: Vec<f64> = subs
        .into_iter()
        .flat_map(|h| h.join().unwrap_or_default())
        .collect();
    all.sort_by(f64::total_cmp);
    let pct = |q: f64| {
        all.get(((all.len() as f64 - 1.0) * q) as usize)
            .copied()
            .unwrap_or(f64::NAN)
    };
    (pct(0.5), pct(0.99), all.len())
}

fn db_bench() {
    let secs: f64 = std::env::var("MOOS_BENCH_SECS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3.0);
    let db = Db::start(DbConfig {
        port: 0,
        max_queue_bytes: 512 * 1024 * 1024,
        ..DbConfig::default()
    })
    .expect("db");
    let (rate, db_user, db_sys, all_ns) = throughput(db.port(), secs);
    println!(
        "db_throughput/4pub_4sub: {:.3} M delivered notifications/s ({secs} s); \
         CPU per delivery: DB threads {:.0} ns (user {db_user:.0}, sys {db_sys:.0}), \
         whole process {all_ns:.0} ns",
        rate / 1e6,
        db_user + db_sys
    );
    drop(db);
    let db = Db::start(DbConfig {
        port: 0,
        ..DbConfig::default()
    })
    .expect("db");
    let (p50, p99, n) = latency(db.port(), secs);
    println!("db_latency/4pub_4sub_100Hz: p50 {p50:.0} us, p99 {p99:.0} us ({n} samples)");
}

fn main() {
    benches();
    Criterion::default().configure_from_args().final_summary();
    // Skip the DB part when cargo runs benches as tests (`cargo test --benches`).
    if !std::env::args().any(|a| a == "--test" || a == "--list") {
        db_bench();
    }
}
