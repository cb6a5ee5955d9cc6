//! Unit tests of `outbox` (flow control, stalls, holds).
use super::*;
use std::net::TcpListener;

const MARKS: Marks = Marks {
    high: 1000,
    low: 500,
    total_cap: 1_000_000,
    stalled_cap: 500_000,
};

fn gates(n: usize) -> Vec<Arc<Gate>> {
    (0..n).map(|_| Arc::new(Gate::new())).collect()
}

/// Add `n` bytes from `from` to the queue, as a push does.
fn add(q: &mut OutQ, from: &Arc<Gate>, n: usize) {
    q.buf.extend(std::iter::repeat_n(0u8, n));
    q.account(from, n, MARKS.high);
}

#[test]
fn only_the_heavy_contributor_is_held_back() {
    let g = gates(2);
    let (flood, helm) = (&g[0], &g[1]);
    let mut q = OutQ::new();
    let total = AtomicUsize::new(0);
    for _ in 0..19 {
        add(&mut q, flood, 50);
        q.regulate(MARKS, &total);
    }
    add(&mut q, helm, 10);
    q.regulate(MARKS, &total);
    assert!(
        flood.is_open() && helm.is_open(),
        "below the high-water mark"
    );
    add(&mut q, flood, 50);
    q.regulate(MARKS, &total);
    assert!(!flood.is_open(), "the flooder fills the queue");
    assert!(helm.is_open(), "a light publisher goes on");
    // It drains: still above the low-water mark, then below it.
    q.buf.truncate(600);
    q.release_if_drained();
    assert!(!flood.is_open());
    q.buf.truncate(499);
    q.release_if_drained();
    assert!(flood.is_open());
}

#[test]
fn equal_heavy_contributors_are_all_held_back() {
    let g = gates(3);
    let mut q = OutQ::new();
    let total = AtomicUsize::new(0);
    for _ in 0..4 {
        for p in &g {
            add(&mut q, p, 100);
        }
    }
    q.regulate(MARKS, &total);
    assert!(g.iter().all(|p| !p.is_open()));
}

#[test]
fn growth_past_the_next_step_holds_who_kept_adding() {
    let g = gates(3);
    let (a, b, light) = (&g[0], &g[1], &g[2]);
    let mut q = OutQ::new();
    let total = AtomicUsize::new(0);
    add(&mut q, a, 1000);
    add(&mut q, light, 5);
    q.regulate(MARKS, &total);
    assert!(!a.is_open() && b.is_open() && light.is_open());
    // b keeps filling while a is held: nothing more until the next step (high / 2).
    add(&mut q, b, 400);
    q.regulate(MARKS, &total);
    assert!(b.is_open());
    add(&mut q, b, 200);
    q.regulate(MARKS, &total);
    assert!(!b.is_open() && light.is_open());
}

#[test]
fn at_the_total_cap_every_contributor_is_held_back() {
    let g = gates(2);
    let (flood, helm) = (&g[0], &g[1]);
    let mut q = OutQ::new();
    let total = AtomicUsize::new(MARKS.total_cap);
    add(&mut q, flood, 2000);
    add(&mut q, helm, 10);
    q.regulate(MARKS, &total);
    assert!(!flood.is_open() && !helm.is_open());
    q.release_all();
    assert!(flood.is_open() && helm.is_open());
}

#[test]
fn a_stalled_client_holds_no_one_and_is_over_its_cap_at_last() {
    let g = gates(1);
    let mut q = OutQ::new();
    let total = AtomicUsize::new(0);
    add(&mut q, &g[0], 2000);
    q.regulate(MARKS, &total);
    assert!(!g[0].is_open(), "a client making progress holds back");
    // The writer marks it stalled: the hold goes, and none comes back while stalled.
    q.stalled = true;
    q.release_all();
    assert!(g[0].is_open());
    add(&mut q, &g[0], 100_000);
    q.regulate(MARKS, &total);
    assert!(g[0].is_open(), "a stalled client held a publisher back");
    assert!(!q.over_cap(MARKS, &total));
    total.store(MARKS.total_cap, Ordering::Relaxed);
    assert!(q.over_cap(MARKS, &total), "the DB-wide cap is reached");
    total.store(0, Ordering::Relaxed);
    add(&mut q, &g[0], MARKS.stalled_cap);
    assert!(q.over_cap(MARKS, &total), "its own cap is reached");
    // Progress again: it holds back as before.
    q.stalled = false;
    assert!(!q.over_cap(MARKS, &total));
    q.regulate(MARKS, &total);
    assert!(!g[0].is_open());
}

/// A hold lasts the hold limit at most; the client then holds no one back for as long
/// again.
#[test]
fn a_long_hold_ends_and_none_for_as_long() {
    let l = TcpListener::bind("127.0.0.1:0").expect("bind");
    let _peer = std::net::TcpStream::connect(l.local_addr().expect("addr")).expect("connect");
    let (s, _) = l.accept().expect("accept");
    let out = Outbox::new(s, Arc::new(AtomicUsize::new(0)), "t");
    let g = gates(1);
    let mut pkt = vec![0u8; 2000];
    out.push_packet(&mut pkt, false, Some(&g[0]), MARKS);
    assert!(!g[0].is_open());
    out.end_long_hold(Duration::from_secs(60));
    assert!(!g[0].is_open(), "not yet");
    std::thread::sleep(Duration::from_millis(30));
    out.end_long_hold(Duration::from_millis(20));
    assert!(g[0].is_open(), "the hold lasted its limit");
    pkt.resize(2000, 0);
    out.push_packet(&mut pkt, false, Some(&g[0]), MARKS);
    assert!(g[0].is_open(), "held again at once");
    // The sleep is a lower bound: the cool-down of 5 ms has passed after it.
    std::thread::sleep(Duration::from_millis(30));
    pkt.resize(2000, 0);
    out.push_packet(&mut pkt, false, Some(&g[0]), MARKS);
    assert!(!g[0].is_open(), "after the cool-down it holds back again");
}

#[test]
fn window_halves_so_old_traffic_fades() {
    let g = gates(2);
    let mut q = OutQ::new();
    add(&mut q, &g[0], 900);
    add(&mut q, &g[1], 200); // sum 1100 > high: halved
    assert_eq!(q.contrib_sum, 450 + 100);
    assert_eq!(q.contrib.len(), 2);
}

#[test]
fn gate_wait_wakes_on_release() {
    let g = Arc::new(Gate::new());
    g.hold();
    assert!(!g.wait_open(Duration::from_millis(20)));
    let g2 = g.clone();
    let t = std::thread::spawn(move || g2.wait_open(Duration::from_secs(5)));
    std::thread::sleep(Duration::from_millis(20));
    g.release();
    assert!(t.join().expect("waiter"));
}

/// A real socket whose peer never reads: pushes past the high-water mark hold the
/// publisher; closing releases it and the memory, and the total goes back to 0.
#[test]
fn outbox_holds_then_close_releases_everything() {
    let l = TcpListener::bind("127.0.0.1:0").expect("bind");
    let _peer = std::net::TcpStream::connect(l.local_addr().expect("addr")).expect("connect");
    let (s, _) = l.accept().expect("accept");
    let total = Arc::new(AtomicUsize::new(0));
    let out = Outbox::new(s, total.clone(), "t");
    let publisher = Arc::new(Gate::new());
    let marks = Marks {
        high: 4 << 20,
        low: 2 << 20,
        total_cap: 64 << 20,
        stalled_cap: 32 << 20,
    };
    let mut pkt = Vec::new();
    for _ in 0..200 {
        pkt.resize(64 << 10, 7);
        out.push_packet(&mut pkt, false, Some(&publisher), marks);
        out.try_flush();
        if !publisher.is_open() {
            break;
        }
    }
    assert!(!publisher.is_open(), "never held back");
    assert!(out.queued() >= marks.high);
    assert!(total.load(Ordering::Relaxed) + COUNT_STEP >= out.queued());
    assert_eq!(out.holding(), 1);
    out.close();
    assert!(publisher.is_open());
    assert_eq!(out.queued(), 0);
    assert_eq!(total.load(Ordering::Relaxed), 0);
    assert!(out.is_cut());
}
