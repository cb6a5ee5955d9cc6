//! Replay the captured C++ client byte streams against our DB: the replies must have the
//! same types, keys and values as the real MOOSDB's (DB clock values and skews excepted).

use std::collections::BTreeMap;
use std::io::Write;
use std::net::TcpStream;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use moos::wire::{self, FrameReader, Message, MsgType};
use moosdb::{Db, DbConfig};
use serde_json::Value;

fn hex(s: &str) -> Vec<u8> {
    (0..s.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&s[i..i + 2], 16).expect("hex"))
        .collect()
}

#[derive(Default)]
struct Conn {
    banner: Option<Vec<u8>>,
    c2s: Vec<Vec<u8>>,
    s2c: Vec<Vec<Message>>,
}

fn load() -> BTreeMap<u64, Conn> {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../conformance/moos-wire/packets.jsonl");
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("capture file {} is required: {e}", path.display()));
    let mut conns: BTreeMap<u64, Conn> = BTreeMap::new();
    for line in text.lines().filter(|l| !l.trim().is_empty()) {
        let o: Value = serde_json::from_str(line).expect("json");
        let c = conns
            .entry(o["connection"].as_u64().expect("conn"))
            .or_default();
        let bytes = hex(o["hex"].as_str().expect("hex"));
        match (o["kind"].as_str(), o["direction"].as_str()) {
            (Some("banner"), _) => c.banner = Some(bytes),
            (Some("packet"), Some("C2S")) => c.c2s.push(bytes),
            (Some("packet"), Some("S2C")) => c
                .s2c
                .push(wire::decode_packet(&bytes, 1 << 24).expect("captured packet")),
            other => panic!("unexpected record {other:?}"),
        }
    }
    conns
}

fn read_all(s: &mut TcpStream, fr: &mut FrameReader, quiet: Duration) -> Vec<Vec<Message>> {
    s.set_read_timeout(Some(Duration::from_millis(50)))
        .expect("timeout");
    let mut out = Vec::new();
    let mut last = Instant::now();
    let start = Instant::now();
    while last.elapsed() < quiet && start.elapsed() < Duration::from_secs(5) {
        while let Some(r) = fr.next_frame().expect("frame") {
            out.push(wire::decode_packet(fr.frame(r), 1 << 24).expect("reply decodes"));
            last = Instant::now();
        }
        match fr.fill(s) {
            Ok(0) => break,
            Ok(_) => last = Instant::now(),
            Err(_) => {}
        }
    }
    out
}

/// The fields that must agree: everything except the DB's own clock in T echoes and the
/// welcome's time, skew and host name.
fn same(got: &Message, want: &Message) -> bool {
    let base = got.msg_type == want.msg_type
        && got.data_type == want.data_type
        && got.key == want.key
        && got.source == want.source
        && got.community == want.community
        && got.id == want.id
        && got.sval == want.sval;
    // Values the DB makes itself (DB_TIME, DB_UPTIME, ...) depend on its clock.
    if want.source.starts_with("MOOSDB_") {
        return got.msg_type == want.msg_type && got.key == want.key && got.source == want.source;
    }
    base && match want.msg_type {
        MsgType::TIMING => got.time == want.time && got.dval2 == want.dval2,
        MsgType::WELCOME => got.dval2 == want.dval2 && got.source_aux.starts_with("hostname="),
        _ => {
            got.time == want.time
                && got.dval.to_bits() == want.dval.to_bits()
                && got.dval2.to_bits() == want.dval2.to_bits()
                && got.source_aux == want.source_aux
        }
    }
}

/// Client send time of a captured packet (largest message time), for interleaving.
fn packet_time(p: &[u8]) -> f64 {
    wire::decode_packet(p, 1 << 24)
        .expect("c2s")
        .iter()
        .map(|m| m.time)
        .fold(f64::MIN, f64::max)
}

#[test]
fn captured_clients_get_the_same_replies() {
    let conns = load();
    let community = conns
        .values()
        .flat_map(|c| c.s2c.iter().flatten())
        .find(|m| m.msg_type == MsgType::WELCOME)
        .map(|m| m.community.clone())
        .expect("capture has a welcome");
    let db = Db::start(DbConfig {
        port: 0,
        community,
        ..DbConfig::default()
    })
    .expect("db");

    // Every C2S packet in (approximate) send order, the handshakes first per connection.
    let mut schedule: Vec<(f64, u64, usize)> = Vec::new();
    for (id, c) in &conns {
        for (i, p) in c.c2s.iter().enumerate() {
            schedule.push((packet_time(p), *id, i));
        }
    }
    schedule.sort_by(|a, b| a.0.total_cmp(&b.0));

    // Replay at the captured pace (interval throttling and the DB's 2 s refresh depend
    // on it), capped so a long capture cannot stall the suite.
    let t_first = schedule.first().map(|s| s.0).unwrap_or(0.0);
    let started = Instant::now();
    let mut socks: BTreeMap<u64, (TcpStream, FrameReader, Vec<Vec<Message>>)> = BTreeMap::new();
    for (t, id, i) in schedule {
        let due = Duration::from_secs_f64((t - t_first).clamp(0.0, 20.0));
        if let Some(wait) = due.checked_sub(started.elapsed()) {
            std::thread::sleep(wait);
        }
        let c = &conns[&id];
        if let std::collections::btree_map::Entry::Vacant(e) = socks.entry(id) {
            let mut s = TcpStream::connect(("127.0.0.1", db.port())).expect("connect");
            s.set_nodelay(true).expect("nodelay");
            s.write_all(c.banner.as_deref().unwrap_or(&wire::BANNER))
                .expect("banner");
            e.insert((s, FrameReader::new(1 << 24), Vec::new()));
        }
        let (s, fr, got) = socks.get_mut(&id).expect("socket");
        s.write_all(&c.c2s[i]).expect("send captured packet");
        std::thread::sleep(Duration::from_millis(30));
        got.extend(read_all(s, fr, Duration::from_millis(20)));
    }
    let mut compared = 0;
    for (id, (s, fr, got)) in socks.iter_mut() {
        got.extend(read_all(s, fr, Duration::from_millis(200)));
        let want = &conns[id].s2c;
        // Welcome first, identical in every compared field.
        assert!(
            same(&got[0][0], &want[0][0]),
            "conn {id} welcome: {:?}",
            got[0]
        );
        // Notification packets: same grouping and contents, in order (the capture may
        // end earlier than our replay, so it must be a prefix).
        let n_got: Vec<&Vec<Message>> = got
            .iter()
            .filter(|p| p[0].msg_type != MsgType::TIMING)
            .skip(1)
            .collect();
        let n_want: Vec<&Vec<Message>> = want
            .iter()
            .filter(|p| p[0].msg_type != MsgType::TIMING)
            .skip(1)
            .collect();
        assert!(
            n_got.len() >= n_want.len(),
            "conn {id}: {} notify packets, want {}",
            n_got.len(),
            n_want.len()
        );
        for (k, (g, w)) in n_got.iter().zip(&n_want).enumerate() {
            assert_eq!(g.len(), w.len(), "conn {id} notify packet {k}");
            compared += g.len();
            for (a, b) in g.iter().zip(w.iter()) {
                assert!(same(a, b), "conn {id} packet {k}: got {a:?} want {b:?}");
            }
        }
        // Timing echoes: one per T-led packet sent, echoing the client's time.
        let t_got: Vec<&Message> = got
            .iter()
            .filter(|p| p[0].msg_type == MsgType::TIMING)
            .map(|p| &p[0])
            .collect();
        let t_want: Vec<&Message> = want
            .iter()
            .filter(|p| p[0].msg_type == MsgType::TIMING)
            .map(|p| &p[0])
            .collect();
        assert!(
            t_got.len() >= t_want.len(),
            "conn {id}: {} T echoes, want {}",
            t_got.len(),
            t_want.len()
        );
        for (a, b) in t_got.iter().zip(&t_want) {
            assert!(same(a, b), "conn {id}: T echo {a:?} vs {b:?}");
            assert!(a.dval > 0.0, "echo carries the DB time");
        }
        // Every T-only packet was answered with only its echo.
        for p in got.iter().filter(|p| p[0].msg_type == MsgType::TIMING) {
            assert!(p.iter().skip(1).all(|m| m.msg_type != MsgType::TIMING));
        }
    }
    assert!(compared > 0, "no notification was compared");
    db.shutdown();
}
