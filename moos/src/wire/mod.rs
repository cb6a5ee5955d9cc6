//! The MOOS V10 wire format (spec §1–§3).
//!
//! Everything is little-endian; lengths and counts are `i32`. Decoding never panics and
//! never allocates more than the input justifies: every length is checked against the
//! bytes left in the enclosing packet before anything is reserved.

mod error;
mod frame;
mod message;
mod packet;

pub use error::WireError;
pub use frame::{FrameReader, Piece};
pub use message::{DataType, Message, MsgType, MsgView, MESSAGE_OVERHEAD};
pub use packet::{
    decode_packet, decode_packet_lenient, decode_packet_views, encode_packet, PacketBuilder,
    PacketHeader, PACKET_HEADER_LEN,
};

/// The 32-byte protocol banner a client sends first (23 ASCII bytes + 9 NULs).
pub const BANNER: [u8; 32] = *b"ELKS CAN'T DANCE 2/8/10\0\0\0\0\0\0\0\0\0";
/// The handshake key of a V10 asynchronous client.
pub const ASYNC_KEY: &str = "asynchronous";
/// Key of the automatic timing message.
pub const TIMING_KEY: &str = "_async_timing";
/// Default packet-size cap used by the DB and client (64 MiB).
pub const DEFAULT_MAX_PACKET: usize = 64 * 1024 * 1024;

/// Whether a received banner is acceptable: text up to the first NUL equals the V10 banner,
/// ignoring ASCII case (spec §4.3 step 2).
pub fn banner_ok(b: &[u8]) -> bool {
    let end = b.iter().position(|&c| c == 0).unwrap_or(b.len());
    b[..end].eq_ignore_ascii_case(&BANNER[..23])
}
