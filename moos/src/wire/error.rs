use thiserror::Error;

/// A malformed or unacceptable message or packet.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum WireError {
    /// A field needed more bytes than are left in the packet.
    #[error("truncated {field}: needs {needed} bytes, {left} left")]
    Truncated {
        field: &'static str,
        needed: usize,
        left: usize,
    },
    /// A string length was negative.
    #[error("negative length {len} for {field}")]
    NegativeLength { field: &'static str, len: i32 },
    /// `msg_len` is below the 54-byte minimum.
    #[error("message length {0} is below the 54-byte minimum")]
    MessageTooShort(i32),
    /// `msg_len` runs past the end of the packet.
    #[error("message length {len} runs past the packet end ({left} bytes left)")]
    MessageOverrun { len: i32, left: usize },
    /// The fields parsed extend past the declared `msg_len`.
    #[error("message fields ({parsed} bytes) exceed the declared msg_len {declared}")]
    FieldsExceedLength { parsed: usize, declared: i32 },
    /// `pkt_len` is below 9 or disagrees with the bytes given.
    #[error("bad packet length {len} ({have} bytes available)")]
    BadPacketLength { len: i32, have: usize },
    /// `pkt_len` exceeds the configured cap.
    #[error("packet length {len} exceeds the cap of {cap} bytes")]
    PacketTooLarge { len: usize, cap: usize },
    /// `count` is negative or more than the bytes could hold.
    #[error("bad message count {count} for {bytes} bytes of messages")]
    BadCount { count: i32, bytes: usize },
    /// A name field (source, source_aux, community, key) is not UTF-8.
    #[error("{0} is not valid UTF-8")]
    NonUtf8(&'static str),
    /// A field too long to encode in an i32 length.
    #[error("{0} is too long to encode")]
    TooLong(&'static str),
}
