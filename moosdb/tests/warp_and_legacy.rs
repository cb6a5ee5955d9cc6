//! Time warp (timestamps, warped intervals, DB_* refresh) and legacy synchronous clients.

use std::io::Write;
use std::net::TcpStream;
use std::time::{Duration, Instant};

use moos::client::{Client, ClientConfig};
use moos::wire::{self, DataType, FrameReader, Message, MsgType};
use moosdb::{Db, DbConfig};

#[test]
fn time_warp_scales_clocks_intervals_and_db_vars() {
    let warp = 10.0;
    let db = Db::start(DbConfig {
        port: 0,
        time_warp: warp,
        community: "warped".into(),
        ..DbConfig::default()
    })
    .expect("db");
    let mut cfg = ClientConfig::new("127.0.0.1", db.port(), "warper");
    cfg.time_warp = warp;
    let c = Client::connect(cfg.clone()).expect("connect");
    let wall = moos::time::wall_time();
    assert!(
        (c.moos_time() - wall * warp).abs() < 5.0,
        "MOOSTime is wall x warp"
    );
    c.register("DB_CLIENTS", 0.0).expect("register");
    c.register("DB_TIME", 0.0).expect("register");
    cfg.name = "warppub".into();
    let p = Client::connect(cfg).expect("connect");
    // interval 5 MOOS s = 0.5 real s: a delivery at most every 0.5 s of the time that
    // actually passed (bounds from measured time, not a schedule).
    c.register("TICK", 5.0).expect("register");
    std::thread::sleep(Duration::from_millis(100));
    let t0 = Instant::now();
    let mut posted = 0;
    while t0.elapsed() < Duration::from_millis(1200) {
        p.notify_double("TICK", 1.0, None).expect("post");
        posted += 1;
        std::thread::sleep(Duration::from_millis(20));
    }
    // A marker through the same DB: once it is back, every TICK has been processed.
    p.notify_double("DB_MARK", 1.0, None).expect("post");
    c.register("DB_MARK", 0.0).expect("register");
    let mut m = Vec::new();
    let deadline = Instant::now() + Duration::from_secs(10);
    while !m.iter().any(|m: &moos::Message| m.key == "DB_MARK") && Instant::now() < deadline {
        c.wait_for_mail(Duration::from_millis(50));
        c.fetch(&mut m);
    }
    let span = t0.elapsed();
    let ticks = m.iter().filter(|m| m.key == "TICK").count();
    let most = 1 + (span.as_secs_f64() / 0.5) as usize;
    assert!(
        ticks >= 1 && ticks <= most && ticks < posted,
        "5 MOOS s interval at warp 10: {ticks} of {posted} posts in {span:?} (at most {most})"
    );
    // more than 2 MOOS s have passed: DB_* refreshed on traffic
    let clients: Vec<String> = m
        .iter()
        .filter(|m| m.key == "DB_CLIENTS")
        .map(|m| m.string().into_owned())
        .collect();
    assert!(!clients.is_empty(), "DB_CLIENTS refreshed");
    let last = clients.last().expect("one");
    assert!(
        last.contains("warper,") && last.contains("warppub,"),
        "{last}"
    );
    let t = m.iter().find(|m| m.key == "DB_TIME").expect("DB_TIME");
    assert!((t.dval - wall * warp).abs() < 60.0);
    assert_eq!(t.source, "MOOSDB_warped");
    assert_eq!(t.data_type, DataType::DOUBLE);
}

fn read_packet(s: &mut TcpStream, fr: &mut FrameReader) -> Vec<Message> {
    let deadline = Instant::now() + Duration::from_secs(3);
    while Instant::now() < deadline {
        if let Ok(Some(r)) = fr.next_frame() {
            return wire::decode_packet(fr.frame(r), 1 << 20).expect("decode");
        }
        let _ = fr.fill(s);
    }
    panic!("no packet");
}

/// A legacy synchronous client named `legacy`: banner and handshake sent, nothing read.
fn legacy_handshake(port: u16) -> TcpStream {
    let mut s = TcpStream::connect(("127.0.0.1", port)).expect("connect");
    s.set_read_timeout(Some(Duration::from_millis(100)))
        .expect("timeout");
    let hs = Message {
        msg_type: MsgType::DATA,
        data_type: DataType::STRING,
        key: String::new(), // legacy synchronous: no asynchronous key
        time: moos::time::wall_time(),
        sval: b"legacy".to_vec(),
        ..Message::default()
    };
    let mut buf = wire::BANNER.to_vec();
    wire::encode_packet(&[hs], &mut buf).expect("encode");
    s.write_all(&buf).expect("handshake");
    s
}

#[test]
fn synchronous_client_gets_null_first_and_held_mail() {
    let db = Db::start(DbConfig {
        port: 0,
        ..DbConfig::default()
    })
    .expect("db");
    let p = Client::connect(ClientConfig::new("127.0.0.1", db.port(), "apub")).expect("connect");
    let mut s = legacy_handshake(db.port());
    let mut fr = FrameReader::new(1 << 20);
    let w = read_packet(&mut s, &mut fr);
    assert_eq!(w[0].msg_type, MsgType::WELCOME);
    let reg = Message {
        msg_type: MsgType::REGISTER,
        source: "legacy".into(),
        key: "SV".into(),
        dval: 0.0,
        id: 0,
        ..Message::default()
    };
    let mut buf = Vec::new();
    wire::encode_packet(&[reg], &mut buf).expect("encode");
    s.write_all(&buf).expect("register");
    let r = read_packet(&mut s, &mut fr);
    assert_eq!(r[0].msg_type, MsgType::NULL, "NULL first in every reply");
    assert!(r[0].dval > 1e9, "NULL carries the DB time");
    p.notify_string("SV", "v1", None).expect("post");
    std::thread::sleep(Duration::from_millis(200));
    // nothing is pushed to a synchronous client ...
    let _ = fr.fill(&mut s);
    assert!(fr.next_frame().expect("frame").is_none());
    // ... until it polls
    let null = Message {
        source: "legacy".into(),
        ..Message::default()
    };
    let mut buf = Vec::new();
    wire::encode_packet(&[null], &mut buf).expect("encode");
    s.write_all(&buf).expect("poll");
    let r = read_packet(&mut s, &mut fr);
    assert_eq!(r[0].msg_type, MsgType::NULL);
    assert_eq!(r[1].key, "SV");
    assert_eq!(r[1].string(), "v1");
}

/// A synchronous client only gets mail when it polls, so its held mail is its queue:
/// polling slowly under a flood, it holds the flooder back and loses nothing.
#[test]
fn slow_polling_synchronous_client_holds_back_the_flooder() {
    let cap = 4 << 20;
    let db = Db::start(DbConfig {
        port: 0,
        max_queue_bytes: cap,
        ..DbConfig::default()
    })
    .expect("db");
    let mut s = legacy_handshake(db.port());
    let mut fr = FrameReader::new(64 << 20);
    assert_eq!(read_packet(&mut s, &mut fr)[0].msg_type, MsgType::WELCOME);
    let reg = Message {
        msg_type: MsgType::REGISTER,
        source: "legacy".into(),
        key: "LOAD".into(),
        ..Message::default()
    };
    let poll = |s: &mut TcpStream, fr: &mut FrameReader, m: &Message| {
        let mut buf = Vec::new();
        wire::encode_packet(std::slice::from_ref(m), &mut buf).expect("encode");
        s.write_all(&buf).expect("poll");
        let deadline = Instant::now() + Duration::from_secs(3);
        while Instant::now() < deadline {
            if let Ok(Some(r)) = fr.next_frame() {
                return wire::decode_packet(fr.frame(r), usize::MAX).expect("decode");
            }
            let _ = fr.fill(s);
        }
        panic!("no reply");
    };
    poll(&mut s, &mut fr, &reg);
    let null = Message {
        source: "legacy".into(),
        ..Message::default()
    };
    let flooder = Client::connect(ClientConfig::new("127.0.0.1", db.port(), "flood")).expect("pub");
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let st2 = stop.clone();
    let pubt = std::thread::spawn(move || {
        let payload = "x".repeat(200);
        let mut i = 0usize;
        while !st2.load(std::sync::atomic::Ordering::Relaxed) {
            if flooder.unsent_bytes() > 256 << 10 {
                std::thread::sleep(Duration::from_micros(300));
                continue;
            }
            flooder
                .notify_string("LOAD", &format!("{i}:{payload}"), None)
                .expect("post");
            i += 1;
        }
        (i, flooder)
    });
    let (mut next, mut held_back, mut max_q) = (0usize, false, 0usize);
    let take = |r: Vec<Message>, next: &mut usize| {
        for m in r.iter().filter(|m| m.key == "LOAD") {
            let i: usize = m
                .string()
                .split(':')
                .next()
                .and_then(|x| x.parse().ok())
                .expect("i");
            assert_eq!(i, *next, "lost or out of order");
            *next += 1;
        }
    };
    let t0 = Instant::now();
    while t0.elapsed() < Duration::from_millis(1500) {
        std::thread::sleep(Duration::from_millis(200));
        held_back |= db.client_holding("legacy").unwrap_or(0) > 0;
        max_q = max_q.max(db.client_queued_bytes("legacy").unwrap_or(0));
        let r = poll(&mut s, &mut fr, &null);
        take(r, &mut next);
    }
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    let (posted, _flooder) = pubt.join().expect("publisher");
    let deadline = Instant::now() + Duration::from_secs(20);
    while next < posted && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(20));
        let r = poll(&mut s, &mut fr, &null);
        take(r, &mut next);
    }
    assert_eq!(
        next, posted,
        "the synchronous client did not get everything"
    );
    assert!(
        held_back,
        "the flooder was never held back ({posted} posted)"
    );
    assert!(max_q <= cap, "queue reached {max_q} B");
    assert!(db.client_names().contains(&"legacy".to_string()));
}
