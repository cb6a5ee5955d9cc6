#![no_main]
//! Arbitrary bytes as an `.alog`: never panics; what reads, written again, reads the same.

use libfuzzer_sys::fuzz_target;
use moos::alog::{self, AlogValue, AlogWriter};
use moos::wire::Message;

fuzz_target!(|data: &[u8]| {
    let Ok(log) = alog::read(data) else {
        return;
    };
    let mut w = AlogWriter::new(Vec::new(), 0.0, "again.alog").expect("header");
    for e in &log.entries {
        let mut m = match &e.value {
            AlogValue::Double(d) => Message::notify_double(&e.key, *d, e.time),
            AlogValue::String(s) => Message::notify_string(&e.key, s, e.time),
        };
        m.source = e.source.clone();
        m.source_aux = e.source_aux.clone();
        w.write(&m).expect("write to a Vec");
    }
    let again = alog::read(&w.into_inner()[..]).expect("our own alog reads back");
    assert_eq!(again.entries.len(), log.entries.len());
    for (a, b) in log.entries.iter().zip(&again.entries) {
        assert_eq!((&a.key, &a.source, &a.source_aux), (&b.key, &b.source, &b.source_aux));
    }
});
