//! Terminal output of `helm run`: the heartbeat characters (helm.md §12 terse mode:
//! `$` DRIVE, `*` PARK, one per iteration, no newline), a summary line every few seconds
//! of real time, and the MALCONFIG box. Logs go through `tracing` (stderr); this is
//! plain stdout.

use std::io::Write;
use std::time::{Duration, Instant};

use crate::HelmState;

/// Real time between summary lines.
pub const SUMMARY_EVERY: Duration = Duration::from_secs(5);

/// The heartbeat character of one iteration (only enabled helms print one).
pub fn heartbeat_char(state: HelmState) -> Option<char> {
    match state {
        HelmState::Drive => Some('$'),
        HelmState::Park => Some('*'),
        _ => None,
    }
}

/// The box shown when the helm is MALCONFIG: it runs, but it will never drive.
pub fn malconfig_box(problems: usize) -> String {
    let bar = "!".repeat(78);
    let lines = [
        "The helm is MALCONFIG: it will NEVER DRIVE (it posts no DESIRED_*).".to_string(),
        format!("{problems} configuration problem(s), listed above with file and line."),
        "Fix them and restart; `helm check MISSION` lists them too.".to_string(),
        "It keeps running, posting IVPHELM_STATE=MALCONFIG, as pHelmIvP does.".to_string(),
    ];
    let mut s = format!("{bar}\n");
    for l in lines {
        s.push_str(&format!("!! {l:<73}!!\n"));
    }
    s.push_str(&bar);
    s
}

/// Heartbeat and summary printer.
pub struct Terminal {
    quiet: bool,
    /// Characters printed since the last newline.
    column: usize,
    last_summary: Instant,
}

impl Terminal {
    pub fn new(quiet: bool) -> Terminal {
        Terminal {
            quiet,
            column: 0,
            last_summary: Instant::now(),
        }
    }

    /// One iteration's character.
    pub fn heartbeat(&mut self, state: HelmState) {
        if self.quiet {
            return;
        }
        if let Some(c) = heartbeat_char(state) {
            let mut out = std::io::stdout().lock();
            let _ = write!(out, "{c}");
            let _ = out.flush();
            self.column += 1;
        }
    }

    /// Whether a summary is due (then the clock restarts); also when quiet.
    pub fn summary_due(&mut self) -> bool {
        if self.last_summary.elapsed() < SUMMARY_EVERY {
            return false;
        }
        self.last_summary = Instant::now();
        true
    }

    /// A summary line (not when quiet).
    pub fn summary(&mut self, text: &str) {
        if !self.quiet {
            self.line(text);
        }
    }

    /// Print a whole line, after ending the heartbeat line if one is open.
    pub fn line(&mut self, text: &str) {
        let mut out = std::io::stdout().lock();
        if self.column > 0 {
            let _ = writeln!(out);
            self.column = 0;
        }
        let _ = writeln!(out, "{text}");
        let _ = out.flush();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_lines_are_aligned() {
        let b = malconfig_box(2);
        assert!(b.contains("NEVER DRIVE"));
        assert!(b.contains("2 configuration problem(s)"));
        let widths: Vec<usize> = b.lines().map(|l| l.chars().count()).collect();
        assert!(widths.iter().all(|w| *w == 78), "{widths:?}");
    }

    #[test]
    fn only_enabled_states_beat() {
        assert_eq!(heartbeat_char(HelmState::Drive), Some('$'));
        assert_eq!(heartbeat_char(HelmState::Park), Some('*'));
        assert_eq!(heartbeat_char(HelmState::Malconfig), None);
    }
}
