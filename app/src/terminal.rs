//! Terminal output of `helm run`: the heartbeat characters (helm.md §12 terse mode:
//! `$` DRIVE, `*` PARK, one per iteration, no newline), a summary line every few seconds
//! of real time, and the MALCONFIG box. Logs go through `tracing` (stderr); this is
//! plain stdout.

use std::io::Write;
use std::time::{Duration, Instant};

use helm_engine::HelmState;

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

/// What the terminal shows during a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// `helm run`: heartbeat characters, a summary line every few seconds, a final line.
    Summary,
    /// pHelmIvP `verbose`: the appcast report (printed when the AppCasting rule says).
    Report,
    /// pHelmIvP `terse`: one `$` (DRIVE) or `*` (PARK) per iteration.
    Terse,
    /// Nothing but start-up text.
    Quiet,
}

/// Heartbeat and summary printer.
pub struct Terminal {
    mode: Mode,
    /// The MALCONFIG report was printed (it is printed once).
    malconfig_shown: bool,
    /// Print the run's last line (`helm run`, quiet or not; pHelmIvP prints none).
    closing: bool,
    /// Characters printed since the last newline.
    column: usize,
    last_summary: Instant,
}

impl Terminal {
    pub fn new(mode: Mode, closing: bool) -> Terminal {
        Terminal {
            mode,
            malconfig_shown: false,
            closing,
            column: 0,
            last_summary: Instant::now(),
        }
    }

    /// One iteration's character.
    pub fn heartbeat(&mut self, state: HelmState) {
        if !matches!(self.mode, Mode::Summary | Mode::Terse) {
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

    /// A summary line (`helm run` only).
    pub fn summary(&mut self, text: &str) {
        if self.mode == Mode::Summary {
            self.line(text);
        }
    }

    /// The last line of a run (`helm run` only: pHelmIvP prints none).
    pub fn last_line(&mut self, text: &str) {
        if self.closing {
            self.line(text);
        }
    }

    /// The appcast report in its terminal form, after 9 newlines as the AppCasting
    /// base prints it. A MALCONFIG report is printed once.
    pub fn report(&mut self, text: &str, malconfig: bool) {
        if self.mode != Mode::Report || (malconfig && self.malconfig_shown) {
            return;
        }
        self.malconfig_shown |= malconfig;
        let mut out = std::io::stdout().lock();
        let _ = write!(out, "{}{text}", "\n".repeat(9));
        let _ = out.flush();
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
