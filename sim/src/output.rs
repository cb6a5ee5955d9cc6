//! What a single `helm sim` run leaves behind: the output folder, `summary.json`, the
//! picture and the terminal summary.

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::observe::AllStop;
use super::run::{Outcome, SimError};

/// `summary.json`.
#[derive(Debug, Serialize)]
pub struct Summary<'a> {
    pub mission: &'a str,
    pub sim_time_s: f64,
    pub wall_time_s: f64,
    pub end_reason: &'a str,
    pub distance_m: f64,
    pub iterations: u64,
    pub allstops: &'a [AllStop],
    pub behavior_errors: &'a [String],
    pub waypoints_reached: u64,
    pub start: Pose,
    pub end: Pose,
    pub helm_state: &'a str,
    /// Whether the helm was ever in DRIVE.
    pub drove: bool,
    pub behavior_panics: &'a [String],
    /// What went wrong, in plain words, worst first.
    pub warnings: Vec<String>,
}

#[derive(Debug, Serialize)]
pub struct Pose {
    pub x: f64,
    pub y: f64,
    pub heading: f64,
    pub speed: f64,
    pub depth: f64,
}

impl From<vehicle_model::Nav> for Pose {
    fn from(n: vehicle_model::Nav) -> Pose {
        Pose {
            x: n.x,
            y: n.y,
            heading: n.heading,
            speed: n.speed,
            depth: n.depth,
        }
    }
}

impl<'a> Summary<'a> {
    pub fn of(mission: &'a str, o: &'a Outcome) -> Summary<'a> {
        Summary {
            mission,
            sim_time_s: o.sim_time_s,
            wall_time_s: o.wall_time_s,
            end_reason: &o.end_reason,
            distance_m: o.observer.track.distance,
            iterations: o.iterations,
            allstops: &o.observer.allstops,
            behavior_errors: &o.observer.behavior_errors,
            waypoints_reached: o.observer.waypoints_reached,
            start: o.start.into(),
            end: o.end.into(),
            helm_state: o.helm_state,
            drove: o.drove,
            behavior_panics: &o.observer.behavior_panics,
            warnings: o.warnings(),
        }
    }
}

/// `YYYYmmdd-HHMMSS` (UTC) of now, for folder names.
pub fn utc_stamp() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let (days, rem) = (secs / 86_400, secs % 86_400);
    // Civil date from days since 1970-01-01 (H. Hinnant's algorithm).
    let z = days as i64 + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}{m:02}{d:02}-{:02}{:02}{:02}",
        rem / 3600,
        rem % 3600 / 60,
        rem % 60
    )
}

/// The output folder: `out` if given, else a new `runs/<name>-<stamp>[-N]`; created.
pub fn out_dir(out: Option<&Path>, name: &str) -> Result<PathBuf, SimError> {
    let dir = match out {
        Some(d) => d.to_path_buf(),
        None => {
            let base = PathBuf::from("runs").join(format!("{name}-{}", utc_stamp()));
            let mut dir = base.clone();
            let mut n = 2;
            while dir.exists() {
                dir = PathBuf::from(format!("{}-{n}", base.display()));
                n += 1;
            }
            dir
        }
    };
    std::fs::create_dir_all(&dir).map_err(|source| SimError::Write {
        path: dir.clone(),
        source,
    })?;
    Ok(dir)
}

pub fn write(path: &Path, text: &str) -> Result<(), SimError> {
    std::fs::write(path, text).map_err(|source| SimError::Write {
        path: path.to_path_buf(),
        source,
    })
}

/// The picture's title and subtitle.
pub fn picture_titles(name: &str, o: &Outcome) -> (String, String) {
    let mut sub = format!(
        "helm {}, {} iterations, {} waypoint(s) reached, {} all-stop(s), {} behavior error(s)",
        o.helm_state,
        o.iterations,
        o.observer.waypoints_reached,
        o.observer
            .allstops
            .iter()
            .filter(|a| super::observe::is_problem_allstop(&a.reason))
            .count(),
        o.observer.behavior_errors.len()
    );
    // What went wrong leads: a picture of a parked or panicked run must say so.
    for w in o.warnings().iter().rev() {
        sub = format!("{}: {w}. {sub}", "PROBLEM");
    }
    (
        format!(
            "{name}: {} after {:.1} s, {:.0} m",
            o.end_reason, o.sim_time_s, o.observer.track.distance
        ),
        sub,
    )
}

/// The all-stops line: the problems first; `NothingToDo` (no behavior active, as at a
/// mission's normal end) said apart, not as a failure.
fn allstop_text(stops: &[AllStop]) -> String {
    let list = |v: Vec<&AllStop>| {
        let more = if v.len() > 5 { ", ..." } else { "" };
        v.iter()
            .take(5)
            .map(|a| format!("{} at {:.1} s", a.reason, a.time))
            .collect::<Vec<_>>()
            .join(", ")
            + more
    };
    let (problems, idle): (Vec<&AllStop>, Vec<&AllStop>) = stops
        .iter()
        .partition(|a| super::observe::is_problem_allstop(&a.reason));
    let mut s = if problems.is_empty() {
        "none".to_string()
    } else {
        list(problems)
    };
    if !idle.is_empty() {
        let times: Vec<String> = idle
            .iter()
            .take(5)
            .map(|a| format!("{:.1} s", a.time))
            .collect();
        s.push_str(&format!(
            " (idle, no behavior active: NothingToDo at {})",
            times.join(", ")
        ));
    }
    s
}

/// The terminal summary (lines).
pub fn terminal_summary(name: &str, o: &Outcome) -> String {
    let speedup = if o.wall_time_s > 0.0 {
        format!("{:.0}x real time", o.sim_time_s / o.wall_time_s)
    } else {
        "-".into()
    };
    let stops = allstop_text(&o.observer.allstops);
    let errors = if o.observer.behavior_errors.is_empty() {
        "none".to_string()
    } else {
        format!(
            "{} (first: {})",
            o.observer.behavior_errors.len(),
            o.observer.behavior_errors[0]
        )
    };
    let problems: String = o
        .warnings()
        .iter()
        .map(|w| format!("PROBLEM: {w}\n"))
        .collect();
    format!(
        "{problems}{name}: {} after {:.1} s simulated, {:.3} s wall ({speedup}), {} helm iterations, \
         helm {}\n  \
         distance {:.1} m, waypoints reached {}, end x={:.1} y={:.1} heading={:.0} speed={:.2}\n  \
         all-stops: {stops}\n  behavior errors: {errors}",
        o.end_reason,
        o.sim_time_s,
        o.wall_time_s,
        o.iterations,
        o.helm_state,
        o.observer.track.distance,
        o.observer.waypoints_reached,
        o.end.x,
        o.end.y,
        o.end.heading,
        o.end.speed,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stamp_is_a_plausible_utc_time() {
        let s = utc_stamp();
        assert_eq!(s.len(), 15, "{s}");
        assert!(s.starts_with("20"), "{s}");
        assert_eq!(&s[8..9], "-");
    }
}
