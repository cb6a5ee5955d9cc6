//! Hostile MOOS peers against the real `moosdb` binary (issue 10).
//!
//! Each test starts its own `moosdb` on 127.0.0.1 (a free port, `--moos_timeout=2`),
//! connects two well-behaved watchers (a publisher and a subscriber of `PING`), lets a
//! raw TCP peer misbehave, and then checks that:
//! * the DB process is still running;
//! * its resident memory (VmRSS of /proc/PID/status) stays under a bound;
//! * the watchers are still connected on their first connection and `PING` still flows;
//! * the offender's socket was closed by the DB, and the DB logged why (its log is the
//!   process's stdout, kept in a temp file).
//!
//! Misbehaviours: a 2 GB length prefix (before and after the handshake), a truncated
//! packet then silence, garbage after a valid handshake, a flood of connections (bounded:
//! 200 idle sockets and 60 full handshakes), a name clash, and 1 MB strings (as value
//! and as variable name).
//!
//! The second half turns it round: a fake DB (a raw listener on 127.0.0.1) that
//! misbehaves towards the helm's client (`moos::Client`) after a valid welcome. The
//! client must drop that connection (the fake sees it closed), log why, and reconnect
//! (to the same fake, which then behaves), with its memory bounded; 1 MB strings from
//! the DB arrive intact.
//!
//! The tests run one at a time (a lock): they measure memory, and the machine is small.

use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use moos::client::{Client, ClientConfig};
use moos::wire::{self, DataType, FrameReader, Message, MsgType};
use test_support::free_port;

/// One test at a time (memory is measured; the machine has 2 cores).
fn serial() -> std::sync::MutexGuard<'static, ()> {
    static LOCK: std::sync::Mutex<()> = std::sync::Mutex::new(());
    LOCK.lock().unwrap_or_else(|p| p.into_inner())
}

/// A `moosdb` child process, killed on drop.
struct MoosDb {
    child: Child,
    port: u16,
    log: PathBuf,
}

impl MoosDb {
    fn start(tag: &str) -> MoosDb {
        MoosDb::start_with(tag, 2)
    }

    /// With `--moos_timeout=<timeout>` seconds.
    fn start_with(tag: &str, timeout: u32) -> MoosDb {
        static N: AtomicUsize = AtomicUsize::new(0);
        let log = std::env::temp_dir().join(format!(
            "moosdb-hostile-{tag}-{}-{}.log",
            std::process::id(),
            N.fetch_add(1, Ordering::SeqCst)
        ));
        let port = free_port();
        let out = std::fs::File::create(&log).expect("log file");
        let err = out.try_clone().expect("log file");
        let child = Command::new(env!("CARGO_BIN_EXE_moosdb"))
            .arg(format!("--moos_port={port}"))
            .arg("--bind=127.0.0.1")
            .arg(format!("--moos_timeout={timeout}"))
            .arg("--moos_community=hostile")
            .env("RUST_LOG", "info")
            .env("NO_COLOR", "1")
            .stdout(Stdio::from(out))
            .stderr(Stdio::from(err))
            .spawn()
            .expect("start moosdb");
        let db = MoosDb { child, port, log };
        let t0 = Instant::now();
        while TcpStream::connect(("127.0.0.1", port)).is_err() {
            assert!(
                t0.elapsed() < Duration::from_secs(10),
                "moosdb did not listen"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
        db
    }

    fn alive(&mut self) -> bool {
        matches!(self.child.try_wait(), Ok(None))
    }

    /// Resident memory in kB.
    fn rss_kb(&self) -> u64 {
        vm_rss_kb(&format!("/proc/{}/status", self.child.id()))
    }

    fn log(&self) -> String {
        std::fs::read_to_string(&self.log).unwrap_or_default()
    }

    /// Wait until the log contains every one of `words` on one line.
    fn wait_log(&self, words: &[&str], limit: Duration) -> bool {
        wait_line(|| self.log(), words, limit)
    }

    /// The log gets a line with every one of `words` within `limit`; else fail, saying
    /// `what` and showing the log.
    fn assert_logged(&self, words: &[&str], limit: Duration, what: &str) {
        assert!(self.wait_log(words, limit), "{what}:\n{}", self.log());
    }
}

/// VmRSS, in kB, of a `/proc/.../status` file.
fn vm_rss_kb(status: &str) -> u64 {
    std::fs::read_to_string(status)
        .ok()
        .and_then(|s| {
            s.lines()
                .find_map(|l| l.strip_prefix("VmRSS:"))
                .and_then(|v| v.split_whitespace().next())
                .and_then(|v| v.parse().ok())
        })
        .unwrap_or_else(|| panic!("no VmRSS in {status}"))
}

/// Wait until `text()` has a line containing every one of `words`.
fn wait_line(text: impl Fn() -> String, words: &[&str], limit: Duration) -> bool {
    let t0 = Instant::now();
    while t0.elapsed() < limit {
        if text().lines().any(|l| words.iter().all(|w| l.contains(w))) {
            return true;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    false
}

/// A read that only timed out (the peer is still there).
fn timed_out(e: &std::io::Error) -> bool {
    matches!(
        e.kind(),
        std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
    )
}

/// A raw TCP connection to the DB, nothing sent yet.
fn connect(port: u16) -> TcpStream {
    TcpStream::connect(("127.0.0.1", port)).expect("connect")
}

/// `msgs` as one packet.
fn packet(msgs: &[Message]) -> Vec<u8> {
    let mut p = Vec::new();
    wire::encode_packet(msgs, &mut p).expect("encode");
    p
}

/// The first half of a packet holding a 5000-byte string: a peer that stops mid-packet.
fn half_packet() -> Vec<u8> {
    let p = packet(&[Message::notify_string("X", &"y".repeat(5000), 1.0)]);
    p[..p.len() / 2].to_vec()
}

impl Drop for MoosDb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
        let _ = std::fs::remove_file(&self.log);
    }
}

/// Two good clients: `watch_pub` posts PING, `watch_sub` receives it.
struct Watchers {
    publ: Client,
    sub: Client,
    n: f64,
}

impl Watchers {
    fn new(port: u16) -> Watchers {
        let publ = Client::connect(ClientConfig::new("127.0.0.1", port, "watch_pub"))
            .expect("watch_pub connects");
        let sub = Client::connect(ClientConfig::new("127.0.0.1", port, "watch_sub"))
            .expect("watch_sub connects");
        sub.register("PING", 0.0).expect("register");
        let mut w = Watchers { publ, sub, n: 0.0 };
        w.assert_service("before the attack");
        w
    }

    /// A fresh PING value reaches the subscriber within 5 s, on the first connections.
    fn assert_service(&mut self, when: &str) {
        self.n += 1.0;
        let want = self.n;
        let t0 = Instant::now();
        let mut got = Vec::new();
        loop {
            let _ = self.publ.notify_double("PING", want, None);
            self.sub.wait_for_mail(Duration::from_millis(200));
            self.sub.fetch(&mut got);
            if got.iter().any(|m| m.key == "PING" && m.dval == want) {
                break;
            }
            assert!(
                t0.elapsed() < Duration::from_secs(5),
                "{when}: PING {want} not delivered"
            );
        }
        assert_eq!(
            self.publ.connection_count(),
            1,
            "{when}: watch_pub reconnected"
        );
        assert_eq!(
            self.sub.connection_count(),
            1,
            "{when}: watch_sub reconnected"
        );
    }
}

fn handshake_bytes(name: &str) -> Vec<u8> {
    let hs = Message {
        msg_type: MsgType::DATA,
        data_type: DataType::STRING,
        key: wire::ASYNC_KEY.into(),
        time: moos::time::wall_time(),
        sval: name.as_bytes().to_vec(),
        ..Message::default()
    };
    [wire::BANNER.to_vec(), packet(&[hs])].concat()
}

/// A raw peer that completed the handshake; returns the stream and the welcome.
fn raw_peer(port: u16, name: &str) -> (TcpStream, Message) {
    let mut s = connect(port);
    s.write_all(&handshake_bytes(name)).expect("send handshake");
    s.set_read_timeout(Some(Duration::from_secs(5)))
        .expect("timeout");
    let mut fr = FrameReader::new(1 << 20);
    loop {
        if let Some(r) = fr.next_frame().expect("welcome frame") {
            let m = wire::decode_packet(fr.frame(r), 1 << 20).expect("welcome packet");
            return (s, m.into_iter().next().expect("welcome message"));
        }
        assert!(
            fr.fill(&mut s).expect("read welcome") > 0,
            "closed in handshake"
        );
    }
}

/// Wait until the DB closes `s` (EOF or reset), reading and discarding what it sends.
fn closed_within(s: &mut TcpStream, limit: Duration) -> bool {
    let t0 = Instant::now();
    let _ = s.set_read_timeout(Some(Duration::from_millis(100)));
    let mut buf = vec![0u8; 64 * 1024];
    while t0.elapsed() < limit {
        match s.read(&mut buf) {
            Ok(0) => return true,
            Ok(_) => {}
            Err(e) if timed_out(&e) => {}
            Err(_) => return true,
        }
    }
    false
}

/// The DB closes `s` within `secs` seconds; else fail, saying `what`.
fn assert_closed(s: &mut TcpStream, secs: u64, what: &str) {
    assert!(closed_within(s, Duration::from_secs(secs)), "{what}");
}

/// The start of every attack on the DB: the test lock, a fresh `moosdb` (`tag` names
/// its log) and its two watchers, served.
fn attack(tag: &str) -> (std::sync::MutexGuard<'static, ()>, MoosDb, Watchers) {
    attack_with(tag, 2)
}

/// [`attack`] with a client timeout of `timeout` s: peers that must stay silent for a
/// while on a loaded machine.
fn attack_with(tag: &str, timeout: u32) -> (std::sync::MutexGuard<'static, ()>, MoosDb, Watchers) {
    let serial = serial();
    let db = MoosDb::start_with(tag, timeout);
    let w = Watchers::new(db.port);
    (serial, db, w)
}

/// The mail of `c` from now until `enough` holds for it; fails, saying `what`, after
/// `limit`.
fn mail_until(
    c: &Client,
    limit: Duration,
    what: &str,
    enough: impl Fn(&[Message]) -> bool,
) -> Vec<Message> {
    let mut got = Vec::new();
    let t0 = Instant::now();
    while !enough(&got) {
        assert!(t0.elapsed() < limit, "{what}: got {}", got.len());
        c.wait_for_mail(Duration::from_millis(200));
        c.fetch(&mut got);
    }
    got
}

fn assert_healthy(db: &mut MoosDb, w: &mut Watchers, rss_limit_kb: u64, when: &str) {
    assert!(db.alive(), "{when}: moosdb died\n{}", db.log());
    let rss = db.rss_kb();
    println!("{when}: moosdb VmRSS {rss} kB");
    assert!(
        rss < rss_limit_kb,
        "{when}: moosdb VmRSS {rss} kB > {rss_limit_kb} kB"
    );
    w.assert_service(when);
}

#[test]
fn two_gigabyte_length_prefix_is_refused_without_allocating() {
    let (_serial, mut db, mut w) = attack("2gb");
    // After the handshake.
    let (mut s, _) = raw_peer(db.port, "liar");
    s.write_all(&0x7fff_fff0_i32.to_le_bytes()).expect("send");
    s.write_all(&[0u8; 1024]).expect("send");
    assert_closed(&mut s, 5, "offender not dropped");
    db.assert_logged(
        &["liar", "bad packet framing"],
        Duration::from_secs(3),
        "not logged",
    );
    // As the handshake packet itself.
    let mut s = connect(db.port);
    s.write_all(&wire::BANNER).expect("banner");
    s.write_all(&u32::MAX.wrapping_sub(1).to_le_bytes())
        .expect("send");
    s.write_all(&0x7fff_ffff_i32.to_le_bytes()).expect("send");
    assert_closed(&mut s, 7, "offender not dropped");
    assert_healthy(&mut db, &mut w, 64 * 1024, "after 2 GB length prefixes");
}

#[test]
fn truncated_packet_then_silence_is_dropped_at_the_timeout() {
    let (_serial, mut db, mut w) = attack("trunc");
    let (mut s, _) = raw_peer(db.port, "halfway");
    s.write_all(&half_packet()).expect("send half");
    let t0 = Instant::now();
    assert_closed(&mut s, 8, "offender not dropped");
    let took = t0.elapsed();
    assert!(
        took >= Duration::from_millis(1500),
        "dropped too early: {took:?}"
    );
    db.assert_logged(
        &["halfway", "sent nothing for"],
        Duration::from_secs(3),
        "not logged",
    );
    // Half a handshake: closed at the handshake timeout (5 s).
    let mut s = connect(db.port);
    let hs = handshake_bytes("half_hs");
    s.write_all(&hs[..hs.len() - 10]).expect("send");
    assert_closed(&mut s, 9, "half handshake kept");
    assert_healthy(&mut db, &mut w, 64 * 1024, "after truncated packets");
}

#[test]
fn garbage_after_handshake_drops_the_offender() {
    let (_serial, mut db, mut w) = attack("garbage");
    // Deterministic noise (xorshift), several flavours.
    let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut noise = |n: usize| -> Vec<u8> {
        (0..n)
            .map(|_| {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                x as u8
            })
            .collect()
    };
    let junk: Vec<(&str, Vec<u8>)> = vec![
        ("noise", noise(64 * 1024)),
        ("negative", (-5i32).to_le_bytes().repeat(100)),
        ("badcount", {
            let mut p = 100i32.to_le_bytes().to_vec();
            p.extend_from_slice(&i32::MAX.to_le_bytes());
            p.extend(noise(92));
            p
        }),
        ("badmsg", {
            let mut p = packet(&[Message::notify_double("A", 1.0, 1.0)]);
            p[9 + 10..9 + 14].copy_from_slice(&(-1i32).to_le_bytes());
            p.extend(noise(4096));
            p
        }),
    ];
    for (name, bytes) in &junk {
        let who = format!("garbage_{name}");
        let (mut s, _) = raw_peer(db.port, &who);
        let _ = s.write_all(bytes);
        assert_closed(&mut s, 8, &format!("{who} not dropped"));
        db.assert_logged(
            &[who.as_str(), "client disconnected"],
            Duration::from_secs(3),
            &format!("{who}: not logged"),
        );
    }
    assert_healthy(&mut db, &mut w, 64 * 1024, "after garbage");
}

#[test]
fn connection_flood_is_survived() {
    let (_serial, mut db, mut w) = attack("flood");
    let base = db.rss_kb();
    // 200 idle sockets: no banner at all.
    let mut idle: Vec<TcpStream> = (0..200)
        .filter_map(|_| TcpStream::connect(("127.0.0.1", db.port)).ok())
        .collect();
    assert!(
        idle.len() >= 150,
        "only {} connections accepted",
        idle.len()
    );
    // 60 full handshakes with distinct names, then gone.
    let peers: Vec<TcpStream> = (0..60)
        .map(|i| raw_peer(db.port, &format!("flood{i}")).0)
        .collect();
    assert_healthy(&mut db, &mut w, base + 128 * 1024, "during the flood");
    drop(peers);
    db.assert_logged(
        &["flood59", "client disconnected"],
        Duration::from_secs(5),
        "flood clients not released",
    );
    // The idle ones are closed by the DB at the handshake timeout (5 s).
    let t0 = Instant::now();
    for s in &mut idle {
        let left = Duration::from_secs(9).saturating_sub(t0.elapsed());
        assert!(
            closed_within(s, left.max(Duration::from_millis(200))),
            "idle socket kept"
        );
    }
    assert_healthy(&mut db, &mut w, base + 128 * 1024, "after the flood");
}

#[test]
fn name_clash_is_refused_and_the_first_keeps_its_service() {
    let (_serial, mut db, mut w) = attack("clash");
    let (mut s, welcome) = raw_peer(db.port, "watch_pub");
    assert_eq!(welcome.msg_type, MsgType::POISON, "{welcome:?}");
    assert!(welcome.string().contains("already exists"), "{welcome:?}");
    assert_closed(&mut s, 3, "clash not closed");
    db.assert_logged(
        &["watch_pub", "handshake refused"],
        Duration::from_secs(3),
        "not logged",
    );
    assert_healthy(&mut db, &mut w, 64 * 1024, "after a name clash");
}

#[test]
fn one_megabyte_strings_are_delivered_and_memory_stays_bounded() {
    let (_serial, mut db, mut w) = attack("big");
    let big = Client::connect(ClientConfig::new("127.0.0.1", db.port, "big_pub")).expect("big");
    let rx = Client::connect(ClientConfig::new("127.0.0.1", db.port, "big_sub")).expect("rx");
    rx.register("BIG", 0.0).expect("register");
    std::thread::sleep(Duration::from_millis(300));
    let mb = 1 << 20;
    for i in 0..20u8 {
        let v: String = char::from(b'a' + i % 26).to_string().repeat(mb);
        big.notify_string("BIG", &v, None).expect("post big value");
        // A 1 MB variable name too (each a new variable the DB keeps).
        let key: String = char::from(b'A' + i % 26).to_string().repeat(mb);
        big.notify_double(&format!("{key}{i}"), 1.0, None)
            .expect("post big key");
    }
    let got = mail_until(
        &rx,
        Duration::from_secs(20),
        "big values not delivered",
        |got| got.iter().filter(|m| m.key == "BIG").count() >= 20,
    );
    for m in got.iter().filter(|m| m.key == "BIG") {
        assert_eq!(m.sval.len(), mb);
    }
    // 20 MB of values passed, 20 MB of names kept: bounded well under 256 MB.
    assert_healthy(&mut db, &mut w, 256 * 1024, "after 1 MB strings");
}

/// A peer that fails before or during the handshake (bad banner, oversize handshake
/// packet) is closed with one log line naming its address and the reason.
#[test]
fn pre_handshake_offenders_are_logged() {
    let _serial = serial();
    let db = MoosDb::start("prehs");
    let mut s = connect(db.port);
    s.write_all(b"GET / HTTP/1.1\r\nHost: x\r\n\r\n+++++")
        .expect("send");
    assert_closed(&mut s, 7, "bad banner kept");
    let mut s = connect(db.port);
    s.write_all(&wire::BANNER).expect("banner");
    s.write_all(&0x7fff_ffff_i32.to_le_bytes()).expect("send");
    assert_closed(&mut s, 7, "bad handshake kept");
    let log = db.log();
    assert!(log.contains("banner"), "bad banner not logged:\n{log}");
    assert!(
        log.contains("handshake"),
        "bad handshake not logged:\n{log}"
    );
    assert!(log.contains("127.0.0.1:"), "peer not named:\n{log}");
}

/// Issue 19 point 3: a client that reconnects under the name of a connection the DB
/// still holds is welcomed when that connection is known dead (here: reset by its peer
/// while its reader waited for room for a long message, so the reader never saw it).
#[test]
fn a_reconnect_replaces_a_connection_known_dead() {
    let (_serial, mut db, mut w) = attack_with("replace", 30);
    // Two peers in the middle of a 40 MiB message, more than half the cap each: one
    // holds the room, the other waits for it, not read. Welcomes left unread, so that
    // closing resets the connection.
    let long = packet(&[Message::notify_string("L", &"l".repeat(40 << 20), 1.0)]);
    let mut peers: Vec<(String, TcpStream)> = ["peer_a", "peer_b"]
        .iter()
        .map(|name| {
            let mut s = connect(db.port);
            s.write_all(&handshake_bytes(name)).expect("handshake");
            s.write_all(&long[..1 << 20])
                .expect("part of a long message");
            (name.to_string(), s)
        })
        .collect();
    db.assert_logged(
        &["waiting for room"],
        Duration::from_secs(10),
        "no peer waits",
    );
    let log = db.log();
    let waiting = log
        .lines()
        .find(|l| l.contains("waiting for room"))
        .and_then(|l| peers.iter().position(|(n, _)| l.contains(n.as_str())))
        .expect("the waiting peer is named");
    let (name, s) = peers.remove(waiting);
    drop(s);
    std::thread::sleep(Duration::from_millis(200));
    let (_again, welcome) = raw_peer(db.port, &name);
    assert_eq!(welcome.msg_type, MsgType::WELCOME, "{welcome:?}");
    db.assert_logged(
        &[&name, "dead connection"],
        Duration::from_secs(3),
        "replacement not logged",
    );
    // A live name is still refused.
    let (_, clash) = raw_peer(db.port, &name);
    assert_eq!(clash.msg_type, MsgType::POISON, "{clash:?}");
    drop(peers);
    assert_healthy(&mut db, &mut w, 256 * 1024, "after a replaced connection");
}

/// Every connection may start a packet of up to `max_packet` (64 MiB) and stall; a few
/// such peers would take the DB's memory to peers × 64 MiB. A message longer than a
/// piece (256 KiB) is read only with a reservation (long ones together within half the
/// cap, or one at a time): the others wait, not read, and none is dropped. Once they
/// finish, every message is delivered whole.
#[test]
fn partial_packets_from_many_peers_stay_within_a_total_bound() {
    let (_serial, mut db, mut w) = attack_with("partial", 30);
    let sub = Client::connect(ClientConfig::new("127.0.0.1", db.port, "hog_sub")).expect("sub");
    sub.register("HOG", 0.0).expect("register");
    let base = db.rss_kb();
    let len = 20 << 20;
    let paused = Arc::new(std::sync::Barrier::new(5));
    let go = Arc::new(std::sync::Barrier::new(5));
    let writers: Vec<_> = (0..4u8)
        .map(|i| {
            let (mut s, _) = raw_peer(db.port, &format!("hog{i}"));
            let (paused, go) = (paused.clone(), go.clone());
            std::thread::spawn(move || {
                let v = char::from(b'a' + i).to_string().repeat(len);
                let p = packet(&[Message::notify_string("HOG", &v, 1.0)]);
                // 12 of its 20 MiB, as far as the DB reads them within 300 ms.
                s.set_write_timeout(Some(Duration::from_millis(300)))
                    .expect("timeout");
                let mut sent = 0;
                while sent < 12 << 20 {
                    match s.write(&p[sent..sent + (64 << 10)]) {
                        Ok(n) => sent += n,
                        Err(_) => break,
                    }
                }
                paused.wait();
                go.wait();
                s.set_write_timeout(Some(Duration::from_secs(60)))
                    .expect("timeout");
                s.write_all(&p[sent..]).expect("rest of the message");
                s
            })
        })
        .collect();
    paused.wait();
    let rss = db.rss_kb();
    println!(
        "moosdb VmRSS {rss} kB with 4 peers in the middle of a 20 MiB message (idle {base} kB)"
    );
    assert!(rss < base + 40 * 1024, "moosdb VmRSS {rss} kB");
    // They finish: each message goes through in turn.
    go.wait();
    let got = mail_until(&sub, Duration::from_secs(60), "long messages lost", |m| {
        m.iter().filter(|m| m.key == "HOG").count() >= 4
    });
    let mut firsts: Vec<u8> = got
        .iter()
        .filter(|m| m.key == "HOG")
        .map(|m| {
            assert_eq!(m.sval.len(), len, "cut short");
            assert!(m.sval.iter().all(|b| *b == m.sval[0]), "mixed up");
            m.sval[0]
        })
        .collect();
    firsts.sort();
    assert_eq!(firsts, b"abcd");
    let _hogs: Vec<TcpStream> = writers
        .into_iter()
        .map(|h| h.join().expect("hog"))
        .collect();
    let log = db.log();
    assert!(!log.contains("cutting off"), "a client was cut off:\n{log}");
    assert!(!log.contains("dropped"), "a peer was dropped:\n{log}");
    assert_healthy(&mut db, &mut w, base + 160 * 1024, "after long messages");
}

// ---------------------------------------------------------------------------------------
// A hostile DB against the helm's client.

/// Log lines of this test binary (the client logs through `tracing`).
fn captured_log() -> String {
    static LOG: std::sync::OnceLock<std::sync::Arc<std::sync::Mutex<Vec<u8>>>> =
        std::sync::OnceLock::new();
    let buf = LOG.get_or_init(|| {
        let buf = std::sync::Arc::new(std::sync::Mutex::new(Vec::new()));
        let b2 = buf.clone();
        let _ = tracing_subscriber::fmt()
            .with_ansi(false)
            .with_env_filter(tracing_subscriber::EnvFilter::new("info"))
            .with_writer(move || Capture(b2.clone()))
            .try_init();
        buf
    });
    String::from_utf8_lossy(&buf.lock().unwrap_or_else(|p| p.into_inner())).into_owned()
}

struct Capture(std::sync::Arc<std::sync::Mutex<Vec<u8>>>);

impl Write for Capture {
    fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
        self.0
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .extend_from_slice(b);
        Ok(b.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

fn wait_captured(words: &[&str], limit: Duration) -> bool {
    wait_line(captured_log, words, limit)
}

/// The client logged a line with every one of `words` within 2 s; else fail, showing
/// the log.
fn assert_captured(words: &[&str]) {
    assert!(
        wait_captured(words, Duration::from_secs(2)),
        "{}",
        captured_log()
    );
}

fn self_rss_kb() -> u64 {
    vm_rss_kb("/proc/self/status")
}

/// A fake DB: a listener on a free port of 127.0.0.1.
fn fake_db() -> (TcpListener, u16) {
    let l = TcpListener::bind("127.0.0.1:0").expect("bind");
    let port = l.local_addr().expect("addr").port();
    (l, port)
}

/// `c` reconnects within 10 s (its second connection, up); else fail, saying `what()`.
fn wait_reconnected(c: &Client, what: impl Fn() -> String) {
    let t0 = Instant::now();
    while c.connection_count() < 2 || !c.is_connected() {
        assert!(t0.elapsed() < Duration::from_secs(10), "{}", what());
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Accept one client, read its banner and handshake, send a welcome.
fn fake_welcome(l: &TcpListener) -> TcpStream {
    let (mut s, _) = l.accept().expect("accept");
    s.set_read_timeout(Some(Duration::from_secs(5)))
        .expect("timeout");
    let mut banner = [0u8; 32];
    s.read_exact(&mut banner).expect("banner");
    assert!(wire::banner_ok(&banner));
    let mut fr = FrameReader::new(1 << 20);
    while fr.next_frame().expect("handshake").is_none() {
        assert!(fr.fill(&mut s).expect("read handshake") > 0);
    }
    let welcome = Message {
        msg_type: MsgType::WELCOME,
        data_type: DataType::DOUBLE,
        source_aux: "hostname=fake-db".into(),
        community: "fake".into(),
        time: moos::time::wall_time(),
        dval: 0.0,
        sval: wire::ASYNC_KEY.as_bytes().to_vec(),
        ..Message::default()
    };
    s.write_all(&packet(&[welcome])).expect("welcome");
    s
}

/// Answer every packet of `s` with a timing echo until it closes or `limit` passes.
fn behave(mut s: TcpStream, limit: Duration) {
    let _ = s.set_read_timeout(Some(Duration::from_millis(100)));
    let mut fr = FrameReader::new(1 << 24);
    let t0 = Instant::now();
    while t0.elapsed() < limit {
        while let Ok(Some(_)) = fr.next_frame() {
            let echo = Message {
                msg_type: MsgType::TIMING,
                data_type: DataType::DOUBLE,
                key: wire::TIMING_KEY.into(),
                time: moos::time::wall_time(),
                dval: moos::time::wall_time(),
                ..Message::default()
            };
            let mut p = Vec::new();
            let _ = wire::encode_packet(&[echo], &mut p);
            if s.write_all(&p).is_err() {
                return;
            }
        }
        match fr.fill(&mut s) {
            Ok(0) => return,
            Ok(_) => {}
            Err(e) if timed_out(&e) => {}
            Err(_) => return,
        }
    }
}

/// Run `misbehave` on the client's first connection; the second behaves. Returns the
/// client (reconnected) and the time the fake waited for the client to drop it.
fn against_client(
    name: &str,
    silence: Duration,
    misbehave: impl FnOnce(&mut TcpStream) + Send + 'static,
) -> (Client, Duration) {
    let _ = captured_log(); // installs the capturing subscriber before the client logs
    let (l, port) = fake_db();
    let (tx, rx) = std::sync::mpsc::channel();
    let fake = std::thread::spawn(move || {
        let mut s = fake_welcome(&l);
        misbehave(&mut s);
        let t0 = Instant::now();
        let dropped = closed_within(&mut s, Duration::from_secs(15));
        let _ = tx.send((dropped, t0.elapsed()));
        behave(fake_welcome(&l), Duration::from_secs(5));
    });
    let mut cfg = ClientConfig::new("127.0.0.1", port, name);
    cfg.silence_timeout = silence;
    let c = Client::connect(cfg).expect("first connection");
    let (dropped, took) = rx
        .recv_timeout(Duration::from_secs(20))
        .expect("fake reports");
    assert!(dropped, "{name}: the client kept the hostile connection");
    wait_reconnected(&c, || format!("{name}: no reconnect"));
    drop(fake);
    (c, took)
}

#[test]
fn client_drops_a_db_with_a_two_gigabyte_length_prefix() {
    let _serial = serial();
    let before = self_rss_kb();
    let (c, took) = against_client("victim_2gb", Duration::from_secs(5), |s| {
        let _ = s.write_all(&0x7fff_fff0_i32.to_le_bytes());
        let _ = s.write_all(&[0u8; 4096]);
    });
    assert!(took < Duration::from_secs(3), "{took:?}");
    assert_captured(&["victim_2gb", "bad packet from DB"]);
    let grew = self_rss_kb().saturating_sub(before);
    assert!(grew < 64 * 1024, "client grew by {grew} kB");
    c.close();
}

#[test]
fn client_drops_a_db_that_stops_mid_packet() {
    let _serial = serial();
    let (c, took) = against_client("victim_silent", Duration::from_secs(2), |s| {
        let _ = s.write_all(&half_packet());
    });
    assert!(
        (Duration::from_millis(1500)..Duration::from_secs(6)).contains(&took),
        "dropped after {took:?}"
    );
    assert_captured(&["victim_silent", "nothing from the DB"]);
    c.close();
}

#[test]
fn client_drops_a_db_that_sends_garbage() {
    let _serial = serial();
    let (c, _) = against_client("victim_garbage", Duration::from_secs(2), |s| {
        let mut p = 20i32.to_le_bytes().to_vec();
        p.extend_from_slice(&(-7i32).to_le_bytes());
        p.extend((0..20_000u32).map(|i| (i.wrapping_mul(2_654_435_761) >> 24) as u8));
        let _ = s.write_all(&p);
    });
    assert_captured(&["victim_garbage", "DB, dropping the connection"]);
    c.close();
}

#[test]
fn client_receives_one_megabyte_strings_intact() {
    let _serial = serial();
    let (l, port) = fake_db();
    let mb = 1 << 20;
    let fake = std::thread::spawn(move || {
        let mut s = fake_welcome(&l);
        let v = "z".repeat(mb);
        let msgs: Vec<Message> = (0..5)
            .map(|i| {
                let mut m = Message::notify_string(&format!("BIG{i}"), &v, 1.0);
                m.source = "fake".into();
                m
            })
            .collect();
        s.write_all(&packet(&msgs)).expect("send");
        behave(s, Duration::from_secs(3));
    });
    let c = Client::connect(ClientConfig::new("127.0.0.1", port, "victim_big")).expect("connect");
    let got = mail_until(&c, Duration::from_secs(10), "big values", |got| {
        got.len() >= 5
    });
    assert!(got
        .iter()
        .all(|m| m.sval.len() == mb && m.sval.iter().all(|&b| b == b'z')));
    assert!(c.is_connected());
    c.close();
    let _ = fake.join();
}

/// A DB that still holds our previous connection (it was frozen, or the network
/// dropped) refuses the reconnect as a name clash. Found with a frozen `moosdb` in
/// helm/tests/db_death.rs: the client took that refusal as final and the helm never
/// reconnected. A refused *reconnect* is now retried; a refused first connect stays final.
#[test]
fn client_retries_a_reconnect_refused_as_a_name_clash() {
    let _serial = serial();
    let _ = captured_log();
    let (l, port) = fake_db();
    let fake = std::thread::spawn(move || {
        let s = fake_welcome(&l);
        drop(s); // the connection is lost
                 // The reconnect: refused as a clash, twice.
        for _ in 0..2 {
            let (mut s, _) = l.accept().expect("accept");
            let mut hs = vec![0u8; 4096];
            let _ = s.set_read_timeout(Some(Duration::from_secs(2)));
            let _ = s.read(&mut hs);
            let m = Message {
                msg_type: MsgType::POISON,
                data_type: DataType::STRING,
                sval: b"A client of this name (\"victim_clash\") already exists".to_vec(),
                ..Message::default()
            };
            let _ = s.write_all(&packet(&[m]));
        }
        behave(fake_welcome(&l), Duration::from_secs(5));
    });
    let c = Client::connect(ClientConfig::new("127.0.0.1", port, "victim_clash")).expect("first");
    wait_reconnected(&c, || {
        format!("no reconnect after refusals:\n{}", captured_log())
    });
    assert!(wait_captured(
        &["victim_clash", "refused the reconnect"],
        Duration::from_secs(1)
    ));
    c.close();
    let _ = fake.join();
}
