//! The `helm sim` command line.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use super::montecarlo::{self, Jitter};
use super::output;
use super::run::{Prepared, RunOptions, SimError, StartShift};

/// `helm sim` arguments.
#[derive(clap::Args, Debug, Clone)]
pub struct SimArgs {
    /// The mission file (`.moos`), or a folder holding one.
    pub mission: PathBuf,
    /// Extra behavior files (`.bhv`).
    pub bhv: Vec<PathBuf>,
    /// Output folder (default: runs/<mission>-<UTC time>).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Scenario file (default: scenario.toml beside the mission, if any).
    #[arg(long)]
    pub scenario: Option<PathBuf>,
    /// Stop after this many simulated seconds (overrides the scenario's max_time).
    #[arg(long)]
    pub max_time: Option<f64>,
    /// Monte Carlo: run the mission N times from perturbed starts, on all cores.
    #[arg(long, default_value_t = 1)]
    pub runs: usize,
    /// Seed of the first run (run i uses seed+i).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Start perturbation, uniform in ± each amount: `x=5,y=5,heading=20` (m, m, deg).
    #[arg(long)]
    pub jitter: Option<Jitter>,
}

fn progress(len: u64, template: &str) -> ProgressBar {
    // Hidden when stderr is not a terminal (indicatif checks), so logs stay clean.
    let bar = ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::stderr());
    if let Ok(style) = ProgressStyle::with_template(template) {
        bar.set_style(style);
    }
    bar
}

/// Run `helm sim`; prints the summary and where the outputs are.
pub fn main(args: &SimArgs) -> ExitCode {
    match run(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(args: &SimArgs) -> Result<(), SimError> {
    if let Some(t) = args.max_time {
        if !(t.is_finite() && t > 0.0) {
            return Err(SimError::Malconfig {
                problems: format!("--max-time {t}: must be a number > 0"),
            });
        }
    }
    let prep = Prepared::load(&args.mission, &args.bhv, args.scenario.as_deref())?;
    for line in &prep.library_report {
        tracing::info!("{line}");
    }
    if args.runs > 1 {
        return monte_carlo(args, &prep);
    }
    single(args, &prep)
}

fn single(args: &SimArgs, prep: &Prepared) -> Result<(), SimError> {
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
    Ok(())
}

fn monte_carlo(args: &SimArgs, prep: &Prepared) -> Result<(), SimError> {
    let dir = output::out_dir(
        args.out.as_deref(),
        &format!("{}-mc{}", prep.name, args.runs),
    )?;
    let jitter = args.jitter.unwrap_or_default();
    let bar = progress(
        args.runs as u64,
        "{spinner} runs {pos}/{len} [{bar:40}] {elapsed_precise} eta {eta}",
    );
    let wall = std::time::Instant::now();
    let done = || bar.inc(1);
    let rows = montecarlo::run_all(prep, args.runs, args.seed, jitter, args.max_time, &done)?;
    bar.finish_and_clear();
    let csv_path = dir.join("runs.csv");
    output::write(&csv_path, &montecarlo::csv(&rows))?;
    println!(
        "{}: {} runs (seeds {}..{}, jitter x={} y={} heading={}) in {:.1} s wall on {} thread(s)",
        prep.name,
        rows.len(),
        args.seed,
        args.seed.wrapping_add(args.runs as u64 - 1),
        jitter.x,
        jitter.y,
        jitter.heading,
        wall.elapsed().as_secs_f64(),
        rayon::current_num_threads()
    );
    println!("{}", montecarlo::distribution(&rows));
    println!("table:   {}", csv_path.display());
    Ok(())
}

/// The mission name used for output folders (for callers outside this module).
pub fn mission_name(path: &Path) -> Option<String> {
    super::find_mission(path)
        .ok()
        .and_then(|p| p.file_stem().map(|s| s.to_string_lossy().into_owned()))
}
