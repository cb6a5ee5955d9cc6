//! What `helm view PATH` replays. A run is what the time slider plays at once:
//! - one `.alog`, or a folder holding one (`helm sim`'s `runs/alpha-<time>/`);
//! - a one-run fleet folder (`helm sim missions/encounter`): the logs of its vehicles,
//!   each reporting a vehicle of its own in `NODE_REPORT_LOCAL`, make one run;
//! - a folder of many runs (`--runs N --alogs`): a single vehicle's runs are its logs
//!   (`run-0000.alog`, ...), a fleet's are its sub-folders (`run-0000/`, one log per
//!   vehicle). `runs.csv` is the table when it has a row per run.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use serde::Serialize;
use thiserror::Error;

use crate::alog_index::{summary, AlogIndex, AlogIndexError};
use crate::frame::Frame;

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

/// One log of a run.
#[derive(Debug)]
pub struct Log {
    /// The file name relative to the opened path.
    pub name: String,
    pub index: AlogIndex,
    /// The vehicles this log is the ownship of: in a fleet's run, drawn from it alone.
    pub own: BTreeSet<String>,
    /// What names this log's shapes and variables beside the others' of its run.
    pub vehicle: String,
    /// Run time minus log time (s): the logs of a run may start at different times.
    pub offset: f64,
}

/// One replayable run: one log, or a fleet's logs played together.
#[derive(Debug)]
pub struct Run {
    /// The log's file name (a fleet's run: its folder) relative to the opened path.
    pub name: String,
    pub logs: Vec<Log>,
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

impl Run {
    fn new(name: String, mut logs: Vec<Log>) -> Run {
        // Logs of one run share a clock only through their LOGSTART headers.
        let starts: Option<Vec<f64>> = logs.iter().map(|l| l.index.logstart).collect();
        if let Some(first) = starts
            .as_ref()
            .and_then(|s| s.iter().copied().reduce(f64::min))
        {
            for (l, s) in logs.iter_mut().zip(starts.iter().flatten()) {
                l.offset = s - first;
            }
        }
        Run { name, logs }
    }

    pub fn t0(&self) -> f64 {
        let t = self.logs.iter().map(|l| l.index.t0 + l.offset);
        t.reduce(f64::min).unwrap_or(0.0)
    }

    pub fn t1(&self) -> f64 {
        let t = self.logs.iter().map(|l| l.index.t1 + l.offset);
        t.reduce(f64::max).unwrap_or(0.0)
    }

    pub fn lines(&self) -> u64 {
        self.logs.iter().map(|l| l.index.lines).sum()
    }

    pub fn skipped(&self) -> BTreeMap<String, u64> {
        let mut all = BTreeMap::new();
        for (k, n) in self.logs.iter().flat_map(|l| &l.index.skipped) {
            *all.entry(k.clone()).or_insert(0) += n;
        }
        all
    }

    pub fn skipped_summary(&self) -> String {
        summary(&self.skipped())
    }

    pub fn bounds(&self) -> Option<[f64; 4]> {
        let b = self.logs.iter().filter_map(|l| l.index.bounds);
        b.reduce(|a, b| {
            [
                a[0].min(b[0]),
                a[1].min(b[1]),
                a[2].max(b[2]),
                a[3].max(b[3]),
            ]
        })
    }

    /// Which log draws each vehicle: its own log; a contact no log owns, the first
    /// log that knows it (so a vehicle is never drawn twice).
    fn drawn_by(&self) -> BTreeMap<String, usize> {
        let mut by = BTreeMap::new();
        for (i, l) in self.logs.iter().enumerate() {
            for v in &l.own {
                by.entry(v.clone()).or_insert(i);
            }
        }
        for (i, l) in self.logs.iter().enumerate() {
            for v in l.index.vehicle_names() {
                by.entry(v).or_insert(i);
            }
        }
        by
    }

    pub fn vehicle_names(&self) -> Vec<String> {
        self.drawn_by().into_keys().collect()
    }

    /// Every vehicle's whole track thinned to at most `n` points.
    pub fn tracks(&self, n: usize) -> BTreeMap<String, Vec<[f64; 2]>> {
        if let [l] = self.logs.as_slice() {
            return l.index.tracks(n);
        }
        let by = self.drawn_by();
        let mut all = BTreeMap::new();
        for (i, l) in self.logs.iter().enumerate() {
            let mine = l.index.tracks(n).into_iter();
            all.extend(mine.filter(|(k, _)| by.get(k) == Some(&i)));
        }
        all
    }

    /// The picture at run time `t`: each log's at its own time, every vehicle from the
    /// log that draws it; shapes and variables carry their log's vehicle name, since
    /// the helms of a fleet post under the same labels.
    pub fn frame(&self, t: f64) -> Frame {
        if let [l] = self.logs.as_slice() {
            return l.index.frame(t);
        }
        let by = self.drawn_by();
        let mut f = Frame::full(t);
        for (i, l) in self.logs.iter().enumerate() {
            let mut g = l.index.frame(t - l.offset);
            for mut v in g.vehicles.drain(..) {
                if by.get(&v.name) == Some(&i) {
                    if let Some(tr) = g.trails.remove(&v.name) {
                        f.trails.insert(v.name.clone(), tr);
                    }
                    v.t += l.offset;
                    f.vehicles.push(v);
                }
            }
            for mut o in g.objects {
                o.key = format!("{}/{}", l.vehicle, o.key);
                f.objects.push(o);
            }
            let vars = g.vars.into_iter();
            f.vars
                .extend(vars.map(|(k, v)| (format!("{}/{k}", l.vehicle), v)));
            for a in g.appcasts {
                if f.appcasts.iter().all(|b| b.key != a.key) {
                    f.appcasts.push(a);
                }
            }
        }
        f
    }
}

/// The `.alog` files directly in a folder, and those of each direct sub-folder that
/// holds any (with the sub-folder's path), sorted by path.
#[allow(clippy::type_complexity)]
fn logs_in(dir: &Path) -> Result<(Vec<PathBuf>, Vec<(PathBuf, Vec<PathBuf>)>), RunsError> {
    let read = |d: &Path| {
        std::fs::read_dir(d).map_err(|source| RunsError::Folder {
            path: d.display().to_string(),
            source,
        })
    };
    let (mut top, mut subs) = (Vec::new(), Vec::new());
    for e in read(dir)?.flatten() {
        let p = e.path();
        if p.is_dir() {
            // A sub-folder that cannot be read is left out, not fatal.
            if let Ok(rd) = read(&p) {
                let mut logs: Vec<PathBuf> = rd
                    .flatten()
                    .map(|e| e.path())
                    .filter(|p| is_alog(p))
                    .collect();
                logs.sort();
                if !logs.is_empty() {
                    subs.push((p, logs));
                }
            }
        } else if is_alog(&p) {
            top.push(p);
        }
    }
    top.sort();
    subs.sort();
    Ok((top, subs))
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

/// `p` relative to the opened `root` (itself when it is the root).
fn relative(root: &Path, p: &Path) -> String {
    p.strip_prefix(root)
        .ok()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(p)
        .display()
        .to_string()
}

fn read_log(root: &Path, f: &Path) -> Result<Log, RunsError> {
    // The ownship of a log without node reports is named after the log
    // (`alpha.alog` of `helm sim missions/alpha`: the vehicle alpha).
    let stem = stem(f);
    let index = AlogIndex::open(f, &stem)?;
    let own = if !index.local.is_empty() {
        index.local.clone()
    } else if index.vehicle_names().contains(&stem) {
        BTreeSet::from([stem.clone()])
    } else {
        BTreeSet::new()
    };
    let vehicle = own.first().cloned().unwrap_or(stem);
    Ok(Log {
        name: relative(root, f),
        index,
        own,
        vehicle,
        offset: 0.0,
    })
}

/// How a folder's logs make runs.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Layout {
    /// Every log is a run.
    PerLog,
    /// Every sub-folder is a run (a fleet's Monte Carlo).
    Folders,
    /// All the logs are one run (a one-run fleet).
    OneRun,
}

/// The logs of one fleet's run: each reports a vehicle of its own, none the same.
fn is_fleet(logs: &[Log]) -> bool {
    let mut seen = BTreeSet::new();
    logs.iter()
        .all(|l| !l.index.local.is_empty() && l.index.local.iter().all(|v| seen.insert(v)))
}

/// `rows`: the rows of `runs.csv`, which `helm sim --runs` writes one per run.
fn layout(top: &[Log], subs: &[(String, Vec<Log>)], rows: Option<usize>) -> Layout {
    let total = top.len() + subs.iter().map(|s| s.1.len()).sum::<usize>();
    if top.is_empty() {
        let fleets = subs.iter().any(|s| s.1.len() > 1) && subs.iter().all(|s| is_fleet(&s.1));
        return match rows {
            Some(n) if n == total => Layout::PerLog,
            Some(n) if n == subs.len() => Layout::Folders,
            // No table to go by: the folders' contents tell.
            _ if fleets => Layout::Folders,
            _ => Layout::PerLog,
        };
    }
    // A Monte Carlo of one vehicle has a runs.csv; a one-run fleet has none.
    if subs.is_empty() && top.len() > 1 && rows.is_none() && is_fleet(top) {
        return Layout::OneRun;
    }
    Layout::PerLog
}

/// Open a log or a folder of logs.
pub fn open(path: &Path) -> Result<Runs, RunsError> {
    let title = path.display().to_string();
    if !path.is_dir() {
        let log = read_log(path, path)?;
        let runs = vec![Run::new(log.name.clone(), vec![log])];
        let table = default_table(&runs);
        return Ok(Runs { title, runs, table });
    }
    let (top, subs) = logs_in(path)?;
    if top.is_empty() && subs.is_empty() {
        return Err(RunsError::NoLog(title));
    }
    let csv = std::fs::read_to_string(path.join("runs.csv"))
        .ok()
        .and_then(|csv| read_csv(&csv));
    let top = top
        .iter()
        .map(|f| read_log(path, f))
        .collect::<Result<Vec<_>, _>>()?;
    let subs = subs
        .iter()
        .map(|(d, fs)| {
            let logs = fs.iter().map(|f| read_log(path, f));
            Ok((
                relative(path, d),
                logs.collect::<Result<Vec<_>, RunsError>>()?,
            ))
        })
        .collect::<Result<Vec<_>, RunsError>>()?;
    let runs: Vec<Run> = match layout(&top, &subs, csv.as_ref().map(|t| t.rows.len())) {
        Layout::PerLog => {
            let mut logs: Vec<Log> = top
                .into_iter()
                .chain(subs.into_iter().flat_map(|s| s.1))
                .collect();
            logs.sort_by(|a, b| Path::new(&a.name).cmp(Path::new(&b.name)));
            logs.into_iter()
                .map(|l| Run::new(l.name.clone(), vec![l]))
                .collect()
        }
        Layout::Folders => subs
            .into_iter()
            .map(|(d, logs)| Run::new(d, logs))
            .collect(),
        Layout::OneRun => {
            let name = path
                .file_name()
                .map_or_else(|| title.clone(), |n| n.to_string_lossy().into_owned());
            vec![Run::new(name, top)]
        }
    };
    let table = csv
        .filter(|t| t.rows.len() == runs.len())
        .unwrap_or_else(|| default_table(&runs));
    Ok(Runs { title, runs, table })
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
                    r.vehicle_names().join(" "),
                    format!("{:.1}", r.t1() - r.t0()),
                    r.lines().to_string(),
                    r.skipped().values().sum::<u64>().to_string(),
                ]
            })
            .collect(),
    }
}

#[cfg(test)]
pub(crate) mod tests {
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
        assert_eq!(r.runs[1].vehicle_names(), ["run-1"]);
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

    /// A fleet vehicle's log: `me` moves east 1 m/s along y = `y` from t = 0 to 10
    /// (its own clock, LOGSTART `start`), and hears of `other` through node reports that
    /// put it 1000 m off, so a drawing from the wrong log shows.
    fn fleet_log(me: &str, other: &str, y: f64, start: f64) -> String {
        let mut s = format!("%% LOGSTART {start}\n");
        for i in 0..=10 {
            s += &format!(
                "{i}.0 NODE_REPORT_LOCAL pNodeReporter NAME={me},X={i},Y={y},SPD=1,HDG=90\n"
            );
            s += &format!("{i}.0 NODE_REPORT pHelmIvP NAME={other},X=1000,Y=1000\n");
            s += &format!("{i}.0 DESIRED_SPEED pHelmIvP {y}\n");
        }
        s + "1.0 VIEW_POINT pHelmIvP x=0,y=0,label=nextpt\n"
    }

    pub(crate) fn folder(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("viewer-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// `dir/run-000N/{abe,ben}.alog` for N in 0..n; ben's log starts 2 s later.
    pub(crate) fn fleet_runs(dir: &Path, n: usize) {
        for r in 0..n {
            let d = dir.join(format!("run-{r:04}"));
            std::fs::create_dir_all(&d).unwrap();
            let y = r as f64 * 10.0;
            std::fs::write(d.join("abe.alog"), fleet_log("abe", "ben", y, 100.0)).unwrap();
            std::fs::write(d.join("ben.alog"), fleet_log("ben", "abe", y + 5.0, 102.0)).unwrap();
        }
    }

    #[test]
    fn a_fleets_runs_are_its_sub_folders_with_every_vehicle_from_its_own_log() {
        let dir = folder("fleet-runs");
        fleet_runs(&dir, 2);
        std::fs::write(
            dir.join("runs.csv"),
            "run,seed,closest_m\n0,1,5.0\n1,2,6.5\n",
        )
        .unwrap();
        let r = open(&dir).unwrap();
        let names: Vec<&str> = r.runs.iter().map(|r| r.name.as_str()).collect();
        assert_eq!(names, ["run-0000", "run-0001"]);
        assert_eq!(r.table.columns, ["run", "seed", "closest_m"]);
        assert_eq!(r.table.rows[1][2], "6.5");
        let run = &r.runs[1];
        assert_eq!(run.logs.len(), 2);
        assert_eq!(run.vehicle_names(), ["abe", "ben"]);
        // ben's clock starts 2 s after abe's: the run lasts 12 s of abe's clock.
        assert_eq!((run.t0(), run.t1()), (0.0, 12.0));
        let f = run.frame(6.0);
        let at: Vec<(&str, f64, f64, f64)> = f
            .vehicles
            .iter()
            .map(|v| (v.name.as_str(), v.x, v.y, v.t))
            .collect();
        assert_eq!(at, [("abe", 6.0, 10.0, 6.0), ("ben", 4.0, 15.0, 6.0)]);
        assert_eq!(f.trails["abe"].len(), 7);
        assert_eq!(f.trails["ben"].len(), 5);
        // Both helms posted the same labels: each keeps its own.
        let keys: Vec<&str> = f.objects.iter().map(|o| o.key.as_str()).collect();
        assert_eq!(keys, ["abe/point:nextpt", "ben/point:nextpt"]);
        assert_eq!(f.vars["abe/DESIRED_SPEED"], "10");
        assert_eq!(f.vars["ben/DESIRED_SPEED"], "15");
        let tracks = run.tracks(400);
        assert_eq!(tracks.keys().collect::<Vec<_>>(), ["abe", "ben"]);
        assert_eq!(tracks["ben"][0], [0.0, 15.0]);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_single_vehicles_runs_stay_one_per_log() {
        let dir = folder("alpha-runs");
        for i in 0..2 {
            let log = format!("%% LOGSTART 5\n0.0 NODE_REPORT_LOCAL p NAME=alpha,X={i},Y=0\n");
            std::fs::write(dir.join(format!("run-000{i}.alog")), log).unwrap();
        }
        // Without runs.csv too: two logs of one vehicle are two runs.
        for csv in [None, Some("run,seed\n0,1\n1,2\n")] {
            if let Some(c) = csv {
                std::fs::write(dir.join("runs.csv"), c).unwrap();
            }
            let r = open(&dir).unwrap();
            let names: Vec<&str> = r.runs.iter().map(|r| r.name.as_str()).collect();
            assert_eq!(names, ["run-0000.alog", "run-0001.alog"]);
            assert_eq!(r.table.rows.len(), 2);
            assert_eq!(r.runs[1].frame(1.0).vehicles[0].x, 1.0);
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_fleet_with_a_mismatched_csv_keeps_its_runs_and_gets_a_table_of_them() {
        let dir = folder("fleet-mismatch");
        fleet_runs(&dir, 2);
        // A table of 3 rows for 2 runs (say, a run's folder deleted): not this folder's.
        std::fs::write(dir.join("runs.csv"), "run,seed\n0,1\n1,2\n2,3\n").unwrap();
        let r = open(&dir).unwrap();
        assert_eq!(r.runs.len(), 2);
        assert_eq!(r.table.columns[..3], ["run", "log", "vehicles"]);
        assert_eq!(r.table.rows[1][..4], ["1", "run-0001", "abe ben", "12.0"]);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_one_run_fleet_folder_is_one_run_of_all_its_vehicles() {
        let dir = folder("fleet-one");
        std::fs::write(dir.join("abe.alog"), fleet_log("abe", "ben", 0.0, 100.0)).unwrap();
        std::fs::write(dir.join("ben.alog"), fleet_log("ben", "abe", 5.0, 100.0)).unwrap();
        std::fs::write(dir.join("summary.json"), "{}").unwrap();
        let r = open(&dir).unwrap();
        assert_eq!(r.runs.len(), 1);
        assert_eq!(r.runs[0].logs.len(), 2);
        assert_eq!(r.table.rows[0][2], "abe ben");
        let f = r.runs[0].frame(3.0);
        let at: Vec<(&str, f64)> = f.vehicles.iter().map(|v| (v.name.as_str(), v.y)).collect();
        assert_eq!(at, [("abe", 0.0), ("ben", 5.0)]);
        // One log alone is still a run of its own, with its contact as it heard it.
        let one = open(&dir.join("abe.alog")).unwrap();
        assert_eq!(one.runs[0].frame(3.0).vehicles.len(), 2);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
