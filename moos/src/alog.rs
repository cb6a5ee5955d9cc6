//! pLogger `.alog` files: a `%%` header with `LOGSTART <unix time>`, then one line per
//! message: `time var source value`, white-space separated, time relative to LOGSTART
//! with 3 decimals. A message's `source_aux` is written as `source:aux` in the source
//! column. Values are free text up to the end of the line; the format does not mark types,
//! so a reader takes a value that parses as a number as a double (as the C++ alog tools
//! do). Binary payloads are not text and are logged as `<binary N bytes>`.

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
        })
    }

    pub fn log_start(&self) -> f64 {
        self.start
    }

    /// Append one message.
    pub fn write(&mut self, m: &Message) -> io::Result<()> {
        let src = if m.source_aux.is_empty() {
            m.source.clone()
        } else {
            format!("{}:{}", m.source, m.source_aux)
        };
        let value = match m.data_type {
            DataType::DOUBLE => format!("{}", m.dval),
            DataType::BINARY => format!("<binary {} bytes>", m.sval.len()),
            _ => m.string().replace(['\n', '\r'], " "),
        };
        let t = format!("{:.3}", m.time - self.start);
        writeln!(self.w, "{t:<15} {:<20} {src:<15} {value}", m.key)
    }

    pub fn flush(&mut self) -> io::Result<()> {
        self.w.flush()
    }

    pub fn into_inner(self) -> W {
        self.w
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
            Some((s, a)) => (s.to_owned(), a.to_owned()),
            None => (src.to_owned(), String::new()),
        };
        log.entries.push(AlogEntry {
            time,
            key: key.to_owned(),
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
        let end = s.find([' ', '\t']).unwrap_or(s.len());
        self.s = &s[end..];
        Some(&s[..end])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
