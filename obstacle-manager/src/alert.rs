//! The alert protocol with the helm (obstacles.md §2.6): the `OBM_ALERT_REQUEST` a
//! behavior template posts at helm start, the `general_alert` channel, and the update
//! string the helm's spawn mechanism reads.

use std::fmt::Write as _;

use geometry::{pts_spec, Polygon};

/// A refused alert request (or `general_alert` line).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum RequestError {
    #[error("unknown field: {0}")]
    UnknownField(String),
    #[error("field without '=': {0}")]
    NotAPair(String),
    #[error("missing or empty {0}")]
    Missing(&'static str),
    #[error("alert_range is not a number > 0: {0}")]
    BadRange(String),
}

/// One requester: where to post updates, the name prefix, the range.
#[derive(Clone, Debug, PartialEq)]
pub struct AlertRequest {
    pub name: String,
    pub update_var: String,
    pub range: f64,
}

impl AlertRequest {
    /// `name=<n>,update_var=<VAR>,alert_range=<r>`: keys in any case, all three
    /// present and non-empty, the range a number > 0.
    ///
    /// ```
    /// use obstacle_manager::AlertRequest;
    /// let r = AlertRequest::parse("name=avd_ob_,update_var=OBSTACLE_ALERT,alert_range=15").unwrap();
    /// assert_eq!((r.name.as_str(), r.update_var.as_str(), r.range), ("avd_ob_", "OBSTACLE_ALERT", 15.0));
    /// assert!(AlertRequest::parse("name=a,update_var=B,alert_range=0").is_err());
    /// ```
    pub fn parse(s: &str) -> Result<AlertRequest, RequestError> {
        Self::fields(s, false)
    }

    /// The `general_alert` configuration: `name` defaults to `gen_alert`, and a `_` is
    /// appended when missing.
    pub fn parse_general(s: &str) -> Result<AlertRequest, RequestError> {
        let mut r = Self::fields(s, true)?;
        if r.name.is_empty() {
            r.name = "gen_alert".into();
        }
        if !r.name.ends_with('_') {
            r.name.push('_');
        }
        Ok(r)
    }

    fn fields(s: &str, name_optional: bool) -> Result<AlertRequest, RequestError> {
        let (mut name, mut var, mut range) = (String::new(), String::new(), None);
        for part in s.split(',') {
            let part = part.trim();
            if part.is_empty() {
                continue;
            }
            let (k, v) = part
                .split_once('=')
                .ok_or_else(|| RequestError::NotAPair(part.to_string()))?;
            let v = v.trim();
            match k.trim().to_ascii_lowercase().as_str() {
                "name" => name = v.to_string(),
                "update_var" => var = v.to_string(),
                "alert_range" => {
                    range = Some(
                        mbutil::parse_number(v)
                            .filter(|r| r.is_finite() && *r > 0.0)
                            .ok_or_else(|| RequestError::BadRange(v.to_string()))?,
                    )
                }
                other => return Err(RequestError::UnknownField(other.to_string())),
            }
        }
        if name.is_empty() && !name_optional {
            return Err(RequestError::Missing("name"));
        }
        if var.is_empty() {
            return Err(RequestError::Missing("update_var"));
        }
        let range = range.ok_or(RequestError::Missing("alert_range"))?;
        Ok(AlertRequest {
            name,
            update_var: var,
            range,
        })
    }
}

/// The update for obstacle `key` into `out` (cleared first):
/// `name=<prefix><key>#poly=<pts, precision 5>,label=<key>[,vsource=<v>]#id=<key>`.
///
/// ```
/// use geometry::Polygon;
/// let p = Polygon::from_xy(&[(60.0, -12.0), (60.0, 6.0), (80.0, 6.0), (80.0, -12.0)]);
/// let mut s = String::new();
/// obstacle_manager::alert::update_string(&mut s, "avd_ob_", "oba", &p, "");
/// assert_eq!(s, "name=avd_ob_oba#poly=pts={60,-12:60,6:80,6:80,-12},label=oba#id=oba");
/// ```
pub fn update_string(out: &mut String, prefix: &str, key: &str, poly: &Polygon, vsource: &str) {
    out.clear();
    let _ = write!(
        out,
        "name={prefix}{key}#poly={},label={key}",
        pts_spec(poly.vertices(), 5)
    );
    if !vsource.is_empty() {
        let _ = write!(out, ",vsource={vsource}");
    }
    let _ = write!(out, "#id={key}");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn requests() {
        let r = AlertRequest::parse(" NAME=avd_ , Update_Var=OBSTACLE_ALERT , alert_range=30 ")
            .unwrap();
        assert_eq!(r.name, "avd_");
        for (s, e) in [
            (
                "name=a,update_var=V,alert_range=3,x=1",
                RequestError::UnknownField("x".into()),
            ),
            (
                "name=,update_var=V,alert_range=3",
                RequestError::Missing("name"),
            ),
            ("name=a,alert_range=3", RequestError::Missing("update_var")),
            ("name=a,update_var=V", RequestError::Missing("alert_range")),
            (
                "name=a,update_var=V,alert_range=nan",
                RequestError::BadRange("nan".into()),
            ),
            (
                "name=a,update_var",
                RequestError::NotAPair("update_var".into()),
            ),
        ] {
            assert_eq!(AlertRequest::parse(s), Err(e), "{s}");
        }
        let g = AlertRequest::parse_general("update_var=GEN_ALERT, alert_range=40000").unwrap();
        assert_eq!(g.name, "gen_alert_");
        let g = AlertRequest::parse_general("name=g,update_var=G,alert_range=4").unwrap();
        assert_eq!(g.name, "g_");
    }

    #[test]
    fn update_with_vsource() {
        let p = Polygon::from_xy(&[(60.0, -4.0), (63.0, 5.0), (70.0, 3.0), (66.0, -6.0)]);
        let mut s = String::from("old");
        update_string(&mut s, "avd_obstacles_", "pa", &p, "lidar");
        assert_eq!(
            s,
            "name=avd_obstacles_pa#poly=pts={60,-4:63,5:70,3:66,-6},label=pa,vsource=lidar#id=pa"
        );
    }
}
