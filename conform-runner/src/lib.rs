//! `helm-conform`: replaying the golden cases recorded from the real C++ helm
//! (`conformance/README.md`) through the engine, step by step, and comparing every
//! checked posting; also timing the decision step per case (`helm conform --bench`).
//!
//! It depends on `helm-engine` (and `bhv` to read a case's behavior file) and must not
//! depend on the MOOS app, the simulator or any socket: a case is replayed in memory.
//!
//! ```
//! use helm_conform::{run_file, Outcome};
//! use helm_engine::factory::BehaviorFactory;
//! let case = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
//!     .join("../conformance/helm/two_wpt_weighted.toml");
//! let result = run_file(&case, &BehaviorFactory::with_builtins());
//! assert_eq!(result.outcome(), Outcome::Passed, "{:?}", result.mismatches);
//! ```

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::Deserialize;

use helm_engine::config::{BlockLine, HelmConfig};
use helm_engine::factory::BehaviorFactory;
use helm_engine::posting::{Posting, Value};
use helm_engine::{Helm, Mail};

mod bench;
pub use bench::{bench_file, BenchOutcome, BenchResult, CppTiming};

/// One recorded case.
#[derive(Debug, Deserialize)]
pub struct Case {
    pub name: String,
    #[serde(default)]
    pub description: String,
    pub domain: Vec<String>,
    pub check: Vec<String>,
    pub bhv: String,
    #[serde(default)]
    pub config: BTreeMap<String, toml::Value>,
    #[serde(default)]
    pub tolerance: Option<f64>,
    pub step: Vec<Step>,
}

#[derive(Debug, Deserialize)]
pub struct Step {
    pub time: f64,
    #[serde(default)]
    pub mail: Vec<(String, toml::Value)>,
    #[serde(default)]
    pub expect: BTreeMap<String, toml::Value>,
}

/// A difference between the recording and our helm.
#[derive(Debug, Clone, PartialEq)]
pub struct Mismatch {
    pub step: usize,
    pub var: String,
    pub expected: String,
    pub got: String,
}

/// The result of one case.
#[derive(Debug)]
pub struct CaseResult {
    pub name: String,
    pub file: PathBuf,
    /// Set when the helm could not be built for the case (e.g. unknown behavior type).
    pub error: Option<String>,
    pub mismatches: Vec<Mismatch>,
    /// The behavior types the case names that this project does not have yet (sorted):
    /// such a case is not run, and neither passes nor fails.
    pub waiting_for: Vec<String>,
}

/// How a case ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    Passed,
    Failed,
    /// Names a behavior type the project does not have yet.
    Waiting,
}

impl CaseResult {
    pub fn outcome(&self) -> Outcome {
        if !self.waiting_for.is_empty() {
            Outcome::Waiting
        } else if self.error.is_none() && self.mismatches.is_empty() {
            Outcome::Passed
        } else {
            Outcome::Failed
        }
    }

    pub fn passed(&self) -> bool {
        self.outcome() == Outcome::Passed
    }

    fn failed(name: String, file: &Path, error: String) -> Self {
        CaseResult {
            name,
            file: file.to_path_buf(),
            error: Some(error),
            mismatches: Vec::new(),
            waiting_for: Vec::new(),
        }
    }
}

/// The behavior types `case` names that neither `factory` offers nor this project has:
/// the case waits for them. A type the project has but the factory lacks (a shipped
/// library not found) is not listed: building the helm then fails with its own error.
pub fn missing_types(case: &Case, file: &Path, factory: &BehaviorFactory) -> Vec<String> {
    let Ok(spec) = bhv::reader::parse_str(&case.bhv, &file.with_extension("bhv")) else {
        return Vec::new();
    };
    let mut missing: Vec<String> = spec
        .behaviors
        .iter()
        .map(|b| b.type_name.clone())
        .filter(|t| !factory.knows(t) && !helm_engine::factory::project_has_type(t))
        .collect();
    missing.sort();
    missing.dedup();
    missing
}

/// Errors reading a case file.
#[derive(Debug, thiserror::Error)]
pub enum CaseError {
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path}: not a conformance case: {source}")]
    Parse {
        path: PathBuf,
        source: toml::de::Error,
    },
    #[error("no conformance cases (*.toml) in {}", paths)]
    NoCases { paths: String },
}

/// Case files named by `paths` (a file, or a folder of `*.toml` files, searched
/// recursively), sorted per folder. In subfolders, only files that read as helm cases are
/// taken (so `conformance/` skips the IvP-level cases beside the helm ones). No case at
/// all is an error: a typo must not read as "0 failed".
pub fn collect(paths: &[PathBuf]) -> Result<Vec<PathBuf>, CaseError> {
    let mut out = Vec::new();
    for p in paths {
        if p.is_dir() {
            collect_dir(p, true, &mut out)?;
        } else if p.exists() {
            out.push(p.clone());
        } else {
            return Err(CaseError::Io {
                path: p.clone(),
                source: std::io::Error::new(std::io::ErrorKind::NotFound, "no such file"),
            });
        }
    }
    if out.is_empty() {
        return Err(CaseError::NoCases {
            paths: paths
                .iter()
                .map(|p| p.display().to_string())
                .collect::<Vec<_>>()
                .join(", "),
        });
    }
    Ok(out)
}

fn collect_dir(dir: &Path, top: bool, out: &mut Vec<PathBuf>) -> Result<(), CaseError> {
    let rd = std::fs::read_dir(dir).map_err(|source| CaseError::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    let mut entries: Vec<PathBuf> = rd.filter_map(|e| e.ok().map(|e| e.path())).collect();
    entries.sort();
    let (dirs, files): (Vec<PathBuf>, Vec<PathBuf>) = entries.into_iter().partition(|p| p.is_dir());
    for f in files {
        if f.extension().is_some_and(|e| e == "toml") && (top || load(&f).is_ok()) {
            out.push(f);
        }
    }
    for d in dirs {
        collect_dir(&d, false, out)?;
    }
    Ok(())
}

/// Every case named by `paths` ([`collect`]), each with its file, read ([`load`]).
pub fn load_all(paths: &[PathBuf]) -> Result<Vec<(PathBuf, Case)>, CaseError> {
    let files = collect(paths)?;
    files
        .into_iter()
        .map(|f| load(&f).map(|case| (f, case)))
        .collect()
}

pub fn load(path: &Path) -> Result<Case, CaseError> {
    let text = std::fs::read_to_string(path).map_err(|source| CaseError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    toml::from_str(&text).map_err(|source| CaseError::Parse {
        path: path.to_path_buf(),
        source,
    })
}

fn toml_value(v: &toml::Value) -> Value {
    match v {
        toml::Value::Float(f) => Value::Num(*f),
        toml::Value::Integer(i) => Value::Num(*i as f64),
        toml::Value::String(s) => Value::Str(s.clone()),
        toml::Value::Boolean(b) => Value::Str(b.to_string()),
        other => Value::Str(other.to_string()),
    }
}

fn show(v: &Value) -> String {
    match v {
        Value::Num(n) => format!("{n}"),
        Value::Str(s) => format!("{s:?}"),
    }
}

/// Build a helm for the case, as the recording did.
pub fn build_helm(case: &Case, file: &Path, factory: &BehaviorFactory) -> Result<Helm, String> {
    let mut lines: Vec<BlockLine> = case
        .domain
        .iter()
        .enumerate()
        .map(|(i, d)| BlockLine {
            line: i + 1,
            name: "domain".into(),
            value: d.clone(),
        })
        .collect();
    for (k, v) in &case.config {
        let value = match v {
            toml::Value::String(s) => s.clone(),
            other => other.to_string(),
        };
        lines.push(BlockLine {
            line: 0,
            name: k.clone(),
            value,
        });
    }
    let (config, warnings) = HelmConfig::from_lines(&lines);
    let bhv_path = file.with_extension("bhv");
    let spec = bhv::reader::parse_str(&case.bhv, &bhv_path).map_err(|e| e.to_string())?;
    let warnings: Vec<String> = warnings.iter().map(|w| w.to_string()).collect();
    let helm = Helm::new(config, spec, factory, "alpha", warnings);
    if !helm.config_warnings().is_empty() {
        return Err(helm.config_warnings().join("; "));
    }
    Ok(helm)
}

/// The helm's own postings on subscribed variables come back as mail, in order.
fn echo(helm: &Helm, posted: &[Posting], time: f64, out: &mut Vec<Mail>) {
    for p in posted {
        if helm.is_subscribed(&p.var) {
            out.push(Mail {
                var: p.var.clone(),
                value: p.value.clone(),
                time,
                source: helm.app_name().to_string(),
                source_aux: p.source_aux.clone(),
            });
        }
    }
}

/// Replay a case; compares only when `compare` (the bench replays without comparing).
pub fn replay(case: &Case, helm: &mut Helm, compare: bool) -> Vec<Mismatch> {
    let tol = case.tolerance.unwrap_or(1e-6);
    let mut mismatches = Vec::new();
    let mut mail: Vec<Mail> = Vec::new();
    let mut posted: Vec<Posting> = Vec::new();
    let mut last_time = case.step.first().map_or(0.0, |s| s.time);
    let start = helm.startup(last_time).to_vec();
    posted.extend(start);
    for (k, step) in case.step.iter().enumerate() {
        mail.clear();
        echo(helm, &posted, last_time, &mut mail);
        if k > 0 {
            posted.clear();
        }
        for (var, v) in &step.mail {
            mail.push(Mail {
                var: var.clone(),
                value: toml_value(v),
                time: step.time,
                source: "uSimMarine".into(),
                source_aux: String::new(),
            });
        }
        helm.handle_mail(step.time, &mail);
        // The first step's expectations include what start-up published.
        let out = helm.iterate(step.time);
        posted.extend_from_slice(out);
        last_time = step.time;
        if compare {
            compare_step(case, k, &posted, tol, &mut mismatches);
        }
    }
    mismatches
}

fn compare_step(case: &Case, k: usize, posted: &[Posting], tol: f64, out: &mut Vec<Mismatch>) {
    let step = &case.step[k];
    for var in &case.check {
        let got = posted
            .iter()
            .rev()
            .find(|p| &p.var == var)
            .map(|p| &p.value);
        let expected = step.expect.get(var).map(toml_value);
        let same = match (&expected, got) {
            (None, None) => true,
            (Some(Value::Num(a)), Some(Value::Num(b))) => (a - b).abs() <= tol,
            (Some(Value::Str(a)), Some(Value::Str(b))) => a == b,
            _ => false,
        };
        if !same {
            out.push(Mismatch {
                step: k,
                var: var.clone(),
                expected: expected.as_ref().map_or("(not published)".into(), show),
                got: got.map_or("(not published)".into(), show),
            });
        }
    }
}

/// Run one case file.
pub fn run_file(file: &Path, factory: &BehaviorFactory) -> CaseResult {
    let case = match load(file) {
        Ok(c) => c,
        Err(e) => return CaseResult::failed(file.display().to_string(), file, e.to_string()),
    };
    let waiting_for = missing_types(&case, file, factory);
    if !waiting_for.is_empty() {
        return CaseResult {
            name: case.name,
            file: file.to_path_buf(),
            error: None,
            mismatches: Vec::new(),
            waiting_for,
        };
    }
    match build_helm(&case, file, factory) {
        Ok(mut helm) => CaseResult {
            name: case.name.clone(),
            file: file.to_path_buf(),
            error: None,
            mismatches: replay(&case, &mut helm, true),
            waiting_for: Vec::new(),
        },
        Err(e) => CaseResult::failed(case.name, file, e),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `load_all` gives every file `collect` finds, in its order, each with its case,
    /// and fails as `collect` does on a folder without cases.
    #[test]
    fn load_all_reads_every_collected_case_in_order() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../conformance/helm");
        let files = collect(std::slice::from_ref(&dir)).unwrap();
        let all = load_all(&[dir]).unwrap();
        assert!(all.len() >= 28, "{}", all.len());
        let paths: Vec<&PathBuf> = all.iter().map(|(p, _)| p).collect();
        assert_eq!(paths, files.iter().collect::<Vec<_>>());
        for (p, case) in &all {
            let stem = p.file_stem().and_then(|s| s.to_str()).unwrap_or_default();
            assert_eq!(case.name, stem);
            assert!(!case.step.is_empty(), "{stem}");
        }
        let empty = std::env::temp_dir().join(format!("conform-empty-{}", std::process::id()));
        std::fs::create_dir_all(&empty).unwrap();
        let err = load_all(std::slice::from_ref(&empty)).unwrap_err();
        assert!(matches!(err, CaseError::NoCases { .. }), "{err}");
        let _ = std::fs::remove_dir(&empty);
    }
}
