//! Ctrl-C during a Monte Carlo, and progress off a terminal.
//!
//! The first SIGINT/SIGTERM asks the runs not yet started to be skipped; the runs in
//! flight finish (a few hundred milliseconds each), so `runs.csv` keeps every finished
//! run and the summary says `interrupted after N of M runs`. A second signal ends the
//! process at once (130). An output folder left empty is removed. Off a terminal the
//! progress bar is hidden, so [`Progress`] prints a line every few seconds instead.

use std::io::{IsTerminal, Write as _};
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Mutex, Once};
use std::time::{Duration, Instant};

/// The exit code of an interrupted command (see `helm --help`).
pub const EXIT_INTERRUPTED: u8 = 130;

static REQUESTED: AtomicBool = AtomicBool::new(false);

/// Catch SIGINT/SIGTERM for the rest of the process (once; later calls do nothing).
pub fn install() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let set = ctrlc::set_handler(|| {
            if REQUESTED.swap(true, Ordering::SeqCst) {
                // The second one: the user does not want to wait for the runs in flight.
                std::process::exit(i32::from(EXIT_INTERRUPTED));
            }
        });
        if let Err(e) = set {
            // Another handler owns the signals: Ctrl-C then ends the process as before.
            tracing::warn!("cannot catch Ctrl-C: {e}");
        }
    });
}

/// Whether an interruption was asked for.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::SeqCst)
}

/// Ask for an interruption, as the signal does (tests).
pub fn request() {
    REQUESTED.store(true, Ordering::SeqCst);
}

/// The summary line of an interrupted Monte Carlo.
pub fn interrupted_line(name: &str, done: usize, total: u64) -> String {
    format!("{name}: interrupted after {done} of {total} runs")
}

/// Remove `dir` if it holds nothing (a Monte Carlo interrupted before any run ended
/// leaves no empty folder behind); true if it was removed.
pub fn remove_if_empty(dir: &Path) -> bool {
    let empty = std::fs::read_dir(dir).is_ok_and(|mut d| d.next().is_none());
    empty && std::fs::remove_dir(dir).is_ok()
}

/// Progress of `total` runs as lines on stderr, at most one per `every`, when stderr
/// is not a terminal (on a terminal the progress bar shows it).
pub struct Progress {
    total: u64,
    done: AtomicU64,
    start: Instant,
    every: Duration,
    last: Mutex<Instant>,
    enabled: bool,
}

impl Progress {
    /// Lines every 2 s when stderr is not a terminal.
    pub fn new(total: u64) -> Progress {
        Progress::with(
            total,
            Duration::from_secs(2),
            !std::io::stderr().is_terminal(),
        )
    }

    pub fn with(total: u64, every: Duration, enabled: bool) -> Progress {
        let start = Instant::now();
        Progress {
            total,
            done: AtomicU64::new(0),
            start,
            every,
            last: Mutex::new(start),
            enabled,
        }
    }

    /// One more run finished; the line to print, if one is due (also printed).
    pub fn tick(&self) -> Option<String> {
        let done = self.done.fetch_add(1, Ordering::SeqCst) + 1;
        if !self.enabled {
            return None;
        }
        let mut last = self.last.lock().unwrap_or_else(|p| p.into_inner());
        if last.elapsed() < self.every && done < self.total {
            return None;
        }
        *last = Instant::now();
        let line = format!(
            "runs {done}/{} ({:.0} s)",
            self.total,
            self.start.elapsed().as_secs_f64()
        );
        let _ = writeln!(std::io::stderr(), "{line}");
        Some(line)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn progress_lines_are_spaced_and_the_last_is_always_said() {
        let p = Progress::with(3, Duration::from_secs(3600), true);
        assert_eq!(p.tick(), None, "too soon");
        assert_eq!(p.tick(), None);
        assert_eq!(p.tick().as_deref().map(|l| &l[..9]), Some("runs 3/3 "));
        let p = Progress::with(3, Duration::ZERO, true);
        assert!(p.tick().is_some_and(|l| l.starts_with("runs 1/3")));
        let off = Progress::with(1, Duration::ZERO, false);
        assert_eq!(off.tick(), None, "on a terminal the bar shows it");
    }

    #[test]
    fn only_an_empty_folder_is_removed() {
        let d = std::env::temp_dir().join(format!("helm-sim-interrupt-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).expect("mkdir");
        std::fs::write(d.join("runs.csv"), "run\n").expect("write");
        assert!(!remove_if_empty(&d));
        std::fs::remove_file(d.join("runs.csv")).expect("rm");
        assert!(remove_if_empty(&d));
        assert!(!d.exists());
    }

    #[test]
    fn the_summary_line_counts() {
        assert_eq!(
            interrupted_line("alpha", 37, 200),
            "alpha: interrupted after 37 of 200 runs"
        );
    }
}
