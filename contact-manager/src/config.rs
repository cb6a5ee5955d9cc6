//! pContactMgrV20's configuration block (contacts-appcast.md §4; the parameter names
//! the MOOS-IvP missions use), as plain `param = value` pairs.

use contacts::{ContactFilter, Decay, FilterError};

use crate::alert::{AlertSet, AlertSpecError, Flag};

/// A configuration line that was refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ConfigError {
    #[error("unknown parameter: {0}")]
    Unknown(String),
    #[error("{param}: not a boolean (true/false): {value}")]
    BadBool { param: String, value: String },
    #[error("{param}: not a number >= {min}: {value}")]
    BadNumber {
        param: String,
        value: String,
        min: f64,
    },
    #[error("{param}: {msg}: {value}")]
    BadValue {
        param: String,
        value: String,
        msg: &'static str,
    },
    #[error("alert: {0}")]
    Alert(#[from] AlertSpecError),
    #[error("{0}")]
    Filter(#[from] FilterError),
}

/// How a contact's x/y are taken from its report (`contact_local_coords`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LocalCoords {
    /// x/y as reported (from LAT/LON only when the report has no x/y).
    #[default]
    Verbatim,
    /// From LAT/LON only when x/y are missing (the same as verbatim here).
    LazyLatLon,
    /// From LAT/LON whenever the report has them.
    ForceLatLon,
}

/// The configuration of one manager. Defaults are pContactMgrV20's.
#[derive(Clone, Debug, PartialEq)]
pub struct Config {
    pub alerts: AlertSet,
    /// The global filter (contacts failing it are not kept).
    pub filter: ContactFilter,
    pub contact_max_age: f64,
    pub reject_range: f64,
    pub max_contacts: usize,
    pub decay: Decay,
    pub recap_interval: f64,
    pub max_retired_history: usize,
    pub range_report_timeout: f64,
    pub range_report_maxsize: usize,
    pub alert_verbose: bool,
    pub display_radii: bool,
    pub display_radii_id: String,
    pub alert_range_color: String,
    pub cpa_range_color: String,
    pub post_closest_range: bool,
    pub post_closest_relbng: bool,
    pub post_all_ranges: bool,
    pub hold_alerts_for_helm: bool,
    pub local_coords: LocalCoords,
    pub disable_var: String,
    pub enable_var: String,
    pub expunge_var: String,
    pub able_flags: Vec<Flag>,
    pub disable_flags: Vec<Flag>,
    pub enable_flags: Vec<Flag>,
    pub ownship_group: String,
    pub ownship_type: String,
    /// Accepted so missions load; not acted on (no facts in the specs yet).
    pub inert: Vec<(String, String)>,
}

impl Default for Config {
    fn default() -> Self {
        Config {
            alerts: AlertSet::default(),
            filter: ContactFilter::default(),
            contact_max_age: 60.0,
            reject_range: 2000.0,
            max_contacts: 500,
            decay: Decay::default(),
            recap_interval: 1.0,
            max_retired_history: 5,
            range_report_timeout: 10.0,
            range_report_maxsize: 20,
            alert_verbose: false,
            display_radii: false,
            display_radii_id: String::new(),
            alert_range_color: "gray65".into(),
            cpa_range_color: "gray35".into(),
            post_closest_range: false,
            post_closest_relbng: false,
            post_all_ranges: false,
            hold_alerts_for_helm: false,
            local_coords: LocalCoords::Verbatim,
            disable_var: String::new(),
            enable_var: String::new(),
            expunge_var: String::new(),
            able_flags: Vec::new(),
            disable_flags: Vec::new(),
            enable_flags: Vec::new(),
            ownship_group: String::new(),
            ownship_type: String::new(),
            inert: Vec::new(),
        }
    }
}

/// Parameters accepted and kept without effect (they configure drawing or features
/// the specs do not describe).
const INERT: &[&str] = &[
    "early_warning_range",
    "early_warning_flag",
    "early_warning_ref_spd",
    "early_warning_radii",
    "cease_warning_flag",
    "eval_range_far",
    "eval_range_near",
    "max_appcast_events",
];

fn boolean(param: &str, value: &str) -> Result<bool, ConfigError> {
    match value.trim().to_ascii_lowercase().as_str() {
        "true" => Ok(true),
        "false" => Ok(false),
        _ => Err(ConfigError::BadBool {
            param: param.into(),
            value: value.into(),
        }),
    }
}

fn number(param: &str, value: &str, min: f64) -> Result<f64, ConfigError> {
    mbutil::parse_number(value)
        .filter(|v| *v >= min && v.is_finite())
        .ok_or_else(|| ConfigError::BadNumber {
            param: param.into(),
            value: value.into(),
            min,
        })
}

fn count(param: &str, value: &str, min: f64) -> Result<usize, ConfigError> {
    let v = number(param, value, min)?;
    Ok(v.min(1e9) as usize)
}

fn variable(param: &str, value: &str) -> Result<String, ConfigError> {
    let v = value.trim();
    if v.is_empty() || v.contains(|c: char| c.is_whitespace() || c == '=' || c == ',') {
        return Err(ConfigError::BadValue {
            param: param.into(),
            value: value.into(),
            msg: "not a MOOS variable name",
        });
    }
    Ok(v.to_string())
}

fn color(param: &str, value: &str) -> Result<String, ConfigError> {
    if mbutil::is_color(value.trim()) {
        Ok(value.trim().to_string())
    } else {
        Err(ConfigError::BadValue {
            param: param.into(),
            value: value.into(),
            msg: "not a colour",
        })
    }
}

fn flag(param: &str, value: &str) -> Result<Flag, ConfigError> {
    Flag::parse(value).ok_or_else(|| ConfigError::BadValue {
        param: param.into(),
        value: value.into(),
        msg: "want VAR=VALUE",
    })
}

impl Config {
    /// Apply one block line (`param` in any case). An error leaves the config as it was.
    ///
    /// ```
    /// let mut c = contact_manager::Config::default();
    /// c.set("Contact_Max_Age", "35").unwrap();
    /// c.set("alert", "id=avd, var=CONTACT_INFO, val=\"name=$[VNAME] # contact=$[VNAME]\"").unwrap();
    /// assert_eq!(c.contact_max_age, 35.0);
    /// assert!(c.set("decay", "60,30").is_err());
    /// assert!(c.set("bogus", "1").is_err());
    /// ```
    pub fn set(&mut self, param: &str, value: &str) -> Result<(), ConfigError> {
        let p = param.trim().to_ascii_lowercase();
        let v = value.trim();
        match p.as_str() {
            "alert" => {
                self.alerts.apply(v)?;
            }
            "contact_max_age" => self.contact_max_age = number(&p, v, 0.0)?,
            "reject_range" => self.reject_range = number(&p, v, 0.0)?,
            "max_contacts" => self.max_contacts = count(&p, v, 1.0)?,
            "decay" => {
                self.decay = Decay::parse(v).map_err(|_| ConfigError::BadValue {
                    param: p.clone(),
                    value: v.into(),
                    msg: "want start,end with 0 <= start <= end",
                })?
            }
            "recap_interval" | "contacts_recap_interval" => {
                self.recap_interval = number(&p, v, 0.0)?
            }
            "max_retired_history" => self.max_retired_history = count(&p, v, 0.0)?,
            "range_report_timeout" => self.range_report_timeout = number(&p, v, 0.0)?,
            "range_report_maxsize" => self.range_report_maxsize = count(&p, v, 1.0)?,
            "alert_verbose" => self.alert_verbose = boolean(&p, v)?,
            "display_radii" => self.display_radii = boolean(&p, v)?,
            "display_radii_id" => self.display_radii_id = v.to_string(),
            "alert_range_color" => self.alert_range_color = color(&p, v)?,
            "cpa_range_color" => self.cpa_range_color = color(&p, v)?,
            "post_closest_range" => self.post_closest_range = boolean(&p, v)?,
            "post_closest_relbng" => self.post_closest_relbng = boolean(&p, v)?,
            "post_all_ranges" => self.post_all_ranges = boolean(&p, v)?,
            "hold_alerts_for_helm" => self.hold_alerts_for_helm = boolean(&p, v)?,
            "contact_local_coords" => {
                self.local_coords = match v.to_ascii_lowercase().as_str() {
                    "verbatim" => LocalCoords::Verbatim,
                    "lazy_lat_lon" => LocalCoords::LazyLatLon,
                    "force_lat_lon" => LocalCoords::ForceLatLon,
                    _ => {
                        return Err(ConfigError::BadValue {
                            param: p,
                            value: v.into(),
                            msg: "want verbatim, lazy_lat_lon or force_lat_lon",
                        })
                    }
                }
            }
            "disable_var" => self.disable_var = variable(&p, v)?,
            "enable_var" => self.enable_var = variable(&p, v)?,
            "expunge_var" => self.expunge_var = variable(&p, v)?,
            "able_flag" => self.able_flags.push(flag(&p, v)?),
            "disable_flag" => self.disable_flags.push(flag(&p, v)?),
            "enable_flag" => self.enable_flags.push(flag(&p, v)?),
            "ownship_group" => self.ownship_group = v.to_string(),
            "ownship_type" => self.ownship_type = v.to_string(),
            "match_name" | "ignore_name" | "match_group" | "ignore_group" | "match_type"
            | "ignore_type" | "match_region" | "ignore_region" | "strict_ignore" => {
                self.filter.set_param(&p, v)?;
            }
            _ if INERT.contains(&p.as_str()) => self.inert.push((p, v.to_string())),
            _ => return Err(ConfigError::Unknown(param.trim().to_string())),
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every line of the pContactMgrV20 blocks of the distribution's missions we read
    /// (berta_cmgr and the like), in their spelling.
    #[test]
    fn distribution_block_lines_are_accepted() {
        let mut c = Config::default();
        for (p, v) in [
            ("decay", "30,60"),
            ("alert_verbose", "true"),
            ("contact_local_coords", "force_lat_lon"),
            ("contact_max_age", "35"),
            ("display_radii", "true"),
            ("display_radii_id", "avd"),
            ("alert_range_color", "gray70"),
            ("cpa_range_color", "gray30"),
            ("early_warning_range", "60"),
            (
                "early_warning_flag",
                "CMGR_WARNING = Warning=$[CONTACT], at $[RNG]",
            ),
            ("early_warning_ref_spd", "3.4"),
            ("early_warning_radii", "true"),
            ("cease_warning_flag", "CMGR_WARNING = off"),
            ("disable_var", "XYZ_DISABLE_TARGET"),
            ("enable_var", "XYZ_REENABLE_TARGET"),
            ("post_closest_range", "true"),
            ("hold_alerts_for_helm", "true"),
            ("alert", "id=say, on_flag=SAY_MOOS=hello"),
            ("alert", "id=say, alert_range=80, cpa_range=100"),
            ("ownship_group", "blue_team"),
            ("ownship_type", "kayak"),
            ("reject_range", "2000"),
            ("max_contacts", "500"),
            ("post_closest_relbng", "false"),
            ("post_all_ranges", "false"),
            ("recap_interval", "1"),
            ("max_retired_history", "5"),
            ("ignore_group", "red"),
        ] {
            c.set(p, v).unwrap_or_else(|e| panic!("{p} = {v}: {e}"));
        }
        assert_eq!(c.decay, Decay::parse("30,60").unwrap());
        assert_eq!(c.local_coords, LocalCoords::ForceLatLon);
        assert_eq!(c.disable_var, "XYZ_DISABLE_TARGET");
        assert!(c.alerts.get("say").unwrap().valid());
        assert_eq!(c.inert.len(), 5);
    }

    #[test]
    fn bad_values_are_refused_and_change_nothing() {
        let mut c = Config::default();
        let before = c.clone();
        for (p, v) in [
            ("contact_max_age", "-3"),
            ("contact_max_age", "soon"),
            ("alert_verbose", "yes"),
            ("contact_local_coords", "utm"),
            ("alert_range_color", "notacolour"),
            ("disable_var", "two words"),
            ("able_flag", "noequals"),
            ("max_contacts", "0"),
            ("alert", "id=a, on_flag=X=1, bogus=2"),
            ("nonsense", "1"),
        ] {
            assert!(c.set(p, v).is_err(), "{p} = {v} accepted");
        }
        assert_eq!(c, before);
        assert_eq!(
            c.set("Frobnicate", "1").unwrap_err().to_string(),
            "unknown parameter: Frobnicate"
        );
    }
}
