//! pObstacleMgr's configuration block (obstacles.md §2.1), as plain `param = value`
//! pairs: names lower-cased, values trimmed; a refused line is a typed error (the app
//! shows it as an "unhandled config" warning with its file and line).

use crate::alert::{AlertRequest, RequestError};
use crate::flags::{Flag, FlagError, MailFlag};
use crate::obstacle::{Given, GivenError};

/// A configuration line that was refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ConfigError {
    #[error("unknown parameter: {0}")]
    Unknown(String),
    #[error("{param}: not a boolean (true/false): {value}")]
    BadBool { param: String, value: String },
    #[error("{param}: not a number {rule}: {value}")]
    BadNumber {
        param: String,
        value: String,
        rule: &'static str,
    },
    #[error("{param}: {msg}: {value}")]
    BadValue {
        param: String,
        value: String,
        msg: &'static str,
    },
    #[error("general_alert: {0}")]
    GeneralAlert(RequestError),
    #[error("{0}")]
    Flag(#[from] FlagError),
    #[error("given_obstacle: {0}: {1}")]
    Given(GivenError, String),
}

/// Most vertices of a lasso polygon (the reference has no limit).
pub const MAX_LASSO_POINTS: usize = 1000;

/// The OBM_DIST_TO_OBJ policy (`post_dist_to_polys`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DistPolicy {
    /// Every obstacle, every iteration.
    All,
    /// None.
    Off,
    /// Only those within the alert range.
    #[default]
    Close,
}

/// The configuration of one manager. Defaults are pObstacleMgr's.
#[derive(Clone, Debug, PartialEq)]
pub struct Config {
    pub point_var: String,
    /// `given_obstacle` lines, handled at startup in order.
    pub given: Vec<String>,
    pub alert_range: f64,
    /// ≤ 0: off.
    pub ignore_range: f64,
    pub max_pts_per_cluster: usize,
    pub max_age_per_point: f64,
    pub post_dist_to_polys: DistPolicy,
    pub post_view_polys: bool,
    pub obstacles_color: String,
    pub poly_label_thresh: usize,
    pub poly_shade_thresh: usize,
    pub poly_vertex_thresh: usize,
    /// ≤ 0: no limit on mailed given obstacles.
    pub given_max_duration: f64,
    pub general_alert: Option<AlertRequest>,
    pub new_obs_flags: Vec<Flag>,
    pub mail_flags: Vec<MailFlag>,
    pub disable_var: String,
    pub enable_var: String,
    pub expunge_var: String,
    pub lasso: bool,
    pub lasso_points: usize,
    pub lasso_radius: f64,
    /// Configuration warnings the real app gives while accepting a value.
    pub notes: Vec<String>,
}

impl Default for Config {
    fn default() -> Self {
        Config {
            point_var: "TRACKED_FEATURE".into(),
            given: Vec::new(),
            alert_range: 20.0,
            ignore_range: -1.0,
            max_pts_per_cluster: 20,
            max_age_per_point: 20.0,
            post_dist_to_polys: DistPolicy::Close,
            post_view_polys: true,
            obstacles_color: "blue".into(),
            poly_label_thresh: 25,
            poly_shade_thresh: 100,
            poly_vertex_thresh: 150,
            given_max_duration: 60.0,
            general_alert: None,
            new_obs_flags: Vec::new(),
            mail_flags: Vec::new(),
            disable_var: String::new(),
            enable_var: String::new(),
            expunge_var: String::new(),
            lasso: false,
            lasso_points: 6,
            lasso_radius: 5.0,
            notes: Vec::new(),
        }
    }
}

fn boolean(param: &str, value: &str) -> Result<bool, ConfigError> {
    match value.to_ascii_lowercase().as_str() {
        "true" => Ok(true),
        "false" => Ok(false),
        _ => Err(ConfigError::BadBool {
            param: param.into(),
            value: value.into(),
        }),
    }
}

fn number(param: &str, value: &str, positive: bool) -> Result<f64, ConfigError> {
    let rule = if positive { "> 0" } else { ">= 0" };
    match mbutil::parse_number(value).filter(|v| v.is_finite()) {
        Some(v) if (positive && v > 0.0) || (!positive && v >= 0.0) => Ok(v),
        _ => Err(ConfigError::BadNumber {
            param: param.into(),
            value: value.into(),
            rule,
        }),
    }
}

/// A count (number ≥ 0, truncated), capped so a hostile value cannot size a buffer.
fn count(param: &str, value: &str) -> Result<usize, ConfigError> {
    let v = number(param, value, false)?;
    Ok(v.min(1e6) as usize)
}

fn var_name(param: &str, value: &str) -> Result<String, ConfigError> {
    if value.is_empty() || value.chars().any(char::is_whitespace) {
        return Err(ConfigError::BadValue {
            param: param.into(),
            value: value.into(),
            msg: "not a variable name",
        });
    }
    Ok(value.to_string())
}

impl Config {
    /// Apply one block line. A refused line leaves the configuration unchanged.
    ///
    /// ```
    /// let mut c = obstacle_manager::Config::default();
    /// c.set("Alert_Range", "35").unwrap();
    /// assert_eq!(c.alert_range, 35.0);
    /// assert!(c.set("alert_range", "-1").is_err());
    /// assert!(c.set("colour", "red").is_err());
    /// ```
    pub fn set(&mut self, param: &str, value: &str) -> Result<(), ConfigError> {
        let p = param.trim().to_ascii_lowercase();
        let v = value.trim();
        match p.as_str() {
            "point_var" => self.point_var = var_name(&p, v)?,
            "given_obstacle" | "given_obstable" => {
                Given::parse(v).map_err(|e| ConfigError::Given(e, v.into()))?;
                self.given.push(v.to_string());
            }
            "alert_range" => self.alert_range = number(&p, v, true)?,
            "ignore_range" => self.ignore_range = number(&p, v, true)?,
            "max_pts_per_cluster" => self.max_pts_per_cluster = count(&p, v)?,
            "max_age_per_point" => self.max_age_per_point = number(&p, v, true)?,
            "post_dist_to_polys" => {
                self.post_dist_to_polys = match v.to_ascii_lowercase().as_str() {
                    "true" => DistPolicy::All,
                    "false" => DistPolicy::Off,
                    "close" => DistPolicy::Close,
                    _ => {
                        return Err(ConfigError::BadValue {
                            param: p,
                            value: v.into(),
                            msg: "not true, false or close",
                        })
                    }
                }
            }
            "post_view_polys" => self.post_view_polys = boolean(&p, v)?,
            "obstacles_color" => {
                if !mbutil::is_color(v) {
                    return Err(ConfigError::BadValue {
                        param: p,
                        value: v.into(),
                        msg: "not a colour",
                    });
                }
                self.obstacles_color = v.to_string();
            }
            "poly_label_thresh" => self.poly_label_thresh = count(&p, v)?,
            "poly_shade_thresh" => self.poly_shade_thresh = count(&p, v)?,
            "poly_vertex_thresh" => self.poly_vertex_thresh = count(&p, v)?,
            "given_max_duration" => {
                self.given_max_duration = if v.eq_ignore_ascii_case("off") {
                    -1.0
                } else {
                    number(&p, v, true)?
                }
            }
            "general_alert" => {
                self.general_alert =
                    Some(AlertRequest::parse_general(v).map_err(ConfigError::GeneralAlert)?)
            }
            "new_obs_flag" => self.new_obs_flags.push(Flag::parse(v)?),
            "mailflag" => self.mail_flags.push(MailFlag::parse(v)?),
            "disable_var" => self.disable_var = var_name(&p, v)?,
            "enable_var" => self.enable_var = var_name(&p, v)?,
            "expunge_var" => self.expunge_var = var_name(&p, v)?,
            "lasso" => self.lasso = boolean(&p, v)?,
            "lasso_points" => {
                let n = count(&p, v)?;
                if n < 3 {
                    self.notes
                        .push("lasso_points must be at least 3 points".into());
                }
                // Capped: each hull is a polygon of this many vertices, checked for
                // convexity in quadratic time every iteration.
                self.lasso_points = n.clamp(3, MAX_LASSO_POINTS);
            }
            "lasso_radius" => {
                let r = mbutil::parse_number(v)
                    .filter(|r| r.is_finite())
                    .ok_or_else(|| ConfigError::BadNumber {
                        param: p.clone(),
                        value: v.into(),
                        rule: "(finite)",
                    })?;
                if r <= 0.0 {
                    self.notes
                        .push("lasso_radius must be at positive number".into());
                }
                self.lasso_radius = if r <= 0.0 { 1.0 } else { r };
            }
            _ => return Err(ConfigError::Unknown(p)),
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_missions_blocks_are_accepted() {
        let mut c = Config::default();
        for (p, v) in [
            ("point_var", "TRACKED_FEATURE"),
            ("obstacles_color", "invisible"),
            ("post_view_polys", "false"),
            ("given_max_duration", "1000"),
            ("general_alert", "update_var=GEN_ALERT, alert_range=40000"),
            ("max_pts_per_cluster", "50"),
            ("max_age_per_point", "60"),
            ("alert_range", "35"),
            ("ignore_range", "40"),
            ("lasso", "true"),
            ("lasso_radius", "6"),
            ("lasso_points", "8"),
            ("poly_label_thresh", "5000"),
            (
                "given_obstacle",
                "pts={50,-100:50,-120:80,-120:80,-100}, label=one",
            ),
            ("new_obs_flag", "NEWOBS=now:$[OBS_NOW],ever:$[OBS_EVER]"),
        ] {
            c.set(p, v).unwrap_or_else(|e| panic!("{p} = {v}: {e}"));
        }
        let g = c.general_alert.as_ref().expect("general alert");
        assert_eq!(
            (g.name.as_str(), g.update_var.as_str(), g.range),
            ("gen_alert_", "GEN_ALERT", 40000.0)
        );
        assert_eq!(c.given.len(), 1);
        assert!(c.notes.is_empty());
    }

    #[test]
    fn refused_and_adjusted_values() {
        let mut c = Config::default();
        let before = c.clone();
        for (p, v) in [
            ("max_age_per_point", "0"),
            ("post_dist_to_polys", "maybe"),
            ("general_alert", "update_var=G, alert_range=-3"),
            ("general_alert", "update_var=G, alert_range=3, colour=red"),
            ("point_var", "TWO WORDS"),
            ("new_obs_flag", "NOEQUALS"),
            ("given_obstacle", "pts={0,0:10,0:5,1:10,10:0,10},label=c"),
            ("bogus", "1"),
        ] {
            assert!(c.set(p, v).is_err(), "{p} = {v}");
        }
        assert_eq!(c, before);
        c.set("given_max_duration", "OFF").unwrap();
        assert_eq!(c.given_max_duration, -1.0);
        c.set("post_dist_to_polys", "TRUE").unwrap();
        assert_eq!(c.post_dist_to_polys, DistPolicy::All);
        c.set("lasso_points", "2").unwrap();
        c.set("lasso_radius", "-4").unwrap();
        assert_eq!((c.lasso_points, c.lasso_radius), (3, 1.0));
        assert_eq!(c.notes.len(), 2);
    }
}
