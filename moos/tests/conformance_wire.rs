//! Every captured packet decodes to its listed fields and re-encodes to the same bytes.

use std::path::PathBuf;

use moos::wire::{self, DataType, Message, MsgType};
use serde_json::Value;

fn capture_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../conformance/moos-wire/packets.jsonl")
}

fn hex(s: &str) -> Vec<u8> {
    assert!(s.len().is_multiple_of(2), "odd hex length");
    (0..s.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&s[i..i + 2], 16).expect("hex digit"))
        .collect()
}

fn ch(v: &Value) -> u8 {
    let s = v.as_str().expect("char field");
    assert_eq!(s.len(), 1, "type field must be one char: {s:?}");
    s.as_bytes()[0]
}

fn f(v: &Value) -> f64 {
    v.as_str().expect("float string").parse().expect("f64")
}

fn s(v: &Value) -> String {
    v.as_str().expect("string field").to_owned()
}

fn expected(m: &Value) -> Message {
    Message {
        id: m["id"].as_i64().expect("id") as i32,
        msg_type: MsgType(ch(&m["msg_type"])),
        data_type: DataType(ch(&m["data_type"])),
        source: s(&m["source"]),
        source_aux: s(&m["source_aux"]),
        community: s(&m["community"]),
        key: s(&m["key"]),
        time: f(&m["time"]),
        dval: f(&m["dval"]),
        dval2: f(&m["dval2"]),
        sval: s(&m["sval"]).into_bytes(),
    }
}

#[test]
fn every_captured_packet_round_trips() {
    let path = capture_path();
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("capture file {} is required: {e}", path.display()));
    let (mut packets, mut banners, mut messages) = (0, 0, 0);
    for (n, line) in text.lines().enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let o: Value = serde_json::from_str(line).unwrap_or_else(|e| panic!("line {}: {e}", n + 1));
        let bytes = hex(o["hex"].as_str().expect("hex"));
        match o["kind"].as_str() {
            Some("banner") => {
                assert_eq!(bytes.len(), 32);
                assert!(wire::banner_ok(&bytes), "line {}", n + 1);
                assert_eq!(bytes, wire::BANNER);
                banners += 1;
            }
            Some("packet") => {
                assert_eq!(bytes.len() as u64, o["packet_len"].as_u64().expect("len"));
                let got = wire::decode_packet(&bytes, wire::DEFAULT_MAX_PACKET)
                    .unwrap_or_else(|e| panic!("line {}: {e}", n + 1));
                let want: Vec<Message> = o["messages"]
                    .as_array()
                    .expect("messages")
                    .iter()
                    .map(expected)
                    .collect();
                assert_eq!(got.len() as u64, o["msg_count"].as_u64().expect("count"));
                for (i, (g, w)) in got.iter().zip(&want).enumerate() {
                    assert_eq!(g, w, "line {} message {i}", n + 1);
                    let ml = o["messages"][i]["msg_len"].as_u64().expect("msg_len");
                    assert_eq!(g.encoded_len() as u64, ml);
                    // bit-exact doubles
                    assert_eq!(g.time.to_bits(), w.time.to_bits());
                    assert_eq!(g.dval.to_bits(), w.dval.to_bits());
                    assert_eq!(g.dval2.to_bits(), w.dval2.to_bits());
                }
                let mut enc = Vec::new();
                wire::encode_packet(&want, &mut enc).expect("encode");
                assert_eq!(enc, bytes, "line {}: re-encoding differs", n + 1);
                packets += 1;
                messages += want.len();
            }
            other => panic!("line {}: unknown kind {other:?}", n + 1),
        }
    }
    assert!(packets > 0 && banners > 0, "capture had no packets");
    eprintln!("{packets} packets, {messages} messages, {banners} banners checked");
}

#[test]
fn spec_worked_examples() {
    let a = Message {
        id: 7,
        source: "pNav".into(),
        ..Message::notify_double("DEPTH", 12.5, 1700000000.25)
    };
    let b = Message {
        id: 3,
        source: "pHelm".into(),
        ..Message::notify_string("MODE", "SURVEY", 1700000000.25)
    };
    let mut out = Vec::new();
    wire::encode_packet(&[a.clone(), b.clone()], &mut out).expect("encode");
    let want = hex(concat!(
        "8d00000002000000003f000000070000004e44040000",
        "00704e617600000000000000000500000044455054480000",
        "1040fc54d9410000000000002940000000000000f0bf0000",
        "00004500000003000000",
        "4e5305000000704865",
        "6c6d00000000000000000400000",
        "04d4f44450000104",
        "0fc54d941000000000000f0bf000000000000f0bf0600000053555256",
        "4559"
    ));
    assert_eq!(out, want);
    assert_eq!(
        wire::decode_packet(&out, 1 << 20).expect("decode"),
        vec![a, b]
    );
}
