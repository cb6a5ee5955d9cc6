//! Fuzz harnesses of everything the `moos` crate reads from outside (issue 10), run by
//! `cargo test` on a bounded budget (`FUZZ_CASES`, `FUZZ_SECS`; see the `fuzzkit`
//! crate): the `.moos` mission reader, the `.alog` reader, and the wire decoder (one
//! message, a packet strictly / leniently / in place, and a byte stream through the
//! frame reader). Seeds are real files: `missions/*/*.moos`, and the packets recorded
//! from the C++ MOOS in `conformance/moos-wire/packets.jsonl` (also written out as an
//! alog for the alog reader).
//!
//! Invariants: no panic, no hang, bounded memory (fuzzkit); mission errors name the file
//! and line; what decodes re-encodes to bytes that decode to the same messages; what the
//! alog reader reads, written again and re-read, reads the same.

use std::path::{Path, PathBuf};

use moos::alog::{AlogValue, AlogWriter};
use moos::mission::MissionFile;
use moos::wire::{self, FrameReader, Message, MsgView};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn unhex(s: &str) -> Vec<u8> {
    (0..s.len() / 2)
        .map(|i| u8::from_str_radix(&s[2 * i..2 * i + 2], 16).expect("hex"))
        .collect()
}

/// The recorded packets (and banners) of the golden wire cases.
fn packet_seeds() -> Vec<Vec<u8>> {
    let text = std::fs::read_to_string(repo().join("conformance/moos-wire/packets.jsonl"))
        .expect("conformance/moos-wire/packets.jsonl");
    let mut v: Vec<Vec<u8>> = text
        .lines()
        .filter_map(|l| serde_json::from_str::<serde_json::Value>(l).ok())
        .filter_map(|j| j.get("hex").and_then(|h| h.as_str()).map(unhex))
        .collect();
    v.sort();
    v.dedup();
    assert!(v.len() > 10, "too few packet seeds");
    v
}

fn mission_seeds() -> Vec<Vec<u8>> {
    let mut v = fuzzkit::seed_files(&repo().join("missions"), "moos");
    v.push(
        b"ServerHost = localhost\nServerPort = 9000\ndefine: V = alpha\n\
          ProcessConfig = pHelmIvP\n{\n  behaviors = ${V}.bhv // c\n  url = \"a//b\"\n\
          [bracket]\n}\n"
            .to_vec(),
    );
    assert!(v.len() >= 2);
    v
}

const MOOS_DICT: &[&[u8]] = &[
    b"ProcessConfig = pHelmIvP\n",
    b"{\n",
    b"}\n",
    b"${",
    b"}",
    b"define: A = ${A}\n",
    b"//",
    b"\"",
    b" = ",
    b"[",
    b"]",
    b"#include self.moos\n",
    b"\xff",
    b"\r\n",
];

fn check_mission(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let path = Path::new("fuzz.moos");
    match MissionFile::parse(&text, path) {
        Ok(m) => {
            for g in ["ServerHost", "ServerPort", "MOOSTimeWarp", "Community"] {
                let _ = m.global(g);
                let _ = m.global_f64(g);
                let _ = m.global_bool(g);
            }
            for app in ["pHelmIvP", "uSimMarine", "nope"] {
                if let Some(lines) = m.process_config(app) {
                    let n = text.split('\n').count();
                    for l in lines {
                        assert!(l.line >= 1 && l.line <= n);
                        let _ = moos::mission::config_f64(&l.value);
                    }
                }
                let _ = m.config_value(app, "AppTick");
            }
        }
        Err(e) => {
            let s = e.to_string();
            assert!(s.contains("fuzz.moos:"), "error without file:line: {s}");
        }
    }
}

#[test]
fn fuzz_mission_reader() {
    fuzzkit::fuzz(
        "moos_mission",
        10000,
        &mission_seeds(),
        MOOS_DICT,
        check_mission,
    );
}

/// Same value, NaN included.
fn same_f64(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

fn same_msg(a: &Message, b: &Message) -> bool {
    a.id == b.id
        && a.msg_type == b.msg_type
        && a.data_type == b.data_type
        && (
            a.source.as_str(),
            a.source_aux.as_str(),
            a.community.as_str(),
            a.key.as_str(),
        ) == (
            b.source.as_str(),
            b.source_aux.as_str(),
            b.community.as_str(),
            b.key.as_str(),
        )
        && same_f64(a.time, b.time)
        && same_f64(a.dval, b.dval)
        && same_f64(a.dval2, b.dval2)
        && a.sval == b.sval
}

fn check_wire(data: &[u8]) {
    const CAP: usize = 1 << 20;
    // One message.
    if let Ok((m, used)) = Message::decode(data) {
        assert!(used <= data.len());
        let (v, used2) = MsgView::parse(data).expect("view agrees with owned decode");
        assert_eq!(used, used2);
        assert!(same_msg(&m, &v.to_message()));
        let enc = m.encode().expect("re-encode");
        let (back, n) = Message::decode(&enc).expect("re-decode");
        assert_eq!(n, enc.len());
        assert!(same_msg(&m, &back), "{m:?} != {back:?}");
    }
    // A packet: strict, lenient and in place agree, and round-trip.
    let strict = wire::decode_packet(data, CAP);
    let lenient = wire::decode_packet_lenient(data, CAP);
    let mut views = Vec::new();
    let inplace = wire::decode_packet_views(data, CAP, &mut views);
    match (&lenient, &inplace) {
        (Ok((msgs, err)), Ok(err2)) => {
            assert_eq!(err, err2);
            assert_eq!(msgs.len(), views.len());
            for (m, v) in msgs.iter().zip(&views) {
                assert!(same_msg(m, &v.to_message()));
            }
        }
        (Err(a), Err(b)) => assert_eq!(a, b),
        (a, b) => panic!("lenient {a:?} vs in-place {b:?}"),
    }
    if let Ok(msgs) = strict {
        let mut out = Vec::new();
        wire::encode_packet(&msgs, &mut out).expect("re-encode packet");
        let back = wire::decode_packet(&out, usize::MAX).expect("re-decode packet");
        assert_eq!(back.len(), msgs.len());
        for (a, b) in msgs.iter().zip(&back) {
            assert!(same_msg(a, b));
        }
        // Read in pieces (the DB's way with big packets): the same messages.
        let (got, _) = pieces(&out, 64, 5);
        assert_eq!(got.len(), msgs.len());
        for (a, b) in msgs.iter().zip(&got) {
            assert!(same_msg(a, b), "{a:?} != {b:?}");
        }
    }
    // Any bytes in pieces: no panic, and never more buffered than was sent.
    let _ = pieces(data, 64, 61 + data.len() % 97);
    // A stream, delivered in uneven pieces, through the frame reader.
    let mut fr = FrameReader::new(CAP);
    let mut frames = 0usize;
    'stream: for chunk in data.chunks(7 + data.len() % 13) {
        let mut r = chunk;
        match fr.fill(&mut r) {
            Ok(n) => assert_eq!(n, chunk.len()),
            Err(e) => panic!("fill from a slice failed: {e}"),
        }
        loop {
            match fr.next_frame() {
                Ok(Some(range)) => {
                    frames += 1;
                    let _ = fr.header(range.clone());
                    let _ = wire::decode_packet_lenient(fr.frame(range), CAP);
                }
                Ok(None) => break,
                Err(_) => break 'stream,
            }
        }
    }
    assert!(frames <= data.len() / wire::PACKET_HEADER_LEN + 1);
    assert!(fr.pending() <= data.len());
}

/// The messages `FrameReader::next_piece` yields for `data` fed `step` bytes at a time,
/// with pieces of `piece` bytes, up to the first framing error; and the bytes left.
fn pieces(data: &[u8], piece: usize, step: usize) -> (Vec<Message>, usize) {
    let mut fr = FrameReader::new(1 << 20);
    let mut got = Vec::new();
    'stream: for chunk in data.chunks(step) {
        let mut r = chunk;
        fr.fill(&mut r).expect("fill from a slice");
        loop {
            match fr.next_piece(piece) {
                Ok(Some(wire::Piece::Packet(range))) => {
                    if let Ok((m, _)) = wire::decode_packet_lenient(fr.frame(range), 1 << 20) {
                        got.extend(m);
                    }
                }
                Ok(Some(wire::Piece::Messages { range, count, .. })) => {
                    let mut b = fr.frame(range);
                    for _ in 0..count {
                        let (v, used) = MsgView::parse(b).expect("a piece holds whole messages");
                        got.push(v.to_message());
                        b = &b[used..];
                    }
                    assert!(b.is_empty(), "bytes after a piece's messages");
                }
                Ok(None) => break,
                Err(_) => break 'stream,
            }
        }
        assert!(fr.pending() <= data.len());
    }
    let _ = fr.take_bad();
    (got, fr.pending())
}

const WIRE_DICT: &[&[u8]] = &[
    &[0xff, 0xff, 0xff, 0x7f],
    &[0x00, 0x00, 0x00, 0x80],
    &[0xff, 0xff, 0xff, 0xff],
    &[0x36, 0, 0, 0],
    &[0x09, 0, 0, 0],
    &[0, 0, 0, 0],
    b"N",
    b"S",
    b"B",
    b"D",
    b"asynchronous",
    b"ELKS CAN'T DANCE 2/8/10\0\0\0\0\0\0\0\0\0",
];

#[test]
fn fuzz_wire_decoder() {
    fuzzkit::fuzz("moos_wire", 30000, &packet_seeds(), WIRE_DICT, check_wire);
}

/// The recorded messages, written as a pLogger-style alog.
fn alog_seeds() -> Vec<Vec<u8>> {
    let mut msgs = Vec::new();
    for p in packet_seeds() {
        if let Ok(m) = wire::decode_packet(&p, usize::MAX) {
            msgs.extend(m);
        }
    }
    let start = msgs.iter().map(|m| m.time).fold(f64::INFINITY, f64::min);
    let start = if start.is_finite() { start } else { 0.0 };
    let mut w = AlogWriter::new(Vec::new(), start, "fuzz.alog").expect("header");
    for m in msgs.iter().filter(|m| !m.key.is_empty()) {
        w.write(m).expect("write");
    }
    let whole = w.into_inner();
    let mut v = vec![whole.clone()];
    // Smaller pieces too, so mutations reach every part.
    for c in whole.split(|&b| b == b'\n').collect::<Vec<_>>().chunks(20) {
        v.push(c.join(&b'\n'));
    }
    v.push(
        b"%% LOGSTART  1795316330.37\n0.152  DB_TIME  MOOSDB_alpha  1795316330.5\n\
          1.000  DEPLOY  uPokeDB:aux  true\n"
            .to_vec(),
    );
    v
}

const ALOG_DICT: &[&[u8]] = &[
    b"%%",
    b"LOGSTART",
    b" ",
    b"\t",
    b":",
    b"\n",
    b"NaN",
    b"1e400",
];

/// An entry's value as the reader sees it once written back.
fn value_text(v: &AlogValue) -> String {
    match v {
        AlogValue::Double(d) => format!("{d}"),
        AlogValue::String(s) => s.clone(),
    }
}

fn check_alog(data: &[u8]) {
    let Ok(log) = moos::alog::read(data) else {
        return;
    };
    // Write what was read (as messages), read it again: same keys, sources and values.
    let start = 0.0;
    let mut w = AlogWriter::new(Vec::new(), start, "again.alog").expect("header");
    for e in &log.entries {
        let mut m = match &e.value {
            AlogValue::Double(d) => Message::notify_double(&e.key, *d, e.time),
            AlogValue::String(s) => Message::notify_string(&e.key, s, e.time),
        };
        m.source = e.source.clone();
        m.source_aux = e.source_aux.clone();
        w.write(&m).expect("write to a Vec");
    }
    let again = moos::alog::read(&w.into_inner()[..]).expect("our own alog reads back");
    assert_eq!(again.entries.len(), log.entries.len());
    for (a, b) in log.entries.iter().zip(&again.entries) {
        assert_eq!(a.key, b.key);
        assert_eq!((&a.source, &a.source_aux), (&b.source, &b.source_aux));
        assert_eq!(
            value_text(&a.value).replace(['\n', '\r'], " ").trim(),
            value_text(&b.value),
            "{a:?} vs {b:?}"
        );
        // Written with 3 decimals: off by up to half a millisecond (plus rounding of that).
        let close = (a.time - b.time).abs() <= 1e-3 * a.time.abs().max(1.0)
            || (a.time.is_nan() && b.time.is_nan())
            || a.time == b.time;
        assert!(close, "time {} read back as {}", a.time, b.time);
    }
}

#[test]
fn fuzz_alog_reader() {
    fuzzkit::fuzz("alog", 10000, &alog_seeds(), ALOG_DICT, check_alog);
}
