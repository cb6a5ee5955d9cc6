//! The helm as a MOOS app: connect to a MOOSDB (or start an embedded one with a vehicle
//! simulator), and each AppTick: mail → `Helm::handle_mail` → `Helm::iterate` → postings.

use std::path::PathBuf;

/// How `helm run` was asked to run.
#[derive(Clone, Debug)]
pub struct RunOptions {
    pub mission: PathBuf,
    pub bhv: Vec<PathBuf>,
    /// MOOS app name: selects the ProcessConfig block and is the name used with the DB.
    pub alias: String,
    /// Start an embedded MOOSDB and a vehicle simulator in this process.
    pub embedded: bool,
    /// Stop after this many seconds of MOOS time (none: run until interrupted or the
    /// mission ends, with --embedded).
    pub duration: Option<f64>,
    /// Terminal output: the heartbeat characters (`$` DRIVE, `*` PARK) and summary lines.
    pub quiet: bool,
}

/// Errors that stop `helm run`.
#[derive(Debug, thiserror::Error)]
pub enum AppError {
    #[error("{0}")]
    Mission(#[from] crate::mission::MissionLoadError),
    #[error("not implemented yet: {0}")]
    NotYet(String),
}

/// Run the helm until the duration ends or the process is interrupted.
pub fn run(_opts: &RunOptions) -> Result<(), AppError> {
    Err(AppError::NotYet("helm run".into()))
}
