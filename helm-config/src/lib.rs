//! `helm-config`: the pHelmIvP block of the mission file, read into a typed config
//! (helm.md §2). It depends on `ivp` (the domain) and `mbutil` alone: nothing of the
//! engine, the behaviors or MOOS. `helm_engine::config` is this crate.
//!
//! The real helm gets the block's lines last-first with every blank removed (the MOOS
//! config reader's `GetConfiguration`), so "the first setting wins" means the last line
//! in the file, and the domain is the `domain =` lines in reverse. Both are reproduced
//! (QUIRKS.md).

use std::path::PathBuf;

use ivp::Domain;

/// Verbosity of the terminal output.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verbose {
    Verbose,
    Terse,
    Quiet,
}

/// The verbose words of the block, the command line and `HELM_VERBOSE`.
pub fn parse_verbose(v: &str) -> Option<Verbose> {
    match v.trim().to_ascii_lowercase().as_str() {
        "verbose" | "true" => Some(Verbose::Verbose),
        "terse" | "false" => Some(Verbose::Terse),
        "quiet" => Some(Verbose::Quiet),
        _ => None,
    }
}

/// One line of the pHelmIvP block as written.
#[derive(Clone, Debug)]
pub struct BlockLine {
    pub line: usize,
    pub name: String,
    pub value: String,
}

/// The helm's configuration, with the real helm's defaults.
#[derive(Clone, Debug)]
pub struct HelmConfig {
    pub domain: Domain,
    /// Per domain variable: a missing decision does not cause an all-stop.
    pub optional: Vec<bool>,
    pub behaviors: Vec<PathBuf>,
    /// `ivp_behavior_dir` values, with their lines.
    pub behavior_dirs: Vec<(PathBuf, usize)>,
    pub bhv_dir_not_found_ok: bool,
    pub ok_skew: Option<f64>,
    pub verbose: Verbose,
    pub start_in_drive: bool,
    pub allow_park: bool,
    pub park_on_allstop: bool,
    pub goals_mandatory: bool,
    pub helm_alias: String,
    pub standby: Option<f64>,
    pub helm_prefix: String,
    pub hold_on_apps: Vec<String>,
    pub nav_grace: f64,
    /// Seconds after which a contact with no report leaves the ledger is twice this
    /// (contacts-appcast.md §2.4); 10..=1800, default 45.
    pub contact_max_age: f64,
    /// The mission's `LatOrigin`/`LongOrigin` (globals, not block lines): the ledger turns
    /// LAT/LON-only reports into local x/y with it.
    pub origin: Option<(f64, f64)>,
    pub other_override_var: String,
    pub app_tick: f64,
}

impl Default for HelmConfig {
    fn default() -> Self {
        HelmConfig {
            domain: Domain::new(),
            optional: Vec::new(),
            behaviors: Vec::new(),
            behavior_dirs: Vec::new(),
            bhv_dir_not_found_ok: false,
            ok_skew: Some(60.0),
            verbose: Verbose::Verbose,
            start_in_drive: false,
            allow_park: true,
            park_on_allstop: false,
            goals_mandatory: false,
            helm_alias: String::new(),
            standby: None,
            helm_prefix: String::new(),
            hold_on_apps: Vec::new(),
            nav_grace: 5.0,
            contact_max_age: 45.0,
            origin: None,
            other_override_var: String::new(),
            app_tick: 5.0,
        }
    }
}

/// A line the helm did not accept: "Unhandled config line" (the helm goes MALCONFIG).
#[derive(Clone, Debug, PartialEq)]
pub struct ConfigWarning {
    pub line: usize,
    pub text: String,
}

impl std::fmt::Display for ConfigWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.line > 0 {
            write!(f, "line {}: {}", self.line, self.text)
        } else {
            f.write_str(&self.text)
        }
    }
}

pub use mbutil::parse_bool;

/// `domain = name:low:high:points[:optional]` (helm.md §2.3).
fn add_domain_var(cfg: &mut HelmConfig, value: &str) -> bool {
    let v = value.trim().replace(',', ":");
    let f: Vec<&str> = v.split(':').collect();
    if f.len() != 4 && f.len() != 5 {
        return false;
    }
    let low = mbutil::atof(f[1]);
    let high = mbutil::atof(f[2]);
    if high < low {
        return false;
    }
    let mut points = atoi(f[3]);
    if let Some(d) = f[3].strip_prefix("delta=") {
        if high > low && mbutil::is_number(d) {
            let d = mbutil::atof(d);
            if d > 0.0 && d <= high - low {
                points = ((high - low) / d + 1.0).trunc() as i64;
            }
        }
    }
    if points < 1 || points > u32::MAX as i64 {
        return false;
    }
    let optional = f.len() == 5 && f[4].eq_ignore_ascii_case("optional");
    if cfg.domain.add_var(f[0], low, high, points as u32).is_err() {
        return false;
    }
    cfg.optional.push(optional);
    true
}

/// C `atoi`: leading sign and digits, else 0.
fn atoi(s: &str) -> i64 {
    let s = s.trim_start();
    let (neg, rest) = match s.as_bytes().first() {
        Some(b'-') => (true, &s[1..]),
        Some(b'+') => (false, &s[1..]),
        _ => (false, s),
    };
    let digits: String = rest.chars().take_while(|c| c.is_ascii_digit()).collect();
    let n: i64 = digits.parse().unwrap_or(0);
    if neg {
        -n
    } else {
        n
    }
}

impl HelmConfig {
    /// Read the block's lines (in file order); returns the config and the lines it did
    /// not accept. Lines are applied last-first, as the real helm does.
    pub fn from_lines(lines: &[BlockLine]) -> (HelmConfig, Vec<ConfigWarning>) {
        let mut cfg = HelmConfig::default();
        let mut warnings = Vec::new();
        let mut verbose_locked = false;
        for l in lines.iter().rev() {
            let name = l.name.trim().to_ascii_lowercase();
            // The real reader removes every blank from the line.
            let value: String = l.value.chars().filter(|c| !c.is_whitespace()).collect();
            let ok = match name.as_str() {
                "behaviors" => {
                    let p = PathBuf::from(&value);
                    if cfg.behaviors.contains(&p) {
                        false
                    } else {
                        cfg.behaviors.push(p);
                        true
                    }
                }
                "domain" => add_domain_var(&mut cfg, &value),
                "ok_skew" => {
                    if value.eq_ignore_ascii_case("any") {
                        cfg.ok_skew = None;
                        true
                    } else if mbutil::is_number(&value) && mbutil::atof(&value) >= 0.0 {
                        cfg.ok_skew = Some(mbutil::atof(&value));
                        true
                    } else {
                        false
                    }
                }
                "verbose" => match parse_verbose(&value) {
                    Some(v) => {
                        if !verbose_locked && v != Verbose::Verbose {
                            cfg.verbose = v;
                            verbose_locked = true;
                        }
                        true
                    }
                    None => false,
                },
                "start_engaged" | "active_start" | "start_indrive" | "start_in_drive" => {
                    set_bool(&mut cfg.start_in_drive, &value)
                }
                "allow_park" => set_bool(&mut cfg.allow_park, &value),
                "park_on_allstop" => set_bool(&mut cfg.park_on_allstop, &value),
                "goals_mandatory" => set_bool(&mut cfg.goals_mandatory, &value),
                "seed_random" => parse_bool(&value).is_some(),
                "helm_alias" => {
                    cfg.helm_alias = value.clone();
                    true
                }
                "standby" => match positive_number(&value) {
                    Some(t) => {
                        cfg.standby = Some(t);
                        true
                    }
                    None => false,
                },
                "node_skew" => value.contains(','),
                "helm_prefix" => {
                    cfg.helm_prefix = value.clone();
                    true
                }
                "hold_on_app" | "hold_on_apps" => {
                    let mut ok = !value.is_empty();
                    for a in value.split(',') {
                        if a.is_empty() || cfg.hold_on_apps.iter().any(|x| x == a) {
                            ok = false;
                        } else {
                            cfg.hold_on_apps.push(a.to_string());
                        }
                    }
                    ok
                }
                "nav_grace" => match number(&value) {
                    Some(t) => {
                        cfg.nav_grace = t;
                        true
                    }
                    None => false,
                },
                "contact_max_age" => {
                    let v = mbutil::atof(&value);
                    let ok = mbutil::is_number(&value) && (10.0..=1800.0).contains(&v);
                    if ok {
                        cfg.contact_max_age = v;
                    }
                    ok
                }
                "ivp_behavior_dir" | "ivp_behavior_dirs" => {
                    cfg.behavior_dirs.push((PathBuf::from(&value), l.line));
                    true
                }
                "bhv_dir_not_found_ok" | "bhv_dirs_not_found_ok" => {
                    set_bool(&mut cfg.bhv_dir_not_found_ok, &value)
                }
                "pmgen" => true,
                "other_override_var" => {
                    cfg.other_override_var = value.clone();
                    true
                }
                "apptick" => {
                    if mbutil::is_number(&value) {
                        cfg.app_tick = mbutil::atof(&value);
                    }
                    true
                }
                "commstick"
                | "maxapptick"
                | "app_logging"
                | "term_report_interval"
                | "max_appcast_events"
                | "deprecated_ok" => true,
                _ => false,
            };
            if !ok {
                warnings.push(ConfigWarning {
                    line: l.line,
                    text: format!(
                        "Unhandled config line: {} = {}",
                        l.name.trim(),
                        l.value.trim()
                    ),
                });
            }
        }
        (cfg, warnings)
    }

    /// The helm domain as `name,low,high,points` joined by `:`.
    pub fn domain_string(&self) -> String {
        self.domain.to_string()
    }
}

fn number(v: &str) -> Option<f64> {
    mbutil::is_number(v).then(|| mbutil::atof(v))
}

fn positive_number(v: &str) -> Option<f64> {
    number(v).filter(|x| *x > 0.0)
}

fn set_bool(slot: &mut bool, v: &str) -> bool {
    match v.to_ascii_lowercase().as_str() {
        "toggle" => {
            *slot = !*slot;
            true
        }
        _ => match parse_bool(v) {
            Some(b) => {
                *slot = b;
                true
            }
            None => false,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(n: usize, name: &str, value: &str) -> BlockLine {
        BlockLine {
            line: n,
            name: name.into(),
            value: value.into(),
        }
    }

    #[test]
    fn domain_lines_are_reversed_and_validated() {
        let (cfg, w) = HelmConfig::from_lines(&[
            line(1, "domain", "course:0:359:360"),
            line(2, "domain", "speed,0,4,41"),
            line(3, "domain", "depth:0:100:delta=1:optional"),
            line(4, "Domain", "bad:5:1:3"),
        ]);
        assert_eq!(
            cfg.domain.to_string(),
            "depth,0,100,101:speed,0,4,41:course,0,359,360"
        );
        assert_eq!(cfg.optional, vec![true, false, false]);
        assert_eq!(w.len(), 1);
        assert_eq!(w[0].line, 4);
    }

    #[test]
    fn booleans_and_unknowns() {
        let (cfg, w) = HelmConfig::from_lines(&[
            line(1, "START_IN_DRIVE", "true"),
            line(2, "comms_policy", "lean"),
        ]);
        assert!(cfg.start_in_drive);
        assert_eq!(w.len(), 1, "comms_policy is not exempted (quirk)");
        let (cfg, _) = HelmConfig::from_lines(&[line(1, "helm_alias", "my helm")]);
        assert_eq!(cfg.helm_alias, "myhelm");
    }
}
