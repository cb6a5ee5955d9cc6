//! pLogger `.alog` files: a `%%` header with `LOGSTART <unix time>`, then one line per
//! message: `time var source value`, white-space separated, time relative to LOGSTART
//! with 3 decimals. A message's `source_aux` is written as `source:aux` in the source
//! column. Values are free text up to the end of the line; the format does not mark types,
//! so a reader takes a value that parses as a number as a double (as the C++ alog tools
//! do). Binary payloads are not text and are logged as `<binary N bytes>`.
//!
//! The columns are separated by blanks, so the writer keeps every line readable: an
//! empty key or source is written as `-` (read back as empty), and blanks inside a key
//! or source become `_` (an empty source once shifted the value into the source column;
//! found by the round-trip fuzz harness).

use std::io::{self, BufRead, Write};

use thiserror::Error;

use crate::wire::{DataType, Message};

/// One logged value.
#[derive(Clone, Debug, PartialEq)]
pub enum AlogValue {
    Double(f64),
    String(String),
}

/// One data line.
#[derive(Clone, Debug, PartialEq)]
pub struct AlogEntry {
    /// Seconds since LOGSTART.
    pub time: f64,
    pub key: String,
    pub source: String,
    pub source_aux: String,
    pub value: AlogValue,
}

/// A malformed alog.
#[derive(Debug, Error)]
pub enum AlogError {
    #[error("alog I/O error: {0}")]
    Io(#[from] io::Error),
    #[error("alog line {line}: {why}")]
    Bad { line: usize, why: &'static str },
}

/// Writes an alog.
pub struct AlogWriter<W: Write> {
    w: W,
    start: f64,
    /// The line being written, kept between calls (no allocation per line).
    line: String,
}

/// An alog file being written through a buffer.
pub type AlogFile = AlogWriter<io::BufWriter<std::fs::File>>;

impl AlogFile {
    /// A new alog file at `path` (replacing one there), its header written with the
    /// file's name (the whole path if it has none).
    pub fn create(path: &std::path::Path, log_start: f64) -> io::Result<AlogFile> {
        let f = std::fs::File::create(path)?;
        let name = path.file_name().map_or_else(
            || path.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        );
        AlogWriter::new(io::BufWriter::new(f), log_start, &name)
    }
}

impl<W: Write> AlogWriter<W> {
    /// Write the header. `log_start` is the MOOS time that line times are relative to.
    pub fn new(mut w: W, log_start: f64, file_name: &str) -> io::Result<AlogWriter<W>> {
        let bar = "%".repeat(80);
        writeln!(w, "{bar}")?;
        writeln!(w, "%% LOG FILE:       {file_name}")?;
        writeln!(w, "%% FILE OPENED ON  {log_start:.2}")?;
        writeln!(w, "%% LOGSTART           {log_start:.2}")?;
        writeln!(w, "{bar}")?;
        Ok(AlogWriter {
            w,
            start: log_start,
            line: String::with_capacity(256),
        })
    }

    pub fn log_start(&self) -> f64 {
        self.start
    }

    /// Append one message.
    pub fn write(&mut self, m: &Message) -> io::Result<()> {
        let text;
        let value = match m.data_type {
            DataType::DOUBLE => LineValue::Double(m.dval),
            DataType::BINARY => LineValue::Binary(m.sval.len()),
            _ => {
                text = m.string();
                LineValue::Text(&text)
            }
        };
        self.write_line(m.time, &m.key, &m.source, &m.source_aux, value)
    }

    /// Append one message given by its parts (what [`AlogWriter::write`] writes for a
    /// message with these fields), for a caller that holds them apart and need not
    /// build a [`Message`] (copying its value) per line.
    pub fn write_line(
        &mut self,
        time: f64,
        key: &str,
        source: &str,
        source_aux: &str,
        value: LineValue<'_>,
    ) -> io::Result<()> {
        use std::fmt::Write as _;
        let line = &mut self.line;
        line.clear();
        mbutil::push_fixed(line, time - self.start, 3);
        // The time is ASCII: its length is its width.
        let pad = 15usize.saturating_sub(line.len());
        line.extend(std::iter::repeat_n(' ', pad));
        line.push(' ');
        push_column(line, &[key], 20);
        line.push(' ');
        if source_aux.is_empty() {
            push_column(line, &[source], 15);
        } else {
            push_column(line, &[source, ":", source_aux], 15);
        }
        line.push(' ');
        match value {
            LineValue::Double(v) => {
                let _ = write!(line, "{v}");
            }
            LineValue::Binary(n) => {
                let _ = write!(line, "<binary {n} bytes>");
            }
            LineValue::Text(t) => push_one_line(line, t),
        }
        line.push('\n');
        self.w.write_all(line.as_bytes())
    }

    pub fn flush(&mut self) -> io::Result<()> {
        self.w.flush()
    }

    pub fn into_inner(self) -> W {
        self.w
    }
}

/// A value as [`AlogWriter::write_line`] takes it.
#[derive(Clone, Copy, Debug)]
pub enum LineValue<'a> {
    Double(f64),
    Text(&'a str),
    /// A binary payload of this many bytes (logged as its size).
    Binary(usize),
}

/// `text` with its line breaks turned into blanks (one line per message), pushed a run
/// of characters at a time.
fn push_one_line(line: &mut String, text: &str) {
    // Nearly every value has no break: two byte scans (memchr) instead of decoding
    // every character of the long ones (BHV_IPF, appcasts).
    let bytes = text.as_bytes();
    if !bytes.contains(&b'\n') && !bytes.contains(&b'\r') {
        line.push_str(text);
        return;
    }
    let mut rest = text;
    while let Some(i) = rest.find(['\n', '\r']) {
        line.push_str(&rest[..i]);
        line.push(' ');
        // Both breaks are one byte: `i + 1` is a character boundary.
        rest = &rest[i + 1..];
    }
    line.push_str(rest);
}

/// A key or source (the concatenation of `parts`) as one column padded to `width`
/// characters: `-` when empty, blanks replaced by `_`.
fn push_column(line: &mut String, parts: &[&str], width: usize) {
    let mut n = 0;
    // The usual names are ASCII without blanks: copied whole, their length their width.
    if parts
        .iter()
        .all(|p| p.bytes().all(|b| b.is_ascii_graphic()))
    {
        for p in parts {
            line.push_str(p);
            n += p.len();
        }
    } else {
        n = push_column_chars(line, parts);
    }
    if n == 0 {
        line.push('-');
        n = 1;
    }
    line.extend(std::iter::repeat_n(' ', width.saturating_sub(n)));
}

/// [`push_column`]'s text character by character, blanks replaced: how many characters.
fn push_column_chars(line: &mut String, parts: &[&str]) -> usize {
    let mut n = 0;
    for c in parts.iter().flat_map(|p| p.chars()) {
        line.push(if c.is_whitespace() { '_' } else { c });
        n += 1;
    }
    n
}

/// The reader's side of [`column`]: `-` is empty.
fn uncolumn(s: &str) -> &str {
    if s == "-" {
        ""
    } else {
        s
    }
}

/// A read alog: the LOGSTART time (if the header had one) and the entries in file order.
#[derive(Clone, Debug, Default)]
pub struct Alog {
    pub log_start: Option<f64>,
    pub entries: Vec<AlogEntry>,
}

/// Read an alog written by pLogger or by [`AlogWriter`].
pub fn read<R: BufRead>(r: R) -> Result<Alog, AlogError> {
    let mut log = Alog::default();
    for (i, line) in r.lines().enumerate() {
        let line = line?;
        let l = line.trim();
        if l.is_empty() {
            continue;
        }
        if let Some(h) = l.strip_prefix("%%") {
            if let Some(v) = h.trim().strip_prefix("LOGSTART") {
                log.log_start = v.trim().parse().ok();
            }
            continue;
        }
        if l.starts_with('%') {
            continue;
        }
        let mut it = Fields { s: l };
        let (Some(t), Some(key), Some(src)) = (it.next(), it.next(), it.next()) else {
            return Err(AlogError::Bad {
                line: i + 1,
                why: "expected `time var source value`",
            });
        };
        let time: f64 = t.parse().map_err(|_| AlogError::Bad {
            line: i + 1,
            why: "time is not a number",
        })?;
        let rest = it.s.trim();
        let value = match rest.parse::<f64>() {
            Ok(v) if !rest.is_empty() => AlogValue::Double(v),
            _ => AlogValue::String(rest.to_owned()),
        };
        let (source, source_aux) = match src.split_once(':') {
            Some((s, a)) => (uncolumn(s).to_owned(), a.to_owned()),
            None => (uncolumn(src).to_owned(), String::new()),
        };
        log.entries.push(AlogEntry {
            time,
            key: uncolumn(key).to_owned(),
            source,
            source_aux,
            value,
        });
    }
    Ok(log)
}

struct Fields<'a> {
    s: &'a str,
}

impl<'a> Fields<'a> {
    fn next(&mut self) -> Option<&'a str> {
        let s = self.s.trim_start();
        if s.is_empty() {
            return None;
        }
        // Any white space separates columns (the writer puts none inside one).
        let end = s.find(char::is_whitespace).unwrap_or(s.len());
        self.s = &s[end..];
        Some(&s[..end])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_are_laid_out_in_padded_columns() {
        let mut w = AlogWriter::new(Vec::new(), 100.0, "t.alog").expect("header");
        let msg = |key: &str, src: &str, aux: &str, s: &str| Message {
            data_type: DataType::STRING,
            key: key.into(),
            source: src.into(),
            source_aux: aux.into(),
            time: 112.3456,
            sval: s.as_bytes().to_vec(),
            ..Message::default()
        };
        w.write(&msg("DEPLOY", "pHelmIvP", "", "true"))
            .expect("write");
        w.write(&msg("WPT STAT", "", "", "a\nb")).expect("write");
        w.write(&msg("ÉTAT", "p", "x y", "v")).expect("write");
        let num = Message {
            data_type: DataType::DOUBLE,
            key: "NAV_X".into(),
            source: "uSim".into(),
            time: 100.0,
            dval: -2.5,
            ..Message::default()
        };
        w.write(&num).expect("write");
        let text = String::from_utf8(w.into_inner()).expect("utf8");
        let lines: Vec<&str> = text.lines().skip(5).collect();
        assert_eq!(
            lines,
            [
                "12.346          DEPLOY               pHelmIvP        true",
                "12.346          WPT_STAT             -               a b",
                "12.346          ÉTAT                 p:x_y           v",
                "0.000           NAV_X                uSim            -2.5",
            ]
        );
    }

    /// The whole-name copy gives the character-by-character column for every name it
    /// takes (ASCII without blanks), including empty parts and names over the width.
    #[test]
    fn columns_copied_whole_match_the_character_rule() {
        let names = [
            "",
            "pHelmIvP",
            "a",
            "NODE_REPORT_LOCAL_WITH_A_LONG_NAME",
            ":",
            "x-1",
        ];
        for a in names {
            for b in names {
                let parts = [a, ":", b];
                let mut fast = String::new();
                push_column(&mut fast, &parts, 15);
                let mut slow = String::new();
                let n = push_column_chars(&mut slow, &parts).max(1);
                if slow.is_empty() {
                    slow.push('-');
                }
                slow.extend(std::iter::repeat_n(' ', 15usize.saturating_sub(n)));
                assert_eq!(fast, slow, "{parts:?}");
            }
        }
    }

    /// Line breaks become blanks exactly as the character-by-character rule did, for
    /// texts with runs of breaks, breaks at either end, `\r\n` pairs and multi-byte
    /// characters.
    #[test]
    fn text_values_stay_on_one_line() {
        let texts = [
            "",
            "plain",
            "\n",
            "\r\n",
            "a\r\nb\n\nc\r",
            "\nédge\n",
            "x=1,y=2\nlabel=é→\r",
            "no break but ünïcode",
        ];
        for t in texts {
            let mut fast = String::new();
            push_one_line(&mut fast, t);
            let slow: String = t
                .chars()
                .map(|c| if c == '\n' || c == '\r' { ' ' } else { c })
                .collect();
            assert_eq!(fast, slow, "{t:?}");
        }
        let mut a = AlogWriter::new(Vec::new(), 0.0, "t.alog").expect("header");
        let mut b = AlogWriter::new(Vec::new(), 0.0, "t.alog").expect("header");
        let m = Message::notify_string("VIEW POINT", "x=1\ny=2", 3.25);
        a.write(&m).expect("write");
        b.write_line(3.25, "VIEW POINT", "", "", LineValue::Text("x=1\ny=2"))
            .expect("write");
        let n = Message::notify_double("NAV_X", -0.5, 1.0);
        a.write(&n).expect("write");
        b.write_line(1.0, "NAV_X", "", "", LineValue::Double(-0.5))
            .expect("write");
        assert_eq!(a.into_inner(), b.into_inner());
    }

    #[test]
    fn round_trip() {
        let start = 1795316330.25;
        let mut w = AlogWriter::new(Vec::new(), start, "test.alog").unwrap();
        let mut a = Message::notify_double("NAV_X", 12.5, start + 1.5);
        a.source = "uSimMarine".into();
        let mut b = Message::notify_string("IVPHELM_SUMMARY", "iter=3, mode=DRIVE", start + 2.0);
        b.source = "pHelmIvP".into();
        b.source_aux = "waypt_survey".into();
        w.write(&a).unwrap();
        w.write(&b).unwrap();
        let text = w.into_inner();
        let log = read(&text[..]).unwrap();
        assert_eq!(log.log_start, Some(start));
        assert_eq!(
            log.entries[0],
            AlogEntry {
                time: 1.5,
                key: "NAV_X".into(),
                source: "uSimMarine".into(),
                source_aux: String::new(),
                value: AlogValue::Double(12.5)
            }
        );
        assert_eq!(log.entries[1].source_aux, "waypt_survey");
        assert_eq!(
            log.entries[1].value,
            AlogValue::String("iter=3, mode=DRIVE".into())
        );
    }

    #[test]
    fn alog_file_is_named_by_its_file_and_reads_back() {
        let dir = std::env::temp_dir().join(format!("moos-alog-file-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("abe.alog");
        let mut w = AlogFile::create(&path, 100.0).unwrap();
        w.write(&Message::notify_double("NAV_X", 3.0, 101.0))
            .unwrap();
        w.flush().unwrap();
        drop(w);
        let text = std::fs::read(&path).unwrap();
        assert!(String::from_utf8_lossy(&text).contains("%% LOG FILE:       abe.alog\n"));
        let log = read(&text[..]).unwrap();
        assert_eq!((log.log_start, log.entries.len()), (Some(100.0), 1));
        assert_eq!(log.entries[0].value, AlogValue::Double(3.0));
        // A folder that does not exist: an error, not a panic.
        assert!(AlogFile::create(&dir.join("no/such/dir.alog"), 0.0).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Reproducer from the fuzz harness: a message without a source (the DB's timing
    /// echo has none) was written as `t KEY  VALUE` and read back with VALUE as the source.
    #[test]
    fn regression_empty_source_and_key_round_trip() {
        let mut w = AlogWriter::new(Vec::new(), 0.0, "t.alog").unwrap();
        w.write(&Message::notify_string(
            "_async_timing",
            "1795316330.46",
            0.102,
        ))
        .unwrap();
        w.write(&Message::notify_string("", "v", 1.0)).unwrap();
        let mut spaced = Message::notify_double("A B", 2.0, 2.0);
        spaced.source = "my app".into();
        w.write(&spaced).unwrap();
        let log = read(&w.into_inner()[..]).unwrap();
        assert_eq!(log.entries.len(), 3);
        assert_eq!(log.entries[0].key, "_async_timing");
        assert_eq!(log.entries[0].source, "");
        assert_eq!(log.entries[0].value, AlogValue::Double(1795316330.46));
        assert_eq!(
            (log.entries[1].key.as_str(), log.entries[1].source.as_str()),
            ("", "")
        );
        assert_eq!(log.entries[1].value, AlogValue::String("v".into()));
        assert_eq!(log.entries[2].key, "A_B");
        assert_eq!(log.entries[2].source, "my_app");
        // Later finds of the same harness: a source `-:` (empty source, empty aux) and
        // white space other than blanks inside a key.
        let log = read("1.0 K -: v\n2.0 c\u{b}d src w\n".as_bytes()).unwrap();
        assert_eq!(
            (
                log.entries[0].source.as_str(),
                log.entries[0].source_aux.as_str()
            ),
            ("", "")
        );
        assert_eq!(
            (log.entries[1].key.as_str(), log.entries[1].source.as_str()),
            ("c", "d")
        );
        let mut w = AlogWriter::new(Vec::new(), 0.0, "t.alog").unwrap();
        w.write(&Message::notify_string("c\u{b}d", "x", 1.0))
            .unwrap();
        let log = read(&w.into_inner()[..]).unwrap();
        assert_eq!(log.entries[0].key, "c_d");
    }

    #[test]
    fn reads_plogger_style() {
        let text = "%%%%%%%%\n%% LOG FILE:  x.alog\n%% LOGSTART           1795316330.37\n%%%%\n\
                    0.152     DB_TIME         MOOSDB_alpha   1795316330.5\n\
                    1.000     DEPLOY          uPokeDB        true\n";
        let log = read(text.as_bytes()).unwrap();
        assert_eq!(log.log_start, Some(1795316330.37));
        assert_eq!(log.entries.len(), 2);
        assert_eq!(log.entries[1].value, AlogValue::String("true".into()));
        assert!(read("abc\n".as_bytes()).is_err());
    }
}
