//! One `NODE_REPORT` string read into its fields (contacts-appcast.md §2.2).
//!
//! The form pNodeReporter writes is a comma list of `KEY=value` pairs (keys
//! case-insensitive, values trimmed); a report wrapped in `{...}` is read as JSON-ish
//! (`{"NAME":"alpha","X":"1"}`: quotes removed, `:` between key and value). Commas inside
//! braces do not split. Numeric fields count only when their text passes the helm's
//! number test (`mbutil::is_number`: no `nan`, no exponent), so `X=nan` is "no X".
//!
//! Reading never fails: acceptance (what is missing, the type rules) is the ledger's
//! business ([`crate::Ledger::ingest`]); this only finds the fields, borrowing from the
//! input.

/// The fields of one report, borrowed from the report text. A numeric field is `None`
/// when absent or not a number; a text field is `""` when absent.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NodeReport<'a> {
    pub name: &'a str,
    pub vtype: &'a str,
    pub group: &'a str,
    pub color: &'a str,
    pub vsource: &'a str,
    pub mode: &'a str,
    pub allstop: &'a str,
    pub time: Option<f64>,
    pub x: Option<f64>,
    pub y: Option<f64>,
    pub lat: Option<f64>,
    pub lon: Option<f64>,
    pub spd: Option<f64>,
    pub hdg: Option<f64>,
    pub dep: Option<f64>,
    pub length: Option<f64>,
    pub cog: Option<f64>,
    /// Fields of no known key (kept by the C++ as extra properties, unused by the helm;
    /// here only counted, so a hostile report cannot grow memory through them).
    pub unknown_fields: usize,
}

impl<'a> NodeReport<'a> {
    /// Read `text` (either form). Never fails; see the module doc.
    ///
    /// ```
    /// let r = contacts::NodeReport::parse("NAME=bob,X=5,Y=-2.5,SPD=1,HDG=90,TIME=1000,TYPE=kayak");
    /// assert_eq!((r.name, r.x, r.y, r.time), ("bob", Some(5.0), Some(-2.5), Some(1000.0)));
    /// ```
    pub fn parse(text: &'a str) -> Self {
        let mut r = NodeReport::default();
        for_each_field(text, |key, value| r.set(key, value));
        r
    }

    fn set(&mut self, key: Key, value: &'a str) {
        let num = || mbutil::parse_number(value);
        match key {
            Key::Name => self.name = value,
            Key::Type => self.vtype = value,
            Key::Group => self.group = value,
            Key::Color => self.color = value,
            Key::Vsource => self.vsource = value,
            Key::Mode => self.mode = value,
            Key::Allstop => self.allstop = value,
            Key::Time => {
                // A non-numeric TIME leaves an earlier numeric one in place.
                if let Some(v) = num() {
                    self.time = Some(v);
                }
            }
            Key::X => self.x = num().or(self.x),
            Key::Y => self.y = num().or(self.y),
            Key::Lat => self.lat = num().or(self.lat),
            Key::Lon => self.lon = num().or(self.lon),
            Key::Spd => self.spd = num().or(self.spd),
            Key::Hdg => self.hdg = num().or(self.hdg),
            Key::Dep => self.dep = num().or(self.dep),
            Key::Length => self.length = num().or(self.length),
            Key::Cog => self.cog = num().or(self.cog),
            Key::Unknown => self.unknown_fields += 1,
        }
    }

    /// Both X and Y given as numbers.
    pub fn has_xy(&self) -> bool {
        self.x.is_some() && self.y.is_some()
    }

    /// "LAT/LON present", tested on LON alone as the reference does (a LON without LAT
    /// counts, with latitude 0).
    pub fn has_latlon(&self) -> bool {
        self.lon.is_some()
    }
}

/// Reports of one batch of mail already read, by their message's place in the batch
/// (a fleet simulator reads each report once for all its receivers, and hands each
/// receiver its reading when asked, without a copy per receiver).
pub trait ReadReports {
    /// `NodeReport::parse` of the text of message `k`, if read already; `None`: the
    /// receiver reads the text itself.
    fn read(&self, k: usize) -> Option<NodeReport<'_>>;
}

/// Nothing read.
impl ReadReports for () {
    fn read(&self, _k: usize) -> Option<NodeReport<'_>> {
        None
    }
}

/// Readings as (message index, reading), in ascending index.
impl ReadReports for Vec<(usize, NodeReport<'_>)> {
    fn read(&self, k: usize) -> Option<NodeReport<'_>> {
        let i = self.binary_search_by_key(&k, |(i, _)| *i).ok()?;
        Some(self[i].1.clone())
    }
}

/// Each field of `text` (either form) in order: its key and its value, trimmed (and
/// unquoted in the JSON-ish form). What [`NodeReport::parse`] reads; a reader that needs
/// only a few fields uses it to skip the number parsing of the others.
pub(crate) fn for_each_field<'a>(text: &'a str, mut f: impl FnMut(Key, &'a str)) {
    let t = trim(text);
    let json = t.len() >= 2 && t.starts_with('{') && t.ends_with('}');
    let body = if json { &t[1..t.len() - 1] } else { t };
    if body.is_empty() {
        return;
    }
    // One pass: fields end at a comma outside braces (any depth; an unbalanced `}` is
    // ignored); a field's key ends at its first `=` (`:` in the JSON-ish form), braces
    // or not. Every byte tested is ASCII, so every cut is a char boundary. Most bytes
    // are none of these: one table look-up each (a report comes every second from
    // every contact, and ownship's every iteration).
    let between = if json { COLON } else { EQUALS };
    let mut emit = |start: usize, split: usize, end: usize| {
        let (key, value) = match (split < end, json) {
            (true, true) => (unquote(&body[start..split]), unquote(&body[split + 1..end])),
            (false, true) => (unquote(&body[start..end]), ""),
            (true, false) => (trim(&body[start..split]), trim(&body[split + 1..end])),
            (false, false) => (trim(&body[start..end]), ""),
        };
        f(Key::of(key), value);
    };
    // `split == usize::MAX`: no key/value separator in the field yet.
    let (mut depth, mut start, mut split) = (0usize, 0usize, usize::MAX);
    for (i, &b) in body.as_bytes().iter().enumerate() {
        match BYTE_CLASS[usize::from(b)] {
            PLAIN => {}
            COMMA => {
                if depth == 0 {
                    emit(start, split, i);
                    (start, split) = (i + 1, usize::MAX);
                }
            }
            OPEN => depth += 1,
            CLOSE => depth = depth.saturating_sub(1),
            c => {
                if c == between && split == usize::MAX {
                    split = i;
                }
            }
        }
    }
    emit(start, split, body.len());
}

/// [`BYTE_CLASS`] of a byte that separates nothing.
const PLAIN: u8 = 0;
const COMMA: u8 = 1;
const OPEN: u8 = 2;
const CLOSE: u8 = 3;
const EQUALS: u8 = 4;
const COLON: u8 = 5;

/// What each byte is to the field scanner.
const BYTE_CLASS: [u8; 256] = {
    let mut t = [PLAIN; 256];
    t[b',' as usize] = COMMA;
    t[b'{' as usize] = OPEN;
    t[b'}' as usize] = CLOSE;
    t[b'=' as usize] = EQUALS;
    t[b':' as usize] = COLON;
    t
};

/// The known keys of a report (matched without regard to ASCII case).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Key {
    Name,
    Type,
    Group,
    Color,
    Vsource,
    Mode,
    Allstop,
    Time,
    X,
    Y,
    Lat,
    Lon,
    Spd,
    Hdg,
    Dep,
    Length,
    Cog,
    Unknown,
}

impl Key {
    /// Which key `key` is: its (at most 8) bytes read as one little-endian word, the
    /// ASCII letters upper-cased in the word at once ([`upper_ascii`]), then one
    /// `match` on the word and a check of the length (a padding zero is not a NUL of
    /// the key). Upper-casing ASCII leaves other bytes alone, so this is
    /// `eq_ignore_ascii_case` against each upper-case name.
    pub(crate) fn of(key: &str) -> Key {
        let b = key.as_bytes();
        if b.len() > 8 {
            return Key::Unknown;
        }
        let (k, len) = match upper_ascii(word_of(b)) {
            words::NAME => (Key::Name, 4),
            words::TYPE => (Key::Type, 4),
            words::GROUP => (Key::Group, 5),
            words::COLOR => (Key::Color, 5),
            words::VSOURCE => (Key::Vsource, 7),
            words::MODE => (Key::Mode, 4),
            words::ALLSTOP => (Key::Allstop, 7),
            words::TIME => (Key::Time, 4),
            words::UTC_TIME => (Key::Time, 8),
            words::X => (Key::X, 1),
            words::Y => (Key::Y, 1),
            words::LAT => (Key::Lat, 3),
            words::LON => (Key::Lon, 3),
            words::SPD => (Key::Spd, 3),
            words::SPEED => (Key::Spd, 5),
            words::HDG => (Key::Hdg, 3),
            words::HEADING => (Key::Hdg, 7),
            words::DEP => (Key::Dep, 3),
            words::DEPTH => (Key::Dep, 5),
            words::LENGTH => (Key::Length, 6),
            words::LEN => (Key::Length, 3),
            words::COG => (Key::Cog, 3),
            _ => return Key::Unknown,
        };
        if b.len() == len {
            k
        } else {
            Key::Unknown
        }
    }
}

/// The known names as little-endian words, zero-padded (what [`Key::of`] matches).
mod words {
    const fn word(name: &[u8]) -> u64 {
        let mut buf = [0u8; 8];
        let mut i = 0;
        while i < name.len() {
            buf[i] = name[i];
            i += 1;
        }
        u64::from_le_bytes(buf)
    }
    pub const NAME: u64 = word(b"NAME");
    pub const TYPE: u64 = word(b"TYPE");
    pub const GROUP: u64 = word(b"GROUP");
    pub const COLOR: u64 = word(b"COLOR");
    pub const VSOURCE: u64 = word(b"VSOURCE");
    pub const MODE: u64 = word(b"MODE");
    pub const ALLSTOP: u64 = word(b"ALLSTOP");
    pub const TIME: u64 = word(b"TIME");
    pub const UTC_TIME: u64 = word(b"UTC_TIME");
    pub const X: u64 = word(b"X");
    pub const Y: u64 = word(b"Y");
    pub const LAT: u64 = word(b"LAT");
    pub const LON: u64 = word(b"LON");
    pub const SPD: u64 = word(b"SPD");
    pub const SPEED: u64 = word(b"SPEED");
    pub const HDG: u64 = word(b"HDG");
    pub const HEADING: u64 = word(b"HEADING");
    pub const DEP: u64 = word(b"DEP");
    pub const DEPTH: u64 = word(b"DEPTH");
    pub const LENGTH: u64 = word(b"LENGTH");
    pub const LEN: u64 = word(b"LEN");
    pub const COG: u64 = word(b"COG");
}

/// The bytes of `b` (at most 8) as a little-endian word, zero-padded: two loads that
/// may overlap, OR-ed (a byte read twice is the same byte), rather than a copy of a
/// variable length.
fn word_of(b: &[u8]) -> u64 {
    let n = b.len();
    let u32_at = |i: usize| u64::from(u32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]));
    match n {
        0 => 0,
        1..=3 => {
            u64::from(b[0])
                | u64::from(b[n / 2]) << (8 * (n / 2))
                | u64::from(b[n - 1]) << (8 * (n - 1))
        }
        4..=8 => u32_at(0) | u32_at(n - 4) << (8 * (n - 4)),
        // `Key::of` reads at most 8 bytes.
        _ => u64::MAX,
    }
}

/// Each byte of `w` that is an ASCII lower-case letter made upper-case, the others
/// unchanged (`to_ascii_uppercase` on each of the 8 bytes). Per byte, with its top bit
/// cleared (`h` ≤ 0x7f, so no sum below carries into the next byte): `h + 0x1f` has
/// the top bit set iff `h` ≥ `a` (0x61), `h + 0x05` iff `h` > `z` (0x7a); a byte whose
/// own top bit is set is not ASCII. Each lower-case letter loses 0x20.
fn upper_ascii(w: u64) -> u64 {
    const LOW7: u64 = 0x7f7f_7f7f_7f7f_7f7f;
    const TOP: u64 = 0x8080_8080_8080_8080;
    let h = w & LOW7;
    let at_least_a = h + 0x1f1f_1f1f_1f1f_1f1f;
    let past_z = h + 0x0505_0505_0505_0505;
    let lower = at_least_a & !past_z & !w & TOP;
    w - (lower >> 2)
}

/// `str::trim`, with a shortcut for the usual case: both ends an ASCII byte that is not
/// white space (`char::is_whitespace` on ASCII is exactly tab, LF, VT, FF, CR, space).
fn trim(s: &str) -> &str {
    let solid = |b: Option<&u8>| b.is_some_and(|&c| c.is_ascii() && !matches!(c, 9..=13 | b' '));
    let b = s.as_bytes();
    if solid(b.first()) && solid(b.last()) {
        s
    } else {
        s.trim()
    }
}

/// Trim, then drop one pair of surrounding double quotes.
fn unquote(s: &str) -> &str {
    trim(mbutil::strip_quotes(trim(s)))
}

/// The field scanner before the byte table (kept as the reference of [`for_each_field`]'s
/// test): the same one pass, every byte matched as an `Option`.
#[cfg(test)]
fn for_each_field_per_byte<'a>(text: &'a str, mut f: impl FnMut(Key, &'a str)) {
    let t = trim(text);
    let json = t.len() >= 2 && t.starts_with('{') && t.ends_with('}');
    let body = if json { &t[1..t.len() - 1] } else { t };
    if body.is_empty() {
        return;
    }
    // One pass: fields end at a comma outside braces (any depth; an unbalanced `}` is
    // ignored); a field's key ends at its first `=` (`:` in the JSON-ish form), braces
    // or not. Every byte tested is ASCII, so every cut is a char boundary.
    let between = if json { b':' } else { b'=' };
    let bytes = body.as_bytes();
    let (mut depth, mut start, mut split) = (0usize, 0usize, None);
    for i in 0..=bytes.len() {
        let b = bytes.get(i).copied();
        if b.is_none() || (b == Some(b',') && depth == 0) {
            let (key, value) = match (split, json) {
                (Some(k), true) => (unquote(&body[start..k]), unquote(&body[k + 1..i])),
                (None, true) => (unquote(&body[start..i]), ""),
                (Some(k), false) => (trim(&body[start..k]), trim(&body[k + 1..i])),
                (None, false) => (trim(&body[start..i]), ""),
            };
            f(Key::of(key), value);
            (start, split) = (i + 1, None);
            continue;
        }
        match b {
            Some(b'{') => depth += 1,
            Some(b'}') => depth = depth.saturating_sub(1),
            Some(c) if c == between && split.is_none() => split = Some(i),
            _ => {}
        }
    }
}

/// Split at `sep` where not inside `{...}` (any depth). An unbalanced `}` is ignored.
/// (The straightforward splitter, kept as the reference of [`for_each_field`]'s test.)
#[cfg(test)]
fn split_top_level(s: &str, sep: u8) -> impl Iterator<Item = &str> {
    let mut depth = 0usize;
    let mut start = 0usize;
    let bytes = s.as_bytes();
    let mut i = 0usize;
    let mut done = s.is_empty();
    std::iter::from_fn(move || {
        if done {
            return None;
        }
        while i < bytes.len() {
            let b = bytes[i];
            i += 1;
            match b {
                b'{' => depth += 1,
                b'}' => depth = depth.saturating_sub(1),
                _ if b == sep && depth == 0 => {
                    // `sep` is ASCII, so these are char boundaries.
                    let piece = &s[start..i - 1];
                    start = i;
                    return Some(piece);
                }
                _ => {}
            }
        }
        done = true;
        Some(&s[start..])
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Xorshift64 from `seed` (non-zero): the tests' reproducible random stream.
    fn xorshift(mut seed: u64) -> impl FnMut() -> u64 {
        move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        }
    }

    #[test]
    fn reads_the_pnodereporter_form() {
        let s = "NAME=alpha,X=0,Y=0,SPD=0,HDG=0,DEP=0,LAT=43.8253,LON=-70.3304,TYPE=kayak,\
                 COLOR=yellow,MODE=PARK,ALLSTOP=ManualOverride,INDEX=19,YAW=1.5707963,\
                 TIME=3590845246.47,LENGTH=4";
        let r = NodeReport::parse(s);
        assert_eq!(r.name, "alpha");
        assert_eq!(r.vtype, "kayak");
        assert_eq!(r.color, "yellow");
        assert_eq!(r.mode, "PARK");
        assert_eq!(r.allstop, "ManualOverride");
        assert_eq!(r.time, Some(3590845246.47));
        assert_eq!(r.lat, Some(43.8253));
        assert_eq!(r.lon, Some(-70.3304));
        assert_eq!(r.length, Some(4.0));
        assert_eq!(r.unknown_fields, 2); // INDEX, YAW
        assert!(r.has_xy() && r.has_latlon());
    }

    #[test]
    fn keys_are_case_insensitive_values_trimmed_and_aliases_work() {
        let r =
            NodeReport::parse(" name = Bob , speed=2, heading = 45,depth=3, utc_time=7, len=9 ");
        assert_eq!(r.name, "Bob");
        assert_eq!((r.spd, r.hdg, r.dep), (Some(2.0), Some(45.0), Some(3.0)));
        assert_eq!((r.time, r.length), (Some(7.0), Some(9.0)));
    }

    #[test]
    fn numeric_fields_need_the_number_test() {
        let r = NodeReport::parse("NAME=a,X=nan,Y=1e3,TIME=12abc,SPD=inf,HDG=-,DEP=+4");
        assert_eq!(
            (r.x, r.y, r.time, r.spd, r.hdg),
            (None, None, None, None, None)
        );
        assert_eq!(r.dep, Some(4.0));
    }

    #[test]
    fn json_form_and_braces() {
        let r =
            NodeReport::parse(r#"{"NAME":"alpha","X":"12.5","Y":-3,"TIME":"5","GROUP":"{a,b}"}"#);
        assert_eq!(r.name, "alpha");
        assert_eq!((r.x, r.y, r.time), (Some(12.5), Some(-3.0), Some(5.0)));
        assert_eq!(r.group, "{a,b}");
        // Braces inside the plain form do not split either.
        let r = NodeReport::parse("NAME=a,GROUP={x,y},TIME=1");
        assert_eq!((r.group, r.time), ("{x,y}", Some(1.0)));
    }

    #[test]
    fn splitter_edges() {
        let v: Vec<&str> = split_top_level("", b',').collect();
        assert!(v.is_empty());
        let v: Vec<&str> = split_top_level("a,,b,", b',').collect();
        assert_eq!(v, ["a", "", "b", ""]);
        let v: Vec<&str> = split_top_level("}a,{b,c}}d,e", b',').collect();
        assert_eq!(v, ["}a", "{b,c}}d", "e"]);
    }
    /// The straightforward reading: each known name tested with `eq_ignore_ascii_case`.
    fn key_by_names(key: &str) -> Key {
        let names: [(&[&str], Key); 17] = [
            (&["NAME"], Key::Name),
            (&["TYPE"], Key::Type),
            (&["GROUP"], Key::Group),
            (&["COLOR"], Key::Color),
            (&["VSOURCE"], Key::Vsource),
            (&["MODE"], Key::Mode),
            (&["ALLSTOP"], Key::Allstop),
            (&["TIME", "UTC_TIME"], Key::Time),
            (&["X"], Key::X),
            (&["Y"], Key::Y),
            (&["LAT"], Key::Lat),
            (&["LON"], Key::Lon),
            (&["SPD", "SPEED"], Key::Spd),
            (&["HDG", "HEADING"], Key::Hdg),
            (&["DEP", "DEPTH"], Key::Dep),
            (&["LENGTH", "LEN"], Key::Length),
            (&["COG"], Key::Cog),
        ];
        names
            .iter()
            .find(|(ns, _)| ns.iter().any(|n| key.eq_ignore_ascii_case(n)))
            .map_or(Key::Unknown, |(_, k)| *k)
    }

    /// The straightforward field reader: split, then find the key's end in each field.
    fn fields_by_split(text: &str) -> Vec<(Key, &str)> {
        let t = text.trim();
        let json = t.len() >= 2 && t.starts_with('{') && t.ends_with('}');
        let body = if json { &t[1..t.len() - 1] } else { t };
        let mut out = Vec::new();
        for field in split_top_level(body, b',') {
            let (key, value) = if json {
                match field.find(':') {
                    Some(i) => (unquote(&field[..i]), unquote(&field[i + 1..])),
                    None => (unquote(field), ""),
                }
            } else {
                match field.find('=') {
                    Some(i) => (field[..i].trim(), field[i + 1..].trim()),
                    None => (field.trim(), ""),
                }
            };
            out.push((key_by_names(key), value));
        }
        out
    }

    #[test]
    fn one_pass_fields_match_split_then_find() {
        let pieces = [
            "NAME",
            "x",
            "=",
            "==",
            ":",
            ",",
            ",,",
            "{",
            "}",
            "}}",
            "{{",
            "\"",
            " ",
            "\t",
            "é",
            "\u{a0}",
            "12.5",
            "TIME",
            "GROUP",
            "{a,b}",
            "\"X\":\"1\"",
            "LEN=4",
        ];
        let mut rng = xorshift(0x853c_49e6_748f_ea9bu64);
        let mut next = |n: usize| (rng() % n as u64) as usize;
        for _ in 0..30_000 {
            let mut s = String::new();
            if next(3) == 0 {
                s.push('{');
            }
            for _ in 0..next(10) {
                s.push_str(pieces[next(pieces.len())]);
            }
            if next(3) == 0 {
                s.push('}');
            }
            let mut got = Vec::new();
            for_each_field(&s, |k, v| got.push((k, v)));
            assert_eq!(got, fields_by_split(&s), "{s:?}");
        }
    }

    #[test]
    fn table_scanner_matches_the_per_byte_scanner() {
        // Report-like pieces and every separator, both forms, hostile bytes included.
        let pieces = [
            "NAME=alpha",
            "X=-12.34",
            "y = 5 ",
            "\"TIME\":\"7\"",
            "LAT:43.8",
            ",",
            ",,",
            "=",
            ":",
            "{",
            "}",
            "{a,b=c}",
            "\"",
            " ",
            "\t",
            "\r\n",
            "\u{a0}",
            "é",
            "\0",
            "utc_time",
            "Len=4",
            "GROUP={x:y,z}",
            "\u{7f}",
            "\u{ff}",
        ];
        let mut rng = xorshift(0x9e37_79b9_7f4a_7c15u64);
        let mut next = |n: usize| (rng() % n as u64) as usize;
        for _ in 0..50_000 {
            let mut s = String::new();
            match next(4) {
                0 => s.push('{'),
                1 => s.push_str(" {"),
                _ => {}
            }
            for _ in 0..next(14) {
                s.push_str(pieces[next(pieces.len())]);
            }
            match next(4) {
                0 => s.push('}'),
                1 => s.push_str("} "),
                _ => {}
            }
            let (mut got, mut want) = (Vec::new(), Vec::new());
            for_each_field(&s, |k, v| got.push((k, v)));
            for_each_field_per_byte(&s, |k, v| want.push((k, v)));
            assert_eq!(got, want, "{s:?}");
        }
    }

    #[test]
    fn overlapping_loads_read_the_padded_word() {
        let bytes: Vec<u8> = (0..64u8)
            .map(|i| i.wrapping_mul(37).wrapping_add(1))
            .collect();
        for n in 0..=8 {
            for start in 0..bytes.len() - n {
                let b = &bytes[start..start + n];
                let mut buf = [0u8; 8];
                buf[..n].copy_from_slice(b);
                assert_eq!(word_of(b), u64::from_le_bytes(buf), "{b:?}");
            }
        }
    }

    #[test]
    fn word_upper_casing_is_per_byte_upper_casing() {
        let mut rng = xorshift(0x2545_f491_4f6c_dd1du64);
        let mut words: Vec<u64> = (0..=255u8)
            .map(|b| u64::from(b) * 0x0101_0101_0101_0101)
            .collect();
        words.extend((0..100_000).map(|_| rng()));
        for w in words {
            let want = u64::from_le_bytes(w.to_le_bytes().map(|b| b.to_ascii_uppercase()));
            assert_eq!(upper_ascii(w), want, "{w:#x}");
        }
        // Every byte value at every position, the others a letter.
        for pos in 0..8 {
            for b in 0..=255u64 {
                let w = (0x6161_6161_6161_6161 & !(0xff << (8 * pos))) | (b << (8 * pos));
                let want = u64::from_le_bytes(w.to_le_bytes().map(|b| b.to_ascii_uppercase()));
                assert_eq!(upper_ascii(w), want, "{w:#x}");
            }
        }
    }

    #[test]
    fn key_lookup_and_trim_match_the_straightforward_versions() {
        // Pieces that make near-misses: known names, case changes, extra bytes,
        // white space of every kind (ASCII and not), non-ASCII letters.
        let pieces = [
            "NAME",
            "name",
            "Utc_Time",
            "utc_time",
            "UTC_TIMEX",
            "SPEED",
            "speeD",
            "LEN",
            "LENGTH",
            "lengthy",
            "x",
            "X",
            "y",
            "COG",
            "cogs",
            "HEADING",
            "hdg",
            "",
            " ",
            "\t",
            "\u{b}",
            "\u{c}",
            "\r\n",
            "\u{a0}",
            "\u{3000}",
            "\u{85}",
            "é",
            "İ",
            "ſ",
            "K",
            "\u{212a}",
            "_",
            "=",
            "{",
            "}",
            "\"",
            "1.5",
            "nan",
            "\0",
            "\0\0",
            "\u{80}",
            "\u{ff}",
            "@",
            "[",
            "`",
            "{",
        ];
        let mut rng = xorshift(0x2545_f491_4f6c_dd1du64);
        let mut next = |n: usize| (rng() % n as u64) as usize;
        for _ in 0..20_000 {
            let mut s = String::new();
            for _ in 0..next(4) {
                s.push_str(pieces[next(pieces.len())]);
            }
            assert_eq!(Key::of(&s), key_by_names(&s), "{s:?}");
            assert_eq!(trim(&s), s.trim(), "{s:?}");
        }
        for (ns, k) in [
            ("uTc_TiMe", Key::Time),
            ("Vsource", Key::Vsource),
            ("lon", Key::Lon),
        ] {
            assert_eq!(Key::of(ns), k);
        }
    }
}
