//! The pHelmIvP command line (helm.md §1), so `helm` is a drop-in for pHelmIvP.
//!
//! pAntler starts an app as `BINARY MISSION_FILE MOOS_NAME [extra params]`; users type
//! `pHelmIvP mission.moos [file.bhv]... [--alias=NAME] [--verbose=...]`. Both mean: run
//! the helm against the mission's MOOSDB under that name, reading
//! `ProcessConfig = NAME`. [`is_phelmivp_form`] tells this form from our subcommands
//! (`helm run`, `helm check`, ...): a first argument ending in `.moos`/`.moos++`, or a
//! binary called `pHelmIvP` (a link to `helm`). [`parse`] reads the arguments the way
//! pHelmIvP does; `main.rs` carries out the result.

use std::ffi::OsString;
use std::path::{Path, PathBuf};

use helm_engine::config::{parse_verbose, Verbose};

/// The MOOS name when none is given.
pub const DEFAULT_NAME: &str = "pHelmIvP";

/// What the command line asks for.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// Run the helm (the usual case).
    Run(RunArgs),
    Version,
    Example,
    Help,
    Interface,
    Web,
}

/// The run form's arguments.
#[derive(Clone, Debug, PartialEq)]
pub struct RunArgs {
    pub mission: PathBuf,
    pub bhv: Vec<PathBuf>,
    /// MOOS name: the block `ProcessConfig = <name>` and the name at the MOOSDB.
    pub name: String,
    /// `--verbose=` (None: not given).
    pub verbose: Option<Verbose>,
    /// Arguments that mean nothing to pHelmIvP (reported, then ignored).
    pub ignored: Vec<String>,
}

/// A command line pHelmIvP refuses.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ArgError {
    /// pHelmIvP's own words for a bad `--verbose=` value.
    #[error("Illegal verbose setting. Exiting now.")]
    IllegalVerbose(String),
    #[error("no mission file (*.moos or *.moos++) given; `helm --help` shows the usage")]
    NoMission,
    #[error("argument is not valid UTF-8: {0}")]
    NotUtf8(String),
    #[error("--alias needs a name (--alias=NAME)")]
    EmptyAlias,
}

fn is_mission(a: &str) -> bool {
    a.ends_with(".moos") || a.ends_with(".moos++")
}

/// Whether `args` (with the program name first) is the pHelmIvP form.
pub fn is_phelmivp_form(args: &[OsString]) -> bool {
    let called_phelm = args
        .first()
        .and_then(|p| Path::new(p).file_name())
        .and_then(|n| n.to_str())
        .is_some_and(|n| n.starts_with("pHelmIvP"));
    // pHelmIvP's own flags that our subcommand parser does not have.
    let phelm_flags = [
        "-v",
        "-version",
        "-e",
        "--example",
        "-example",
        "-i",
        "--interface",
        "-w",
        "--web",
        "-web",
        "-help",
    ];
    let first = args.get(1).and_then(|a| a.to_str());
    let first_is_mission = first.is_some_and(is_mission);
    let first_is_flag = first.is_some_and(|a| {
        phelm_flags.contains(&a) || a.starts_with("--verbose=") || a.starts_with("--alias=")
    });
    called_phelm || first_is_mission || first_is_flag
}

/// The terminal mode in force: the first *non-default* setting wins, in the order
/// command line, `HELM_VERBOSE`, config block (helm.md §2.1: `verbose`/`true` never
/// locks the setting).
pub fn resolve_verbose(cli: Option<Verbose>, env: Option<Verbose>, config: Verbose) -> Verbose {
    [cli, env, Some(config)]
        .into_iter()
        .flatten()
        .find(|v| *v != Verbose::Verbose)
        .unwrap_or(Verbose::Verbose)
}

/// Read pHelmIvP's arguments (without the program name).
pub fn parse(args: &[OsString]) -> Result<Action, ArgError> {
    let mut mission: Option<PathBuf> = None;
    let mut bhv = Vec::new();
    let mut name: Option<String> = None;
    let mut verbose = None;
    let mut ignored = Vec::new();
    for (i, a) in args.iter().enumerate() {
        let a = a
            .to_str()
            .ok_or_else(|| ArgError::NotUtf8(a.to_string_lossy().into_owned()))?;
        match a {
            "-v" | "--version" | "-version" => return Ok(Action::Version),
            "-e" | "--example" | "-example" => return Ok(Action::Example),
            "-h" | "--help" | "-help" => return Ok(Action::Help),
            "-i" | "--interface" => return Ok(Action::Interface),
            "-w" | "--web" | "-web" => return Ok(Action::Web),
            _ => {}
        }
        if let Some(v) = a.strip_prefix("--verbose=") {
            verbose = Some(parse_verbose(v).ok_or_else(|| ArgError::IllegalVerbose(v.into()))?);
        } else if let Some(n) = a
            .strip_prefix("--alias=")
            // MOOS V10's own option for every app's name: the same thing.
            .or_else(|| a.strip_prefix("--moos_name="))
        {
            if n.trim().is_empty() {
                return Err(ArgError::EmptyAlias);
            }
            name = Some(n.trim().to_string());
        } else if is_mission(a) && mission.is_none() {
            mission = Some(PathBuf::from(a));
        } else if a.ends_with(".bhv") {
            bhv.push(PathBuf::from(a));
        } else if i == 1 && !a.starts_with('-') && name.is_none() {
            // pAntler's convention: the second argument is the MOOS name.
            name = Some(a.to_string());
        } else {
            ignored.push(a.to_string());
        }
    }
    let mission = mission.ok_or(ArgError::NoMission)?;
    Ok(Action::Run(RunArgs {
        mission,
        bhv,
        name: name.unwrap_or_else(|| DEFAULT_NAME.to_string()),
        verbose,
        ignored,
    }))
}

/// `-v`: release information.
pub fn version_text() -> String {
    format!(
        "pHelmIvP (ivp-helm {}): the IvP Helm of MOOS-IvP, rebuilt in Rust\n\
         behavior API {}; built-in behaviors BHV_Waypoint, BHV_Loiter, BHV_Timer",
        env!("CARGO_PKG_VERSION"),
        behavior_api::API_VERSION,
    )
}

/// `-e`: an example pHelmIvP block (`helm check` accepts it with a `.bhv` named
/// `alpha.bhv` beside the mission).
pub const EXAMPLE: &str = "\
===============================================================
pHelmIvP Example MOOS Configuration
===============================================================

ProcessConfig = pHelmIvP
{
  AppTick    = 4
  CommsTick  = 4

  // Behavior files (repeatable); .bhv files on the command line add to these.
  behaviors  = alpha.bhv

  // Decision variables: name:low:high:points[:optional]
  domain     = course:0:359:360
  domain     = speed:0:4:41
  //domain   = depth:0:100:101:optional

  verbose         = terse    // verbose (default), terse or quiet
  start_in_drive  = false    // true: DRIVE at start-up instead of PARK
  allow_park      = true     // false: MOOS_MANUAL_OVERRIDE is ignored
  park_on_allstop = false    // true: PARK after any all-stop
  goals_mandatory = false    // true: all-stop when no goal behavior is active
  ok_skew         = any      // max mail time skew in s (default 60), or any
  nav_grace       = 5        // s before \"Waiting for Helm Nav Solution\"
  helm_alias      = pHelmIvP // posted as IVPHELM_ALIAS

  //standby       = 5        // a standby helm: takes over 5 s after the
  //                         // primary's last IVPHELM_STATE
  //hold_on_apps  = pContactMgrV20, uSimMarineV22
  //other_override_var = MY_OVERRIDE
  //ivp_behavior_dir = /path/to/behavior/libraries  // also IVP_BEHAVIOR_DIRS
}
";

/// `-h`: the usage of both forms.
pub fn help_text() -> String {
    "\
Usage: helm MISSION.moos [FILE.bhv]... [NAME] [OPTIONS]     (the pHelmIvP form)
       helm <COMMAND> ...                                     (helm --help lists them)

Runs the IvP Helm against the MOOSDB named by ServerHost/ServerPort in MISSION, as
pHelmIvP does: it reads the block `ProcessConfig = NAME` (default pHelmIvP) and the
.bhv files named there (`behaviors = ...`) and here, and connects under NAME. pAntler
starts it the same way: `Run = helm @ NewConsole = false ~ pHelmIvP` in the ANTLER
block, or a link to `helm` named `pHelmIvP`.

Options:
  NAME                     the MOOS name (the second argument, as pAntler passes it)
  --alias=NAME             the MOOS name, given anywhere (also --moos_name=NAME)
  --verbose=MODE           verbose (the appcast report, on a terminal), terse (one
                           `$` DRIVE / `*` PARK per iteration) or quiet; overrides
                           `verbose =` of the block and HELM_VERBOSE
  -v, --version, -version  print the release and exit
  -e, --example, -example  print an example pHelmIvP block and exit
  -i, --interface          print the helm's subscriptions and publications and exit
  -w, --web, -web          print where the documentation is and exit
  -h, --help, -help        print this and exit

Environment:
  IVP_BEHAVIOR_DIRS        colon-separated directories of behavior libraries
  IVP_HELM_BUNDLED_DIR     where the libraries shipped with the helm are (default:
                           beside the binary, then ../lib/ivp-helm; empty: none)
  HELM_VERBOSE             verbose, terse or quiet (as --verbose=)
  RUST_LOG                 log filter for the helm's logs on stderr (default: error)

SIGINT and SIGTERM end the helm cleanly.

Examples:
  helm alpha.moos                      run as pHelmIvP
  helm alpha.moos pHelmIvP_Standby     run under another name (its own block)
  helm alpha.moos extra.bhv --verbose=terse
"
    .to_string()
}

/// `-w`: where the documentation is (the helm has no browser to open).
pub const WEB: &str = "The IvP Helm documentation: https://oceanai.mit.edu/ivpman \
(pHelmIvP, behaviors, missions). This helm: README.md of ivp-helm.";

/// `-i`: what the helm subscribes to and publishes (helm.md §4.1, §14).
pub fn interface_text() -> String {
    let subs = [
        ("APPCAST_REQ", "appcast requests (uMAC, pMarineViewer)"),
        ("NAV_X, NAV_Y", "ownship position (m)"),
        (
            "NAV_HEADING, NAV_SPEED, NAV_DEPTH",
            "ownship heading, speed, depth",
        ),
        (
            "MOOS_MANUAL_OVERRIDE",
            "true: PARK (also MOOS_MANUAL_OVERIDE)",
        ),
        ("RESTART_HELM", "type1 or type2: rebuild the behavior set"),
        ("IVPHELM_REJOURNAL", "next IVPHELM_SUMMARY is full"),
        ("IVPHELM_STATE", "another helm's state (standby helm)"),
        ("DB_CLIENTS", "apps present (hold_on_apps)"),
        ("BHV_ABLE_FILTER, HELM_MAP_CLEAR", ""),
        ("NODE_REPORT, NODE_REPORT_LOCAL", "contacts"),
        ("AIS_REPORT, AIS_REPORT_LOCAL", "contacts"),
        ("COMMS_POLICY, LOADCAST_REQ", "appcasting"),
        ("TERM_REPORT_INTERVAL", "appcasting"),
        (
            "<behavior variables>",
            "condition, update, flag and mode variables of the .bhv files",
        ),
    ];
    let pubs = [
        (
            "DESIRED_HEADING, DESIRED_SPEED",
            "the decision (DESIRED_<VAR> per domain variable)",
        ),
        (
            "IVPHELM_STATE",
            "PARK, DRIVE, STANDBY, DISABLED or MALCONFIG",
        ),
        ("IVPHELM_ALLSTOP", "clear, or why the helm all-stopped"),
        ("IVPHELM_SUMMARY", "the iteration in one line"),
        (
            "IVPHELM_BHV_ACTIVE/RUNNING/IDLE",
            "behavior names by run state",
        ),
        (
            "IVPHELM_ITER, IVPHELM_IPF_CNT",
            "iteration, number of IvP functions",
        ),
        ("IVPHELM_DOMAIN, IVPHELM_MODESET", "at start-up"),
        ("IVPHELM_REGISTER", "each variable the helm registers for"),
        (
            "BHV_STATUS, BHV_IPF, BHV_WARNING, BHV_ERROR",
            "per behavior",
        ),
        (
            "<behavior postings>",
            "flags, VIEW_*, WPT_STAT, ... of the behaviors",
        ),
        ("PHELMIVP_PID, PLOGGER_CMD", "at start-up"),
        ("APPCAST", "the helm's report, when asked for"),
    ];
    let mut s =
        String::from("pHelmIvP INTERFACE\n==================\n\nSUBSCRIPTIONS:\n--------------\n");
    for (v, what) in subs {
        s.push_str(&format!("  {v:<36} {what}\n"));
    }
    s.push_str("\nPUBLICATIONS:\n-------------\n");
    for (v, what) in pubs {
        s.push_str(&format!("  {v:<36} {what}\n"));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn os(v: &[&str]) -> Vec<OsString> {
        v.iter().map(OsString::from).collect()
    }

    #[test]
    fn pantler_form_takes_the_second_argument_as_name() {
        let Action::Run(r) = parse(&os(&["m.moos", "pHelmIvP_Standby", "x.bhv"])).expect("ok")
        else {
            panic!("not a run")
        };
        assert_eq!(r.mission, PathBuf::from("m.moos"));
        assert_eq!(r.name, "pHelmIvP_Standby");
        assert_eq!(r.bhv, vec![PathBuf::from("x.bhv")]);
        let Action::Run(r) = parse(&os(&["m.moos++", "a.bhv", "b.bhv"])).expect("ok") else {
            panic!("not a run")
        };
        assert_eq!((r.name.as_str(), r.bhv.len()), ("pHelmIvP", 2));
    }

    #[test]
    fn options() {
        let Action::Run(r) =
            parse(&os(&["m.moos", "--alias=helm2", "--verbose=TERSE", "-x"])).expect("ok")
        else {
            panic!("not a run")
        };
        assert_eq!(r.name, "helm2");
        assert_eq!(r.verbose, Some(Verbose::Terse));
        assert_eq!(r.ignored, vec!["-x".to_string()]);
        let Action::Run(r) = parse(&os(&["m.moos", "--moos_name=helm3"])).expect("ok") else {
            panic!("not a run")
        };
        assert_eq!(r.name, "helm3");
        assert_eq!(parse(&os(&["m.moos", "-v"])), Ok(Action::Version));
        assert_eq!(parse(&os(&["-e"])), Ok(Action::Example));
        assert_eq!(
            parse(&os(&["m.moos", "--interface"])),
            Ok(Action::Interface)
        );
        assert_eq!(parse(&os(&["-help"])), Ok(Action::Help));
        assert_eq!(parse(&os(&["-web"])), Ok(Action::Web));
        assert_eq!(
            parse(&os(&["m.moos", "--verbose=loud"])),
            Err(ArgError::IllegalVerbose("loud".into()))
        );
        assert_eq!(parse(&os(&["x.bhv"])), Err(ArgError::NoMission));
        assert_eq!(
            ArgError::IllegalVerbose("x".into()).to_string(),
            "Illegal verbose setting. Exiting now."
        );
    }

    #[test]
    fn form_detection() {
        assert!(is_phelmivp_form(&os(&["helm", "alpha.moos"])));
        assert!(is_phelmivp_form(&os(&["/usr/bin/pHelmIvP", "-v"])));
        assert!(!is_phelmivp_form(&os(&["helm", "run", "alpha.moos"])));
        assert!(!is_phelmivp_form(&os(&["helm", "--help"])));
        assert!(is_phelmivp_form(&os(&["helm", "-e"])));
        assert!(is_phelmivp_form(&os(&["helm", "-v"])));
        assert!(!is_phelmivp_form(&os(&["helm", "-V"])));
    }

    #[test]
    fn first_non_default_verbose_wins() {
        use Verbose as V;
        assert_eq!(resolve_verbose(None, None, V::Verbose), V::Verbose);
        assert_eq!(resolve_verbose(Some(V::Terse), None, V::Quiet), V::Terse);
        assert_eq!(resolve_verbose(Some(V::Verbose), None, V::Quiet), V::Quiet);
        assert_eq!(resolve_verbose(None, Some(V::Quiet), V::Terse), V::Quiet);
        let all_default = resolve_verbose(Some(V::Verbose), Some(V::Verbose), V::Verbose);
        assert_eq!(all_default, V::Verbose);
    }
}
