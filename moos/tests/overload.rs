//! A subscriber that stops reading is capped, reported and dropped; publishers and the
//! healthy subscribers are not slowed and lose nothing.

use std::io::Write;
use std::net::TcpStream;
use std::time::{Duration, Instant};

use moos::client::{Client, ClientConfig};
use moos::db::{Db, DbConfig};
use moos::wire::{self, DataType, Message, MsgType};

const CAP: usize = 4 * 1024 * 1024;
const PER_PUB: usize = 12_000;

fn raw_stalled_subscriber(port: u16, name: &str, var: &str) -> TcpStream {
    let mut s = TcpStream::connect(("127.0.0.1", port)).expect("connect");
    let hs = Message {
        msg_type: MsgType::DATA,
        data_type: DataType::STRING,
        key: "asynchronous".into(),
        time: moos::time::wall_time(),
        sval: name.as_bytes().to_vec(),
        ..Message::default()
    };
    let reg = Message {
        msg_type: MsgType::REGISTER,
        data_type: DataType::DOUBLE,
        source: name.into(),
        key: var.into(),
        time: moos::time::wall_time(),
        dval: 0.0,
        id: 0,
        ..Message::default()
    };
    let mut buf = wire::BANNER.to_vec();
    wire::encode_packet(&[hs], &mut buf).expect("encode");
    s.write_all(&buf).expect("handshake");
    std::thread::sleep(Duration::from_millis(100));
    let mut buf = Vec::new();
    wire::encode_packet(&[reg], &mut buf).expect("encode");
    s.write_all(&buf).expect("register");
    s // never read from again
}

#[test]
fn stalled_subscriber_is_capped_and_dropped() {
    let db = Db::start(DbConfig {
        port: 0,
        max_queue_bytes: CAP,
        ..DbConfig::default()
    })
    .expect("db");
    let port = db.port();
    let healthy: Vec<Client> = (0..2)
        .map(|i| {
            Client::connect(ClientConfig::new("127.0.0.1", port, &format!("good{i}"))).expect("sub")
        })
        .collect();
    for c in &healthy {
        c.register("LOAD", 0.0).expect("register");
        c.register("DB_EVENT", 0.0).expect("register");
    }
    let _stalled = raw_stalled_subscriber(port, "stalled", "LOAD");
    let pubs: Vec<Client> = (0..2)
        .map(|i| {
            Client::connect(ClientConfig::new("127.0.0.1", port, &format!("pub{i}"))).expect("pub")
        })
        .collect();
    std::thread::sleep(Duration::from_millis(200));
    assert!(db.client_names().contains(&"stalled".to_string()));

    let payload = "x".repeat(1000);
    let t0 = Instant::now();
    let handles: Vec<_> = pubs
        .into_iter()
        .enumerate()
        .map(|(p, c)| {
            let payload = payload.clone();
            std::thread::spawn(move || {
                for i in 0..PER_PUB {
                    c.notify_string("LOAD", &format!("{p}:{i}:{payload}"), None)
                        .expect("post");
                    // ~10k messages/s per publisher: fast, but within what a healthy
                    // subscriber reads, even in a debug build.
                    if i % 50 == 49 {
                        std::thread::sleep(Duration::from_millis(5));
                    }
                }
                c
            })
        })
        .collect();
    // Sample the stalled client's queue while the load runs.
    let mut max_q = 0usize;
    let mut counts = vec![[0usize; 2]; healthy.len()];
    let mut next = vec![[0usize; 2]; healthy.len()];
    let mut events: Vec<String> = Vec::new();
    let mut mail = Vec::new();
    let deadline = Instant::now() + Duration::from_secs(40);
    while Instant::now() < deadline {
        if let Some(q) = db.client_queued_bytes("stalled") {
            max_q = max_q.max(q);
        }
        for (k, c) in healthy.iter().enumerate() {
            mail.clear();
            c.fetch(&mut mail);
            for m in &mail {
                if m.key == "DB_EVENT" {
                    events.push(m.string().into_owned());
                    continue;
                }
                let s = m.string();
                let mut it = s.splitn(3, ':');
                let p: usize = it.next().and_then(|x| x.parse().ok()).expect("publisher");
                let i: usize = it.next().and_then(|x| x.parse().ok()).expect("index");
                assert_eq!(
                    i, next[k][p],
                    "subscriber {k} publisher {p}: out of order or lost"
                );
                next[k][p] += 1;
                counts[k][p] += 1;
            }
        }
        if counts.iter().all(|c| c[0] == PER_PUB && c[1] == PER_PUB) {
            break;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    let elapsed = t0.elapsed();
    let pubs: Vec<Client> = handles
        .into_iter()
        .map(|h| h.join().expect("publisher"))
        .collect();
    for c in &counts {
        assert_eq!(c, &[PER_PUB, PER_PUB], "a healthy subscriber lost messages");
    }
    assert!(
        max_q <= CAP,
        "stalled queue reached {max_q} bytes (cap {CAP})"
    );
    let stats = db.stats();
    assert!(stats.overflows >= 1, "overflow not reported: {stats:?}");
    assert!(!db.client_names().contains(&"stalled".to_string()));
    assert!(events.iter().any(|e| e == "overflow=stalled"), "{events:?}");
    assert!(
        events.iter().any(|e| e == "disconnected=stalled"),
        "{events:?}"
    );
    eprintln!(
        "{} msgs to 2 healthy subscribers in {elapsed:?}; stalled peak {max_q} B",
        2 * PER_PUB
    );

    // It gets the current value again when it comes back.
    let back = Client::connect(ClientConfig::new("127.0.0.1", port, "stalled")).expect("reconnect");
    back.register("LOAD", 0.0).expect("register");
    assert!(back.wait_for_mail(Duration::from_secs(3)));
    let mut m = Vec::new();
    back.fetch(&mut m);
    assert_eq!(m[0].key, "LOAD");
    assert_eq!(m[0].id, -1);
    drop(pubs);
}
