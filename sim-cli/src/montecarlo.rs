//! Monte Carlo: the mission N times from perturbed starts, on all cores (rayon).
//!
//! Run `i` uses seed `S + i`; its start shift is drawn from that seed alone (SplitMix64,
//! uniform in ±jitter), so a row is reproduced by `--runs 1 --seed <its seed>` with the
//! same jitter, and the same `--seed` gives the same table whatever the thread count.

use helm_sim::seed::splitmix64;
use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;

use rayon::prelude::*;

use helm_sim::observe::ViewKind;
use helm_sim::run::{Outcome, Prepared, RunOptions, SimError, StartShift};

/// Half-widths of the uniform perturbation: the start pose, and each vehicle's speed.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Jitter {
    pub x: f64,
    pub y: f64,
    pub heading: f64,
    /// Percent of every commanded speed (below 100): in a fleet, the speeds the vessels
    /// see each other make good vary run to run.
    pub speed: f64,
}

impl std::str::FromStr for Jitter {
    type Err = String;

    /// `x=5,y=5,heading=20` (any subset).
    fn from_str(s: &str) -> Result<Jitter, String> {
        let mut j = Jitter::default();
        for part in s.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            let (k, v) = part
                .split_once('=')
                .ok_or_else(|| format!("`{part}`: expected key=value (x=5,y=5,heading=20)"))?;
            let v: f64 = v
                .trim()
                .parse()
                .ok()
                .filter(|v: &f64| v.is_finite() && *v >= 0.0)
                .ok_or_else(|| format!("`{part}`: the amount must be a number >= 0"))?;
            match k.trim() {
                "x" => j.x = v,
                "y" => j.y = v,
                "heading" => j.heading = v,
                // 100% or more could stop a vehicle or turn its speed negative.
                "speed" if v < 100.0 => j.speed = v,
                "speed" => {
                    return Err(format!(
                        "`{part}`: the speed amount is a percent of the commanded speed, below 100"
                    ))
                }
                other => {
                    return Err(format!(
                        "`{other}`: jitter keys are x, y, heading (m, m, deg) and speed (%)"
                    ))
                }
            }
        }
        Ok(j)
    }
}

impl std::fmt::Display for Jitter {
    /// `x=5 y=5 heading=20`, and ` speed=10%` when the speed is perturbed.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "x={} y={} heading={}", self.x, self.y, self.heading)?;
        if self.speed > 0.0 {
            write!(f, " speed={}%", self.speed)?;
        }
        Ok(())
    }
}

/// Uniform in [-1, 1).
pub(crate) fn unit(state: &mut u64) -> f64 {
    (splitmix64(state) >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
}

impl Jitter {
    /// The start shift of the run with `seed`.
    pub fn shift(&self, seed: u64) -> StartShift {
        let mut s = seed;
        // The speed is drawn last, so the pose draws of a seed are what they were
        // before speed jitter existed.
        StartShift {
            dx: self.x * unit(&mut s),
            dy: self.y * unit(&mut s),
            dheading: self.heading * unit(&mut s),
            dspeed_pct: self.speed * unit(&mut s),
        }
    }
}

/// One row of `runs.csv`.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub run: usize,
    pub seed: u64,
    pub end_reason: String,
    pub sim_time_s: f64,
    pub distance_m: f64,
    pub iterations: u64,
    pub allstops: Vec<String>,
    pub behavior_errors: usize,
    /// The behavior errors that were panics.
    pub behavior_panics: usize,
    pub waypoints_reached: u64,
    pub start: StartShift,
    pub end: vehicle_model::Nav,
    pub helm_state: &'static str,
    /// Closest approach of the track to each labelled polygon and point that stayed put
    /// during the run (markers that move, e.g. a waypoint's next point, are left out).
    pub min_dist: BTreeMap<String, f64>,
    /// The track, thinned to at most [`TRACK_POINTS`] points (for the picture).
    pub track: Vec<(f64, f64)>,
}

/// Points kept of each run's track for the Monte-Carlo picture.
pub const TRACK_POINTS: usize = 400;

fn thin(pts: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    let step = pts.len().div_ceil(TRACK_POINTS).max(1);
    let last = pts.last().copied();
    let mut v: Vec<(f64, f64)> = pts.into_iter().step_by(step).collect();
    if let Some(l) = last {
        if v.last() != Some(&l) {
            v.push(l);
        }
    }
    v
}

fn min_dists(o: &Outcome) -> BTreeMap<String, f64> {
    let track = o.observer.track.points();
    let mut out = BTreeMap::new();
    for ((kind, label), spec) in &o.observer.views {
        if label.is_empty() || o.observer.moved.contains(&(*kind, label.clone())) {
            continue;
        }
        let d = match kind {
            ViewKind::Polygon => geometry::parse_polygon(spec).map(|p| {
                track
                    .iter()
                    .map(|&(x, y)| {
                        if p.contains(x, y) {
                            0.0
                        } else {
                            p.dist_to_poly(x, y)
                        }
                    })
                    .fold(f64::INFINITY, f64::min)
            }),
            ViewKind::Point => geometry::parse_point(spec).map(|p| {
                track
                    .iter()
                    .map(|&(x, y)| (x - p.x).hypot(y - p.y))
                    .fold(f64::INFINITY, f64::min)
            }),
            _ => None,
        };
        if let Some(d) = d.filter(|d| d.is_finite()) {
            out.insert(
                format!(
                    "{}:{label}",
                    if *kind == ViewKind::Polygon {
                        "polygon"
                    } else {
                        "point"
                    }
                ),
                d,
            );
        }
    }
    out
}

/// Run `n` simulations with seeds `seed..seed+n`; `done` is called after each. With
/// `alog_dir`, run i writes its log there as [`run_alog_name`]`(i, n)`. After an
/// [`interrupt`](super::interrupt), runs not yet started are skipped: fewer rows.
pub fn run_all(
    prep: &Prepared,
    n: usize,
    seed: u64,
    jitter: Jitter,
    max_time: Option<f64>,
    alog_dir: Option<&std::path::Path>,
    done: &(dyn Fn() + Sync),
) -> Result<Vec<Row>, SimError> {
    (0..n)
        .into_par_iter()
        .map(|i| {
            if super::interrupt::requested() {
                return Ok(None);
            }
            let s = seed.wrapping_add(i as u64);
            let shift = jitter.shift(s);
            let o = prep.run(
                shift,
                &RunOptions {
                    max_time,
                    alog: alog_dir.map(|d| d.join(run_alog_name(i, n))),
                    ..RunOptions::default()
                },
            )?;
            done();
            Ok(Some(Row {
                run: i,
                seed: s,
                end_reason: o.end_reason.clone(),
                sim_time_s: o.sim_time_s,
                distance_m: o.observer.track.distance,
                iterations: o.iterations,
                allstops: o
                    .observer
                    .allstops
                    .iter()
                    .map(|a| a.reason.clone())
                    .collect(),
                behavior_errors: o.observer.behavior_errors.len(),
                behavior_panics: o.observer.behavior_panics.len(),
                waypoints_reached: o.observer.waypoints_reached,
                start: shift,
                end: o.end,
                helm_state: o.helm_state,
                min_dist: min_dists(&o),
                track: thin(o.observer.track.points()),
            }))
        })
        .collect::<Result<Vec<Option<Row>>, SimError>>()
        .map(|rows| rows.into_iter().flatten().collect())
}

/// The log of run `i` of `n`: zero-padded (at least 4 digits, more for 10 000 runs or
/// more) so that sorting the file names keeps the order of `runs.csv`, which `helm view`
/// relies on.
pub fn run_alog_name(i: usize, n: usize) -> String {
    let width = n.saturating_sub(1).max(1).to_string().len().max(4);
    format!("run-{i:0width$}.alog")
}

fn csv_field(s: &str) -> String {
    s.replace([',', '\n', '"'], " ")
}

/// A column name any CSV reader and dataframe takes: letters, digits and `_` only.
fn csv_column(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect()
}

/// `runs.csv`: one row per run, fixed decimals (same runs, same bytes).
pub fn csv(rows: &[Row]) -> String {
    let labels: BTreeSet<&String> = rows.iter().flat_map(|r| r.min_dist.keys()).collect();
    let mut s = String::from(
        "run,seed,end_reason,sim_time_s,distance_m,iterations,allstops,behavior_errors,\
         behavior_panics,waypoints_reached,start_dx,start_dy,start_dheading,start_dspeed_pct,\
         end_x,end_y,end_heading,end_speed,helm_state",
    );
    for l in &labels {
        let _ = write!(s, ",min_dist_{}", csv_column(l));
    }
    s.push('\n');
    for r in rows {
        let _ = write!(
            s,
            "{},{},{},{:.2},{:.2},{},{},{},{},{},{:.3},{:.3},{:.3},{:.3},{:.2},{:.2},{:.1},{:.2},{}",
            r.run,
            r.seed,
            csv_field(&r.end_reason),
            r.sim_time_s,
            r.distance_m,
            r.iterations,
            csv_field(&r.allstops.join(";")),
            r.behavior_errors,
            r.behavior_panics,
            r.waypoints_reached,
            r.start.dx,
            r.start.dy,
            r.start.dheading,
            r.start.dspeed_pct,
            r.end.x,
            r.end.y,
            r.end.heading,
            r.end.speed,
            r.helm_state
        );
        for l in &labels {
            match r.min_dist.get(*l) {
                Some(d) => {
                    let _ = write!(s, ",{d:.2}");
                }
                None => s.push(','),
            }
        }
        s.push('\n');
    }
    s
}

fn quantile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let i = ((sorted.len() - 1) as f64 * q).round() as usize;
    sorted[i.min(sorted.len() - 1)]
}

fn spread(name: &str, mut v: Vec<f64>) -> String {
    v.sort_by(f64::total_cmp);
    format!(
        "  {name:<12} min {:>9.1}  p50 {:>9.1}  p95 {:>9.1}  max {:>9.1}",
        quantile(&v, 0.0),
        quantile(&v, 0.5),
        quantile(&v, 0.95),
        quantile(&v, 1.0)
    )
}

/// The distribution, for the terminal.
pub fn distribution(rows: &[Row]) -> String {
    let n = rows.len().max(1) as f64;
    let mut reasons: BTreeMap<&str, usize> = BTreeMap::new();
    let mut stops: BTreeMap<&str, usize> = BTreeMap::new();
    for r in rows {
        *reasons.entry(&r.end_reason).or_default() += 1;
        let mut seen: Vec<&str> = r.allstops.iter().map(String::as_str).collect();
        seen.sort_unstable();
        seen.dedup();
        for a in seen
            .into_iter()
            .filter(|a| helm_sim::observe::is_problem_allstop(a))
        {
            *stops.entry(a).or_default() += 1;
        }
    }
    let fmt = |m: &BTreeMap<&str, usize>| {
        if m.is_empty() {
            return "none".to_string();
        }
        m.iter()
            .map(|(k, c)| format!("{k} {c} ({:.1}%)", *c as f64 * 100.0 / n))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let errors = rows.iter().filter(|r| r.behavior_errors > 0).count();
    let mut s = format!("  end reasons  {}\n", fmt(&reasons));
    s.push_str(&spread(
        "sim time s",
        rows.iter().map(|r| r.sim_time_s).collect(),
    ));
    s.push('\n');
    s.push_str(&spread(
        "distance m",
        rows.iter().map(|r| r.distance_m).collect(),
    ));
    s.push('\n');
    let _ = writeln!(s, "  runs with all-stop  {}", fmt(&stops));
    let _ = write!(s, "  runs with behavior errors: {errors}");
    s
}

#[cfg(test)]
mod tests {

    /// Issue 20 point 14: the table has the end pose and helm state, only CSV-safe
    /// column names, and no column for a marker that moved (alpha's next point).
    #[test]
    fn table_columns_end_pose_helm_state_safe_names_no_moving_markers() {
        let mission = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../missions/alpha");
        let prep = Prepared::load(&mission, &[], None).expect("alpha loads");
        let rows =
            run_all(&prep, 2, 1, Jitter::default(), Some(60.0), None, &|| {}).expect("two runs");
        let table = csv(&rows);
        let header = table.lines().next().expect("a header");
        for col in ["end_x", "end_y", "end_heading", "end_speed", "helm_state"] {
            assert!(header.split(',').any(|c| c == col), "{col} in {header}");
        }
        for col in header.split(',') {
            assert!(
                !col.is_empty() && col.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'),
                "column {col:?} is not CSV-safe"
            );
        }
        assert!(
            rows.iter()
                .all(|r| r.min_dist.keys().all(|k| !k.contains("nextpt"))),
            "a moving marker has no closest-approach column: {header}"
        );
        assert!(rows.iter().all(|r| r.helm_state == "DRIVE"));
    }

    #[test]
    fn run_log_names_sort_in_run_order() {
        assert_eq!(run_alog_name(7, 1000), "run-0007.alog");
        let mut names: Vec<String> = [9999, 10000, 2]
            .iter()
            .map(|&i| run_alog_name(i, 20000))
            .collect();
        names.sort();
        assert_eq!(
            names,
            ["run-00002.alog", "run-09999.alog", "run-10000.alog"]
        );
    }

    use super::*;

    #[test]
    fn jitter_parses_and_refuses() {
        let j: Jitter = "x=5, y=2.5,heading=20".parse().expect("parses");
        assert_eq!(
            j,
            Jitter {
                x: 5.0,
                y: 2.5,
                heading: 20.0,
                speed: 0.0
            }
        );
        assert!("z=1"
            .parse::<Jitter>()
            .unwrap_err()
            .contains("x, y, heading (m, m, deg) and speed (%)"));
        assert!("x=-1".parse::<Jitter>().is_err());
        assert!("x".parse::<Jitter>().is_err());
        let s: Jitter = "speed=15".parse().expect("parses");
        assert_eq!(s.speed, 15.0);
        assert!("speed=100"
            .parse::<Jitter>()
            .unwrap_err()
            .contains("below 100"));
        assert_eq!(j.to_string(), "x=5 y=2.5 heading=20");
        assert_eq!(s.to_string(), "x=0 y=0 heading=0 speed=15%");
    }

    #[test]
    fn speed_jitter_leaves_the_pose_draws_of_a_seed_alone() {
        let pose = Jitter {
            x: 5.0,
            y: 1.0,
            heading: 20.0,
            speed: 0.0,
        };
        let both = Jitter {
            speed: 10.0,
            ..pose
        };
        let mut seen_faster = false;
        let mut seen_slower = false;
        for s in 0..1000 {
            let (a, b) = (pose.shift(s), both.shift(s));
            assert_eq!((a.dx, a.dy, a.dheading), (b.dx, b.dy, b.dheading));
            assert_eq!(a.dspeed_pct, 0.0);
            assert!(b.dspeed_pct.abs() <= 10.0);
            seen_faster |= b.dspeed_pct > 5.0;
            seen_slower |= b.dspeed_pct < -5.0;
        }
        assert!(seen_faster && seen_slower, "the draws cover both sides");
    }

    #[test]
    fn shifts_are_bounded_and_seeded() {
        let j = Jitter {
            x: 5.0,
            y: 1.0,
            heading: 20.0,
            speed: 0.0,
        };
        assert_eq!(j.shift(7), j.shift(7));
        assert_ne!(j.shift(7), j.shift(8));
        for s in 0..1000 {
            let sh = j.shift(s);
            assert!(sh.dx.abs() <= 5.0 && sh.dy.abs() <= 1.0 && sh.dheading.abs() <= 20.0);
        }
        assert_eq!(Jitter::default().shift(3), StartShift::default());
    }
}
