//! Error types of the crate.

use std::fmt;
use std::path::PathBuf;

/// A logic expression (condition) that does not follow the grammar of
/// bhv-format.md §8.1, or a malformed flag (behavior-common.md §3.1).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{reason}: [{text}]")]
pub struct LogicError {
    /// The text that was being parsed.
    pub text: String,
    /// What is wrong with it.
    pub reason: String,
}

impl LogicError {
    pub(crate) fn new(text: &str, reason: impl Into<String>) -> Self {
        LogicError {
            text: text.to_string(),
            reason: reason.into(),
        }
    }
}

/// What went wrong while reading a .bhv file.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum BhvErrorKind {
    /// The file could not be read (helm warning `Could not find File: <file>`).
    #[error("Could not find File: {0}")]
    FileNotFound(String),
    /// `{` where no block can open (§3).
    #[error("Unexpected open brace '{{'")]
    UnexpectedOpenBrace,
    /// `}` where no block is open (§3).
    #[error("Unexpected close brace '}}'")]
    UnexpectedCloseBrace,
    /// A line that no state of the reader accepts (free text at top level,
    /// text between `Behavior = X` and `{`, a bare `set`, a `#` line ...).
    #[error("Unexpected line")]
    UnexpectedLine,
    /// A bad `initialize` / `initialize_` line (§4).
    #[error("Bad initialize line: {0}")]
    BadInitialize(String),
    /// A bad `Behavior = <TYPE>` line (§3).
    #[error("Bad behavior declaration: {0}")]
    BadBehavior(String),
    /// A bad `templating` / `max_spawnings` line inside a behavior block (§5, §9).
    #[error("Bad behavior spec line: {0}")]
    BadSpecLine(String),
    /// A bad `set <VAR> = <VALUE>` line (§6.1).
    #[error("Bad mode declaration: {0}")]
    BadSet(String),
    /// A mode condition that is not a valid logic expression (§6.1, §8).
    #[error("Bad mode condition: {0}")]
    BadCondition(LogicError),
    /// A block still open at the end of the input (the line is where it was
    /// opened).
    #[error("Block not closed: {0}")]
    UnclosedBlock(String),
    /// An else-value after a `set` block that is not a single word (§6.1).
    #[error("Bad mode else-value (must be a single word)")]
    BadElseValue,
    /// A `#include`, `#define`, `#ifdef` ... line: an nsplug directive, which the helm
    /// does not expand (§1).
    #[error(
        "{0} is an nsplug directive: the helm does not expand it (run nsplug on the file first)"
    )]
    Preprocessor(String),
    /// Bytes that are not UTF-8 (the line is shown with U+FFFD in their place).
    #[error("invalid UTF-8 (byte {0} of the file); save the file as UTF-8")]
    InvalidUtf8(usize),
    /// A file larger than [`crate::reader::MAX_FILE_BYTES`].
    #[error("file is larger than {limit} bytes (a behavior file is a few kB); not read")]
    TooLarge { limit: u64 },
}

/// An error reading a .bhv file: which file, which line, the line's text,
/// and what is wrong.
///
/// `line` is 1-based and counts lines after `\` joining (the helm's
/// `Problem with line <n+1>` number; the helm's 0-based index is
/// `line - 1`). It is 0 when no line applies (missing file).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub struct BhvError {
    /// The file being read.
    pub file: PathBuf,
    /// 1-based (joined) line number, 0 if not applicable.
    pub line: usize,
    /// The offending line: trimmed, after brace splitting, before comment removal.
    pub text: String,
    /// What is wrong.
    pub kind: BhvErrorKind,
}

impl fmt::Display for BhvError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.kind {
            BhvErrorKind::FileNotFound(reason) => {
                write!(f, "Could not find File: {}", self.file.display())?;
                if !reason.is_empty() {
                    write!(f, " ({reason})")?;
                }
                Ok(())
            }
            BhvErrorKind::TooLarge { .. } => write!(f, "{}: {}", self.file.display(), self.kind),
            // One line: where, what, and the line as written.
            kind => write!(
                f,
                "{}:{}: {} (line: {})",
                self.file.display(),
                self.line,
                kind,
                self.text
            ),
        }
    }
}

impl BhvError {
    /// The helm's config warning(s) for this error (bhv-format.md §7), in
    /// posting order.
    pub fn helm_warnings(&self) -> Vec<String> {
        let file = self.file.display();
        match &self.kind {
            BhvErrorKind::FileNotFound(_) | BhvErrorKind::TooLarge { .. } => {
                vec![format!("Could not find File: {file}")]
            }
            kind => {
                let mut v = Vec::new();
                let n = self.line.saturating_sub(1);
                match kind {
                    BhvErrorKind::UnexpectedOpenBrace => {
                        v.push(format!("File:{file} Line:{n}Unexpected open brace '{{'"))
                    }
                    BhvErrorKind::UnexpectedCloseBrace => {
                        v.push(format!("File:{file} Line:{n}Unexpected close brace '}}'"))
                    }
                    _ => {}
                }
                v.push(format!(
                    "Problem with line {} in the BehaviorSet file: {file} Line: [{}]",
                    self.line, self.text
                ));
                v
            }
        }
    }
}
