//! The `helm sim` arguments, and what the one-vehicle and the fleet command lines share
//! (the progress bar, the exit code of a run).

use std::path::PathBuf;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use super::montecarlo::Jitter;

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
    #[arg(long, value_parser = positive_secs)]
    pub max_time: Option<f64>,
    /// Monte Carlo: run the mission N times from perturbed starts, on all cores
    /// (Ctrl-C keeps the runs finished so far in runs.csv; exit 130).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..))]
    pub runs: u64,
    /// Seed of the first run (run i uses seed+i).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Perturbation, uniform in ± each amount: `x=5,y=5,heading=20` moves the start
    /// (m, m, deg); `speed=10` makes every vehicle go up to 10% faster or slower than
    /// commanded (in a fleet: the contacts' speeds vary too).
    #[arg(long)]
    pub jitter: Option<Jitter>,
    /// With --runs: also write each run's `.alog` (`run-0000.alog`, ... beside
    /// `runs.csv`), so `helm view DIR` can replay every run; for a fleet, each run's
    /// vehicle logs in a folder `run-0000/`, ... as a one-run fleet writes them. About 2 MB
    /// per alpha run.
    /// Without it the helms do not serialise their functions (BHV_IPF), which only a
    /// log would read: the runs are the same, faster.
    #[arg(long)]
    pub alogs: bool,
    /// Exit 3 also when a behavior posted any error or the helm never drove (a
    /// behavior panic always exits 3).
    #[arg(long)]
    pub strict: bool,
    /// Cluster runs (fleets): run only the K-th of N slices of the `--runs` set (K in
    /// 1..N), and leave `shard.json` for `helm sim merge DIR...`.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<Shard>,
}

/// `--shard K/N`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    pub k: usize,
    pub n: usize,
}

impl std::str::FromStr for Shard {
    type Err = String;

    fn from_str(s: &str) -> Result<Shard, String> {
        let (k, n) = s
            .split_once('/')
            .ok_or_else(|| format!("`{s}`: want K/N, e.g. 3/8"))?;
        let num = |v: &str| v.trim().parse::<usize>().ok();
        match (num(k), num(n)) {
            (Some(k), Some(n)) if n >= 1 && (1..=n).contains(&k) => Ok(Shard { k, n }),
            (Some(k), Some(n)) => Err(format!("`{s}`: shard {k} is outside 1..{n}")),
            _ => Err(format!("`{s}`: want K/N with whole numbers, e.g. 3/8")),
        }
    }
}

/// Exit code of a run that went wrong (see `helm --help`).
pub const EXIT_RUN_WENT_WRONG: u8 = 3;

fn positive_secs(s: &str) -> Result<f64, String> {
    s.trim()
        .parse::<f64>()
        .ok()
        .filter(|t| t.is_finite() && *t > 0.0)
        .ok_or_else(|| format!("`{s}`: a number of seconds > 0"))
}

pub fn progress(len: u64, template: &str) -> ProgressBar {
    // Hidden when stderr is not a terminal (indicatif checks), so logs stay clean.
    let bar = ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::stderr());
    if let Ok(style) = ProgressStyle::with_template(template) {
        bar.set_style(style);
    }
    bar
}

/// 0, or [`EXIT_RUN_WENT_WRONG`] for a run with a behavior panic (with `strict`: any
/// behavior error, or a helm that never drove).
pub fn verdict(strict: bool, panics: usize, errors: usize, never_drove: bool) -> u8 {
    if panics > 0 || (strict && (errors > 0 || never_drove)) {
        EXIT_RUN_WENT_WRONG
    } else {
        0
    }
}
