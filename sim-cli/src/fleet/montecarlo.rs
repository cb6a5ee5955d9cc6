//! Encounter Monte Carlo: a fleet N times from perturbed starts, on all cores, and in
//! shards on a cluster.
//!
//! Run `i` uses seed `S + i`; every vehicle's start shift is drawn from that seed alone
//! (vehicle after vehicle, uniform in ±jitter), and so are the comms drops, so a row is
//! reproduced by `--runs 1 --seed <its seed>` and the table does not depend on the thread
//! count. `--shard K/N` runs the K-th of N contiguous slices of the run set and writes its
//! rows (`shard.json`, beside its `runs.csv`); `helm sim merge DIR...` checks that the
//! shards belong to one run set and cover it, and writes the `runs.csv` one process would
//! have written, byte for byte.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::args::{progress, verdict, SimArgs};
use crate::montecarlo::{unit, Jitter};
use crate::output;
use helm_sim::fleet::collide::Detector;
use helm_sim::fleet::run::{FleetOptions, FleetPlan};
use helm_sim::run::{SimError, StartShift};

/// Every vehicle's start shift and speed change for the run with `seed`: the poses
/// vehicle after vehicle, then the speeds, so a seed's poses are what they were before
/// speed jitter existed.
pub fn shifts(j: &Jitter, seed: u64, vehicles: usize) -> Vec<StartShift> {
    let mut s = seed;
    let mut all: Vec<StartShift> = (0..vehicles)
        .map(|_| StartShift {
            dx: j.x * unit(&mut s),
            dy: j.y * unit(&mut s),
            dheading: j.heading * unit(&mut s),
            dspeed_pct: 0.0,
        })
        .collect();
    if j.speed > 0.0 {
        for v in &mut all {
            v.dspeed_pct = j.speed * unit(&mut s);
        }
    }
    all
}

/// One pair in a row.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PairCells {
    pub closest_m: f64,
    pub near_misses: u32,
    pub collisions: u32,
}

/// One row of a fleet's `runs.csv`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Row {
    pub run: usize,
    pub seed: u64,
    pub end_reason: String,
    pub sim_time_s: f64,
    pub encounters: u32,
    pub near_misses: u32,
    pub collisions: u32,
    pub closest_m: f64,
    /// In the order of [`Detector`]'s pairs.
    pub pairs: Vec<PairCells>,
    /// Behaviors each vehicle's helm spawned.
    pub spawned: Vec<u64>,
    /// Each vehicle's speed change (percent of its commanded speed); empty when the run
    /// set does not perturb speeds.
    #[serde(default)]
    pub speed_pct: Vec<f64>,
    pub behavior_panics: usize,
    pub behavior_errors: usize,
    /// Obstacle counts, when the scenario has obstacles (issue 22).
    #[serde(default)]
    pub obstacles: Option<super::stats::ObstacleCells>,
    /// Each ordered pair's COLREGS situation and verdict, in [`super::stats::rule_columns`]' order.
    #[serde(default)]
    pub rules: Vec<super::stats::RuleCell>,
}

/// Which runs of `runs` the shard `k` of `n` (1-based) runs: a contiguous slice.
pub fn slice(runs: usize, k: usize, n: usize) -> std::ops::Range<usize> {
    (k - 1) * runs / n..k * runs / n
}

/// Where run `i` of `runs` writes its vehicles' logs under `dir` (`--alogs`): a folder
/// named as a one-vehicle run's log (`run-0000`, ...), holding `<vehicle>.alog` as a
/// one-run fleet writes them.
pub fn run_alog_dir(dir: &Path, i: usize, runs: usize) -> PathBuf {
    let name = crate::montecarlo::run_alog_name(i, runs);
    dir.join(name.strip_suffix(".alog").unwrap_or(&name))
}

/// Run `range` of the run set of `runs` runs with first seed `seed`; with `alogs`, each
/// run's logs go to [`run_alog_dir`] under it.
#[allow(clippy::too_many_arguments)]
pub fn run_range(
    plan: &FleetPlan,
    range: std::ops::Range<usize>,
    runs: usize,
    seed: u64,
    jitter: Jitter,
    max_time: Option<f64>,
    alogs: Option<&Path>,
    done: &(dyn Fn() + Sync),
) -> Result<Vec<Row>, SimError> {
    range
        .into_par_iter()
        .map(|i| {
            // After Ctrl-C, runs not yet started are skipped: fewer rows.
            if crate::interrupt::requested() {
                return Ok(None);
            }
            let s = seed.wrapping_add(i as u64);
            let shifts = shifts(&jitter, s, plan.vehicles.len());
            let alog_dir = match alogs {
                Some(dir) => {
                    let d = run_alog_dir(dir, i, runs);
                    std::fs::create_dir_all(&d).map_err(|source| SimError::Write {
                        path: d.clone(),
                        source,
                    })?;
                    Some(d)
                }
                None => None,
            };
            let o = plan.run(
                &shifts,
                &FleetOptions {
                    alog_dir,
                    max_time,
                    seed: s,
                    ..FleetOptions::default()
                },
            )?;
            done();
            let (encounters, near_misses, collisions) = Detector::totals(&o.pairs);
            Ok(Some(Row {
                run: i,
                seed: s,
                end_reason: o.end_reason.clone(),
                sim_time_s: o.sim_time_s,
                encounters,
                near_misses,
                collisions,
                closest_m: super::output::closest(&o.pairs),
                pairs: o
                    .pairs
                    .iter()
                    .map(|p| PairCells {
                        closest_m: p.closest_m,
                        near_misses: p.near_misses,
                        collisions: p.collisions,
                    })
                    .collect(),
                spawned: o.vehicles.iter().map(|v| v.observer.spawns).collect(),
                speed_pct: if jitter.speed > 0.0 {
                    shifts.iter().map(|v| v.dspeed_pct).collect()
                } else {
                    Vec::new()
                },
                behavior_panics: o
                    .vehicles
                    .iter()
                    .map(|v| v.observer.behavior_panics.len())
                    .sum(),
                behavior_errors: o
                    .vehicles
                    .iter()
                    .map(|v| v.observer.behavior_errors.len())
                    .sum(),
                obstacles: o.obstacles.as_ref().map(super::stats::ObstacleCells::of),
                rules: super::stats::rule_cells(&o),
            }))
        })
        .collect::<Result<Vec<Option<Row>>, SimError>>()
        .map(|rows| rows.into_iter().flatten().collect())
}

/// A column name any CSV reader takes: letters, digits and `_`.
fn column(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect()
}

/// The pairs' names `a_b`, in [`Detector`]'s order.
fn pair_names(vehicles: &[String]) -> Vec<String> {
    let mut v = Vec::new();
    for i in 0..vehicles.len() {
        for j in i + 1..vehicles.len() {
            v.push(format!("{}_{}", column(&vehicles[i]), column(&vehicles[j])));
        }
    }
    v
}

/// `runs.csv`: one row per run, fixed decimals (same runs, same bytes).
pub fn csv(vehicles: &[String], obstacles: bool, rows: &[Row]) -> String {
    let mut s = String::from(
        "run,seed,end_reason,sim_time_s,encounters,near_misses,collisions,closest_m,\
         behavior_panics,behavior_errors",
    );
    let pairs = pair_names(vehicles);
    for p in &pairs {
        let _ = write!(s, ",cpa_{p},near_misses_{p},collisions_{p}");
    }
    for v in vehicles {
        let _ = write!(s, ",spawned_{}", column(v));
    }
    let speeds = rows.iter().any(|r| !r.speed_pct.is_empty());
    if speeds {
        for v in vehicles {
            let _ = write!(s, ",speed_pct_{}", column(v));
        }
    }
    super::stats::header(&mut s, vehicles, obstacles);
    s.push('\n');
    for r in rows {
        let _ = write!(
            s,
            "{},{},{},{:.2},{},{},{},{:.2},{},{}",
            r.run,
            r.seed,
            r.end_reason.replace([',', '\n', '"'], " "),
            r.sim_time_s,
            r.encounters,
            r.near_misses,
            r.collisions,
            r.closest_m,
            r.behavior_panics,
            r.behavior_errors
        );
        for p in &r.pairs {
            let _ = write!(s, ",{:.2},{},{}", p.closest_m, p.near_misses, p.collisions);
        }
        for n in &r.spawned {
            let _ = write!(s, ",{n}");
        }
        if speeds {
            for i in 0..vehicles.len() {
                match r.speed_pct.get(i) {
                    Some(p) => {
                        let _ = write!(s, ",{p:.3}");
                    }
                    None => s.push(','),
                }
            }
        }
        super::stats::cells(
            &mut s,
            vehicles.len(),
            obstacles,
            r.obstacles.as_ref(),
            &r.rules,
        );
        s.push('\n');
    }
    s
}

/// Wilson score interval (95%) of `k` successes in `n` trials.
pub fn wilson(k: usize, n: usize) -> (f64, f64) {
    if n == 0 {
        return (0.0, 1.0);
    }
    let (k, n) = (k as f64, n as f64);
    let z = 1.959_963_984_540_054_f64;
    let p = k / n;
    let d = 1.0 + z * z / n;
    let c = (p + z * z / (2.0 * n)) / d;
    let h = z * (p * (1.0 - p) / n + z * z / (4.0 * n * n)).sqrt() / d;
    // At 0 (or n) successes the bound is exactly 0 (or 1); rounding would leave 1e-19.
    let lo = if k == 0.0 { 0.0 } else { (c - h).max(0.0) };
    let hi = if k == n { 1.0 } else { (c + h).min(1.0) };
    (lo, hi)
}

/// The terminal lines of a table: end reasons, closest approaches, collision and near
/// miss rates with their 95% intervals.
pub fn distribution(rows: &[Row]) -> String {
    let n = rows.len();
    let mut reasons = std::collections::BTreeMap::<&str, usize>::new();
    for r in rows {
        *reasons.entry(&r.end_reason).or_default() += 1;
    }
    let mut s = String::from("  end reasons  ");
    let list: Vec<String> = reasons.iter().map(|(k, c)| format!("{k} {c}")).collect();
    s.push_str(&list.join(", "));
    s.push('\n');
    let mut cpa: Vec<f64> = rows.iter().map(|r| r.closest_m).collect();
    cpa.sort_by(f64::total_cmp);
    if !cpa.is_empty() {
        let q = |f: f64| cpa[(((cpa.len() - 1) as f64) * f).round() as usize];
        let _ = writeln!(
            s,
            "  closest approach m  min {:.1}  p5 {:.1}  p50 {:.1}  max {:.1}",
            q(0.0),
            q(0.05),
            q(0.5),
            q(1.0)
        );
    }
    for (what, k) in [
        (
            "collision",
            rows.iter().filter(|r| r.collisions > 0).count(),
        ),
        (
            "near miss",
            rows.iter()
                .filter(|r| r.near_misses > 0 || r.collisions > 0)
                .count(),
        ),
    ] {
        let (lo, hi) = wilson(k, n);
        let _ = writeln!(
            s,
            "  {what} rate {k}/{n} runs = {:.2}% (95% interval {:.2}% to {:.2}%)",
            100.0 * k as f64 / n.max(1) as f64,
            100.0 * lo,
            100.0 * hi
        );
    }
    let obs: Vec<_> = rows.iter().filter_map(|r| r.obstacles.as_ref()).collect();
    super::stats::distribution(&mut s, &obs, rows.iter().flat_map(|r| &r.rules), wilson);
    s.pop();
    s
}

/// What a shard leaves for `merge`: the run set it belongs to and its rows.
#[derive(Debug, Serialize, Deserialize)]
pub struct ShardFile {
    pub mission: String,
    pub vehicles: Vec<String>,
    pub runs: usize,
    pub seed: u64,
    pub jitter: String,
    pub max_time: Option<f64>,
    pub shard: usize,
    pub shards: usize,
    pub rows: Vec<Row>,
    /// The scenario has obstacles (the table has their columns).
    #[serde(default)]
    pub obstacles: bool,
    /// The rows as `runs.csv` lines, in the order of `rows`: merged as they are, so the
    /// table does not depend on how JSON carries floating-point numbers.
    pub lines: Vec<String>,
}

/// The run-set identity two shards must share.
fn run_set(f: &ShardFile) -> String {
    format!(
        "mission {} vehicles {} runs {} seed {} jitter {} max_time {:?} in {} shards",
        f.mission,
        f.vehicles.join(","),
        f.runs,
        f.seed,
        f.jitter,
        f.max_time,
        f.shards
    )
}

/// The jitter as a shard's run set names it (speed only when perturbed, so shards
/// written before speed jitter existed still merge with new ones).
fn jitter_text(j: &Jitter) -> String {
    let mut t = format!("x={},y={},heading={}", j.x, j.y, j.heading);
    if j.speed > 0.0 {
        t.push_str(&format!(",speed={}", j.speed));
    }
    t
}

/// `helm sim` with `--runs` or `--shard` on a fleet.
pub fn cli(args: &SimArgs, plan: &FleetPlan) -> Result<u8, SimError> {
    let runs = args.runs as usize;
    let (k, n) = args.shard.map_or((1, 1), |s| (s.k, s.n));
    let range = slice(runs, k, n);
    let tag = if n > 1 {
        format!("{}-mc{runs}-shard{k}of{n}", plan.name)
    } else {
        format!("{}-mc{runs}", plan.name)
    };
    let dir = output::out_dir(args.out.as_deref(), &tag)?;
    let jitter = args.jitter.unwrap_or_default();
    let bar = progress(
        range.len() as u64,
        "{spinner} runs {pos}/{len} [{bar:40}] {elapsed_precise} eta {eta}",
    );
    let wall = std::time::Instant::now();
    crate::interrupt::install();
    let lines = crate::interrupt::Progress::new(range.len() as u64);
    let done = || {
        bar.inc(1);
        lines.tick();
    };
    let alogs = args.alogs.then_some(dir.as_path());
    let rows = run_range(
        plan,
        range.clone(),
        runs,
        args.seed,
        jitter,
        args.max_time,
        alogs,
        &done,
    )?;
    bar.finish_and_clear();
    let vehicles: Vec<String> = plan.vehicles.iter().map(|v| v.spec.name.clone()).collect();
    let csv_path = dir.join("runs.csv");
    let obstacles = plan.scenario.obstacles.is_some();
    if crate::interrupt::requested() {
        // Ctrl-C: keep the finished runs (no shard.json: an incomplete shard must not merge).
        let line = crate::interrupt::interrupted_line(&plan.name, rows.len(), range.len() as u64);
        if rows.is_empty() {
            crate::interrupt::remove_if_empty(&dir);
            println!("{line}; nothing written");
        } else {
            output::write(&csv_path, &csv(&vehicles, obstacles, &rows))?;
            let text = format!("{line}\n{}\n", distribution(&rows));
            output::write(&dir.join("summary.txt"), &text)?;
            print!("{text}");
            println!("table:   {}", csv_path.display());
        }
        return Ok(crate::interrupt::EXIT_INTERRUPTED);
    }
    output::write(&csv_path, &csv(&vehicles, obstacles, &rows))?;
    println!(
        "{}: runs {}..{} of {runs} (seeds {}.., jitter {}) in {:.1} s wall on {} thread(s)",
        plan.name,
        range.start,
        range.end,
        args.seed.wrapping_add(range.start as u64),
        jitter_text(&jitter),
        wall.elapsed().as_secs_f64(),
        rayon::current_num_threads()
    );
    println!("{}", distribution(&rows));
    if n > 1 {
        let table = csv(&vehicles, obstacles, &rows);
        let lines = table.lines().skip(1).map(str::to_string).collect();
        let shard = ShardFile {
            mission: plan.name.clone(),
            vehicles,
            runs,
            seed: args.seed,
            jitter: jitter_text(&jitter),
            max_time: args.max_time,
            shard: k,
            shards: n,
            rows,
            obstacles,
            lines,
        };
        let path = dir.join("shard.json");
        let json = serde_json::to_string(&shard).unwrap_or_default();
        output::write(&path, &(json + "\n"))?;
        println!("shard {k} of {n}: {}", path.display());
        println!("table:   {}", csv_path.display());
        return Ok(0);
    }
    println!("table:   {}", csv_path.display());
    let panics: usize = rows.iter().map(|r| r.behavior_panics).sum();
    let errors: usize = rows.iter().map(|r| r.behavior_errors).sum();
    if panics > 0 {
        println!("PROBLEM: {panics} behavior panic(s) across the runs (runs.csv: behavior_panics)");
    }
    Ok(verdict(args.strict, panics, errors, false))
}

/// Read the shards in `dirs`, check they are one run set, complete, each once; their rows
/// (with their table lines) in run order, with the run set.
pub fn merge_shards(dirs: &[PathBuf]) -> Result<(ShardFile, Vec<(Row, String)>), SimError> {
    let mut files = Vec::new();
    for d in dirs {
        let path = d.join("shard.json");
        let text = std::fs::read_to_string(&path)
            .map_err(|e| SimError::Fleet(format!("{}: cannot read: {e}", path.display())))?;
        let f: ShardFile = serde_json::from_str(&text).map_err(|e| {
            SimError::Fleet(format!(
                "{}:{}: not a shard file: {e}",
                path.display(),
                e.line()
            ))
        })?;
        files.push((path, f));
    }
    let Some((first_path, first)) = files.first() else {
        return Err(SimError::Fleet("merge: no shard folders given".into()));
    };
    let set = run_set(first);
    let mut seen = vec![None::<&Path>; first.shards];
    for (path, f) in &files {
        if run_set(f) != set {
            return Err(SimError::Fleet(format!(
                "{}: shard of another run set ({})\n{}: {set}",
                path.display(),
                run_set(f),
                first_path.display()
            )));
        }
        let slot = f.shard.checked_sub(1).and_then(|i| seen.get_mut(i));
        match slot {
            Some(Some(other)) => {
                return Err(SimError::Fleet(format!(
                    "{}: shard {} of {} given twice (also {})",
                    path.display(),
                    f.shard,
                    f.shards,
                    other.display()
                )))
            }
            Some(s) => *s = Some(path),
            None => {
                return Err(SimError::Fleet(format!(
                    "{}: shard {} is outside 1..{}",
                    path.display(),
                    f.shard,
                    f.shards
                )))
            }
        }
    }
    let missing: Vec<String> = seen
        .iter()
        .enumerate()
        .filter(|(_, s)| s.is_none())
        .map(|(i, _)| (i + 1).to_string())
        .collect();
    if !missing.is_empty() {
        return Err(SimError::Fleet(format!(
            "merge: shard(s) {} of {} missing",
            missing.join(", "),
            first.shards
        )));
    }
    let mut rows: Vec<(Row, String)> = Vec::with_capacity(first.runs);
    let mut head = None;
    for (path, mut f) in files {
        if f.lines.len() != f.rows.len() {
            return Err(SimError::Fleet(format!(
                "{}: {} rows but {} table lines",
                path.display(),
                f.rows.len(),
                f.lines.len()
            )));
        }
        rows.extend(f.rows.drain(..).zip(f.lines.drain(..)));
        if head.is_none() {
            head = Some(f);
        }
    }
    rows.sort_by_key(|(r, _)| r.run);
    let head = head.ok_or_else(|| SimError::Fleet("merge: no shards".into()))?;
    if rows.len() != head.runs || rows.iter().enumerate().any(|(i, (r, _))| r.run != i) {
        return Err(SimError::Fleet(format!(
            "merge: the shards hold {} rows, not runs 0..{} each once",
            rows.len(),
            head.runs
        )));
    }
    Ok((head, rows))
}

/// `helm sim merge DIR... [--out DIR]`.
pub fn merge_cli(dirs: &[PathBuf], out: Option<&Path>) -> Result<u8, SimError> {
    let (head, merged) = merge_shards(dirs)?;
    let dir = output::out_dir(out, &format!("{}-mc{}-merged", head.mission, head.runs))?;
    let path = dir.join("runs.csv");
    let mut table = csv(&head.vehicles, head.obstacles, &[]);
    for (_, line) in &merged {
        table.push_str(line);
        table.push('\n');
    }
    output::write(&path, &table)?;
    let rows: Vec<Row> = merged.into_iter().map(|(r, _)| r).collect();
    println!(
        "{}: {} runs merged from {} shards (seed {}, jitter {})",
        head.mission, head.runs, head.shards, head.seed, head.jitter
    );
    println!("{}", distribution(&rows));
    println!("table:   {}", path.display());
    Ok(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slices_cover_the_run_set_once() {
        for runs in [0, 1, 7, 1000] {
            for n in 1..=9 {
                let all: Vec<usize> = (1..=n).flat_map(|k| slice(runs, k, n)).collect();
                assert_eq!(all, (0..runs).collect::<Vec<_>>(), "{runs} runs in {n}");
            }
        }
    }

    #[test]
    fn wilson_interval_brackets_the_rate() {
        let (lo, hi) = wilson(0, 1000);
        assert_eq!(lo, 0.0);
        assert!(hi > 0.003 && hi < 0.004, "{hi}");
        let (lo, hi) = wilson(50, 100);
        assert!(lo < 0.5 && hi > 0.5 && (0.5 - lo - (hi - 0.5)).abs() < 1e-9);
    }

    #[test]
    fn vehicle_shifts_are_seeded_and_bounded() {
        let j = Jitter {
            x: 5.0,
            y: 5.0,
            heading: 10.0,
            speed: 0.0,
        };
        let a = shifts(&j, 3, 4);
        assert_eq!(a, shifts(&j, 3, 4));
        assert_ne!(a[0], a[1]);
        assert!(a
            .iter()
            .all(|s| s.dx.abs() <= 5.0 && s.dheading.abs() <= 10.0 && s.dspeed_pct == 0.0));
        // Speeds are drawn after every pose: a seed's poses do not move.
        let fast = Jitter { speed: 20.0, ..j };
        let b = shifts(&fast, 3, 4);
        for (p, q) in a.iter().zip(&b) {
            assert_eq!((p.dx, p.dy, p.dheading), (q.dx, q.dy, q.dheading));
            assert!(q.dspeed_pct.abs() <= 20.0 && q.dspeed_pct != 0.0);
        }
        assert_ne!(b[0].dspeed_pct, b[1].dspeed_pct);
    }

    #[test]
    fn speed_columns_only_when_speeds_are_perturbed() {
        let row = |speed_pct: Vec<f64>| Row {
            run: 0,
            seed: 1,
            end_reason: "timeout".into(),
            sim_time_s: 10.0,
            encounters: 0,
            near_misses: 0,
            collisions: 0,
            closest_m: 50.0,
            pairs: vec![PairCells {
                closest_m: 50.0,
                near_misses: 0,
                collisions: 0,
            }],
            spawned: vec![1, 1],
            speed_pct,
            behavior_panics: 0,
            behavior_errors: 0,
            obstacles: None,
            rules: vec![],
        };
        let names = ["abe".to_string(), "ben".to_string()];
        let plain = csv(&names, false, &[row(vec![])]);
        assert!(!plain.contains("speed_pct"), "{plain}");
        let fast = csv(&names, false, &[row(vec![12.5, -3.25])]);
        let mut lines = fast.lines();
        let head: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
        let cells: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
        let at = |name: &str| head.iter().position(|h| *h == name).expect(name);
        assert_eq!(cells[at("speed_pct_abe")], "12.500");
        assert_eq!(cells[at("speed_pct_ben")], "-3.250");
        assert_eq!(head.len(), cells.len());
    }
}
