//! What `helm view PATH` replays: one `.alog`, a run folder holding one (`helm sim`'s
//! `runs/alpha-<time>/`), or a folder of many runs (Monte Carlo: every `.alog` in it or in
//! its sub-folders, with `runs.csv` as the table when it has a row per log).

use std::path::{Path, PathBuf};

use serde::Serialize;
use thiserror::Error;

use crate::alog_index::{AlogIndex, AlogIndexError};

#[derive(Debug, Error)]
pub enum RunsError {
    #[error("{0}")]
    Alog(#[from] AlogIndexError),
    #[error("cannot read folder {path}: {source}")]
    Folder {
        path: String,
        #[source]
        source: std::io::Error,
    },
    #[error("no .alog file in {0} (nor in its sub-folders)")]
    NoLog(String),
}

/// One replayable run.
#[derive(Debug)]
pub struct Run {
    /// The log's file name relative to the opened path.
    pub name: String,
    pub index: AlogIndex,
}

/// The table beside the map in a folder of runs.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Table {
    pub columns: Vec<String>,
    /// One row per run, in the order of [`Runs::runs`].
    pub rows: Vec<Vec<String>>,
}

/// Everything opened for a replay.
#[derive(Debug)]
pub struct Runs {
    pub title: String,
    pub runs: Vec<Run>,
    pub table: Table,
}

/// The `.alog` files of a folder and of its direct sub-folders, sorted by path.
fn logs_in(dir: &Path) -> Result<Vec<PathBuf>, RunsError> {
    let read = |d: &Path| {
        std::fs::read_dir(d).map_err(|source| RunsError::Folder {
            path: d.display().to_string(),
            source,
        })
    };
    let mut out = Vec::new();
    for e in read(dir)?.flatten() {
        let p = e.path();
        if p.is_dir() {
            // A sub-folder that cannot be read is left out, not fatal.
            if let Ok(rd) = read(&p) {
                out.extend(rd.flatten().map(|e| e.path()).filter(|p| is_alog(p)));
            }
        } else if is_alog(&p) {
            out.push(p);
        }
    }
    out.sort();
    Ok(out)
}

fn is_alog(p: &Path) -> bool {
    p.is_file()
        && p.extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("alog"))
}

fn stem(p: &Path) -> String {
    p.file_stem()
        .map_or_else(|| "ownship".into(), |s| s.to_string_lossy().into_owned())
}

/// Open a log or a folder of logs.
pub fn open(path: &Path) -> Result<Runs, RunsError> {
    let files = if path.is_dir() {
        logs_in(path)?
    } else {
        vec![path.to_owned()]
    };
    if files.is_empty() {
        return Err(RunsError::NoLog(path.display().to_string()));
    }
    let mut runs = Vec::with_capacity(files.len());
    for f in &files {
        // The ownship of a log without node reports is named after the log
        // (`alpha.alog` of `helm sim missions/alpha`: the vehicle alpha).
        let index = AlogIndex::open(f, &stem(f))?;
        let name = f
            .strip_prefix(path)
            .ok()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(f)
            .display()
            .to_string();
        runs.push(Run { name, index });
    }
    let table = path
        .is_dir()
        .then(|| std::fs::read_to_string(path.join("runs.csv")).ok())
        .flatten()
        .and_then(|csv| read_csv(&csv))
        .filter(|t| t.rows.len() == runs.len())
        .unwrap_or_else(|| default_table(&runs));
    Ok(Runs {
        title: path.display().to_string(),
        runs,
        table,
    })
}

/// `runs.csv` as `helm sim --runs` writes it (no quoting: its fields hold no comma).
fn read_csv(text: &str) -> Option<Table> {
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let columns: Vec<String> = lines.next()?.split(',').map(str::to_owned).collect();
    let rows = lines
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect();
    Some(Table { columns, rows })
}

fn default_table(runs: &[Run]) -> Table {
    Table {
        columns: ["run", "log", "vehicles", "duration_s", "lines", "skipped"]
            .map(String::from)
            .to_vec(),
        rows: runs
            .iter()
            .enumerate()
            .map(|(i, r)| {
                vec![
                    i.to_string(),
                    r.name.clone(),
                    r.index.vehicle_names().join(" "),
                    format!("{:.1}", r.index.t1 - r.index.t0),
                    r.index.lines.to_string(),
                    r.index.skipped.values().sum::<u64>().to_string(),
                ]
            })
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_folder_of_runs_with_and_without_csv() {
        let dir = std::env::temp_dir().join(format!("viewer-runs-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("run-1")).unwrap();
        std::fs::write(dir.join("run-0.alog"), "1.0 NAV_X s 1\n1.0 NAV_Y s 2\n").unwrap();
        std::fs::write(
            dir.join("run-1/run-1.alog"),
            "2.0 NAV_X s 3\n2.0 NAV_Y s 4\n",
        )
        .unwrap();
        let r = open(&dir).unwrap();
        assert_eq!(r.runs.len(), 2);
        assert_eq!(r.table.rows[1][1], "run-1/run-1.alog");
        assert_eq!(r.runs[1].index.vehicle_names(), ["run-1"]);
        std::fs::write(
            dir.join("runs.csv"),
            "run,seed,end_reason\n0,1,ok\n1,2,timeout\n",
        )
        .unwrap();
        let r = open(&dir).unwrap();
        assert_eq!(r.table.columns, ["run", "seed", "end_reason"]);
        assert_eq!(r.table.rows[1][2], "timeout");
        let empty = dir.join("empty");
        std::fs::create_dir_all(&empty).unwrap();
        assert!(matches!(open(&empty), Err(RunsError::NoLog(_))));
        assert!(open(&dir.join("missing.alog")).is_err());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
