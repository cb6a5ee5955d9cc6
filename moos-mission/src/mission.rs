//! `.moos` mission file reader (spec §7): global `GetValue` lookups, `ProcessConfig`
//! blocks, `define:` lines, `${NAME}` expansion, quotes and `//` comments.
//!
//! There is no `#include`/`#define` handling and there are no `#` comments: those belong to
//! the separate `nsplug` preprocessor. A `#include` line is refused (the C++ reader
//! skips it, silently losing what it names), as are bytes that are not UTF-8 and files
//! over [`MAX_FILE_BYTES`]; every error names the file and line and shows the line.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use thiserror::Error;

/// Lines this long or longer break the C++ reader; we refuse them (spec §7.1).
pub const MAX_LINE: usize = 2000;

/// Largest mission file read (16 MiB; real ones are a few kB).
pub const MAX_FILE_BYTES: u64 = 16 << 20;

/// A mission file that could not be read.
#[derive(Debug, Error)]
pub enum MissionError {
    #[error("{}: file is larger than {MAX_FILE_BYTES} bytes (a mission file is a few kB); not read", path.display())]
    TooLarge { path: PathBuf },
    #[error("{}:{line}: invalid UTF-8 (byte {byte} of the file); save the file as UTF-8 (line: {text})", path.display())]
    InvalidUtf8 {
        path: PathBuf,
        line: usize,
        byte: usize,
        text: String,
    },
    #[error("{}:{line}: #include is an nsplug directive: MOOS does not expand it (run nsplug on the file first) (line: {text})", path.display())]
    Include {
        path: PathBuf,
        line: usize,
        text: String,
    },
    #[error("cannot read mission file {}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{}:{line}: line is {len} characters long (the limit is {MAX_LINE}) (line: {start}...)", path.display())]
    LineTooLong {
        path: PathBuf,
        line: usize,
        len: usize,
        /// The first 40 characters.
        start: String,
    },
}

/// One line of a `ProcessConfig` block.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ConfigLine {
    /// 1-based line number in the file.
    pub line: usize,
    /// Text before the first `=`, trimmed (the whole line for bracket-only lines).
    pub name: String,
    /// Text after the first `=`, trimmed; inner spaces kept. Empty for bracket lines.
    pub value: String,
    /// The line after comment/quote removal and `${}` expansion, trimmed.
    pub raw: String,
}

impl ConfigLine {
    /// Case-insensitive name comparison, as `GetConfigurationParam` does.
    pub fn name_is(&self, name: &str) -> bool {
        self.name.eq_ignore_ascii_case(name)
    }
}

/// A parsed mission file.
#[derive(Clone, Debug)]
pub struct MissionFile {
    path: PathBuf,
    /// (1-based line number, processed text); blank and comment lines are dropped.
    lines: Vec<(usize, String)>,
}

impl MissionFile {
    /// Read and parse a file. Errors name the file (and line where one applies).
    pub fn read(path: &Path) -> Result<MissionFile, MissionError> {
        let io = |source| MissionError::Io {
            path: path.to_owned(),
            source,
        };
        // At most one byte past the cap, so a huge file (or /dev/zero) is not slurped.
        let Some(bytes) = mbutil::file::read_capped(path, MAX_FILE_BYTES).map_err(io)? else {
            return Err(MissionError::TooLarge {
                path: path.to_owned(),
            });
        };
        let text = match String::from_utf8(bytes) {
            Ok(t) => t,
            Err(e) => {
                let byte = e.utf8_error().valid_up_to();
                let bytes = e.into_bytes();
                let line = bytes[..byte].iter().filter(|&&b| b == b'\n').count();
                let text = String::from_utf8_lossy(&bytes)
                    .split('\n')
                    .nth(line)
                    .unwrap_or("")
                    .trim()
                    .to_string();
                return Err(MissionError::InvalidUtf8 {
                    path: path.to_owned(),
                    line: line + 1,
                    byte,
                    text,
                });
            }
        };
        MissionFile::parse(&text, path)
    }

    /// Parse mission text; `path` is used in messages only.
    pub fn parse(text: &str, path: &Path) -> Result<MissionFile, MissionError> {
        let raw: Vec<&str> = text.split('\n').collect();
        for (i, l) in raw.iter().enumerate() {
            let len = l.trim_end_matches('\r').chars().count();
            if len >= MAX_LINE {
                return Err(MissionError::LineTooLong {
                    path: path.to_owned(),
                    line: i + 1,
                    len,
                    start: l.trim().chars().take(40).collect(),
                });
            }
            let t = l.trim();
            if t.len() >= 8 && t.as_bytes()[..8].eq_ignore_ascii_case(b"#include") {
                return Err(MissionError::Include {
                    path: path.to_owned(),
                    line: i + 1,
                    text: t.to_string(),
                });
            }
        }
        let defines = collect_defines(&raw);
        let mut lines = Vec::new();
        for (i, l) in raw.iter().enumerate() {
            if let Some(p) = process_line(l, &defines, path, i + 1) {
                lines.push((i + 1, p));
            }
        }
        Ok(MissionFile {
            path: path.to_owned(),
            lines,
        })
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// `GetValue(name)`: first line in the whole file (blocks included) whose left side,
    /// with all white space removed, equals `name` ignoring case. The value loses all
    /// white space too (spec §7.2 quirk).
    pub fn global(&self, name: &str) -> Option<String> {
        for (_, l) in &self.lines {
            if !l.contains('=') {
                continue;
            }
            let squeezed: String = l
                .chars()
                .filter(|c| !matches!(c, ' ' | '\t' | '\r'))
                .collect();
            if let Some((k, v)) = squeezed.split_once('=') {
                if k.eq_ignore_ascii_case(name) {
                    return Some(v.to_owned());
                }
            }
        }
        None
    }

    /// A global as a double: only `0-9 . e E + -` allowed, then `atof`.
    pub fn global_f64(&self, name: &str) -> Option<f64> {
        let v = self.global(name)?;
        if v.is_empty() || !v.chars().all(|c| c.is_ascii_digit() || ".eE+-".contains(c)) {
            return None;
        }
        Some(crate::text::atof(&v))
    }

    /// `app`'s `AppTick` (iterations per second of MOOS time), or `default` when missing
    /// or not a positive number, as a CMOOSApp reads it.
    pub fn app_tick(&self, app: &str, default: f64) -> f64 {
        self.config_value(app, "AppTick")
            .and_then(|v| config_f64(&v))
            .filter(|t| *t > 0.0 && t.is_finite())
            .unwrap_or(default)
    }

    /// A global as a bool: `TRUE` in any case, or numeric and > 0; anything else false.
    pub fn global_bool(&self, name: &str) -> Option<bool> {
        let v = self.global(name)?;
        Some(text_bool(&v))
    }

    /// The lines of `ProcessConfig = app`, in file order, or `None` if there is no such
    /// block (or its header is not followed by a line starting with `{`).
    pub fn process_config(&self, app: &str) -> Option<Vec<ConfigLine>> {
        let want = format!("PROCESSCONFIG={app}");
        let start = self.lines.iter().position(|(_, l)| {
            let s: String = l
                .chars()
                .filter(|c| !matches!(c, ' ' | '\t' | '\r'))
                .collect();
            s.eq_ignore_ascii_case(&want)
        })?;
        let (_, open) = self.lines.get(start + 1)?;
        if !open.starts_with('{') {
            tracing::warn!(file = %self.path.display(), app, "ProcessConfig not followed by '{{'");
            return None;
        }
        let mut out = Vec::new();
        for (n, l) in &self.lines[start + 2..] {
            if l.starts_with('}') {
                break;
            }
            if let Some((k, v)) = l.split_once('=') {
                out.push(ConfigLine {
                    line: *n,
                    name: k.trim().to_owned(),
                    value: v.trim().to_owned(),
                    raw: l.clone(),
                });
            } else if l.contains('[') || l.contains(']') {
                out.push(ConfigLine {
                    line: *n,
                    name: l.clone(),
                    value: String::new(),
                    raw: l.clone(),
                });
            }
        }
        Some(out)
    }

    /// `GetConfigurationParam`: the first block line whose name matches ignoring case;
    /// gives up at a bracket-only line (spec §7.3 quirk).
    pub fn config_value(&self, app: &str, name: &str) -> Option<String> {
        for l in self.process_config(app)? {
            if l.value.is_empty() && l.raw == l.name {
                return None;
            }
            if l.name_is(name) {
                return Some(l.value);
            }
        }
        None
    }
}

/// Block-parameter double rule: the first character must be a digit or `-`.
pub fn config_f64(value: &str) -> Option<f64> {
    let c = value.chars().next()?;
    if c.is_ascii_digit() || c == '-' {
        Some(crate::text::atof(value))
    } else {
        None
    }
}

/// MOOS bool rule: `TRUE` (any case) or numeric > 0.
pub fn text_bool(v: &str) -> bool {
    let v = v.trim();
    if v.eq_ignore_ascii_case("true") {
        return true;
    }
    let numeric = !v.is_empty() && v.chars().all(|c| c.is_ascii_digit() || ".eE+-".contains(c));
    numeric && crate::text::atof(v) > 0.0
}

fn collect_defines(raw: &[&str]) -> HashMap<String, String> {
    let mut d = HashMap::new();
    for l in raw {
        if let Some(i) = l.find("define:") {
            let rest: String = l[i + "define:".len()..]
                .chars()
                .filter(|c| !c.is_whitespace())
                .collect();
            if let Some((k, v)) = rest.split_once('=') {
                d.insert(k.to_owned(), v.to_owned());
            }
        }
    }
    d
}

fn is_ws(c: char) -> bool {
    matches!(c, ' ' | '\t' | '\r' | '\n')
}

/// Steps 1–5 of spec §7.1. `None` for blank and comment lines.
fn process_line(
    line: &str,
    defines: &HashMap<String, String>,
    path: &Path,
    n: usize,
) -> Option<String> {
    let l = line.trim_matches(is_ws);
    if l.is_empty() || l.starts_with("//") {
        return None;
    }
    // Quotes: the first pair is removed; the span between is protected from `//`.
    let mut text = l.to_owned();
    let mut protected: Option<(usize, usize)> = None;
    if let Some(i) = text.find('"') {
        if let Some(j) = text[i + 1..].find('"').map(|j| j + i + 1) {
            let inner = text[i + 1..j].to_owned();
            text = format!("{}{}{}", &text[..i], inner, &text[j + 1..]);
            protected = Some((i, i + inner.len()));
        }
    }
    let cut = match protected {
        None => text.find("//"),
        Some((a, b)) => text[..a]
            .find("//")
            .or_else(|| text[b..].find("//").map(|k| k + b)),
    };
    if let Some(c) = cut {
        text.truncate(c);
    }
    let text = expand(&text, defines, path, n);
    let t = text.trim_matches(is_ws);
    if t.is_empty() {
        None
    } else {
        Some(t.to_owned())
    }
}

/// `${NAME}` from defines, then the environment; unknown names become bare `NAME`.
fn expand(s: &str, defines: &HashMap<String, String>, path: &Path, n: usize) -> String {
    let mut out = String::with_capacity(s.len());
    let mut rest = s;
    while let Some(i) = rest.find("${") {
        out.push_str(&rest[..i]);
        let after = &rest[i + 2..];
        let Some(j) = after.find('}') else {
            out.push_str(&rest[i..]);
            return out;
        };
        let name = &after[..j];
        if name.is_empty() {
            return out;
        }
        if let Some(v) = defines.get(name) {
            out.push_str(v);
        } else if let Ok(v) = std::env::var(name) {
            out.push_str(&v);
        } else {
            tracing::error!(file = %path.display(), line = n, name, "undefined ${{{name}}} in mission file");
            out.push_str(name);
        }
        rest = &after[j + 1..];
    }
    out.push_str(rest);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const M: &str = "// a comment line\n\
ServerHost = localhost\n\
ServerPort = 9000\n\
Community  = my boat   // trailing\n\
MOOSTimeWarp = 2\n\
define: VNAME = alpha\n\
Verbose = True\n\
\n\
ProcessConfig = pHelmIvP\n\
{\n\
  AppTick   = 4\n\
  behaviors = ${VNAME}.bhv\n\
  domain    = course:0:359:360\n\
  domain    = speed:0:4:41\n\
  MyParam   = some value with spaces   // trailing comment\n\
  url = \"http://x.y//z\"  // c\n\
  [bracket]\n\
  no equals here\n\
  ServerPort = 1234\n\
}\n\
ProcessConfig = other\n\
{\n\
  X = ${UNDEFINED_MOOS_TEST_VAR_Q}\n\
}\n";

    fn m() -> MissionFile {
        MissionFile::parse(M, Path::new("t.moos")).unwrap()
    }

    #[test]
    fn globals() {
        let m = m();
        assert_eq!(m.global("serverhost").as_deref(), Some("localhost"));
        assert_eq!(m.global("COMMUNITY").as_deref(), Some("myboat"));
        assert_eq!(m.global_f64("MOOSTimeWarp"), Some(2.0));
        assert_eq!(m.global_f64("ServerHost"), None);
        assert_eq!(m.global_bool("verbose"), Some(true));
        assert_eq!(m.global("LatOrigin"), None);
        // globals also search inside blocks
        assert_eq!(m.global("AppTick").as_deref(), Some("4"));
    }

    #[test]
    fn blocks() {
        let m = m();
        let b = m.process_config("phelmivp").unwrap();
        let names: Vec<&str> = b.iter().map(|l| l.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "AppTick",
                "behaviors",
                "domain",
                "domain",
                "MyParam",
                "url",
                "[bracket]",
                "ServerPort"
            ]
        );
        assert_eq!(b[1].value, "alpha.bhv");
        assert_eq!(b[1].line, 12);
        assert_eq!(b[2].value, "course:0:359:360");
        assert_eq!(b[4].value, "some value with spaces");
        assert_eq!(b[5].value, "http://x.y//z");
        assert_eq!(
            m.process_config("other").unwrap()[0].value,
            "UNDEFINED_MOOS_TEST_VAR_Q"
        );
        assert!(m.process_config("nope").is_none());
        assert_eq!(m.config_value("pHelmIvP", "apptick").as_deref(), Some("4"));
        assert_eq!(m.config_value("pHelmIvP", "ServerPort"), None); // bracket quirk
        assert_eq!(config_f64(".5"), None);
        assert_eq!(config_f64("-2.5"), Some(-2.5));
    }

    #[test]
    fn brace_must_be_on_next_line() {
        let m = MissionFile::parse("ProcessConfig = a {\nx=1\n}\n", Path::new("t")).unwrap();
        assert!(m.process_config("a").is_none());
    }

    #[test]
    fn env_and_empty_expansion() {
        std::env::set_var("MOOS_MISSION_TEST_ENV", "fromenv");
        let m = MissionFile::parse(
            "A = ${MOOS_MISSION_TEST_ENV}x\nB = k${}rest\n",
            Path::new("t"),
        )
        .unwrap();
        assert_eq!(m.global("a").as_deref(), Some("fromenvx"));
        assert_eq!(m.global("b").as_deref(), Some("k"));
    }

    #[test]
    fn errors_name_file_and_line() {
        let long = format!("a = 1\nb = {}\n", "x".repeat(3000));
        let e = MissionFile::parse(&long, Path::new("big.moos")).unwrap_err();
        let s = e.to_string();
        assert!(s.contains("big.moos:2"), "{s}");
        let e = MissionFile::read(Path::new("/nonexistent/x.moos")).unwrap_err();
        assert!(e.to_string().contains("/nonexistent/x.moos"));
        let e =
            MissionFile::parse("a = 1\n  #include self.moos\n", Path::new("inc.moos")).unwrap_err();
        assert_eq!(
            e.to_string(),
            "inc.moos:2: #include is an nsplug directive: MOOS does not expand it (run nsplug \
             on the file first) (line: #include self.moos)"
        );
    }

    #[test]
    fn invalid_utf8_and_huge_files_are_refused() {
        let dir = std::env::temp_dir().join(format!("mission-bad-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join("bad.moos");
        std::fs::write(&f, b"A = 1\nB = caf\xe9\n").unwrap();
        let e = MissionFile::read(&f).unwrap_err().to_string();
        assert!(
            e.starts_with(&format!("{}:2: invalid UTF-8", f.display())),
            "{e}"
        );
        assert!(e.ends_with("(line: B = caf\u{fffd})"), "{e}");
        let mut big = vec![b'\n'; MAX_FILE_BYTES as usize + 1];
        big[0] = b'A';
        std::fs::write(&f, &big).unwrap();
        let e = MissionFile::read(&f).unwrap_err().to_string();
        assert!(e.contains("larger than"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
