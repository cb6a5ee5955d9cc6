//! A manager's `ProcessConfig` block read from a mission file: the one reading the
//! `contactmgr`/`obstaclemgr` binaries and the simulator's per-vehicle managers share.

use moos::mission::{config_f64, MissionFile};

/// Block lines every MOOS app reads itself (not the manager's business).
pub const APP_PARAMS: &[&str] = &[
    "apptick",
    "commstick",
    "maxapptick",
    "iteratemode",
    "app_logging",
    "comms_policy",
    "term_report_interval",
];

/// Hand each line of `ProcessConfig = app` (but the app-level ones) to `set`. `None`:
/// the mission has no such block; else every refused line as `file:line: problem`,
/// in line order.
pub fn read(
    mission: &MissionFile,
    app: &str,
    mut set: impl FnMut(&str, &str) -> Result<(), String>,
) -> Option<Vec<String>> {
    let lines = mission.process_config(app)?;
    let file = mission.path().display();
    let mut problems = Vec::new();
    for l in lines {
        if APP_PARAMS.iter().any(|p| l.name_is(p)) {
            continue;
        }
        if let Err(e) = set(&l.name, &l.value) {
            problems.push(format!("{file}:{}: {e}", l.line));
        }
    }
    Some(problems)
}

/// The mission's `LatOrigin`/`LongOrigin`, when both are numbers.
pub fn origin(mission: &MissionFile) -> Option<(f64, f64)> {
    let lat = mission.global("LatOrigin").and_then(|v| config_f64(&v))?;
    let lon = mission.global("LongOrigin").and_then(|v| config_f64(&v))?;
    Some((lat, lon))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn app_lines_skipped_problems_with_file_and_line_in_order() {
        let text = "ProcessConfig = pX\n{\n  AppTick = 2\n  good = 1\n  bad = 2\n  bare\n}\n";
        let m = MissionFile::parse(text, Path::new("t.moos")).expect("parses");
        let mut seen = Vec::new();
        let problems = read(&m, "pX", |k, v| {
            seen.push(format!("{k}={v}"));
            if k == "bad" {
                Err("no".into())
            } else {
                Ok(())
            }
        })
        .expect("a block");
        assert_eq!(seen, ["good=1", "bad=2"]);
        // (The mission reader drops a bare word: it never reaches `set`.)
        assert_eq!(problems, ["t.moos:5: no"]);
        assert!(read(&m, "pY", |_, _| Ok(())).is_none());
    }
}
