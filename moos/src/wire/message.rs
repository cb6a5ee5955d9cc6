use std::borrow::Cow;
use std::fmt;

use super::WireError;

/// Fixed bytes of a serialized message besides its five strings (spec §2.1).
pub const MESSAGE_OVERHEAD: usize = 54;

/// Message kind (spec §2.2). Any byte is representable so decoding is lossless.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct MsgType(pub u8);

impl MsgType {
    pub const NOTIFY: MsgType = MsgType(b'N');
    pub const REGISTER: MsgType = MsgType(b'R');
    pub const UNREGISTER: MsgType = MsgType(b'U');
    pub const WILDCARD_REGISTER: MsgType = MsgType(b'*');
    pub const WILDCARD_UNREGISTER: MsgType = MsgType(b'/');
    pub const TIMING: MsgType = MsgType(b'T');
    pub const DATA: MsgType = MsgType(b'i');
    pub const WELCOME: MsgType = MsgType(b'W');
    pub const POISON: MsgType = MsgType(b'K');
    pub const NULL: MsgType = MsgType(b'.');
    pub const SERVER_REQUEST: MsgType = MsgType(b'Q');
    pub const COMMAND: MsgType = MsgType(b'C');
    pub const ANONYMOUS: MsgType = MsgType(b'A');
    pub const NOT_SET: MsgType = MsgType(b'~');
}

impl fmt::Debug for MsgType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "MsgType({:?})", self.0 as char)
    }
}

/// Payload kind (spec §2.3). `S` and `B` are distinct types.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct DataType(pub u8);

impl DataType {
    pub const DOUBLE: DataType = DataType(b'D');
    pub const STRING: DataType = DataType(b'S');
    pub const BINARY: DataType = DataType(b'B');
    pub const NOT_SET: DataType = DataType(b'~');
}

impl fmt::Debug for DataType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "DataType({:?})", self.0 as char)
    }
}

/// One MOOS message (C++ `CMOOSMsg`), fields in wire order.
///
/// The four name fields are `String` (real traffic is ASCII; non-UTF-8 names are a
/// [`WireError::NonUtf8`]); the payload `sval` is raw bytes so binary data round-trips.
#[derive(Clone, Debug, PartialEq)]
pub struct Message {
    pub id: i32,
    pub msg_type: MsgType,
    pub data_type: DataType,
    pub source: String,
    pub source_aux: String,
    pub community: String,
    pub key: String,
    pub time: f64,
    pub dval: f64,
    pub dval2: f64,
    pub sval: Vec<u8>,
}

impl Default for Message {
    /// The C++ default: `.`/`D`, id -1, time/dval/dval2 -1, empty strings (spec §2.4).
    fn default() -> Self {
        Message {
            id: -1,
            msg_type: MsgType::NULL,
            data_type: DataType::DOUBLE,
            source: String::new(),
            source_aux: String::new(),
            community: String::new(),
            key: String::new(),
            time: -1.0,
            dval: -1.0,
            dval2: -1.0,
            sval: Vec::new(),
        }
    }
}

impl Message {
    /// A notification of a double (`N`/`D`, sval empty, dval2 -1).
    pub fn notify_double(key: &str, value: f64, time: f64) -> Message {
        Message {
            msg_type: MsgType::NOTIFY,
            data_type: DataType::DOUBLE,
            key: key.to_owned(),
            time,
            dval: value,
            ..Message::default()
        }
    }

    /// A notification of a string (`N`/`S`, dval -1).
    pub fn notify_string(key: &str, value: &str, time: f64) -> Message {
        Message {
            msg_type: MsgType::NOTIFY,
            data_type: DataType::STRING,
            key: key.to_owned(),
            time,
            sval: value.as_bytes().to_vec(),
            ..Message::default()
        }
    }

    /// A notification of binary data (`N`/`B`, dval -1).
    pub fn notify_binary(key: &str, value: &[u8], time: f64) -> Message {
        Message {
            msg_type: MsgType::NOTIFY,
            data_type: DataType::BINARY,
            key: key.to_owned(),
            time,
            sval: value.to_vec(),
            ..Message::default()
        }
    }

    pub fn is_double(&self) -> bool {
        self.data_type == DataType::DOUBLE
    }
    pub fn is_string(&self) -> bool {
        self.data_type == DataType::STRING
    }
    pub fn is_binary(&self) -> bool {
        self.data_type == DataType::BINARY
    }

    /// The payload as text (lossy for non-UTF-8 bytes).
    pub fn string(&self) -> Cow<'_, str> {
        String::from_utf8_lossy(&self.sval)
    }

    /// The payload as text if it is valid UTF-8.
    pub fn sval_str(&self) -> Option<&str> {
        std::str::from_utf8(&self.sval).ok()
    }

    /// Serialized size: `54 + Σ string lengths` (spec §2.1).
    pub fn encoded_len(&self) -> usize {
        self.view().encoded_len()
    }

    /// Append the serialized message to `out`.
    ///
    /// Fails only when the message is too long for an i32 length.
    pub fn encode_into(&self, out: &mut Vec<u8>) -> Result<(), WireError> {
        self.view().encode_into(out)
    }

    /// Serialize into a fresh buffer.
    pub fn encode(&self) -> Result<Vec<u8>, WireError> {
        let mut v = Vec::with_capacity(self.encoded_len());
        self.encode_into(&mut v)?;
        Ok(v)
    }

    /// Decode one message from the start of `buf`, where `buf` is everything left in the
    /// enclosing packet. Returns the message and the declared `msg_len` (the number of
    /// bytes the caller must skip, spec §2.5).
    pub fn decode(buf: &[u8]) -> Result<(Message, usize), WireError> {
        let (v, used) = MsgView::parse(buf)?;
        Ok((v.to_message(), used))
    }

    /// Borrow this message as a [`MsgView`].
    pub fn view(&self) -> MsgView<'_> {
        MsgView {
            id: self.id,
            msg_type: self.msg_type,
            data_type: self.data_type,
            source: &self.source,
            source_aux: &self.source_aux,
            community: &self.community,
            key: &self.key,
            time: self.time,
            dval: self.dval,
            dval2: self.dval2,
            sval: &self.sval,
        }
    }
}

/// A message decoded in place: the same fields as [`Message`], borrowing the packet bytes
/// (no allocation). [`MsgView::parse`] applies exactly the checks of [`Message::decode`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MsgView<'a> {
    pub id: i32,
    pub msg_type: MsgType,
    pub data_type: DataType,
    pub source: &'a str,
    pub source_aux: &'a str,
    pub community: &'a str,
    pub key: &'a str,
    pub time: f64,
    pub dval: f64,
    pub dval2: f64,
    pub sval: &'a [u8],
}

impl<'a> MsgView<'a> {
    /// Decode one message from the start of `buf` (everything left in the packet).
    /// Returns the view and the declared `msg_len` (spec §2.5).
    pub fn parse(buf: &'a [u8]) -> Result<(MsgView<'a>, usize), WireError> {
        // A well-formed message lies within its declared length: parse that quickly, and
        // on any problem re-parse with the checked path for the exact error.
        if let Some(ok) = Self::parse_fast(buf) {
            return Ok(ok);
        }
        Self::parse_checked(buf)
    }

    fn parse_fast(buf: &'a [u8]) -> Option<(MsgView<'a>, usize)> {
        let len = i32::from_le_bytes(buf.get(..4)?.try_into().ok()?);
        if len < MESSAGE_OVERHEAD as i32 {
            return None;
        }
        let declared = len as usize;
        let mut c = Fast {
            buf: buf.get(..declared)?,
            pos: 4,
        };
        let id = i32::from_le_bytes(c.array()?);
        let [t, d] = c.array()?;
        // The four names, with their short (< 128, so ASCII) length prefixes between
        // them, are valid UTF-8 together exactly when each is: one validation call.
        let start = c.pos;
        let mut spans = [(0usize, 0usize); 4];
        for sp in &mut spans {
            let b = c.bytes()?;
            if b.len() >= 128 {
                return None;
            }
            *sp = (c.pos - b.len() - start, c.pos - start);
        }
        let names = std::str::from_utf8(&c.buf[start..c.pos]).ok()?;
        let [source, source_aux, community, key] = spans.map(|(a, b)| names.get(a..b));
        let (source, source_aux, community, key) = (source?, source_aux?, community?, key?);
        let time = f64::from_le_bytes(c.array()?);
        let dval = f64::from_le_bytes(c.array()?);
        let dval2 = f64::from_le_bytes(c.array()?);
        let sval = c.bytes()?;
        Some((
            MsgView {
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
            declared,
        ))
    }

    fn parse_checked(buf: &'a [u8]) -> Result<(MsgView<'a>, usize), WireError> {
        let mut c = Cursor { buf, pos: 0 };
        let len = c.i32("msg_len")?;
        if len < MESSAGE_OVERHEAD as i32 {
            return Err(WireError::MessageTooShort(len));
        }
        let declared = len as usize;
        if declared > buf.len() {
            return Err(WireError::MessageOverrun {
                len,
                left: buf.len(),
            });
        }
        let id = c.i32("id")?;
        let msg_type = MsgType(c.u8("msg_type")?);
        let data_type = DataType(c.u8("data_type")?);
        let source = c.str("source")?;
        let source_aux = c.str("source_aux")?;
        let community = c.str("community")?;
        let key = c.str("key")?;
        let time = c.f64("time")?;
        let dval = c.f64("dval")?;
        let dval2 = c.f64("dval2")?;
        let sval = c.bytes("sval")?;
        if c.pos > declared {
            return Err(WireError::FieldsExceedLength {
                parsed: c.pos,
                declared: len,
            });
        }
        Ok((
            MsgView {
                id,
                msg_type,
                data_type,
                source,
                source_aux,
                community,
                key,
                time,
                dval,
                dval2,
                sval,
            },
            declared,
        ))
    }

    /// An owned copy.
    pub fn to_message(&self) -> Message {
        Message {
            id: self.id,
            msg_type: self.msg_type,
            data_type: self.data_type,
            source: self.source.to_owned(),
            source_aux: self.source_aux.to_owned(),
            community: self.community.to_owned(),
            key: self.key.to_owned(),
            time: self.time,
            dval: self.dval,
            dval2: self.dval2,
            sval: self.sval.to_vec(),
        }
    }

    /// The payload as text (lossy for non-UTF-8 bytes).
    pub fn string(&self) -> Cow<'a, str> {
        String::from_utf8_lossy(self.sval)
    }

    /// Serialized size: `54 + Σ string lengths` (spec §2.1).
    pub fn encoded_len(&self) -> usize {
        MESSAGE_OVERHEAD
            + self.source.len()
            + self.source_aux.len()
            + self.community.len()
            + self.key.len()
            + self.sval.len()
    }

    /// Append the serialized message to `out` (same bytes as [`Message::encode_into`]).
    pub fn encode_into(&self, out: &mut Vec<u8>) -> Result<(), WireError> {
        let len = self.encoded_len();
        let len32 = i32::try_from(len).map_err(|_| WireError::TooLong("message"))?;
        out.reserve(len);
        out.extend_from_slice(&len32.to_le_bytes());
        out.extend_from_slice(&self.id.to_le_bytes());
        out.push(self.msg_type.0);
        out.push(self.data_type.0);
        put_str(out, self.source.as_bytes());
        put_str(out, self.source_aux.as_bytes());
        put_str(out, self.community.as_bytes());
        put_str(out, self.key.as_bytes());
        out.extend_from_slice(&self.time.to_le_bytes());
        out.extend_from_slice(&self.dval.to_le_bytes());
        out.extend_from_slice(&self.dval2.to_le_bytes());
        put_str(out, self.sval);
        Ok(())
    }
}

fn put_str(out: &mut Vec<u8>, s: &[u8]) {
    // Lengths were checked as a whole by encoded_len, so each part fits in an i32.
    out.extend_from_slice(&(s.len() as i32).to_le_bytes());
    out.extend_from_slice(s);
}

/// Reads within a declared message; `None` on anything unusual.
struct Fast<'a> {
    buf: &'a [u8],
    pos: usize,
}

impl<'a> Fast<'a> {
    #[inline]
    fn take(&mut self, n: usize) -> Option<&'a [u8]> {
        let s = self.buf.get(self.pos..self.pos.checked_add(n)?)?;
        self.pos += n;
        Some(s)
    }
    #[inline]
    fn array<const N: usize>(&mut self) -> Option<[u8; N]> {
        self.take(N)?.try_into().ok()
    }
    #[inline]
    fn bytes(&mut self) -> Option<&'a [u8]> {
        let n = i32::from_le_bytes(self.array()?);
        self.take(usize::try_from(n).ok()?)
    }
}

struct Cursor<'a> {
    buf: &'a [u8],
    pos: usize,
}

impl<'a> Cursor<'a> {
    fn take(&mut self, field: &'static str, n: usize) -> Result<&'a [u8], WireError> {
        let left = self.buf.len() - self.pos;
        if n > left {
            return Err(WireError::Truncated {
                field,
                needed: n,
                left,
            });
        }
        let s = &self.buf[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }
    fn array<const N: usize>(&mut self, field: &'static str) -> Result<[u8; N], WireError> {
        let s = self.take(field, N)?;
        let mut a = [0u8; N];
        a.copy_from_slice(s);
        Ok(a)
    }
    fn i32(&mut self, field: &'static str) -> Result<i32, WireError> {
        Ok(i32::from_le_bytes(self.array(field)?))
    }
    fn u8(&mut self, field: &'static str) -> Result<u8, WireError> {
        Ok(self.array::<1>(field)?[0])
    }
    fn f64(&mut self, field: &'static str) -> Result<f64, WireError> {
        Ok(f64::from_le_bytes(self.array(field)?))
    }
    fn bytes(&mut self, field: &'static str) -> Result<&'a [u8], WireError> {
        let len = self.i32(field)?;
        if len < 0 {
            return Err(WireError::NegativeLength { field, len });
        }
        self.take(field, len as usize)
    }
    fn str(&mut self, field: &'static str) -> Result<&'a str, WireError> {
        let b = self.bytes(field)?;
        std::str::from_utf8(b).map_err(|_| WireError::NonUtf8(field))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fast path agrees with the checked path on every single-byte mutation.
    #[test]
    fn fast_parse_matches_checked_parse() {
        let m = Message {
            id: 7,
            msg_type: MsgType::NOTIFY,
            data_type: DataType::STRING,
            source: "pNav".into(),
            source_aux: "é€".into(),
            community: "#1".into(),
            key: "DEPTH".into(),
            time: 1.5,
            dval: 2.5,
            dval2: -1.0,
            sval: b"SURVEY".to_vec(),
        };
        let enc = m.encode().expect("encode");
        for i in 0..enc.len() {
            for v in [0u8, 1, 3, 0x7f, 0x80, 0xa9, 0xc3, 0xff] {
                let mut b = enc.clone();
                b[i] = v;
                b.extend_from_slice(&[0xff; 3]);
                // Compared as Debug text so that NaN fields compare equal.
                let checked = format!("{:?}", MsgView::parse_checked(&b));
                if let Some(fast) = MsgView::parse_fast(&b) {
                    assert_eq!(format!("{:?}", Ok::<_, WireError>(fast)), checked);
                }
                assert_eq!(
                    format!("{:?}", MsgView::parse(&b)),
                    checked,
                    "byte {i} = {v:#x}"
                );
            }
        }
    }
}
