//! Our client against our DB over loopback. Every wait is bounded.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::time::{Duration, Instant};

use moos::client::{Client, ClientConfig, ClientError};
use moos::wire::{self, DataType, FrameReader, Message, MsgType};
use moosdb::{Db, DbConfig};

fn db() -> Db {
    Db::start(DbConfig {
        port: 0,
        community: "testcomm".into(),
        ..DbConfig::default()
    })
    .expect("db starts")
}

fn client(db: &Db, name: &str) -> Client {
    Client::connect(ClientConfig::new("127.0.0.1", db.port(), name)).expect("client connects")
}

/// Collect mail until `pred` holds or `timeout` passes.
fn collect(c: &Client, timeout: Duration, pred: impl Fn(&[Message]) -> bool) -> Vec<Message> {
    let deadline = Instant::now() + timeout;
    let mut all = Vec::new();
    while Instant::now() < deadline && !pred(&all) {
        c.wait_for_mail(Duration::from_millis(50));
        c.fetch(&mut all);
    }
    all
}

fn keyed<'a>(m: &'a [Message], key: &str) -> Vec<&'a Message> {
    m.iter().filter(|m| m.key == key).collect()
}

#[test]
fn handshake_and_community() {
    let db = db();
    let c = client(&db, "alpha");
    assert!(c.is_connected());
    assert_eq!(c.community(), "testcomm");
    assert!(c.skew().abs() < 1.0);
    assert!((c.moos_time() - moos::time::wall_time()).abs() < 1.0);
    assert_eq!(db.client_names(), vec!["alpha".to_string()]);
}

#[test]
fn name_clash_is_refused() {
    let db = db();
    let _a = client(&db, "dup");
    let e = Client::connect(ClientConfig::new("127.0.0.1", db.port(), "dup")).err();
    assert_eq!(
        e,
        Some(ClientError::Poisoned(
            "A client of this name (\"dup\") already exists".into()
        ))
    );
}

#[test]
fn notify_types_order_and_current_value() {
    let db = db();
    let sub = client(&db, "sub");
    let pubr = client(&db, "pub");
    pubr.notify_double("EARLY", 7.0, Some(123.0)).expect("post");
    std::thread::sleep(Duration::from_millis(100));
    sub.register("EARLY", 0.0).expect("register");
    sub.register("X", 0.0).expect("register");
    sub.register("S", 0.0).expect("register");
    sub.register("B", 0.0).expect("register");
    // current value arrives on Register
    let m = collect(&sub, Duration::from_secs(3), |m| {
        !keyed(m, "EARLY").is_empty()
    });
    let e = keyed(&m, "EARLY")[0];
    assert_eq!(
        (e.dval, e.time, e.id, e.source.as_str()),
        (7.0, 123.0, -1, "pub")
    );
    assert_eq!(e.community, "testcomm");
    std::thread::sleep(Duration::from_millis(100));
    for i in 0..50 {
        pubr.notify_double("X", i as f64, None).expect("post");
    }
    pubr.notify_with_aux(
        Message::notify_string("S", "hello", pubr.moos_time()),
        "aux-info",
    )
    .expect("post");
    pubr.notify_binary("B", &[0, 1, 2, 255], None)
        .expect("post");
    let m = collect(&sub, Duration::from_secs(3), |m| !keyed(m, "B").is_empty());
    let xs: Vec<f64> = keyed(&m, "X").iter().map(|m| m.dval).collect();
    assert_eq!(
        xs,
        (0..50).map(f64::from).collect::<Vec<_>>(),
        "in order, none lost"
    );
    let s = keyed(&m, "S")[0];
    assert_eq!(
        (s.string().as_ref(), s.source_aux.as_str()),
        ("hello", "aux-info")
    );
    let b = keyed(&m, "B")[0];
    assert_eq!(
        (b.data_type, b.sval.as_slice()),
        (DataType::BINARY, &[0u8, 1, 2, 255][..])
    );
    assert!(m.iter().all(|m| m.msg_type == MsgType::NOTIFY));
}

/// A subscriber registered with an interval gets a post only when that interval has
/// passed (DB clock) since its last delivery: the others are dropped, not delayed.
/// Asserted on counts bounded by the time that actually passed, so a slow machine only
/// widens the bounds.
#[test]
fn register_interval_throttles_by_dropping() {
    let db = db();
    let sub = client(&db, "slowsub");
    let fast = client(&db, "fastsub");
    let pubr = client(&db, "pub");
    let interval = Duration::from_millis(500);
    sub.register("V", interval.as_secs_f64()).expect("register");
    fast.register("V", 0.0).expect("register");
    std::thread::sleep(Duration::from_millis(200));
    let start = Instant::now();
    let mut n = 0;
    while start.elapsed() < Duration::from_millis(1200) {
        pubr.notify_double("V", n as f64, None).expect("post");
        n += 1;
        std::thread::sleep(Duration::from_millis(20));
    }
    let fm = collect(&fast, Duration::from_secs(10), |m| keyed(m, "V").len() >= n);
    assert_eq!(
        keyed(&fm, "V").len(),
        n,
        "the unthrottled subscriber got them all"
    );
    // Every post has been processed: the DB's clock has advanced at most this much.
    let span = start.elapsed();
    let sm = collect(&sub, Duration::from_millis(300), |_| false);
    let got: Vec<f64> = keyed(&sm, "V").iter().map(|m| m.dval).collect();
    let most = 1 + (span.as_secs_f64() / interval.as_secs_f64()) as usize;
    assert!(
        !got.is_empty() && got.len() <= most,
        "{} deliveries of {n} posts in {span:?} (at most {most})",
        got.len()
    );
    assert!(got.windows(2).all(|w| w[1] > w[0]), "{got:?}");
    assert_eq!(got[0], 0.0, "the first post is delivered");
    // Dropped, not queued: a post once the interval has passed is delivered at once, and
    // it is that post, not an old one.
    std::thread::sleep(interval + Duration::from_millis(50));
    pubr.notify_double("V", -1.0, None).expect("post");
    let late = collect(&sub, Duration::from_secs(10), |m| !keyed(m, "V").is_empty());
    let late: Vec<f64> = keyed(&late, "V").iter().map(|m| m.dval).collect();
    assert_eq!(late, vec![-1.0], "after the interval");
}

#[test]
fn wildcard_and_unregister() {
    let db = db();
    let sub = client(&db, "wsub");
    let pubr = client(&db, "wpub");
    pubr.notify_string("W_OLD", "before", None).expect("post");
    std::thread::sleep(Duration::from_millis(100));
    sub.register_wildcard("W_*", "*", 0.0).expect("wildcard");
    sub.register("U", 0.0).expect("register");
    let m = collect(&sub, Duration::from_secs(2), |m| {
        !keyed(m, "W_OLD").is_empty()
    });
    assert_eq!(keyed(&m, "W_OLD")[0].string(), "before");
    pubr.notify_string("W_NEW", "after", None).expect("post");
    pubr.notify_string("OTHER", "no", None).expect("post");
    let m = collect(&sub, Duration::from_secs(2), |m| {
        !keyed(m, "W_NEW").is_empty()
    });
    assert_eq!(keyed(&m, "W_NEW")[0].string(), "after");
    assert!(keyed(&m, "OTHER").is_empty());
    sub.unregister("U").expect("unregister");
    std::thread::sleep(Duration::from_millis(100));
    pubr.notify_double("U", 1.0, None).expect("post");
    pubr.notify_string("W_NEW", "again", None).expect("post");
    let m = collect(&sub, Duration::from_secs(2), |m| {
        !keyed(m, "W_NEW").is_empty()
    });
    assert!(keyed(&m, "U").is_empty(), "unregistered variable delivered");
}

#[test]
fn type_is_fixed_by_first_write() {
    let db = db();
    let sub = client(&db, "tsub");
    let pubr = client(&db, "tpub");
    sub.register("T1", 0.0).expect("register");
    std::thread::sleep(Duration::from_millis(100));
    pubr.notify_double("T1", 1.0, None).expect("post");
    pubr.notify_string("T1", "wrong type", None).expect("post");
    pubr.notify_binary("T1", b"also wrong", None).expect("post");
    pubr.notify_double("T1", 2.0, None).expect("post");
    let m = collect(&sub, Duration::from_secs(2), |m| keyed(m, "T1").len() >= 2);
    std::thread::sleep(Duration::from_millis(100));
    let mut m = m;
    sub.fetch(&mut m);
    let t: Vec<&Message> = keyed(&m, "T1");
    assert_eq!(t.len(), 2);
    assert!(t.iter().all(|m| m.data_type == DataType::DOUBLE));
    assert_eq!((t[0].dval, t[1].dval), (1.0, 2.0));
}

#[test]
fn silent_client_dropped_after_five_seconds() {
    let db = db();
    let watcher = client(&db, "watcher");
    watcher.register("DB_EVENT", 0.0).expect("register");
    let mut s = TcpStream::connect(("127.0.0.1", db.port())).expect("connect");
    let hs = Message {
        msg_type: MsgType::DATA,
        data_type: DataType::STRING,
        key: "asynchronous".into(),
        time: moos::time::wall_time(),
        sval: b"silent".to_vec(),
        ..Message::default()
    };
    let mut buf = wire::BANNER.to_vec();
    wire::encode_packet(&[hs], &mut buf).expect("encode");
    s.write_all(&buf).expect("handshake");
    s.set_read_timeout(Some(Duration::from_millis(200)))
        .expect("timeout");
    let mut fr = FrameReader::new(1 << 20);
    let t0 = Instant::now();
    let mut closed_at = None;
    while t0.elapsed() < Duration::from_secs(9) {
        while let Ok(Some(_)) = fr.next_frame() {}
        match fr.fill(&mut s) {
            Ok(0) => {
                closed_at = Some(t0.elapsed());
                break;
            }
            Ok(_) => {}
            Err(_) => {}
        }
    }
    // Not before the 5 s client timeout (the upper bound is the 9 s of the loop: the
    // reader checks once a second, and a loaded machine may be late).
    let closed_at = closed_at.expect("DB closed the silent client");
    assert!(
        closed_at >= Duration::from_millis(4900),
        "closed after {closed_at:?}"
    );
    assert_eq!(db.client_names(), vec!["watcher".to_string()]);
    // the watcher (which heartbeats) is still there and saw the disconnect event
    watcher
        .notify_double("POKE", 1.0, None)
        .expect("still connected");
    let m = collect(&watcher, Duration::from_secs(2), |m| {
        m.iter().any(|m| m.string() == "disconnected=silent")
    });
    assert!(
        m.iter().any(|m| m.string() == "disconnected=silent"),
        "{m:?}"
    );
    let _ = s.read(&mut [0u8; 1]);
}

#[test]
fn bad_banner_is_closed_silently() {
    let db = db();
    let mut s = TcpStream::connect(("127.0.0.1", db.port())).expect("connect");
    s.write_all(&[b'x'; 32]).expect("write");
    s.set_read_timeout(Some(Duration::from_secs(3)))
        .expect("timeout");
    let mut b = [0u8; 16];
    let n = s.read(&mut b).unwrap_or(0);
    assert_eq!(n, 0, "nothing is sent for a bad banner");
}

#[test]
fn db_restart_client_reconnects_and_resubscribes() {
    let first = db();
    let port = first.port();
    let mut cfg = ClientConfig::new("127.0.0.1", port, "survivor");
    cfg.reconnect_max = Duration::from_millis(200);
    let sub = Client::connect(cfg).expect("connect");
    sub.register("R", 0.0).expect("register");
    sub.register_wildcard("RW_*", "*", 0.0).expect("wildcard");
    first.shutdown();
    let deadline = Instant::now() + Duration::from_secs(3);
    while sub.is_connected() && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(20));
    }
    assert!(!sub.is_connected(), "client noticed the DB went away");
    assert!(matches!(
        sub.notify_double("R", 1.0, None),
        Err(ClientError::NotConnected)
    ));
    let second = Db::start(DbConfig {
        port,
        community: "again".into(),
        ..DbConfig::default()
    })
    .expect("restart on the same port");
    sub.wait_connected(Duration::from_secs(5))
        .expect("reconnected");
    assert_eq!(sub.community(), "again");
    assert_eq!(sub.connection_count(), 2);
    let pubr = client(&second, "pub2");
    std::thread::sleep(Duration::from_millis(200));
    pubr.notify_double("R", 42.0, None).expect("post");
    pubr.notify_string("RW_1", "wild", None).expect("post");
    let m = collect(&sub, Duration::from_secs(3), |m| {
        !keyed(m, "R").is_empty() && !keyed(m, "RW_1").is_empty()
    });
    assert_eq!(keyed(&m, "R")[0].dval, 42.0);
    assert_eq!(keyed(&m, "RW_1")[0].string(), "wild");
}

#[test]
fn server_request_var_summary() {
    let db = db();
    let c = client(&db, "asker");
    c.notify_double("ZED", 1.0, None).expect("post");
    c.server_request("VAR_SUMMARY").expect("request");
    let m = collect(&c, Duration::from_secs(2), |m| {
        !keyed(m, "VAR_SUMMARY").is_empty()
    });
    let r = keyed(&m, "VAR_SUMMARY")[0];
    assert_eq!(r.id, -2);
    assert!(r.string().contains("ZED"));
}

#[test]
fn posts_made_just_before_close_are_delivered() {
    let db = db();
    let sub = client(&db, "sub");
    sub.register("LAST", 0.0).expect("register");
    std::thread::sleep(Duration::from_millis(100));
    let pubr = client(&db, "leaver");
    for i in 0..5000 {
        pubr.notify_double("LAST", f64::from(i), None)
            .expect("post");
    }
    drop(pubr); // at once: most of it is still in the client's queue or socket
    let m = collect(&sub, Duration::from_secs(5), |m| {
        keyed(m, "LAST").len() >= 5000
    });
    let got: Vec<f64> = keyed(&m, "LAST").iter().map(|m| m.dval).collect();
    assert_eq!(got.len(), 5000, "lost posts on close");
    assert!(got.iter().enumerate().all(|(i, v)| *v == i as f64));
}

#[test]
fn a_client_that_does_not_fetch_holds_a_bounded_inbox_and_loses_nothing() {
    // The subscriber's inbox is capped at 1 MiB: past it, it stops reading and the DB
    // holds the publisher back. 20 MB are posted; once fetched, every message is there,
    // in order.
    let db = db();
    let mut cfg = ClientConfig::new("127.0.0.1", db.port(), "slowapp");
    cfg.max_inbox_bytes = 1 << 20;
    let sub = Client::connect(cfg).expect("connect");
    sub.register("BULK", 0.0).expect("register");
    std::thread::sleep(Duration::from_millis(200));
    let publisher = client(&db, "bulk");
    let payload = "p".repeat(10_000);
    let n = 2000;
    let posting = std::thread::spawn(move || {
        for i in 0..n {
            publisher
                .notify_string("BULK", &format!("{i}:{payload}"), None)
                .expect("post");
        }
        publisher
    });
    std::thread::sleep(Duration::from_millis(1500));
    let held = sub.pending_mail_bytes();
    assert!(held < 3 << 20, "inbox grew to {held} bytes");
    let mut got = 0;
    let deadline = Instant::now() + Duration::from_secs(30);
    let mut mail = Vec::new();
    while got < n && Instant::now() < deadline {
        sub.wait_for_mail(Duration::from_millis(50));
        mail.clear();
        sub.fetch(&mut mail);
        for m in keyed(&mail, "BULK") {
            let s = m.string();
            let i: usize = s
                .split(':')
                .next()
                .and_then(|x| x.parse().ok())
                .expect("index");
            assert_eq!(i, got, "lost or out of order");
            got += 1;
        }
    }
    assert_eq!(got, n, "incomplete");
    let _publisher = posting.join().expect("publisher");
}
