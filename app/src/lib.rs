//! `helm-app`: the helm as a MOOS app: connect to a MOOSDB (or start an embedded one with
//! a vehicle simulator), and each AppTick: mail → `Helm::handle_mail` → `Helm::iterate` →
//! postings. Also AppCasting ([`appcast`]), the terminal ([`terminal`]) and pHelmIvP's
//! command line ([`phelmivp`]).
//!
//! It may depend on `helm-engine` (which decides) and `helm-cycle` (the loop that drives it), `moos` (client, DB, alog) and
//! `vehicle-model` (the embedded simulator's model); it must not depend on `helm-sim`,
//! and nothing but the `helm` binary depends on it.
//!
//! `helm run MISSION [BHV...]`:
//! 1. reads the mission ([`helm_mission::load`]); prints the library report; a
//!    MALCONFIG helm has its problems printed (file:line) and a box saying it will never
//!    drive — it still runs and posts `IVPHELM_STATE=MALCONFIG`, as pHelmIvP does, and
//!    `helm run` then ends with an error (exit 1) when it stops;
//! 2. with `--embedded`, starts a MOOSDB on the mission's ServerPort (Community,
//!    MOOSTimeWarp from the mission) and the `uSimMarine` simulator ([`embedded_sim`]);
//! 3. connects as `--alias` (ServerHost/ServerPort), runs `startup`, registers every
//!    variable the helm lists (posting `IVPHELM_REGISTER=<var>` for each, and again for
//!    variables that appear later), then loops at the block's AppTick (default 5 Hz, in
//!    MOOS time, so a time warp speeds it up): fetch → mail → iterate → publish, through
//!    [`helm_cycle::HelmCycle`], the same code `helm sim` drives the helm with;
//! 4. prints the heartbeat (`$` DRIVE, `*` PARK) and a summary line every 5 s
//!    ([`terminal`]), unless `--quiet`; always a last `final: ...` line;
//! 5. stops after `--duration` MOOS seconds, or, with `--embedded`, once the mission is
//!    over ([`helm_cycle::status::EndWatch`]: after a first clear decision, the all-stop stayed
//!    non-clear for 5 MOOS seconds). Ctrl-C ends the process (default signal action).
//!
//! Which command line is pHelmIvP's (what pAntler runs) rather than `helm`'s own:
//!
//! ```
//! use std::ffi::OsString;
//! use helm_app::phelmivp::is_phelmivp_form;
//! let argv = |a: &[&str]| a.iter().map(OsString::from).collect::<Vec<_>>();
//! assert!(is_phelmivp_form(&argv(&["helm", "alpha.moos", "pHelmIvP"])));
//! assert!(!is_phelmivp_form(&argv(&["helm", "sim", "missions/alpha"])));
//! ```

pub mod appcast;
pub mod embedded_sim;
pub mod moos_io;
pub mod phelmivp;
pub mod terminal;

use std::io::Write as _;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use moos::client::{Client, ClientError};
use moos::wire::Message;
use moosdb::{Db, DbConfig, DbError};

use crate::appcast::{AppCast, Caster};
use helm_cycle::{Bus, HelmCycle};
use helm_engine::config::Verbose;
use helm_engine::posting::{Posting, Value};
use helm_engine::Helm;
use moos_io::{AlogSink, AppSettings, Registrar};
use terminal::Terminal;

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

/// Options of `helm run` beyond [`RunOptions`] (kept apart so that adding one does not
/// change how `RunOptions` is built).
#[derive(Clone, Debug, Default)]
pub struct RunExtras {
    /// Write an `.alog` of every posting and every mail from other apps.
    pub alog: Option<PathBuf>,
    /// Set (e.g. by a Ctrl-C handler) to end the run cleanly: final line, alog flushed,
    /// embedded DB shut down.
    pub stop: Option<std::sync::Arc<std::sync::atomic::AtomicBool>>,
    /// Terminal output as pHelmIvP's (helm.md §12): the `--verbose=` and `HELM_VERBOSE`
    /// settings, resolved with the block's `verbose =`. None: `helm run`'s heartbeat and
    /// summary lines.
    pub phelmivp_verbose: Option<(Option<Verbose>, Option<Verbose>)>,
    /// `HELM_VERBOSE` for `helm run` (pHelmIvP's form uses `phelmivp_verbose`): quiet
    /// as `--quiet`, terse the heartbeat alone, verbose (or none) heartbeat and summaries.
    pub run_verbose: Option<Verbose>,
}

impl RunExtras {
    fn stopped(&self) -> bool {
        self.stop
            .as_ref()
            .is_some_and(|s| s.load(std::sync::atomic::Ordering::Relaxed))
    }
}

/// Errors that stop `helm run`.
#[derive(Debug, thiserror::Error)]
pub enum AppError {
    #[error("{0}")]
    Mission(#[from] helm_mission::MissionLoadError),
    #[error(
        "port {port} is busy: another MOOSDB (or program) listens on it. Stop it, or set \
         another ServerPort in the mission"
    )]
    PortBusy { port: u16 },
    #[error("cannot start the embedded MOOSDB: {0}")]
    Db(#[source] DbError),
    #[error("{problems}\n{count} problem(s) in the simulator block; nothing run")]
    SimBlock { problems: String, count: usize },
    #[error("cannot start the simulator uSimMarine: {0}")]
    Sim(#[source] ClientError),
    #[error("cannot connect to the MOOSDB at {host}:{port} as {name}: {source}")]
    Connect {
        host: String,
        port: u16,
        name: String,
        #[source]
        source: ClientError,
    },
    #[error("cannot write the alog {}: {source}", path.display())]
    Alog {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("the helm was MALCONFIG for the whole run ({problems} configuration problem(s)); it never drove")]
    Malconfig { problems: usize },
    #[error("interrupted before the MOOSDB answered")]
    Interrupted,
}

impl AppError {
    /// The process exit code (see `helm --help`): 2 a mission file that cannot be
    /// read as one, 1 a mission that is wrong, 4 the MOOSDB, the network or an output failed.
    pub fn exit_code(&self) -> u8 {
        match self {
            AppError::Mission(_) => 2,
            AppError::SimBlock { .. } | AppError::Malconfig { .. } => 1,
            AppError::Interrupted => 130,
            _ => 4,
        }
    }
}

/// Why the loop ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum StopReason {
    Duration,
    MissionOver,
    Interrupted,
}

impl StopReason {
    fn as_str(self) -> &'static str {
        match self {
            StopReason::Duration => "duration",
            StopReason::MissionOver => "mission-over",
            StopReason::Interrupted => "interrupted",
        }
    }
}

/// The embedded simulator's block: a value it cannot read stops the run before it
/// starts; an unknown name is shown and ignored.
fn check_sim_block(mission: &moos::mission::MissionFile) -> Result<(), AppError> {
    let block = vehicle_model::SimBlock::read(mission);
    let errors = block.error_texts();
    if !errors.is_empty() {
        return Err(AppError::SimBlock {
            problems: errors.join("\n"),
            count: errors.len(),
        });
    }
    for w in block.warning_texts() {
        eprintln!("warning: {w}");
    }
    Ok(())
}

/// Run the helm until the duration ends or the process is interrupted.
pub fn run(opts: &RunOptions) -> Result<(), AppError> {
    run_with(opts, &RunExtras::default())
}

/// [`run`] with the extra options.
pub fn run_with(opts: &RunOptions, extras: &RunExtras) -> Result<(), AppError> {
    let loaded = helm_mission::load(&opts.mission, &opts.bhv, &opts.alias)?;
    // A closed stdout must not stop a helm (`helm run ... | head`): write errors are ignored.
    // Quiet keeps only what needs attention: a library that could not be loaded.
    let quiet = run_is_quiet(opts, extras);
    let mut out = std::io::stdout().lock();
    for line in &loaded.library_report {
        if !quiet || is_library_problem(line) {
            let _ = writeln!(out, "{line}");
        }
    }
    drop(out);
    let (mut helm, mission) = loaded.into_helm();
    let problems = helm.config_warnings().len();
    if problems > 0 {
        for w in helm.config_warnings() {
            eprintln!("{w}");
        }
        eprintln!("{}", terminal::malconfig_box(problems));
    }

    let mut settings = AppSettings::read(&mission, &opts.alias, 5.0);
    let (db, sim) = if opts.embedded {
        settings.host = "127.0.0.1".into();
        check_sim_block(&mission)?;
        let db = start_db(&mission)?;
        if !quiet {
            let _ = writeln!(
                std::io::stdout(),
                "Embedded MOOSDB on 127.0.0.1:{} (community {}, time warp {})",
                db.port(),
                mission.global("Community").unwrap_or_else(|| "#1".into()),
                settings.time_warp
            );
        }
        let sim = embedded_sim::Sim::start(&mission).map_err(AppError::Sim)?;
        (Some(db), Some(sim))
    } else {
        (None, None)
    };

    let term = terminal_setup(&helm, &mission, opts, extras);
    let client = connect(&settings, &opts.alias, opts.embedded, extras)?;
    let outcome = drive(&mut helm, &client, &settings, opts, extras, term);
    // Stop the simulator and the DB after the helm's client is gone.
    client.close();
    if let Some(s) = sim {
        s.stop();
    }
    if let Some(d) = db {
        d.shutdown();
    }
    outcome?;
    if problems > 0 {
        return Err(AppError::Malconfig { problems });
    }
    Ok(())
}

/// `helm run --quiet`, or `HELM_VERBOSE=quiet` (pHelmIvP's form decides in
/// [`terminal_setup`] with its own rules).
fn run_is_quiet(opts: &RunOptions, extras: &RunExtras) -> bool {
    extras.phelmivp_verbose.is_none() && (opts.quiet || extras.run_verbose == Some(Verbose::Quiet))
}

/// A library report line that says something went wrong (shown even when quiet).
fn is_library_problem(line: &str) -> bool {
    let t = line.trim_start();
    t.starts_with("skipped ") || t.starts_with("warning:") || t.starts_with("Could not find")
}

/// How the run talks to the terminal, and who it is for AppCasting.
struct TermSetup {
    mode: terminal::Mode,
    closing: bool,
    /// Appcasts are printed (verbose mode on a terminal, or `TERM_REPORTING = true`).
    term_reporting: bool,
    community: String,
}

fn terminal_setup(
    helm: &Helm,
    mission: &moos::mission::MissionFile,
    opts: &RunOptions,
    extras: &RunExtras,
) -> TermSetup {
    use std::io::IsTerminal;
    let community = mission.global("Community").unwrap_or_default();
    let (mode, closing) = match extras.phelmivp_verbose {
        None if run_is_quiet(opts, extras) => (terminal::Mode::Quiet, true),
        None if extras.run_verbose == Some(Verbose::Terse) => (terminal::Mode::Terse, true),
        None => (terminal::Mode::Summary, true),
        Some((cli, env)) => {
            let v = crate::phelmivp::resolve_verbose(cli, env, helm.configured_verbose());
            let mode = match v {
                Verbose::Verbose => terminal::Mode::Report,
                Verbose::Terse => terminal::Mode::Terse,
                Verbose::Quiet => terminal::Mode::Quiet,
            };
            (mode, false)
        }
    };
    let forced = mission
        .global("TERM_REPORTING")
        .and_then(|v| helm_engine::config::parse_bool(&v));
    let term_reporting =
        mode == terminal::Mode::Report && forced.unwrap_or_else(|| std::io::stdout().is_terminal());
    TermSetup {
        mode,
        closing,
        term_reporting,
        community,
    }
}

fn start_db(mission: &moos::mission::MissionFile) -> Result<Db, AppError> {
    let mut cfg = DbConfig::default();
    cfg.apply_mission(mission);
    if mission.global_f64("ServerPort").is_none() {
        cfg.port = 9000;
    }
    let port = cfg.port;
    Db::start(cfg).map_err(|e| match e {
        DbError::Bind { source, .. } if source.kind() == std::io::ErrorKind::AddrInUse => {
            AppError::PortBusy { port }
        }
        e => AppError::Db(e),
    })
}

/// Connect as `name`. An embedded DB is already up, so failing is final; an external
/// one may come later, so wait for it (saying so) as a MOOS app does.
fn connect(
    settings: &AppSettings,
    name: &str,
    embedded: bool,
    extras: &RunExtras,
) -> Result<Client, AppError> {
    let err = |source| AppError::Connect {
        host: settings.host.clone(),
        port: settings.port,
        name: name.to_string(),
        source,
    };
    let cfg = settings.client_config(name);
    if embedded {
        return Client::connect(cfg).map_err(err);
    }
    let client = Client::start(cfg).map_err(err)?;
    let mut told = false;
    loop {
        if extras.stopped() {
            return Err(AppError::Interrupted);
        }
        match client.wait_connected(Duration::from_secs(2)) {
            Ok(()) => return Ok(client),
            Err(ClientError::Timeout(_)) if !told => {
                told = true;
                eprintln!(
                    "waiting for the MOOSDB at {}:{} (start one with `moosdb MISSION`, or use \
                     `helm run --embedded`)...",
                    settings.host, settings.port
                );
            }
            Err(ClientError::Timeout(_)) => {}
            Err(e) => return Err(err(e)),
        }
    }
}

/// Everything the loop needs besides the helm and the client.
struct Run<'a> {
    client: &'a Client,
    app: String,
    community: String,
    reg: Registrar,
    alog: Option<AlogSink>,
    /// Postings refused because the DB went away in the middle of an iteration: the
    /// loss is told once, with this count, instead of a warning per variable.
    unposted: usize,
}

impl Bus for Run<'_> {
    fn subscribe_new(&mut self, subs: &[String]) -> Vec<String> {
        self.reg.sync(self.client, subs)
    }

    fn subscribe_again(&mut self, vars: &[String]) -> Vec<String> {
        self.reg.again(self.client, vars)
    }

    fn publish(&mut self, p: &Posting, now: f64) {
        match moos_io::publish(self.client, p, now) {
            Ok(()) => {}
            Err(ClientError::NotConnected) => self.unposted += 1,
            Err(e) => tracing::warn!(var = %p.var, "not posted: {e}"),
        }
        if let Some(a) = &mut self.alog {
            if let Err(e) = a.posting(p, now) {
                tracing::error!("alog {} stopped: {e}", a.path().display());
                self.alog = None;
            }
        }
    }
}

impl Run<'_> {
    fn log_mail(&mut self, msgs: &[Message]) {
        if let Some(a) = &mut self.alog {
            for m in msgs {
                if let Err(e) = a.mail(m) {
                    tracing::error!("alog {} stopped: {e}", a.path().display());
                    self.alog = None;
                    return;
                }
            }
        }
    }

    /// The AppCasting step after an iteration: print and/or post the report.
    fn appcast(&mut self, helm: &mut Helm, caster: &mut Caster, term: &mut Terminal, now: f64) {
        let due = caster.after_iterate(helm.appcast_warnings(), now);
        if !due.print && !due.post {
            return;
        }
        let body = helm.appcast_body(now, caster.comms_policy);
        let malconfig = helm.state() == helm_engine::HelmState::Malconfig;
        let iteration = caster.iteration;
        let warnings = helm.appcast_warnings().clone();
        let cast = AppCast {
            proc_name: &self.app,
            community: &self.community,
            iteration,
            body: &body,
            config_warnings: helm.config_warnings(),
            warnings: &warnings,
        };
        if due.print {
            term.report(&cast.terminal(), malconfig);
        }
        if due.post {
            let p = Posting {
                var: "APPCAST".into(),
                value: Value::Str(cast.serialize()),
                source_aux: String::new(),
            };
            self.publish(&p, now);
        }
    }
}

/// A pause of the loop longer than this (real time) counts as a stall.
const STALL: Duration = Duration::from_secs(1);

/// After a stall: wait (at most 2 s) until the mail has caught up with the present, i.e.
/// a message stamped within two periods of now has arrived. The mail stays in `inbox`
/// for the iteration that follows.
fn catch_up(client: &Client, inbox: &mut Vec<Message>, period: Duration, warp: f64) {
    inbox.clear();
    let present = client.moos_time() - 2.0 * period.as_secs_f64() * warp;
    let t0 = Instant::now();
    while t0.elapsed() < Duration::from_secs(2) && client.is_connected() {
        client.wait_for_mail(period);
        let before = inbox.len();
        client.fetch(inbox);
        if inbox[before..].iter().any(|m| m.time >= present) {
            break;
        }
    }
}

fn drive(
    helm: &mut Helm,
    client: &Client,
    settings: &AppSettings,
    opts: &RunOptions,
    extras: &RunExtras,
    setup: TermSetup,
) -> Result<(), AppError> {
    let start = client.moos_time();
    let alog = match &extras.alog {
        Some(path) => Some(
            AlogSink::create(path, start, &opts.alias).map_err(|source| AppError::Alog {
                path: path.clone(),
                source,
            })?,
        ),
        None => None,
    };
    let mut run = Run {
        client,
        app: opts.alias.clone(),
        community: setup.community.clone(),
        reg: Registrar::default(),
        alog,
        unposted: 0,
    };
    let mut term = Terminal::new(setup.mode, setup.closing);
    let mut caster = Caster::new(settings.time_warp, setup.term_reporting);
    tracing::info!(app = %run.app, host = %settings.host, port = settings.port, "helm connected");

    // The AppCasting base's own variables (no IVPHELM_REGISTER for these).
    for v in crate::appcast::BASE_VARS {
        if let Err(e) = client.register(v, 0.0) {
            tracing::warn!(var = v, "cannot register: {e}");
        }
    }
    let mut cycle = HelmCycle::startup(helm, &mut run, start);

    let period = settings.period();
    let deadline = opts.duration.map(|d| start + d.max(0.0));
    let mut inbox: Vec<Message> = Vec::new();
    let mut next = Instant::now();
    let mut last_tick = Instant::now();
    let mut disconnected_told = false;
    let reason = loop {
        next += period;
        match next.checked_duration_since(Instant::now()) {
            Some(wait) => std::thread::sleep(wait),
            None => next = Instant::now(),
        }
        let stalled = last_tick.elapsed() > STALL.max(period * 5);
        last_tick = Instant::now();
        if stalled {
            // The process was frozen (SIGSTOP, a debugger, a starved machine): read the
            // mail that came meanwhile before deciding anything, so that, e.g., a
            // standby helm that took over disables this one before it posts a stale
            // decision.
            catch_up(client, &mut inbox, period, settings.time_warp);
            next = Instant::now();
        }
        let now = client.moos_time();
        if deadline.is_some_and(|d| now >= d) {
            break StopReason::Duration;
        }
        if extras.stopped() {
            break StopReason::Interrupted;
        }
        if opts.embedded && cycle.status.end.is_over(now) {
            break StopReason::MissionOver;
        }

        if !stalled {
            inbox.clear();
        }
        client.fetch(&mut inbox);
        run.log_mail(&inbox);
        let mut mail = moos_io::to_mail(&inbox);
        // The AppCasting base's mail never reaches the helm.
        mail.retain(|m| {
            if !crate::appcast::BASE_VARS.contains(&m.var.as_str()) {
                return true;
            }
            let text = match &m.value {
                Value::Str(s) => s.clone(),
                Value::Num(n) => n.to_string(),
            };
            let ids = (setup.community.as_str(), opts.alias.as_str());
            caster.handle_mail(helm.appcast_warnings(), &m.var, &text, ids, now);
            false
        });
        cycle.mail(helm, now, &mail);
        // As CMOOSApp: no Iterate while disconnected.
        if !client.is_connected() {
            if !disconnected_told {
                disconnected_told = true;
                let lost = std::mem::take(&mut run.unposted);
                if lost > 0 {
                    tracing::warn!(
                        "lost the MOOSDB; waiting to reconnect ({lost} postings of the \
                         last iteration not delivered)"
                    );
                } else {
                    tracing::warn!("lost the MOOSDB; waiting to reconnect");
                }
            }
            continue;
        }
        disconnected_told = false;
        let lost = std::mem::take(&mut run.unposted);
        if lost > 0 {
            // The connection dropped and came back between two looks at it.
            tracing::warn!("{lost} postings not delivered: the MOOSDB connection dropped");
        }
        cycle.iterate(helm, &mut run, now);
        run.appcast(helm, &mut caster, &mut term, now);
        term.heartbeat(helm.state());
        if term.summary_due() {
            term.summary(&cycle.status.summary(now - start, helm.state().as_str()));
            if let Some(a) = &mut run.alog {
                let _ = a.flush();
            }
        }
    };
    let end = client.moos_time();
    term.last_line(
        &cycle
            .status
            .final_line(reason.as_str(), end - start, helm.state().as_str()),
    );
    if let Some(a) = &mut run.alog {
        a.flush().map_err(|source| AppError::Alog {
            path: a.path().to_path_buf(),
            source,
        })?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_posting_refused_for_want_of_a_db_is_counted_not_warned_per_variable() {
        // Port 1 on localhost: nothing listens, the client stays unconnected.
        let client = Client::start(moos::client::ClientConfig::new("127.0.0.1", 1, "t"))
            .expect("client starts without a DB");
        assert!(!client.is_connected());
        let mut run = Run {
            client: &client,
            app: "pHelmIvP".into(),
            community: "alpha".into(),
            reg: Registrar::default(),
            alog: None,
            unposted: 0,
        };
        for var in ["DESIRED_SPEED", "DESIRED_HEADING"] {
            let p = Posting {
                var: var.into(),
                value: Value::Num(1.0),
                source_aux: String::new(),
            };
            run.publish(&p, 0.0);
        }
        assert_eq!(run.unposted, 2);
    }
}
