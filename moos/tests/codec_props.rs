//! Property tests: arbitrary bytes never panic the decoder; encode→decode round-trips.

use moos::wire::{self, DataType, FrameReader, Message, MsgType, WireError};
use proptest::prelude::*;

fn arb_message() -> impl Strategy<Value = Message> {
    (
        any::<i32>(),
        any::<u8>(),
        prop_oneof![Just(b'D'), Just(b'S'), Just(b'B'), any::<u8>()],
        ".{0,12}",
        ".{0,12}",
        ".{0,12}",
        ".{0,16}",
        any::<f64>(),
        any::<f64>(),
        any::<f64>(),
        proptest::collection::vec(any::<u8>(), 0..64),
    )
        .prop_map(
            |(id, t, d, source, source_aux, community, key, time, dval, dval2, sval)| Message {
                id,
                msg_type: MsgType(t),
                data_type: DataType(d),
                source,
                source_aux,
                community,
                key,
                time,
                dval,
                dval2,
                sval,
            },
        )
}

fn same(a: &Message, b: &Message) -> bool {
    a.id == b.id
        && a.msg_type == b.msg_type
        && a.data_type == b.data_type
        && a.source == b.source
        && a.source_aux == b.source_aux
        && a.community == b.community
        && a.key == b.key
        && a.time.to_bits() == b.time.to_bits()
        && a.dval.to_bits() == b.dval.to_bits()
        && a.dval2.to_bits() == b.dval2.to_bits()
        && a.sval == b.sval
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..512)) {
        let _ = wire::decode_packet(&bytes, 1 << 16);
        let _ = wire::decode_packet_lenient(&bytes, 1 << 16);
        let _ = Message::decode(&bytes);
        let mut fr = FrameReader::new(1 << 16);
        let mut r = &bytes[..];
        while fr.fill(&mut r).map(|n| n > 0).unwrap_or(false) {}
        while let Ok(Some(range)) = fr.next_frame() {
            let _ = fr.header(range.clone());
            let _ = wire::decode_packet(fr.frame(range), 1 << 16);
        }
    }

    #[test]
    fn mutated_packets_never_panic(
        msgs in proptest::collection::vec(arb_message(), 1..4),
        flips in proptest::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..6),
    ) {
        let mut out = Vec::new();
        wire::encode_packet(&msgs, &mut out).unwrap();
        for (i, b) in flips {
            let i = i.index(out.len());
            out[i] = b;
        }
        let _ = wire::decode_packet(&out, 1 << 20);
    }

    #[test]
    fn encode_decode_round_trip(msgs in proptest::collection::vec(arb_message(), 1..6)) {
        let mut out = Vec::new();
        wire::encode_packet(&msgs, &mut out).unwrap();
        prop_assert_eq!(out.len(), 9 + msgs.iter().map(Message::encoded_len).sum::<usize>());
        let back = wire::decode_packet(&out, 1 << 20).unwrap();
        prop_assert_eq!(back.len(), msgs.len());
        for (a, b) in back.iter().zip(&msgs) {
            prop_assert!(same(a, b));
        }
        // Split arbitrarily across reads: the frame reader reassembles it.
        let mut fr = FrameReader::new(1 << 20);
        for chunk in out.chunks(7) {
            let mut r = chunk;
            fr.fill(&mut r).unwrap();
        }
        let range = fr.next_frame().unwrap().unwrap();
        prop_assert_eq!(fr.frame(range), &out[..]);
    }
}

#[test]
fn typed_errors() {
    let m = Message::notify_double("X", 1.0, 2.0);
    let mut pkt = Vec::new();
    wire::encode_packet(&[m.clone(), m], &mut pkt).unwrap();
    // oversize
    assert!(matches!(
        wire::decode_packet(&pkt, 20),
        Err(WireError::PacketTooLarge { .. })
    ));
    // absurd count
    let mut bad = pkt.clone();
    bad[4..8].copy_from_slice(&i32::MAX.to_le_bytes());
    assert!(matches!(
        wire::decode_packet(&bad, 1 << 20),
        Err(WireError::BadCount { .. })
    ));
    // negative packet length
    let mut bad = pkt.clone();
    bad[0..4].copy_from_slice(&(-5i32).to_le_bytes());
    assert!(matches!(
        wire::decode_packet(&bad, 1 << 20),
        Err(WireError::BadPacketLength { .. })
    ));
    // negative string length in the second message: the first is kept (lenient)
    let mut bad = pkt.clone();
    let second = 9 + 55;
    bad[second + 10..second + 14].copy_from_slice(&(-1i32).to_le_bytes());
    let (kept, err) = wire::decode_packet_lenient(&bad, 1 << 20).unwrap();
    assert_eq!(kept.len(), 1);
    assert!(matches!(err, Some(WireError::NegativeLength { .. })));
    // string length overrunning the packet
    let mut bad = pkt.clone();
    bad[9 + 10..9 + 14].copy_from_slice(&1_000_000i32.to_le_bytes());
    assert!(matches!(
        wire::decode_packet(&bad, 1 << 20),
        Err(WireError::Truncated { .. })
    ));
    // msg_len too short
    let mut bad = pkt.clone();
    bad[9..13].copy_from_slice(&10i32.to_le_bytes());
    assert!(matches!(
        wire::decode_packet(&bad, 1 << 20),
        Err(WireError::MessageTooShort(10))
    ));
    // frame reader rejects a huge declared length before the bytes arrive
    let mut fr = FrameReader::new(1024);
    let mut r = &i32::MAX.to_le_bytes()[..];
    fr.fill(&mut r).unwrap();
    assert!(matches!(
        fr.next_frame(),
        Err(WireError::PacketTooLarge { .. })
    ));
}
