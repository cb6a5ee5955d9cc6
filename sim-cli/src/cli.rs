//! The `helm sim` command line.

use std::path::PathBuf;
use std::process::ExitCode;

use super::args::{progress, verdict};
pub use super::args::{Shard, SimArgs, EXIT_RUN_WENT_WRONG};
use super::interrupt;
use super::montecarlo;
use super::output;
use helm_sim::run::{Prepared, RunOptions, SimError, StartShift};

/// Run `helm sim`; prints the summary and where the outputs are.
pub fn main(args: &SimArgs) -> ExitCode {
    // `helm sim merge DIR...`: the shards' tables joined (the DIRs land in `bhv`).
    if args.mission.as_os_str() == "merge" && args.bhv.is_empty() {
        eprintln!("error: usage: helm sim merge SHARD_DIR... [--out DIR]");
        return ExitCode::from(2);
    }
    let result = if args.mission.as_os_str() == "merge" {
        super::fleet::montecarlo::merge_cli(&args.bhv, args.out.as_deref())
    } else {
        run(args)
    };
    match result {
        Ok(code) => ExitCode::from(code),
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}

/// The fleet scenario `args` name, if it is one: `--scenario`, else the
/// `scenario.toml` in the folder given, or beside the mission file given.
fn fleet_scenario(args: &SimArgs) -> Option<PathBuf> {
    let path = match &args.scenario {
        Some(p) => p.clone(),
        None if args.mission.is_dir() => args.mission.join("scenario.toml"),
        None => args
            .mission
            .parent()
            .unwrap_or(std::path::Path::new("."))
            .join("scenario.toml"),
    };
    let text = std::fs::read_to_string(&path).ok()?;
    helm_sim::fleet::is_fleet(&text).then_some(path)
}

fn run(args: &SimArgs) -> Result<u8, SimError> {
    if let Some(path) = fleet_scenario(args) {
        return super::fleet::cli::run(args, &path);
    }
    let prep = Prepared::load(&args.mission, &args.bhv, args.scenario.as_deref())?;
    for line in &prep.library_report {
        tracing::info!("{line}");
    }
    for w in &prep.sim_warnings {
        eprintln!("warning: {w}");
    }
    if args.shard.is_some() {
        return Err(SimError::Fleet(
            "--shard: cluster slices are for fleet scenarios ([[vehicle]]) so far".into(),
        ));
    }
    if args.runs > 1 {
        return monte_carlo(args, &prep);
    }
    single(args, &prep)
}

fn single(args: &SimArgs, prep: &Prepared) -> Result<u8, SimError> {
    let dir = output::out_dir(args.out.as_deref(), &prep.name)?;
    let alog = dir.join(format!("{}.alog", prep.name));
    let max = args.max_time.unwrap_or(prep.scenario.max_time);
    let bar = progress(
        max.ceil() as u64,
        "{spinner} simulated {pos}/{len} s [{bar:40}] {elapsed_precise}",
    );
    let tick = |t: f64| bar.set_position(t as u64);
    let shift = args
        .jitter
        .map_or_else(StartShift::default, |j| j.shift(args.seed));
    let o = prep.run(
        shift,
        &RunOptions {
            alog: Some(alog.clone()),
            max_time: args.max_time,
            progress: Some(&tick),
            ..RunOptions::default()
        },
    )?;
    bar.finish_and_clear();
    let summary = output::Summary::of(&prep.name, &o);
    let json = serde_json::to_string_pretty(&summary).unwrap_or_default();
    let summary_path = dir.join("summary.json");
    output::write(&summary_path, &(json + "\n"))?;
    let (title, sub) = output::picture_titles(&prep.name, &o);
    let svg = super::picture::svg(&o.observer, &title, &sub);
    let picture = dir.join(format!("{}.svg", prep.name));
    output::write(&picture, &svg)?;
    println!("{}", output::terminal_summary(&prep.name, &o));
    println!("picture: {}", picture.display());
    println!("log:     {}", alog.display());
    println!("summary: {}", summary_path.display());
    Ok(verdict(
        args.strict,
        o.observer.behavior_panics.len(),
        o.observer.behavior_errors.len(),
        !o.drove,
    ))
}

fn monte_carlo(args: &SimArgs, prep: &Prepared) -> Result<u8, SimError> {
    let dir = output::out_dir(
        args.out.as_deref(),
        &format!("{}-mc{}", prep.name, args.runs),
    )?;
    let jitter = args.jitter.unwrap_or_default();
    let bar = progress(
        args.runs,
        "{spinner} runs {pos}/{len} [{bar:40}] {elapsed_precise} eta {eta}",
    );
    let wall = std::time::Instant::now();
    interrupt::install();
    let lines = interrupt::Progress::new(args.runs);
    let done = || {
        bar.inc(1);
        lines.tick();
    };
    let rows = montecarlo::run_all(
        prep,
        args.runs as usize,
        args.seed,
        jitter,
        args.max_time,
        args.alogs.then_some(dir.as_path()),
        &done,
    )?;
    bar.finish_and_clear();
    if interrupt::requested() {
        return interrupted(&dir, &prep.name, &rows, args.runs);
    }
    let csv_path = dir.join("runs.csv");
    output::write(&csv_path, &montecarlo::csv(&rows))?;
    println!(
        "{}: {} runs (seeds {}..{}, jitter {jitter}) in {:.1} s wall on {} thread(s)",
        prep.name,
        rows.len(),
        args.seed,
        args.seed.wrapping_add(args.runs - 1),
        wall.elapsed().as_secs_f64(),
        rayon::current_num_threads()
    );
    println!("{}", montecarlo::distribution(&rows));
    // The picture: the unperturbed run on top of every perturbed track.
    let nominal = prep.run(
        StartShift::default(),
        &RunOptions {
            max_time: args.max_time,
            ..RunOptions::default()
        },
    )?;
    let tracks: Vec<Vec<(f64, f64)>> = rows.iter().map(|r| r.track.clone()).collect();
    let ok = rows
        .iter()
        .filter(|r| r.end_reason == nominal.end_reason)
        .count();
    let title = format!("{}: {} runs, jitter {jitter}", prep.name, rows.len());
    let sub = format!(
        "{ok} of {} end like the unperturbed run ({} after {:.1} s); table: runs.csv",
        rows.len(),
        nominal.end_reason,
        nominal.sim_time_s
    );
    let svg = super::picture::svg_with_tracks(&nominal.observer, &tracks, &title, &sub);
    let picture = dir.join("runs.svg");
    output::write(&picture, &svg)?;
    println!("picture: {}", picture.display());
    println!("table:   {}", csv_path.display());
    let panics: usize = rows.iter().map(|r| r.behavior_panics).sum();
    let errors: usize = rows.iter().map(|r| r.behavior_errors).sum();
    if panics > 0 {
        println!("PROBLEM: {panics} behavior panic(s) across the runs (runs.csv: behavior_panics)");
    }
    Ok(verdict(args.strict, panics, errors, !nominal.drove))
}

/// Ctrl-C during a Monte Carlo: keep the finished runs (`runs.csv`, `summary.txt`), or
/// leave no folder when none finished; exit 130.
fn interrupted(
    dir: &std::path::Path,
    name: &str,
    rows: &[montecarlo::Row],
    total: u64,
) -> Result<u8, SimError> {
    let line = interrupt::interrupted_line(name, rows.len(), total);
    if rows.is_empty() {
        let gone = interrupt::remove_if_empty(dir);
        println!(
            "{line}; nothing written{}",
            if gone {
                ""
            } else {
                " (the folder was not empty)"
            }
        );
        return Ok(interrupt::EXIT_INTERRUPTED);
    }
    let csv_path = dir.join("runs.csv");
    output::write(&csv_path, &montecarlo::csv(rows))?;
    let text = format!("{line}\n{}\n", montecarlo::distribution(rows));
    output::write(&dir.join("summary.txt"), &text)?;
    print!("{text}");
    println!("table:   {}", csv_path.display());
    Ok(interrupt::EXIT_INTERRUPTED)
}
