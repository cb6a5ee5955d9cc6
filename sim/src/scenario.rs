//! `scenario.toml`: what happens around the mission in `helm sim`.
//!
//! ```toml
//! # Pokes: posted on the bus at a simulated time (s from the start), as uPokeDB would.
//! [[poke]]
//! at = 0
//! var = "DEPLOY"
//! value = "true"        # a string, a number, or a boolean (posted as "true"/"false")
//!
//! [end]
//! max_time = 600        # s of simulated time (default 3600)
//! mission_over = true   # the rule of `helm run --embedded` (default true)
//! [[end.when]]          # ends when any posting sets VAR to VALUE
//! var = "MISSION"
//! value = "complete"
//!
//! [vehicle]             # overrides of the uSimMarine block's start (all optional)
//! x = 0
//! y = -20
//! heading = 180
//! speed = 0
//! depth = 0
//! current_x = 0.0       # a constant current, m/s east
//! current_y = 0.0       # ... and north
//! ```
//!
//! No file: no pokes (the mission's own `initialize` lines still apply: the helm posts
//! them), max time 3600 s, and the end rule of `helm run --embedded`. A bad file is an
//! error naming the file and line; nothing runs.

use std::path::{Path, PathBuf};

use serde::Deserialize;
use toml::Spanned;

use helm_engine::posting::Value;

pub(crate) mod fields;
use fields::{EndDoc, Fields};

/// Default limit of simulated time (s) when the scenario names none.
pub const DEFAULT_MAX_TIME: f64 = 3600.0;

/// A bad `scenario.toml`.
#[derive(Debug, thiserror::Error)]
pub enum ScenarioError {
    #[error("{}: cannot read: {source}", path.display())]
    Read {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{}:{line}: {message}", path.display())]
    Bad {
        path: PathBuf,
        line: usize,
        message: String,
    },
}

/// One poke: `var = value` posted at `at` seconds.
#[derive(Clone, Debug, PartialEq)]
pub struct Poke {
    pub at: f64,
    pub var: String,
    pub value: Value,
}

/// An end condition: some posting sets `var` to `value`.
#[derive(Clone, Debug, PartialEq)]
pub struct When {
    pub var: String,
    pub value: Value,
}

impl When {
    /// `VAR=value`, the run's end reason when it fires.
    pub fn reason(&self) -> String {
        format!("{}={}", self.var, show(&self.value))
    }

    pub fn matches(&self, var: &str, value: &Value) -> bool {
        self.var == var
            && match (&self.value, value) {
                (Value::Num(a), Value::Num(b)) => a == b,
                (Value::Str(a), Value::Str(b)) => a.eq_ignore_ascii_case(b.trim()),
                (Value::Num(a), Value::Str(b)) => b.trim().parse::<f64>().is_ok_and(|b| b == *a),
                (Value::Str(a), Value::Num(b)) => a.parse::<f64>().is_ok_and(|a| a == *b),
            }
    }
}

fn show(v: &Value) -> String {
    match v {
        Value::Num(n) => format!("{n}"),
        Value::Str(s) => s.clone(),
    }
}

/// Start overrides of the vehicle, and a current.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VehicleStart {
    pub x: Option<f64>,
    pub y: Option<f64>,
    pub heading: Option<f64>,
    pub speed: Option<f64>,
    pub depth: Option<f64>,
    /// m/s (east, north).
    pub current: (f64, f64),
}

/// A scenario, read and checked.
#[derive(Clone, Debug, PartialEq)]
pub struct Scenario {
    /// In time order (stable for equal times: file order).
    pub pokes: Vec<Poke>,
    pub max_time: f64,
    pub mission_over: bool,
    pub when: Vec<When>,
    pub vehicle: VehicleStart,
    /// The file it came from (none: the defaults).
    pub path: Option<PathBuf>,
}

impl Default for Scenario {
    fn default() -> Self {
        Scenario {
            pokes: Vec::new(),
            max_time: DEFAULT_MAX_TIME,
            mission_over: true,
            when: Vec::new(),
            vehicle: VehicleStart::default(),
            path: None,
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileDoc {
    #[serde(default)]
    poke: Vec<PokeDoc>,
    end: Option<EndDoc>,
    vehicle: Option<VehicleDoc>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PokeDoc {
    at: Spanned<f64>,
    var: Spanned<String>,
    value: Spanned<toml::Value>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct VehicleDoc {
    x: Option<Spanned<f64>>,
    y: Option<Spanned<f64>>,
    heading: Option<Spanned<f64>>,
    speed: Option<Spanned<f64>>,
    depth: Option<Spanned<f64>>,
    current_x: Option<Spanned<f64>>,
    current_y: Option<Spanned<f64>>,
}

/// 1-based line of byte offset `at` in `text`.
pub(crate) fn line_of(text: &str, at: usize) -> usize {
    text.as_bytes()[..at.min(text.len())]
        .iter()
        .filter(|b| **b == b'\n')
        .count()
        + 1
}

/// The text of a scenario file, or the error naming it.
pub(crate) fn read_text(path: &Path) -> Result<String, ScenarioError> {
    std::fs::read_to_string(path).map_err(|source| ScenarioError::Read {
        path: path.to_path_buf(),
        source,
    })
}

/// `file:line: message` at byte `span.start` of `text` (read from `path`).
pub(crate) fn bad_at(
    path: &Path,
    text: &str,
    span: std::ops::Range<usize>,
    message: String,
) -> ScenarioError {
    ScenarioError::Bad {
        path: path.to_path_buf(),
        line: line_of(text, span.start),
        message,
    }
}

/// `text` as TOML of type `T`; a syntax or type error is a `file:line` error.
pub(crate) fn parse_toml<T: serde::de::DeserializeOwned>(
    text: &str,
    path: &Path,
) -> Result<T, ScenarioError> {
    toml::from_str(text).map_err(|e| {
        let span = e.span().unwrap_or(0..0);
        bad_at(path, text, span, e.message().trim().to_string())
    })
}

impl Scenario {
    /// `scenario.toml` in `dir`, or the defaults if there is none.
    pub fn beside(dir: &Path) -> Result<Scenario, ScenarioError> {
        let path = dir.join("scenario.toml");
        if path.is_file() {
            Scenario::read(&path)
        } else {
            Ok(Scenario::default())
        }
    }

    pub fn read(path: &Path) -> Result<Scenario, ScenarioError> {
        Scenario::parse(&read_text(path)?, path)
    }

    /// Parse and check `text` (read from `path`, for messages).
    pub fn parse(text: &str, path: &Path) -> Result<Scenario, ScenarioError> {
        let f = Fields::new(path, text);
        let doc: FileDoc = parse_toml(text, path)?;
        let mut sc = Scenario {
            path: Some(path.to_path_buf()),
            ..Scenario::default()
        };
        for p in &doc.poke {
            sc.pokes.push(f.poke(&p.at, &p.var, &p.value)?);
        }
        sc.pokes.sort_by(|a, b| a.at.total_cmp(&b.at));
        let end = f.end(doc.end.as_ref())?;
        (sc.max_time, sc.mission_over, sc.when) = (end.max_time, end.mission_over, end.when);
        if let Some(v) = &doc.vehicle {
            sc.vehicle = VehicleStart {
                x: f.opt_number(&v.x, "x", None)?,
                y: f.opt_number(&v.y, "y", None)?,
                heading: f.opt_number(&v.heading, "heading", None)?,
                speed: f.opt_number(&v.speed, "speed", Some(0.0))?,
                depth: f.opt_number(&v.depth, "depth", None)?,
                current: (
                    f.opt_number(&v.current_x, "current_x", None)?
                        .unwrap_or(0.0),
                    f.opt_number(&v.current_y, "current_y", None)?
                        .unwrap_or(0.0),
                ),
            };
        }
        Ok(sc)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(t: &str) -> Result<Scenario, ScenarioError> {
        Scenario::parse(t, Path::new("scenario.toml"))
    }

    #[test]
    fn reads_every_part() {
        let s = parse(
            "[[poke]]\nat = 200\nvar = \"RETURN\"\nvalue = true\n\
             [[poke]]\nat = 0\nvar = \"DEPLOY\"\nvalue = \"true\"\n\
             [end]\nmax_time = 600\nmission_over = false\n\
             [[end.when]]\nvar = \"MISSION\"\nvalue = \"complete\"\n\
             [vehicle]\nx = 5\nheading = 90\ncurrent_x = 0.2\n",
        )
        .expect("parses");
        assert_eq!(s.pokes[0].var, "DEPLOY");
        assert_eq!(s.pokes[1].value, Value::Str("true".into()));
        assert_eq!((s.max_time, s.mission_over), (600.0, false));
        assert_eq!(s.when[0].reason(), "MISSION=complete");
        assert!(s.when[0].matches("MISSION", &Value::Str("complete".into())));
        assert_eq!(s.vehicle.x, Some(5.0));
        assert_eq!(s.vehicle.y, None);
        assert_eq!(s.vehicle.current, (0.2, 0.0));
    }

    #[test]
    fn errors_name_the_line() {
        let cases = [
            (
                "[end]\nmax_time = 10\n\n[[poke]]\nat = -1\nvar = \"A\"\nvalue = 1\n",
                5,
                ">= 0",
            ),
            ("[end]\nmax_time = \"long\"\n", 2, ""),
            (
                "[[poke]]\nat = 1\nvar = \"A\"\nvalue = 1\nwhen = 3\n",
                5,
                "unknown field",
            ),
            ("[vehicle]\nx = 1\n\nspeed = -2\n", 4, "speed"),
            (
                "[[poke]]\nat = 1\nvar = \"A B\"\nvalue = 1\n",
                3,
                "variable",
            ),
            (
                "[[poke]]\nat = 1\nvar = \"A\"\nvalue = [1, 2]\n",
                4,
                "array",
            ),
            ("[end\n", 1, ""),
        ];
        for (text, line, has) in cases {
            let e = parse(text).expect_err(text).to_string();
            assert!(
                e.starts_with(&format!("scenario.toml:{line}: ")),
                "{text:?} -> {e}"
            );
            assert!(e.contains(has), "{text:?} -> {e}");
        }
    }

    #[test]
    fn missing_file_is_the_default() {
        let s = Scenario::beside(Path::new("/nonexistent-dir")).expect("default");
        assert_eq!(s, Scenario::default());
    }
}
