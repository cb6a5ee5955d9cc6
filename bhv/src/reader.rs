//! The behavior-file reader (bhv-format.md §2–§5, §7).
//!
//! Files are read in byte-wise sorted order of their names, de-duplicated,
//! with one reader state carried across files (§2). The first syntax error
//! stops reading (§3). Line numbers are 1-based indexes into the list of
//! lines after `\` joining.

use crate::error::{BhvError, BhvErrorKind};
use crate::modes::{ModeEntry, ModeSet};
use crate::number::{typed_value, Value};
use std::path::{Path, PathBuf};

/// Everything read from the behavior files.
#[derive(Clone, Debug, Default)]
pub struct SetSpec {
    /// `initialize` / `initialize_` assignments, in file order.
    pub inits: Vec<Init>,
    /// Behavior blocks, in file order.
    pub behaviors: Vec<BehaviorSpec>,
    /// Mode declarations.
    pub modes: ModeSet,
    /// The files processed: sorted byte-wise, de-duplicated.
    pub files: Vec<PathBuf>,
}

/// One `VAR = VALUE` of an `initialize` line (§4).
#[derive(Clone, Debug, PartialEq)]
pub struct Init {
    /// Variable name.
    pub var: String,
    /// Typed value (a string that is empty after quote removal is the number 0).
    pub value: Value,
    /// `initialize_` (exactly this lower-case spelling): deferred posting.
    pub deferred: bool,
    /// File of the line.
    pub file: PathBuf,
    /// 1-based line number.
    pub line: usize,
}

/// How a behavior block may spawn instances (§9).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Templating {
    /// No spawning (default).
    #[default]
    Disallow,
    /// Template only: built once for validation, then discarded.
    Spawn,
    /// A normal instance plus spawning.
    Clone,
}

/// One `Behavior = <TYPE> { ... }` block (§5).
#[derive(Clone, Debug, PartialEq)]
pub struct BehaviorSpec {
    /// The type name (case-sensitive).
    pub type_name: String,
    /// File of the block.
    pub file: PathBuf,
    /// 1-based line of `Behavior =`.
    pub line: usize,
    /// Configuration lines passed to the behavior (without `templating`
    /// and `max_spawnings`).
    pub lines: Vec<ConfigLine>,
    /// `templating =` (consumed).
    pub templating: Templating,
    /// `max_spawnings =` (consumed); 0 = unlimited.
    pub max_spawnings: u32,
    /// The last `name =` value seen in this or an earlier block (not reset
    /// between blocks, §5).
    pub name_prefix: String,
    /// `updates = VAR` if VAR has no blanks.
    pub updates_var: Option<String>,
}

/// One configuration line of a behavior block.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ConfigLine {
    /// 1-based line number (the helm's 0-based index is `line - 1`).
    pub line: usize,
    /// Text before the first `=`, trimmed and lower-cased (the whole line if
    /// there is no `=`).
    pub param: String,
    /// Text after the first `=`, trimmed, case kept, comment removed (empty
    /// if there is no `=`).
    pub value: String,
    /// The line as written (trimmed, after brace splitting, before comment
    /// removal).
    pub raw: String,
}

/// Largest behavior file read (16 MiB): real ones are a few kB; a bigger one is a
/// mistake (a log or a binary named `.bhv`), refused at once instead of parsed for long.
pub const MAX_FILE_BYTES: u64 = 16 << 20;

/// Read at most [`MAX_FILE_BYTES`] + 1 bytes (so `/dev/zero` or a huge file cannot
/// exhaust memory); `Ok(None)` if there was more.
fn read_capped(path: &Path) -> std::io::Result<Option<Vec<u8>>> {
    mbutil::file::read_capped(path, MAX_FILE_BYTES)
}

/// The file's text, or the error naming the (joined) line of its first invalid byte.
fn decode(bytes: Vec<u8>, file: &Path) -> Result<String, BhvError> {
    let e = match String::from_utf8(bytes) {
        Ok(text) => return Ok(text),
        Err(e) => e,
    };
    let valid = e.utf8_error().valid_up_to();
    let bytes = e.into_bytes();
    let phys = bytes[..valid].iter().filter(|&&b| b == b'\n').count();
    let text = String::from_utf8_lossy(&bytes);
    let joined = text
        .split('\n')
        .take(phys)
        .filter(|l| !l.trim_end_matches([' ', '\t', '\r']).ends_with('\\'))
        .count();
    let shown = join_lines(&text)
        .get(joined)
        .map(|l| trim(l).to_string())
        .unwrap_or_default();
    Err(BhvError {
        file: file.to_path_buf(),
        line: joined + 1,
        text: shown,
        kind: BhvErrorKind::InvalidUtf8(valid),
    })
}

/// Reads behavior files: sorted by byte-wise file name, de-duplicated,
/// parser state not reset between files.
///
/// The first syntax error is returned at once. A missing file does not stop
/// the other files from being read; it is returned (the first one) at the end
/// if no syntax error occurred.
pub fn read_files(paths: &[PathBuf]) -> Result<SetSpec, BhvError> {
    let mut files: Vec<PathBuf> = paths.to_vec();
    files.sort_by(|a, b| {
        a.as_os_str()
            .as_encoded_bytes()
            .cmp(b.as_os_str().as_encoded_bytes())
    });
    files.dedup();
    let mut r = Reader::default();
    let mut missing: Option<BhvError> = None;
    for f in &files {
        match read_capped(f) {
            Ok(Some(bytes)) => r.feed(&decode(bytes, f)?, f)?,
            Ok(None) => {
                return Err(BhvError {
                    file: f.clone(),
                    line: 0,
                    text: String::new(),
                    kind: BhvErrorKind::TooLarge {
                        limit: MAX_FILE_BYTES,
                    },
                })
            }
            Err(e) => {
                if missing.is_none() {
                    missing = Some(BhvError {
                        file: f.clone(),
                        line: 0,
                        text: String::new(),
                        kind: BhvErrorKind::FileNotFound(e.to_string()),
                    });
                }
            }
        }
    }
    if let Some(e) = missing {
        return Err(e);
    }
    let mut spec = r.finish()?;
    spec.files = files;
    Ok(spec)
}

/// Reads one file's text.
///
/// ```
/// let spec = bhv::reader::parse_str(
///     "initialize DEPLOY = true\nBehavior = BHV_Waypoint\n{\n  speed = 2\n}\n",
///     std::path::Path::new("m.bhv"),
/// ).unwrap();
/// assert_eq!(spec.inits[0].var, "DEPLOY");
/// assert_eq!(spec.behaviors[0].lines[0].param, "speed");
/// ```
pub fn parse_str(text: &str, file: &Path) -> Result<SetSpec, BhvError> {
    let mut r = Reader::default();
    r.feed(text, file)?;
    let mut spec = r.finish()?;
    spec.files = vec![file.to_path_buf()];
    Ok(spec)
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
enum State {
    #[default]
    Top,
    MiscDefining,
    MiscAfter,
    BhvDeclared,
    BhvDefining,
    SetDeclared,
    SetDefining,
    SetAfter,
}

/// Where an open block started (for end-of-input errors).
#[derive(Clone, Debug, Default)]
struct Opened {
    file: PathBuf,
    line: usize,
    text: String,
}

#[derive(Default)]
struct Reader {
    state: State,
    spec: SetSpec,
    bhv: Option<BehaviorSpec>,
    /// Pending mode entry; `false` = will not be stored (blank in name).
    entry: Option<(ModeEntry, bool)>,
    name_prefix: String,
    opened: Opened,
}

/// Joins `\`-continued lines (§2).
fn join_lines(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut acc: Option<String> = None;
    for phys in text.split('\n') {
        let mut cur = acc.take().unwrap_or_default();
        cur.push_str(phys);
        let t = cur.trim_end_matches([' ', '\t', '\r']);
        if let Some(stripped) = t.strip_suffix('\\') {
            let n = stripped.len();
            cur.truncate(n);
            acc = Some(cur);
        } else {
            out.push(cur);
        }
    }
    if let Some(c) = acc {
        out.push(c);
    }
    out
}

fn trim(s: &str) -> &str {
    s.trim_matches([' ', '\t', '\r', '\n'])
}

/// Brace splitting (§2.1) of a trimmed line.
fn brace_split(t: &str) -> Vec<&str> {
    if t.starts_with("//") || t.starts_with('#') || t.len() <= 1 {
        return vec![t];
    }
    let mut v = Vec::with_capacity(3);
    let mut rest = t;
    if t.starts_with('{') || t.starts_with('}') {
        v.push(&t[..1]);
        rest = trim(&t[1..]);
    }
    if rest.len() > 1 && rest.ends_with('{') {
        v.push(trim(&rest[..rest.len() - 1]));
        v.push("{");
    } else {
        v.push(rest);
    }
    v
}

fn strip_comment(s: &str) -> &str {
    match s.find("//") {
        Some(i) => &s[..i],
        None => s,
    }
}

fn starts_with_ci(s: &str, prefix: &str) -> bool {
    s.len() >= prefix.len() && s.as_bytes()[..prefix.len()].eq_ignore_ascii_case(prefix.as_bytes())
}

fn has_blank(s: &str) -> bool {
    s.contains([' ', '\t'])
}

/// Splits on commas outside double quotes and `{...}`.
fn split_assignments(s: &str) -> Vec<&str> {
    let mut v = Vec::new();
    let (mut in_quote, mut depth, mut start) = (false, 0i64, 0usize);
    for (i, c) in s.char_indices() {
        match c {
            '"' => in_quote = !in_quote,
            '{' if !in_quote => depth += 1,
            '}' if !in_quote => depth -= 1,
            ',' if !in_quote && depth <= 0 => {
                v.push(&s[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    v.push(&s[start..]);
    v
}

impl Reader {
    fn feed(&mut self, text: &str, file: &Path) -> Result<(), BhvError> {
        for (idx, line) in join_lines(text).iter().enumerate() {
            for sub in brace_split(trim(line)) {
                self.handle(sub, idx + 1, file)?;
            }
        }
        Ok(())
    }

    fn finish(mut self) -> Result<SetSpec, BhvError> {
        let open = match self.state {
            State::Top | State::MiscAfter => None,
            // A file ending right after `}` of a set block: the entry stays
            // pending and is never stored (§3 subtleties).
            State::SetAfter => None,
            State::MiscDefining => Some("anonymous block never closed"),
            State::BhvDeclared | State::BhvDefining => Some("behavior block never closed"),
            State::SetDeclared | State::SetDefining => Some("set block never closed"),
        };
        if let Some(what) = open {
            let o = std::mem::take(&mut self.opened);
            return Err(BhvError {
                file: o.file,
                line: o.line,
                text: o.text,
                kind: BhvErrorKind::UnclosedBlock(what.to_string()),
            });
        }
        Ok(self.spec)
    }

    fn finish_entry(&mut self) {
        if let Some((e, store)) = self.entry.take() {
            if store {
                self.spec.modes.push(e);
            }
        }
    }

    fn handle(&mut self, raw: &str, line_no: usize, file: &Path) -> Result<(), BhvError> {
        let err = |kind| BhvError {
            file: file.to_path_buf(),
            line: line_no,
            text: raw.to_string(),
            kind,
        };
        let line = trim(strip_comment(raw));
        if line.is_empty() {
            match self.state {
                State::MiscAfter => self.state = State::Top,
                State::SetAfter => {
                    self.finish_entry();
                    self.state = State::Top;
                }
                _ => {}
            }
            return Ok(());
        }
        if line == "{" {
            self.state = match self.state {
                State::Top => {
                    self.opened = Opened {
                        file: file.to_path_buf(),
                        line: line_no,
                        text: raw.to_string(),
                    };
                    State::MiscDefining
                }
                State::BhvDeclared => State::BhvDefining,
                State::SetDeclared => State::SetDefining,
                _ => return Err(err(BhvErrorKind::UnexpectedOpenBrace)),
            };
            return Ok(());
        }
        if line == "}" {
            self.state = match self.state {
                State::MiscDefining => State::MiscAfter,
                State::BhvDefining => {
                    if let Some(mut b) = self.bhv.take() {
                        b.name_prefix = self.name_prefix.clone();
                        self.spec.behaviors.push(b);
                    }
                    State::Top
                }
                State::SetDefining => State::SetAfter,
                _ => return Err(err(BhvErrorKind::UnexpectedCloseBrace)),
            };
            return Ok(());
        }
        if matches!(self.state, State::Top | State::MiscAfter | State::SetAfter) {
            if starts_with_ci(line, "initialize ") || starts_with_ci(line, "initialize_ ") {
                self.finish_entry();
                self.state = State::Top;
                return self.initialize(line, line_no, file).map_err(err);
            }
            if starts_with_ci(line, "behavior") {
                self.finish_entry();
                let type_name = match line.split_once('=') {
                    Some((_, t)) => trim(t),
                    None => return Err(err(BhvErrorKind::BadBehavior("no '='".into()))),
                };
                if type_name.is_empty() {
                    return Err(err(BhvErrorKind::BadBehavior("empty type".into())));
                }
                if has_blank(type_name) || type_name.contains(['{', '}']) {
                    return Err(err(BhvErrorKind::BadBehavior(format!(
                        "bad type name [{type_name}]"
                    ))));
                }
                self.bhv = Some(BehaviorSpec {
                    type_name: type_name.to_string(),
                    file: file.to_path_buf(),
                    line: line_no,
                    lines: Vec::new(),
                    templating: Templating::Disallow,
                    max_spawnings: 0,
                    name_prefix: String::new(),
                    updates_var: None,
                });
                self.open_here(raw, line_no, file);
                self.state = State::BhvDeclared;
                return Ok(());
            }
            if starts_with_ci(line, "set ") {
                self.finish_entry();
                let (var, value) = match line[4..].split_once('=') {
                    Some((v, x)) => (trim(v), trim(x)),
                    None => return Err(err(BhvErrorKind::BadSet("no '='".into()))),
                };
                if var.is_empty() || value.is_empty() {
                    return Err(err(BhvErrorKind::BadSet(
                        "empty mode variable or value".into(),
                    )));
                }
                // A variable name with blanks is silently not stored (§6.1).
                self.entry = Some((ModeEntry::new(var, value), !has_blank(var)));
                self.open_here(raw, line_no, file);
                self.state = State::SetDeclared;
                return Ok(());
            }
        }
        match self.state {
            State::MiscDefining => Ok(()),
            State::SetAfter => {
                if has_blank(line) {
                    return Err(err(BhvErrorKind::BadElseValue));
                }
                if let Some((e, _)) = &mut self.entry {
                    e.set_else_value(line);
                }
                self.finish_entry();
                self.state = State::Top;
                Ok(())
            }
            State::BhvDefining => self.config_line(raw, line, line_no).map_err(err),
            State::SetDefining => {
                if let Some((e, _)) = &mut self.entry {
                    e.add_condition(line)
                        .map_err(|le| err(BhvErrorKind::BadCondition(le)))?;
                }
                Ok(())
            }
            _ if line.starts_with('#') => {
                let directive = line.split_whitespace().next().unwrap_or(line);
                let known = [
                    "#include",
                    "#define",
                    "#ifdef",
                    "#ifndef",
                    "#elseifdef",
                    "#else",
                    "#endif",
                ];
                if known.iter().any(|d| directive.eq_ignore_ascii_case(d)) {
                    Err(err(BhvErrorKind::Preprocessor(directive.to_string())))
                } else {
                    Err(err(BhvErrorKind::UnexpectedLine))
                }
            }
            _ => Err(err(BhvErrorKind::UnexpectedLine)),
        }
    }

    fn open_here(&mut self, raw: &str, line_no: usize, file: &Path) {
        self.opened = Opened {
            file: file.to_path_buf(),
            line: line_no,
            text: raw.to_string(),
        };
    }

    fn initialize(&mut self, line: &str, line_no: usize, file: &Path) -> Result<(), BhvErrorKind> {
        let (keyword, rest) = line.split_once(' ').unwrap_or((line, ""));
        let deferred = keyword == "initialize_";
        let bad = |m: String| BhvErrorKind::BadInitialize(m);
        let mut found = Vec::new();
        for piece in split_assignments(rest) {
            let (var, value) = piece
                .split_once('=')
                .ok_or_else(|| bad(format!("no '=' in [{}]", trim(piece))))?;
            let (var, value) = (trim(var), trim(value));
            if var.is_empty() || has_blank(var) {
                return Err(bad(format!("bad variable name [{var}]")));
            }
            if value.is_empty() {
                return Err(bad(format!("empty value for [{var}]")));
            }
            let value = match typed_value(value) {
                Value::Str(s) if s.is_empty() => Value::Num(0.0),
                v => v,
            };
            found.push(Init {
                var: var.to_string(),
                value,
                deferred,
                file: file.to_path_buf(),
                line: line_no,
            });
        }
        self.spec.inits.extend(found);
        Ok(())
    }

    fn config_line(&mut self, raw: &str, line: &str, line_no: usize) -> Result<(), BhvErrorKind> {
        let (param, value) = match line.split_once('=') {
            Some((p, v)) => (trim(p).to_ascii_lowercase(), trim(v)),
            None => (line.to_ascii_lowercase(), ""),
        };
        if param == "name" {
            self.name_prefix = value.to_string();
        }
        let Some(b) = self.bhv.as_mut() else {
            return Ok(());
        };
        match param.as_str() {
            "templating" => {
                b.templating = match value.to_ascii_lowercase().as_str() {
                    "spawn" => Templating::Spawn,
                    "clone" => Templating::Clone,
                    "disallow" => Templating::Disallow,
                    _ => {
                        return Err(BhvErrorKind::BadSpecLine(format!(
                            "templating must be spawn, clone or disallow, not [{value}]"
                        )))
                    }
                };
                return Ok(());
            }
            "max_spawnings" => {
                let ok = value.bytes().all(|c| c.is_ascii_digit()) && !value.is_empty();
                b.max_spawnings = match value.parse::<u32>() {
                    Ok(n) if ok => n,
                    _ => {
                        return Err(BhvErrorKind::BadSpecLine(format!(
                            "max_spawnings must be a non-negative integer, not [{value}]"
                        )))
                    }
                };
                return Ok(());
            }
            "updates" if !value.is_empty() && !has_blank(value) => {
                b.updates_var = Some(value.to_string());
            }
            _ => {}
        }
        b.lines.push(ConfigLine {
            line: line_no,
            param,
            value: value.to_string(),
            raw: raw.to_string(),
        });
        Ok(())
    }
}

#[cfg(test)]
mod tests;
