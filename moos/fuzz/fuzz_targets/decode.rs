#![no_main]
//! Arbitrary bytes through every decoding entry point: must never panic, and anything that
//! decodes must re-encode to a packet that decodes to the same messages.

use libfuzzer_sys::fuzz_target;
use moos::wire::{self, FrameReader, Message};

fuzz_target!(|data: &[u8]| {
    let _ = Message::decode(data);
    if let Ok(msgs) = wire::decode_packet(data, 1 << 20) {
        let mut out = Vec::new();
        if wire::encode_packet(&msgs, &mut out).is_ok() {
            let back = wire::decode_packet(&out, usize::MAX).expect("re-decode");
            assert_eq!(back.len(), msgs.len());
        }
    }
    let mut fr = FrameReader::new(1 << 20);
    let mut r = data;
    while fr.fill(&mut r).map(|n| n > 0).unwrap_or(false) {}
    while let Ok(Some(range)) = fr.next_frame() {
        let _ = wire::decode_packet_lenient(fr.frame(range), 1 << 20);
    }
});
