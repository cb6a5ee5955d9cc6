//! `helm conform --bench`: the decision step timed per case, beside the C++ helm's time
//! for the same case (`<case>.timing-O2.json`, conformance/README.md).

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use helm_engine::factory::BehaviorFactory;
use serde::Deserialize;

use crate::{build_helm, load, missing_types, replay};

/// Timing of a case replayed repeatedly for at least `min_secs`.
#[derive(Debug, Clone)]
pub struct BenchResult {
    pub name: String,
    /// Mean µs per decision iteration (modes, behaviors, solve): the C++ measure.
    pub decision_us: f64,
    /// The median over the replays of each replay's mean µs per decision: what the
    /// recordings call `median_rep_us_per_iteration`, steadier than the mean on a
    /// shared machine.
    pub median_rep_us: f64,
    /// How many times the case was replayed.
    pub reps: usize,
    /// Mean µs per whole iteration step: mail, iteration, publication, runner echo.
    pub whole_us: f64,
}

/// What `bench_file` measured.
#[derive(Debug, Clone)]
pub enum BenchOutcome {
    Timed(BenchResult),
    /// The case names behavior types the project does not have yet (see [`missing_types`]).
    Waiting(Vec<String>),
}

/// Replay `case` repeatedly, each time through a fresh helm, for at least `min_secs`.
pub fn bench_file(
    file: &Path,
    factory: &BehaviorFactory,
    min_secs: f64,
) -> Result<BenchOutcome, String> {
    let case = load(file).map_err(|e| e.to_string())?;
    let waiting_for = missing_types(&case, file, factory);
    if !waiting_for.is_empty() {
        return Ok(BenchOutcome::Waiting(waiting_for));
    }
    let mut decide = Duration::ZERO;
    let mut decisions = 0u64;
    let mut whole = 0.0;
    let mut per_rep = Vec::new();
    let wall = Instant::now();
    while wall.elapsed().as_secs_f64() < min_secs || per_rep.is_empty() {
        let mut helm = build_helm(&case, file, factory)?;
        let t = Instant::now();
        replay(&case, &mut helm, false);
        whole += t.elapsed().as_secs_f64();
        let (d, n) = helm.decision_timing();
        decide += d;
        decisions += n;
        per_rep.push(d.as_secs_f64() / n.max(1) as f64 * 1e6);
    }
    let decisions = decisions.max(1);
    Ok(BenchOutcome::Timed(BenchResult {
        name: case.name,
        decision_us: decide.as_secs_f64() / decisions as f64 * 1e6,
        median_rep_us: median(&mut per_rep),
        reps: per_rep.len(),
        whole_us: whole / decisions as f64 * 1e6,
    }))
}

/// The middle value (the mean of the two middle ones for an even count); 0 when empty.
fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    if v.len() % 2 == 1 {
        v[m]
    } else {
        (v[m - 1] + v[m]) / 2.0
    }
}

/// The real C++ helm's time for a case (`-O2` build), as its recording gives it.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct CppTiming {
    #[serde(rename = "mean_us_per_iteration")]
    pub mean_us: f64,
    #[serde(rename = "median_rep_us_per_iteration")]
    pub median_rep_us: f64,
    /// The CPU the recording ran on.
    #[serde(default)]
    pub cpu: String,
}

impl CppTiming {
    /// The file beside a case: `<case>.timing-O2.json`.
    pub fn file_for(case: &Path) -> PathBuf {
        case.with_extension("timing-O2.json")
    }

    /// The timing beside `case`: `Ok(None)` when there is none, an error naming the file
    /// when it is there but unreadable.
    pub fn beside(case: &Path) -> Result<Option<CppTiming>, String> {
        let file = Self::file_for(case);
        let text = match std::fs::read_to_string(&file) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(format!("{}: {e}", file.display())),
        };
        serde_json::from_str(&text)
            .map(Some)
            .map_err(|e| format!("{}: {e}", file.display()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_odd_even_and_empty() {
        assert_eq!(median(&mut [3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&mut [4.0, 1.0, 3.0, 2.0]), 2.5);
        assert_eq!(median(&mut []), 0.0);
    }

    #[test]
    fn the_recordings_timing_is_read_beside_the_case() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../conformance/helm");
        let t = CppTiming::beside(&dir.join("two_wpt_weighted.toml"))
            .expect("readable")
            .expect("every recorded case has its timing");
        assert!(t.mean_us > 0.0 && t.median_rep_us > 0.0, "{t:?}");
        assert!(!t.cpu.is_empty());
        assert_eq!(CppTiming::beside(&dir.join("no_such_case.toml")), Ok(None));
    }

    #[test]
    fn an_unreadable_timing_names_its_file() {
        let dir = std::env::temp_dir().join(format!("conform-timing-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        std::fs::write(
            dir.join("c.timing-O2.json"),
            "{\"mean_us_per_iteration\": 1}",
        )
        .expect("write");
        let e = CppTiming::beside(&dir.join("c.toml")).expect_err("a field is missing");
        assert!(e.contains("c.timing-O2.json"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
