use std::io::{self, Read};
use std::ops::Range;

use super::{MsgView, PacketHeader, WireError, MESSAGE_OVERHEAD, PACKET_HEADER_LEN};

const CHUNK: usize = 64 * 1024;

/// Room above this is given back once it holds nothing.
const BIG: usize = 1 << 20;

/// Accumulates bytes from a stream and yields complete packets.
///
/// TCP may split or merge packets; this buffers as bytes arrive and never reserves more
/// than one read chunk ahead, so a lying `pkt_len` costs nothing until the bytes come.
/// The buffer is zeroed only when it grows, not on every read.
pub struct FrameReader {
    /// `buf[start..end]` is buffered data; `buf[end..]` is initialized spare room.
    buf: Vec<u8>,
    start: usize,
    end: usize,
    max_packet: usize,
    /// The packet being taken in pieces ([`FrameReader::next_piece`]), if any.
    open: Option<OpenPacket>,
    /// Why the rest of the open packet is being skipped (taken by `take_bad`).
    bad: Option<WireError>,
}

/// What is left of a packet taken in pieces.
#[derive(Clone, Copy, Debug)]
struct OpenPacket {
    /// Body bytes not yet taken or skipped.
    bytes_left: usize,
    /// Messages not yet taken; 0 once the rest is being skipped.
    count_left: usize,
    /// No piece of it has been returned yet.
    first: bool,
}

/// A unit of input from [`FrameReader::next_piece`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Piece {
    /// A whole packet, header included (decode with `decode_packet_views`).
    Packet(Range<usize>),
    /// `count` whole, well-formed messages of a big packet, back to back (no header).
    /// `first`: the packet's first messages (where a timing message counts).
    Messages {
        range: Range<usize>,
        count: usize,
        first: bool,
    },
}

impl FrameReader {
    pub fn new(max_packet: usize) -> FrameReader {
        FrameReader {
            buf: Vec::new(),
            start: 0,
            end: 0,
            max_packet,
            open: None,
            bad: None,
        }
    }

    /// Read once from `r`, appending what arrives. Returns the bytes read (0 = EOF).
    pub fn fill<R: Read>(&mut self, r: &mut R) -> io::Result<usize> {
        if self.start == self.end && self.buf.len() > BIG {
            // A big packet has been taken: do not keep its room for the connection's life.
            self.buf = Vec::new();
            self.start = 0;
            self.end = 0;
        }
        if self.start > 0 && (self.start == self.end || self.start >= CHUNK) {
            self.buf.copy_within(self.start..self.end, 0);
            self.end -= self.start;
            self.start = 0;
        }
        let old = self.end;
        if self.buf.len() < old + CHUNK {
            self.buf.resize(old + CHUNK, 0);
        }
        let n = r.read(&mut self.buf[old..old + CHUNK])?;
        self.end = old + n;
        Ok(n)
    }

    /// The range of the next complete packet, if one is buffered. The header's length
    /// is validated as soon as 4 bytes are present (so an oversize packet fails early).
    pub fn next_frame(&mut self) -> Result<Option<Range<usize>>, WireError> {
        let avail = &self.buf[self.start..self.end];
        if avail.len() < 4 {
            return Ok(None);
        }
        let len = i32::from_le_bytes([avail[0], avail[1], avail[2], avail[3]]);
        if len < PACKET_HEADER_LEN as i32 {
            return Err(WireError::BadPacketLength {
                len,
                have: avail.len(),
            });
        }
        let ulen = len as usize;
        if ulen > self.max_packet {
            return Err(WireError::PacketTooLarge {
                len: ulen,
                cap: self.max_packet,
            });
        }
        if avail.len() < ulen {
            return Ok(None);
        }
        let r = self.start..self.start + ulen;
        self.start += ulen;
        Ok(Some(r))
    }

    /// Bytes of a frame returned by [`FrameReader::next_frame`] (valid until the next fill).
    pub fn frame(&self, r: Range<usize>) -> &[u8] {
        &self.buf[r]
    }

    /// Validate a frame's header (count etc.).
    pub fn header(&self, r: Range<usize>) -> Result<PacketHeader, WireError> {
        PacketHeader::parse(&self.buf[r], self.max_packet)
    }

    /// Buffered bytes not yet returned as frames.
    pub fn pending(&self) -> usize {
        self.end - self.start
    }

    /// The next packet, or for a packet longer than `piece` bytes the next run of its
    /// messages (at most `piece` bytes, or one message if that is longer): a reader
    /// that takes big packets this way buffers one message at a time, not the packet.
    /// A malformed message ends the packet as in the whole-packet decoder (it and the
    /// rest are skipped; the earlier ones were returned): see [`FrameReader::take_bad`].
    pub fn next_piece(&mut self, piece: usize) -> Result<Option<Piece>, WireError> {
        loop {
            let Some(mut open) = self.open else {
                let avail = &self.buf[self.start..self.end];
                if avail.len() < 4 {
                    return Ok(None);
                }
                let len = i32::from_le_bytes([avail[0], avail[1], avail[2], avail[3]]);
                if len >= PACKET_HEADER_LEN as i32 && len as usize <= piece {
                    return Ok(self.next_frame()?.map(Piece::Packet));
                }
                if avail.len() < PACKET_HEADER_LEN {
                    // Still validate the length early.
                    return self.next_frame().map(|_| None);
                }
                // Validate as a whole packet would be (length, count against the body).
                let h = PacketHeader::parse_prefix(avail, self.max_packet)?;
                self.start += PACKET_HEADER_LEN;
                self.open = Some(OpenPacket {
                    bytes_left: h.len - PACKET_HEADER_LEN,
                    count_left: h.count,
                    first: true,
                });
                continue;
            };
            if open.count_left == 0 {
                // Skip what follows the last message (or a malformed one).
                let n = open.bytes_left.min(self.end - self.start);
                self.start += n;
                open.bytes_left -= n;
                if open.bytes_left > 0 {
                    self.open = Some(open);
                    return Ok(None);
                }
                self.open = None;
                continue;
            }
            let from = self.start;
            let mut pos = from;
            let mut count = 0;
            while open.count_left > 0 {
                let Some(head) = self.buf.get(pos..pos + 4).filter(|_| pos + 4 <= self.end) else {
                    break;
                };
                let len = i32::from_le_bytes([head[0], head[1], head[2], head[3]]);
                let ok = len >= MESSAGE_OVERHEAD as i32 && (len as usize) <= open.bytes_left;
                if !ok {
                    self.bad = Some(WireError::BadPacketLength {
                        len,
                        have: open.bytes_left,
                    });
                    open.count_left = 0;
                    break;
                }
                let len = len as usize;
                if pos + len > self.end || (count > 0 && pos + len - from > piece) {
                    break;
                }
                if let Err(e) = MsgView::parse(&self.buf[pos..pos + len]) {
                    self.bad = Some(e);
                    open.count_left = 0;
                    break;
                }
                pos += len;
                count += 1;
                open.count_left -= 1;
                open.bytes_left -= len;
            }
            self.start = pos;
            let first = open.first;
            if count > 0 {
                open.first = false;
            }
            let more = open.bytes_left > 0;
            self.open = more.then_some(open);
            if count > 0 {
                return Ok(Some(Piece::Messages {
                    range: from..pos,
                    count,
                    first,
                }));
            }
            if more && open.count_left > 0 {
                return Ok(None); // a message still incomplete
            }
            // Otherwise: the rest is skipped, or the packet has ended.
        }
    }

    /// Why the packet being taken in pieces was cut short, once.
    pub fn take_bad(&mut self) -> Option<WireError> {
        self.bad.take()
    }

    /// Bytes that must be buffered at once before [`FrameReader::next_piece`] can
    /// return more: the length of the incomplete packet (taken whole) or message (of a
    /// packet taken in pieces); 0 while that is not known yet.
    pub fn wanted(&self, piece: usize) -> usize {
        let avail = &self.buf[self.start..self.end];
        let Some(head) = avail.get(..4) else {
            return 0;
        };
        let len = i32::from_le_bytes([head[0], head[1], head[2], head[3]]).max(0) as usize;
        match self.open {
            Some(o) if o.count_left > 0 => len,
            Some(_) => 0,
            None if len <= piece => len,
            None => PACKET_HEADER_LEN,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A packet of `len` bytes: a valid length prefix, then filler.
    fn packet(len: usize) -> Vec<u8> {
        let mut p = vec![0u8; len];
        p[..4].copy_from_slice(&(len as i32).to_le_bytes());
        p
    }

    #[test]
    fn room_for_a_big_packet_is_given_back_once_it_is_taken() {
        let mut fr = FrameReader::new(64 << 20);
        let big = packet(3 << 20);
        let mut src: &[u8] = &big;
        while fr.next_frame().expect("frame").is_none() {
            assert!(fr.fill(&mut src).expect("read") > 0);
        }
        assert!(fr.buf.len() >= 3 << 20);
        let small = packet(100);
        let mut src: &[u8] = &small;
        fr.fill(&mut src).expect("read");
        assert!(fr.buf.len() <= 2 * CHUNK, "kept {} bytes", fr.buf.len());
        let r = fr.next_frame().expect("frame").expect("complete");
        assert_eq!(fr.frame(r).len(), 100);
    }

    /// Messages from `next_piece` for `input` fed `step` bytes per read, with a
    /// piece size of `piece`: (message keys, pieces that were whole packets).
    fn pieces(input: &[u8], step: usize, piece: usize) -> (Vec<String>, usize, usize) {
        let mut fr = FrameReader::new(64 << 20);
        let mut src = input;
        let (mut keys, mut whole, mut peak) = (Vec::new(), 0, 0);
        loop {
            while let Some(p) = fr.next_piece(piece).expect("piece") {
                match p {
                    Piece::Packet(r) => {
                        whole += 1;
                        let msgs = super::super::decode_packet(fr.frame(r), 64 << 20).expect("ok");
                        keys.extend(msgs.into_iter().map(|m| m.key));
                    }
                    Piece::Messages { range, count, .. } => {
                        let mut b = fr.frame(range);
                        for _ in 0..count {
                            let (m, used) = MsgView::parse(b).expect("view");
                            keys.push(m.key.to_owned());
                            b = &b[used..];
                        }
                        assert!(b.is_empty());
                    }
                }
            }
            peak = peak.max(fr.pending());
            if src.is_empty() {
                break;
            }
            let n = step.min(src.len());
            let mut chunk = &src[..n];
            let got = fr.fill(&mut chunk).expect("read");
            src = &src[got..];
        }
        (keys, whole, peak)
    }

    fn big_packet(tag: &str, n: usize, size: usize) -> Vec<u8> {
        let msgs: Vec<super::super::Message> = (0..n)
            .map(|i| {
                super::super::Message::notify_string(&format!("{tag}{i}"), &"v".repeat(size), 1.0)
            })
            .collect();
        let mut out = Vec::new();
        super::super::encode_packet(&msgs, &mut out).expect("encode");
        out
    }

    #[test]
    fn big_packets_come_in_pieces_of_whole_messages_in_order() {
        let mut input = big_packet("S", 3, 10);
        input.extend(big_packet("B", 40, 100_000)); // 4 MB: taken in pieces
        input.extend(big_packet("T", 2, 10));
        for step in [1000, 4096, 65536, 1 << 20] {
            let (keys, whole, peak) = pieces(&input, step, 256 << 10);
            let want: Vec<String> = (0..3)
                .map(|i| format!("S{i}"))
                .chain((0..40).map(|i| format!("B{i}")))
                .chain((0..2).map(|i| format!("T{i}")))
                .collect();
            assert_eq!(keys, want, "step {step}");
            assert_eq!(whole, 2, "the small packets come whole");
            assert!(
                peak < (256 << 10) + step.max(CHUNK),
                "buffered {peak} bytes"
            );
        }
    }

    #[test]
    fn a_malformed_message_ends_its_packet_only() {
        let mut bad = big_packet("B", 10, 50_000);
        // Break the 6th message's length prefix.
        let mut pos = PACKET_HEADER_LEN;
        for _ in 0..5 {
            pos += i32::from_le_bytes(bad[pos..pos + 4].try_into().expect("4")) as usize;
        }
        bad[pos..pos + 4].copy_from_slice(&7i32.to_le_bytes());
        bad.extend(big_packet("T", 2, 10));
        let mut fr = FrameReader::new(64 << 20);
        let mut src: &[u8] = &bad;
        let mut keys = 0;
        let mut tail = 0;
        while !src.is_empty() || fr.pending() > 0 {
            match fr.next_piece(64 << 10).expect("piece") {
                Some(Piece::Messages { count, .. }) => keys += count,
                Some(Piece::Packet(_)) => tail += 1,
                None if src.is_empty() => break,
                None => {
                    fr.fill(&mut src).expect("read");
                }
            }
        }
        assert_eq!(keys, 5, "the messages before the bad one");
        assert!(fr.take_bad().is_some());
        assert_eq!(tail, 1, "the next packet is read");
    }
}
