//! Issue 19: the real `moosdb`, our client. Subscribers that stop reading, are cut off,
//! reconnect and stop again never freeze the bus for the others, and the DB's memory
//! stays under its cap for small and large messages, big packets included.
//!
//! Margins (2 loaded cores): a stalled subscriber holds the publishers back for at most
//! the hold limit (0.1 s) plus one writer tick (25 ms); the healthy subscriber's longest
//! gap must stay under 250 ms, which leaves 125 ms for scheduling. Memory: the DB's peak
//! RSS stays under its idle RSS + the cap + `common::OVERHEAD` (24 MiB).

mod common;

use std::io::{Read, Write};
use std::net::TcpStream;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex, OnceLock, Weak};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use common::{client, flooders, serial, DbProc, Reader, OVERHEAD, READER_INBOX};
use moos::client::{Client, ClientConfig};
use moos::wire::{self, DataType, Message, MsgType};

const CAP_MB: usize = 32;
const FLOOD: Duration = Duration::from_millis(3000);
/// The flood goes on past [`FLOOD`] until every staller was cut off twice (a loaded
/// machine floods more slowly), but never longer than this.
const FLOOD_MAX: Duration = Duration::from_secs(60);
const MAX_GAP: Duration = Duration::from_millis(250);

fn db() -> DbProc {
    DbProc::start(&[
        format!("--max_queue_mb={CAP_MB}"),
        "--stall_timeout=1.5".into(),
    ])
}

/// What the event watcher saw: every `DB_EVENT`, and how often each staller was cut.
#[derive(Default)]
struct Seen {
    events: Vec<String>,
    cuts: Vec<u64>,
}

/// A `DB_EVENT` watcher that tells the stallers when they are cut off.
struct Watch {
    seen: Arc<(Mutex<Seen>, Condvar)>,
    stop: Arc<AtomicBool>,
    h: Option<JoinHandle<()>>,
}

impl Watch {
    fn start(port: u16, stallers: usize) -> Watch {
        let c = client(port, "watcher");
        c.register("DB_EVENT", 0.0).expect("register");
        let seen = Arc::new((
            Mutex::new(Seen {
                events: Vec::new(),
                cuts: vec![0; stallers],
            }),
            Condvar::new(),
        ));
        let stop = Arc::new(AtomicBool::new(false));
        let (s2, st2) = (seen.clone(), stop.clone());
        let h = std::thread::spawn(move || {
            let mut mail = Vec::new();
            while !st2.load(Ordering::Relaxed) {
                c.wait_for_mail(Duration::from_millis(20));
                mail.clear();
                c.fetch(&mut mail);
                let (m, cv) = &*s2;
                let mut s = m.lock().expect("seen");
                for e in mail.iter().filter(|m| m.key == "DB_EVENT") {
                    let e = e.string().into_owned();
                    let who = e
                        .strip_prefix("stalled=staller")
                        .and_then(|r| r.split(',').next())
                        .and_then(|i| i.parse::<usize>().ok());
                    if let Some(i) = who {
                        s.cuts[i] += 1;
                        cv.notify_all();
                    }
                    s.events.push(e);
                }
            }
        });
        Watch {
            seen,
            stop,
            h: Some(h),
        }
    }

    fn events(&self) -> Vec<String> {
        self.seen.0.lock().expect("seen").events.clone()
    }

    fn cuts(&self) -> Vec<u64> {
        self.seen.0.lock().expect("seen").cuts.clone()
    }
}

impl Drop for Watch {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        self.seen.1.notify_all();
        if let Some(h) = self.h.take() {
            let _ = h.join();
        }
    }
}

/// A subscriber to `LOAD` whose mail callback blocks on each connection until the DB
/// cuts that connection off; the client then reconnects (as libMOOS does) and blocks
/// again.
fn staller(port: u16, i: usize, w: &Watch) -> Arc<Client> {
    let me: Arc<OnceLock<Weak<Client>>> = Arc::new(OnceLock::new());
    let (seen, stop, me2) = (w.seen.clone(), w.stop.clone(), me.clone());
    let blocked_conn = std::sync::atomic::AtomicU64::new(0);
    let mut cfg = ClientConfig::new("127.0.0.1", port, &format!("staller{i}"));
    cfg.reconnect_max = Duration::from_millis(200);
    let c = Client::connect_with_mail_callback(
        cfg,
        Box::new(move || {
            let Some(conn) = me2
                .get()
                .and_then(Weak::upgrade)
                .map(|c| c.connection_count())
            else {
                return;
            };
            if blocked_conn.swap(conn, Ordering::Relaxed) == conn {
                return; // cut already: let the rest of that connection drain
            }
            let (m, cv) = &*seen;
            let mut s = m.lock().expect("seen");
            let cuts = s.cuts[i];
            // Until cut off, the test ends, or the client is being dropped.
            while s.cuts[i] == cuts
                && !stop.load(Ordering::Relaxed)
                && me2.get().and_then(Weak::upgrade).is_some()
            {
                s = cv
                    .wait_timeout(s, Duration::from_millis(100))
                    .expect("seen")
                    .0;
            }
        }),
    )
    .expect("connect");
    let c = Arc::new(c);
    let _ = me.set(Arc::downgrade(&c));
    c.register("LOAD", 0.0).expect("register");
    c
}

/// The longest time between two deliveries of mail while `on`.
#[derive(Default)]
struct Gaps {
    on: bool,
    last: Option<Instant>,
    longest: Duration,
    worst_at: Option<Instant>,
}

impl Gaps {
    fn mail(&mut self, now: Instant) {
        if !self.on {
            self.last = None;
            return;
        }
        if let Some(l) = self.last {
            if now - l > self.longest {
                self.longest = now - l;
                self.worst_at = Some(l);
            }
        }
        self.last = Some(now);
    }
}

/// The healthy subscriber's record of one flood.
struct Run {
    got: usize,
    longest_gap: Duration,
    peak_rss: usize,
    idle_rss: usize,
}

/// Publishers started by `publish` flood `LOAD` for [`FLOOD`] (or until the stallers
/// were cut off twice, see [`FLOOD_MAX`]) while `stallers`
/// subscribers stall; the healthy subscriber reads everything. Checks that it got every
/// message in order, that no publisher was cut off or reconnected, and that the stallers
/// were cut off and came back.
fn run(
    stallers: usize,
    publishers: usize,
    publish: impl FnOnce(u16, &Arc<AtomicBool>) -> Vec<JoinHandle<(usize, Publisher)>>,
) -> Run {
    let _serial = serial();
    let db = db();
    let w = Watch::start(db.port, stallers);
    // The gaps are taken where mail arrives (the client's reader thread), so the test's
    // own checking of large batches does not count as a gap.
    let gaps = Arc::new(Mutex::new(Gaps::default()));
    let g2 = gaps.clone();
    let mut cfg = ClientConfig::new("127.0.0.1", db.port, "healthy");
    cfg.max_inbox_bytes = READER_INBOX;
    let healthy = Client::connect_with_mail_callback(
        cfg,
        Box::new(move || g2.lock().expect("gaps").mail(Instant::now())),
    )
    .expect("connect");
    healthy.register("LOAD", 0.0).expect("register");
    let mut reader = Reader {
        c: healthy,
        next: vec![0; publishers],
        got: 0,
    };
    let stallers: Vec<Arc<Client>> = (0..stallers).map(|i| staller(db.port, i, &w)).collect();
    std::thread::sleep(Duration::from_millis(300));
    let idle_rss = db.mem("VmRSS");
    let stop = Arc::new(AtomicBool::new(false));
    let pubs = publish(db.port, &stop);
    let t0 = Instant::now();
    let wall0 = moos::time::wall_time();
    gaps.lock().expect("gaps").on = true;
    let cut_twice = |w: &Watch| w.cuts().iter().all(|&n| n >= 2);
    while t0.elapsed() < FLOOD || (t0.elapsed() < FLOOD_MAX && !cut_twice(&w)) {
        reader.drain("LOAD");
    }
    let (longest_gap, worst_at) = {
        let mut g = gaps.lock().expect("gaps");
        g.on = false;
        (g.longest, g.worst_at.map(|t| t - t0))
    };
    stop.store(true, Ordering::Relaxed);
    let (posted, pubs): (Vec<usize>, Vec<Publisher>) = pubs
        .into_iter()
        .map(|h| h.join().expect("publisher"))
        .unzip();
    let total: usize = posted.iter().sum();
    let deadline = Instant::now() + Duration::from_secs(30);
    while reader.got < total && Instant::now() < deadline {
        reader.drain("LOAD");
    }
    assert_eq!(reader.next, posted, "healthy subscriber incomplete");
    let peak_rss = db.mem("VmHWM");
    let events = w.events();
    let cuts = w.cuts();
    eprintln!(
        "{total} messages; longest gap {longest_gap:?} at {worst_at:?} (flood from {wall0:.3}); cuts {cuts:?}; \
         DB RSS idle {} MiB, peak {} MiB (cap {CAP_MB} MiB)",
        idle_rss >> 20,
        peak_rss >> 20
    );
    for p in &pubs {
        assert_eq!(p.connections(), 1, "a publisher reconnected: {events:?}");
    }
    for e in &events {
        let left = e.starts_with("stalled=") || e.starts_with("disconnected=");
        assert!(
            !(left && (e.contains("=flood") || e.contains("=big") || e.contains("=healthy"))),
            "a publisher or the healthy subscriber was cut off or left: {e}"
        );
    }
    for (i, n) in cuts.iter().enumerate() {
        assert!(
            *n >= 2,
            "staller{i} was cut off {n} times (not twice): {events:?}"
        );
        assert!(
            stallers[i].connection_count() >= 2,
            "staller{i} never reconnected"
        );
    }
    drop(w);
    drop(stallers);
    Run {
        got: total,
        longest_gap,
        peak_rss,
        idle_rss,
    }
}

/// A publisher: our client, or a raw connection writing big packets as libMOOS does
/// (kept open until the check).
enum Publisher {
    Client(Client),
    Raw(#[allow(dead_code)] TcpStream),
}

impl Publisher {
    fn connections(&self) -> u64 {
        match self {
            Publisher::Client(c) => c.connection_count(),
            // It never reconnects; a cut would have failed its writes.
            Publisher::Raw(_) => 1,
        }
    }
}

fn check(r: &Run, min_messages: usize) {
    assert!(
        r.got >= min_messages,
        "the flood was too thin to test anything: {}",
        r.got
    );
    assert!(
        r.longest_gap < MAX_GAP,
        "the healthy subscriber waited {:?}",
        r.longest_gap
    );
    assert!(
        r.peak_rss <= r.idle_rss + (CAP_MB << 20) + OVERHEAD,
        "DB peak RSS {} MiB over idle {} MiB + cap {CAP_MB} MiB + {} MiB",
        r.peak_rss >> 20,
        r.idle_rss >> 20,
        OVERHEAD >> 20
    );
}

fn client_flooders(
    n: usize,
    payload: usize,
) -> impl FnOnce(u16, &Arc<AtomicBool>) -> Vec<JoinHandle<(usize, Publisher)>> {
    move |port, stop| {
        flooders(port, n, "LOAD", stop, payload)
            .into_iter()
            .map(|h| {
                std::thread::spawn(move || {
                    let (n, c) = h.join().expect("flooder");
                    (n, Publisher::Client(c))
                })
            })
            .collect()
    }
}

#[test]
fn one_blocked_subscriber_that_reconnects_never_freezes_the_bus() {
    let r = run(1, 3, client_flooders(3, 200));
    check(&r, 20_000);
}

#[test]
fn four_blocked_subscribers_that_reconnect_never_freeze_the_bus() {
    let r = run(4, 3, client_flooders(3, 200));
    check(&r, 20_000);
}

/// A raw publisher writing packets of about 8 MiB of `size`-byte messages
/// (`<p>:<i>:<filler>`), as libMOOS does after being held back, never reading.
fn raw_publisher(
    port: u16,
    p: usize,
    size: usize,
    stop: Arc<AtomicBool>,
) -> JoinHandle<(usize, Publisher)> {
    let name = format!("big{p}");
    let mut s = TcpStream::connect(("127.0.0.1", port)).expect("connect");
    let hs = Message {
        msg_type: MsgType::DATA,
        data_type: DataType::STRING,
        key: wire::ASYNC_KEY.into(),
        time: moos::time::wall_time(),
        sval: name.as_bytes().to_vec(),
        ..Message::default()
    };
    let mut buf = wire::BANNER.to_vec();
    wire::encode_packet(&[hs], &mut buf).expect("encode");
    s.write_all(&buf).expect("handshake");
    let mut welcome = [0u8; 9];
    s.read_exact(&mut welcome).expect("welcome");
    std::thread::spawn(move || {
        let filler = "z".repeat(size);
        let mut i = 0;
        let mut pkt = Vec::new();
        while !stop.load(Ordering::Relaxed) {
            let mut msgs = Vec::new();
            let mut bytes = 0;
            while bytes < 8 << 20 {
                let mut m = Message::notify_string("LOAD", &format!("{p}:{i}:{filler}"), 1.0);
                m.source = name.clone();
                bytes += m.encoded_len();
                msgs.push(m);
                i += 1;
            }
            pkt.clear();
            wire::encode_packet(&msgs, &mut pkt).expect("encode");
            s.write_all(&pkt).expect("the DB took the packet");
        }
        (i, Publisher::Raw(s))
    })
}

/// Point 2: messages of 10 KB in 8 MiB packets, and 1 MB messages, with two stallers.
#[test]
fn ten_kb_and_one_mb_messages_in_big_packets_stay_under_the_cap() {
    let r = run(2, 4, |port, stop| {
        // Publisher 0 is our client's (1 MB messages); 1 and 2 write 10 KB messages and
        // 3 writes 1 MB messages, in 8 MiB packets.
        let mut v = client_flooders(1, 1_000_000)(port, stop);
        v.extend((1..3).map(|p| raw_publisher(port, p, 10_000, stop.clone())));
        v.push(raw_publisher(port, 3, 1_000_000, stop.clone()));
        v
    });
    check(&r, 2_000);
}

/// The scenario B: 8 publishers of 10 kB messages in 8 MiB packets, 4 blocked
/// subscribers that reconnect.
#[test]
fn eight_big_packet_publishers_and_four_blocked_subscribers() {
    let r = run(4, 8, |port, stop| {
        (0..8)
            .map(|p| raw_publisher(port, p, 10_000, stop.clone()))
            .collect()
    });
    check(&r, 2_000);
}

/// The scenario C: 8 publishers of 30 kB messages in 8 MiB packets, no blocked
/// subscriber: nothing lost, no publisher dropped, memory under the cap.
#[test]
fn eight_publishers_of_30_kb_messages_lose_nothing() {
    let r = run(0, 8, |port, stop| {
        (0..8)
            .map(|p| raw_publisher(port, p, 30_000, stop.clone()))
            .collect()
    });
    check(&r, 1_000);
}
