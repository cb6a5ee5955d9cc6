use super::message::MESSAGE_OVERHEAD;
use super::{Message, MsgView, WireError};

/// Bytes of the packet header: i32 pkt_len, i32 count, u8 compressed flag.
pub const PACKET_HEADER_LEN: usize = 9;

/// The decoded 9-byte packet header.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PacketHeader {
    pub len: usize,
    pub count: usize,
    pub compressed: u8,
}

impl PacketHeader {
    /// Validate the header of a complete packet held in `buf`.
    pub fn parse(buf: &[u8], max_packet: usize) -> Result<PacketHeader, WireError> {
        let h = Self::parse_prefix(buf, max_packet)?;
        if h.len > buf.len() {
            return Err(WireError::BadPacketLength {
                len: h.len as i32,
                have: buf.len(),
            });
        }
        Ok(h)
    }

    /// Validate the header at the start of `buf`, which may hold only part of the packet.
    pub fn parse_prefix(buf: &[u8], max_packet: usize) -> Result<PacketHeader, WireError> {
        if buf.len() < PACKET_HEADER_LEN {
            return Err(WireError::Truncated {
                field: "packet header",
                needed: PACKET_HEADER_LEN,
                left: buf.len(),
            });
        }
        let len = i32::from_le_bytes([buf[0], buf[1], buf[2], buf[3]]);
        let count = i32::from_le_bytes([buf[4], buf[5], buf[6], buf[7]]);
        if len < PACKET_HEADER_LEN as i32 {
            return Err(WireError::BadPacketLength {
                len,
                have: buf.len(),
            });
        }
        let ulen = len as usize;
        if ulen > max_packet {
            return Err(WireError::PacketTooLarge {
                len: ulen,
                cap: max_packet,
            });
        }
        let body = ulen - PACKET_HEADER_LEN;
        if count < 0 || count as usize > body / MESSAGE_OVERHEAD {
            return Err(WireError::BadCount { count, bytes: body });
        }
        Ok(PacketHeader {
            len: ulen,
            count: count as usize,
            compressed: buf[8],
        })
    }
}

/// Decode a whole packet strictly: any malformed message is an error.
/// Bytes after the last message (up to `pkt_len`) are ignored, as in C++.
pub fn decode_packet(buf: &[u8], max_packet: usize) -> Result<Vec<Message>, WireError> {
    let (msgs, err) = decode_packet_lenient(buf, max_packet)?;
    match err {
        Some(e) => Err(e),
        None => Ok(msgs),
    }
}

/// Decode a packet the way the C++ reader does: a bad header is an error; a bad message
/// drops it and every later one, keeping the earlier ones (spec §2.5). Returns the kept
/// messages and the error that stopped decoding, if any.
pub fn decode_packet_lenient(
    buf: &[u8],
    max_packet: usize,
) -> Result<(Vec<Message>, Option<WireError>), WireError> {
    let h = PacketHeader::parse(buf, max_packet)?;
    let body = &buf[PACKET_HEADER_LEN..h.len];
    // count was bounded by body/54 in parse, so this reservation is justified by bytes.
    let mut msgs = Vec::with_capacity(h.count);
    let mut pos = 0;
    for _ in 0..h.count {
        match Message::decode(&body[pos..]) {
            Ok((m, used)) => {
                msgs.push(m);
                pos += used;
            }
            Err(e) => return Ok((msgs, Some(e))),
        }
    }
    Ok((msgs, None))
}

/// [`decode_packet_lenient`] without allocation per message: the kept messages are
/// appended to `out` as views into `buf`. Returns the error that stopped decoding, if any.
pub fn decode_packet_views<'a>(
    buf: &'a [u8],
    max_packet: usize,
    out: &mut Vec<MsgView<'a>>,
) -> Result<Option<WireError>, WireError> {
    let h = PacketHeader::parse(buf, max_packet)?;
    let body = &buf[PACKET_HEADER_LEN..h.len];
    out.reserve(h.count);
    let mut pos = 0;
    for _ in 0..h.count {
        match MsgView::parse(&body[pos..]) {
            Ok((m, used)) => {
                out.push(m);
                pos += used;
            }
            Err(e) => return Ok(Some(e)),
        }
    }
    Ok(None)
}

/// Encode `msgs` as one packet appended to `out`.
pub fn encode_packet(msgs: &[Message], out: &mut Vec<u8>) -> Result<(), WireError> {
    let mut b = PacketBuilder::new(out);
    for m in msgs {
        b.push(m)?;
    }
    b.finish()
}

/// Builds a packet in place: header placeholder, messages (encoded or pre-encoded),
/// then [`PacketBuilder::finish`] writes length and count.
pub struct PacketBuilder<'a> {
    out: &'a mut Vec<u8>,
    start: usize,
    count: usize,
}

impl<'a> PacketBuilder<'a> {
    pub fn new(out: &'a mut Vec<u8>) -> PacketBuilder<'a> {
        let start = out.len();
        out.extend_from_slice(&[0u8; PACKET_HEADER_LEN]);
        PacketBuilder {
            out,
            start,
            count: 0,
        }
    }
    /// Append one message.
    pub fn push(&mut self, m: &Message) -> Result<(), WireError> {
        m.encode_into(self.out)?;
        self.count += 1;
        Ok(())
    }
    /// Append `count` messages already serialized back to back.
    pub fn push_encoded(&mut self, bytes: &[u8], count: usize) {
        self.out.extend_from_slice(bytes);
        self.count += count;
    }
    pub fn count(&self) -> usize {
        self.count
    }
    /// Write the header. An empty packet is allowed here; callers must not send one.
    pub fn finish(self) -> Result<(), WireError> {
        let len = self.out.len() - self.start;
        let len32 = i32::try_from(len).map_err(|_| WireError::TooLong("packet"))?;
        let cnt = i32::try_from(self.count).map_err(|_| WireError::TooLong("packet"))?;
        self.out[self.start..self.start + 4].copy_from_slice(&len32.to_le_bytes());
        self.out[self.start + 4..self.start + 8].copy_from_slice(&cnt.to_le_bytes());
        self.out[self.start + 8] = 0;
        Ok(())
    }
}
