use std::io::{self, Read};
use std::ops::Range;

use super::{PacketHeader, WireError, PACKET_HEADER_LEN};

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
}

impl FrameReader {
    pub fn new(max_packet: usize) -> FrameReader {
        FrameReader {
            buf: Vec::new(),
            start: 0,
            end: 0,
            max_packet,
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
}
