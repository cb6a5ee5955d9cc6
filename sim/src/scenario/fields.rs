//! The values both scenario files, one vehicle's `scenario.toml` and a fleet's, read
//! the same way: numbers, `[[poke]]`s (time, variable, value) and `[end]`. Each error
//! names the file and the line of the value.

use std::ops::Range;
use std::path::Path;

use serde::Deserialize;
use toml::Spanned;

use helm_engine::posting::Value;

use super::{bad_at, Poke, ScenarioError, When, DEFAULT_MAX_TIME};

/// `[end]` as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct EndDoc {
    max_time: Option<Spanned<f64>>,
    mission_over: Option<bool>,
    #[serde(default)]
    when: Vec<WhenDoc>,
}

/// `[[end.when]]` as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct WhenDoc {
    var: Spanned<String>,
    value: Spanned<toml::Value>,
}

/// What `[end]` says, defaults filled in.
pub(crate) struct End {
    /// Simulated seconds at most.
    pub max_time: f64,
    /// Whether the mission's end (the rule of `helm run --embedded`) ends the run.
    pub mission_over: bool,
    /// Postings that end the run.
    pub when: Vec<When>,
}

/// A scenario file being read: where its errors point.
#[derive(Clone, Copy)]
pub(crate) struct Fields<'a> {
    path: &'a Path,
    text: &'a str,
}

impl<'a> Fields<'a> {
    /// The file `path`, whose text is `text`.
    pub(crate) fn new(path: &'a Path, text: &'a str) -> Fields<'a> {
        Fields { path, text }
    }

    /// `file:line: message` at the start of `span`.
    pub(crate) fn bad(&self, span: Range<usize>, message: String) -> ScenarioError {
        bad_at(self.path, self.text, span, message)
    }

    /// A finite number, at least `min` when one is given (TOML also writes `inf`
    /// and `nan`).
    pub(crate) fn number(
        &self,
        v: &Spanned<f64>,
        what: &str,
        min: Option<f64>,
    ) -> Result<f64, ScenarioError> {
        let x = *v.get_ref();
        if !x.is_finite() {
            return Err(self.bad(v.span(), format!("`{what} = {x}`: must be a finite number")));
        }
        match min {
            Some(m) if x < m => Err(self.bad(v.span(), format!("`{what} = {x}`: must be >= {m}"))),
            _ => Ok(x),
        }
    }

    /// [`Fields::number`] of a value that may be left out.
    pub(crate) fn opt_number(
        &self,
        v: &Option<Spanned<f64>>,
        what: &str,
        min: Option<f64>,
    ) -> Result<Option<f64>, ScenarioError> {
        v.as_ref().map(|s| self.number(s, what, min)).transpose()
    }

    /// A span of simulated time: a finite number of seconds above 0.
    pub(crate) fn seconds(&self, v: &Spanned<f64>, what: &str) -> Result<f64, ScenarioError> {
        let x = self.number(v, what, None)?;
        if x > 0.0 {
            Ok(x)
        } else {
            Err(self.bad(v.span(), format!("`{what} = {x}`: must be > 0 s")))
        }
    }

    /// A MOOS variable name: one word.
    pub(crate) fn var_name(&self, v: &Spanned<String>) -> Result<String, ScenarioError> {
        let s = v.get_ref().trim();
        if s.is_empty() || s.contains(char::is_whitespace) {
            Err(self.bad(
                v.span(),
                format!("`{s}` is not a MOOS variable name (empty or with blanks)"),
            ))
        } else {
            Ok(s.to_string())
        }
    }

    /// A value to post: a string, a finite number, or a boolean (posted as the string
    /// `true` or `false`, as uPokeDB posts it).
    pub(crate) fn value(&self, v: &Spanned<toml::Value>) -> Result<Value, ScenarioError> {
        match v.get_ref() {
            toml::Value::String(s) => Ok(Value::Str(s.clone())),
            toml::Value::Integer(i) => Ok(Value::Num(*i as f64)),
            toml::Value::Float(f) if f.is_finite() => Ok(Value::Num(*f)),
            toml::Value::Boolean(b) => Ok(Value::Str(b.to_string())),
            other => Err(self.bad(
                v.span(),
                format!(
                    "value must be a string, a finite number or a boolean, not {}",
                    other.type_str()
                ),
            )),
        }
    }

    /// A `[[poke]]`: its time (s from the start, >= 0), variable and value.
    pub(crate) fn poke(
        &self,
        at: &Spanned<f64>,
        var: &Spanned<String>,
        value: &Spanned<toml::Value>,
    ) -> Result<Poke, ScenarioError> {
        Ok(Poke {
            at: self.number(at, "at", Some(0.0))?,
            var: self.var_name(var)?,
            value: self.value(value)?,
        })
    }

    /// `[end]`, or the defaults where it or a key of it is left out.
    pub(crate) fn end(&self, end: Option<&EndDoc>) -> Result<End, ScenarioError> {
        let mut out = End {
            max_time: DEFAULT_MAX_TIME,
            mission_over: true,
            when: Vec::new(),
        };
        if let Some(end) = end {
            if let Some(m) = &end.max_time {
                out.max_time = self.seconds(m, "max_time")?;
            }
            out.mission_over = end.mission_over.unwrap_or(true);
            for w in &end.when {
                out.when.push(When {
                    var: self.var_name(&w.var)?,
                    value: self.value(&w.value)?,
                });
            }
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spanned<T: serde::de::DeserializeOwned>(text: &str) -> T {
        #[derive(Deserialize)]
        struct Doc<T> {
            v: T,
        }
        toml::from_str::<Doc<T>>(text).expect("toml").v
    }

    fn fields(text: &str) -> Fields<'_> {
        Fields::new(Path::new("s.toml"), text)
    }

    #[test]
    fn numbers_are_finite_and_at_least_their_minimum() {
        for (text, min, want) in [
            ("v = 2.5", None, Ok(2.5)),
            ("v = -3", None, Ok(-3.0)),
            ("v = 0", Some(0.0), Ok(0.0)),
            (
                "v = -0.5",
                Some(0.0),
                Err("s.toml:1: `x = -0.5`: must be >= 0"),
            ),
            (
                "v = inf",
                None,
                Err("s.toml:1: `x = inf`: must be a finite number"),
            ),
            (
                "\nv = nan",
                Some(0.0),
                Err("s.toml:2: `x = NaN`: must be a finite number"),
            ),
        ] {
            let v: Spanned<f64> = spanned(text);
            let got = fields(text).number(&v, "x", min).map_err(|e| e.to_string());
            assert_eq!(got, want.map_err(str::to_string), "{text}");
        }
        for (text, ok) in [("v = 0.1", true), ("v = 0", false), ("v = -1", false)] {
            let v: Spanned<f64> = spanned(text);
            let got = fields(text).seconds(&v, "tick");
            assert_eq!(got.is_ok(), ok, "{text}");
            if let Err(e) = got {
                assert!(e.to_string().ends_with("must be > 0 s"), "{e}");
            }
        }
    }

    #[test]
    fn end_has_defaults_and_checks_its_parts() {
        let f = fields("");
        let e = f.end(None).expect("defaults");
        assert_eq!(
            (e.max_time, e.mission_over, e.when.len()),
            (DEFAULT_MAX_TIME, true, 0)
        );
        let text = "max_time = 60\nmission_over = false\n[[when]]\nvar = \"M\"\nvalue = true\n";
        let doc: EndDoc = toml::from_str(text).expect("toml");
        let e = fields(text).end(Some(&doc)).expect("reads");
        assert_eq!((e.max_time, e.mission_over), (60.0, false));
        assert!(e.when[0].matches("M", &Value::Str("true".into())));
        let text = "\n[[when]]\nvar = \"M N\"\nvalue = 1\n";
        let doc: EndDoc = toml::from_str(text).expect("toml");
        let err = fields(text)
            .end(Some(&doc))
            .err()
            .expect("a bad name")
            .to_string();
        assert!(
            err.starts_with("s.toml:3: `M N` is not a MOOS variable name"),
            "{err}"
        );
    }
}
