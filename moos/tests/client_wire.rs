//! What our client puts on the wire, checked by a scripted fake DB: banner in one piece,
//! handshake fields, `T` first, ids, register/wildcard templates (spec §4.2, §5.1).

use std::io::{Read, Write};
use std::net::TcpListener;
use std::time::{Duration, Instant};

use moos::client::{Client, ClientConfig};
use moos::wire::{self, DataType, FrameReader, Message, MsgType};

#[test]
fn client_messages_follow_the_templates() {
    let listener = TcpListener::bind("127.0.0.1:0").expect("bind");
    let port = listener.local_addr().expect("addr").port();
    let fake = std::thread::spawn(move || {
        let (mut s, _) = listener.accept().expect("accept");
        s.set_read_timeout(Some(Duration::from_millis(100)))
            .expect("timeout");
        let mut banner = [0u8; 32];
        s.read_exact(&mut banner).expect("banner");
        let mut fr = FrameReader::new(1 << 20);
        let mut packets: Vec<Vec<Message>> = Vec::new();
        let deadline = Instant::now() + Duration::from_millis(2600);
        let mut welcomed = false;
        while Instant::now() < deadline {
            while let Ok(Some(r)) = fr.next_frame() {
                packets.push(wire::decode_packet(fr.frame(r), 1 << 20).expect("client packet"));
            }
            if !welcomed && !packets.is_empty() {
                let w = Message {
                    msg_type: MsgType::WELCOME,
                    source_aux: "hostname=some-other-host".into(),
                    community: "fakecomm".into(),
                    time: moos::time::wall_time(),
                    dval: 0.25,
                    sval: b"asynchronous".to_vec(),
                    ..Message::default()
                };
                let mut out = Vec::new();
                wire::encode_packet(&[w], &mut out).expect("encode");
                s.write_all(&out).expect("welcome");
                welcomed = true;
            }
            let _ = fr.fill(&mut s);
        }
        (banner, packets)
    });
    let c = Client::connect(ClientConfig::new("127.0.0.1", port, "pTest")).expect("connect");
    assert_eq!(c.community(), "fakecomm");
    assert!(
        (c.skew() - 0.25).abs() < 1e-9,
        "welcome skew applied for another host"
    );
    c.register("NAV_X", 0.5).expect("register");
    c.register_wildcard("W_*", "*", 0.5).expect("wildcard");
    c.notify_string("MODE", "SURVEY", Some(1700000000.25))
        .expect("notify");
    c.unregister("NAV_X").expect("unregister");
    c.server_request("VAR_SUMMARY").expect("request");
    let (banner, packets) = fake.join().expect("fake db");
    assert_eq!(banner, wire::BANNER);

    let hs = &packets[0];
    assert_eq!(hs.len(), 1);
    let h = &hs[0];
    assert_eq!(
        (h.msg_type, h.data_type, h.id),
        (MsgType::DATA, DataType::STRING, -1)
    );
    assert_eq!(
        (h.key.as_str(), h.sval.as_slice()),
        ("asynchronous", &b"pTest"[..])
    );
    assert_eq!((h.source.as_str(), h.dval, h.dval2), ("", -1.0, -1.0));
    assert!((h.time - moos::time::wall_time()).abs() < 5.0);

    // Every T is first in its packet; the first packet after the handshake starts with T.
    assert_eq!(packets[1][0].msg_type, MsgType::TIMING);
    let mut user = Vec::new();
    let mut timings = 0;
    for p in &packets[1..] {
        assert!(!p.is_empty(), "no empty packets");
        for (i, m) in p.iter().enumerate() {
            if m.msg_type == MsgType::TIMING {
                assert_eq!(i, 0, "T only in first position");
                assert_eq!(
                    (m.key.as_str(), m.dval, m.dval2, m.id),
                    ("_async_timing", 0.0, -1.0, -1)
                );
                assert_eq!(m.source, "");
                timings += 1;
            } else {
                user.push(m.clone());
            }
        }
    }
    assert!(timings >= 2, "heartbeat about once a second: {timings}");
    let kinds: Vec<u8> = user.iter().map(|m| m.msg_type.0).collect();
    assert_eq!(kinds, b"R*NUQ".to_vec());
    let ids: Vec<i32> = user.iter().map(|m| m.id).collect();
    assert_eq!(ids, vec![0, 1, 2, 3, -2]);
    assert!(user
        .iter()
        .all(|m| m.source == "pTest" && m.dval2 == -1.0 && m.community.is_empty()));
    assert_eq!(
        (user[0].key.as_str(), user[0].dval, user[0].data_type),
        ("NAV_X", 0.5, DataType::DOUBLE)
    );
    assert_eq!(user[1].key, "pTest");
    assert_eq!(user[1].string(), "AppPattern=*,VarPattern=W_*,Interval=0.5");
    assert_eq!((user[1].data_type, user[1].dval), (DataType::STRING, -1.0));
    assert_eq!(
        (user[2].key.as_str(), user[2].time, user[2].dval),
        ("MODE", 1700000000.25, -1.0)
    );
    assert_eq!(user[2].string(), "SURVEY");
    assert_eq!((user[3].key.as_str(), user[3].dval), ("NAV_X", 0.0));
    assert_eq!(
        (user[4].key.as_str(), user[4].data_type),
        ("VAR_SUMMARY", DataType::STRING)
    );
}
