//! Vehicles: `NODE_REPORT` / `NODE_REPORT_LOCAL` strings (contacts-appcast.md §2.2:
//! `NAME=alpha,X=0,Y=0,SPD=0,HDG=0,...`, keys case-insensitive, or the `{...}` JSON form)
//! and, for a mission without pNodeReporter (the embedded simulator, `helm sim`), the
//! ownship's `NAV_X`/`NAV_Y`/`NAV_HEADING`/`NAV_SPEED`.

use serde::Serialize;

/// One vehicle's state at one time, as sent to the page.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct VehicleState {
    pub name: String,
    /// Seconds (log-relative in a replay, MOOS time live).
    pub t: f64,
    pub x: f64,
    pub y: f64,
    /// Compass degrees (0 north, clockwise).
    pub hdg: f64,
    pub spd: f64,
    #[serde(skip_serializing_if = "String::is_empty")]
    pub vtype: String,
    /// CSS colour of the hull, empty for the page's default.
    #[serde(skip_serializing_if = "String::is_empty")]
    pub color: String,
    pub length: f64,
    #[serde(skip_serializing_if = "String::is_empty")]
    pub mode: String,
}

/// Why a node report was skipped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NodeError {
    MissingName,
    MissingPosition,
}

/// Read a node report. `t` is the posting's time (used as the sample time: the report's
/// own `TIME` is the sender's clock).
///
/// ```
/// let v = viewer::node::read_node_report("NAME=abe,X=10,Y=-5.5,SPD=1.2,HDG=90,TYPE=kayak", 3.0)
///     .unwrap();
/// assert_eq!((v.name.as_str(), v.x, v.y, v.hdg), ("abe", 10.0, -5.5, 90.0));
/// ```
pub fn read_node_report(s: &str, t: f64) -> Result<VehicleState, NodeError> {
    let mut v = VehicleState {
        name: String::new(),
        t,
        x: f64::NAN,
        y: f64::NAN,
        hdg: 0.0,
        spd: 0.0,
        vtype: String::new(),
        color: String::new(),
        length: 0.0,
        mode: String::new(),
    };
    let s = s.trim();
    let json = s.starts_with('{') && s.ends_with('}');
    let body = if json { &s[1..s.len() - 1] } else { s };
    let num = |v: &str| mbutil::parse_number(v).filter(|x| x.is_finite());
    for field in body.split(',') {
        let sep = if json { ':' } else { '=' };
        let Some((k, val)) = field.split_once(sep) else {
            continue;
        };
        let k = k.trim().trim_matches('"');
        let val = val.trim().trim_matches('"');
        // Keys are case-insensitive; compared without allocating (a log holds millions).
        let is = |name: &str| k.eq_ignore_ascii_case(name);
        if is("NAME") {
            v.name = val.to_owned();
        } else if is("X") {
            v.x = num(val).unwrap_or(f64::NAN);
        } else if is("Y") {
            v.y = num(val).unwrap_or(f64::NAN);
        } else if is("SPD") || is("SPEED") {
            v.spd = num(val).unwrap_or(0.0);
        } else if is("HDG") || is("HEADING") {
            v.hdg = num(val).unwrap_or(0.0);
        } else if is("TYPE") {
            v.vtype = val.to_owned();
        } else if is("COLOR") {
            v.color = crate::view::css_color(val).unwrap_or_default();
        } else if is("LENGTH") || is("LEN") {
            v.length = num(val).filter(|l| *l > 0.0).unwrap_or(0.0);
        } else if is("MODE") {
            v.mode = val.to_owned();
        }
    }
    if v.name.is_empty() {
        return Err(NodeError::MissingName);
    }
    if !v.x.is_finite() || !v.y.is_finite() {
        return Err(NodeError::MissingPosition);
    }
    if v.length <= 0.0 {
        v.length = default_length(&v.vtype);
    }
    Ok(v)
}

/// The default hull length of a type (contacts-appcast.md §2.2 step 5), 4 m otherwise
/// (a length only for drawing).
fn default_length(vtype: &str) -> f64 {
    match vtype.to_ascii_lowercase().as_str() {
        "auv" | "kayak" | "heron" => 3.0,
        "glider" => 2.0,
        "cray" | "bcray" | "crayx" | "bcrayx" => 1.5,
        "ship" => 12.0,
        "longship" => 15.0,
        "wamv" | "smr" => 6.0,
        _ => 4.0,
    }
}

/// Builds the ownship from `NAV_*` postings: a sample each time `NAV_X` or `NAV_Y` moves
/// once both are known.
#[derive(Clone, Debug)]
pub struct NavVehicle {
    name: String,
    x: Option<f64>,
    y: Option<f64>,
    hdg: f64,
    spd: f64,
}

impl NavVehicle {
    pub fn new(name: &str) -> NavVehicle {
        NavVehicle {
            name: name.to_owned(),
            x: None,
            y: None,
            hdg: 0.0,
            spd: 0.0,
        }
    }

    /// True for the variables this reads.
    pub fn wants(var: &str) -> bool {
        matches!(var, "NAV_X" | "NAV_Y" | "NAV_HEADING" | "NAV_SPEED")
    }

    /// Take one `NAV_*` value; a new sample when the position changed.
    pub fn apply(&mut self, var: &str, value: f64, t: f64) -> Option<VehicleState> {
        if !value.is_finite() {
            return None;
        }
        match var {
            "NAV_X" => self.x = Some(value),
            "NAV_Y" => self.y = Some(value),
            "NAV_HEADING" => self.hdg = value,
            "NAV_SPEED" => self.spd = value,
            _ => return None,
        }
        if !matches!(var, "NAV_X" | "NAV_Y") {
            return None;
        }
        Some(VehicleState {
            name: self.name.clone(),
            t,
            x: self.x?,
            y: self.y?,
            hdg: self.hdg,
            spd: self.spd,
            vtype: String::new(),
            color: String::new(),
            length: default_length(""),
            mode: String::new(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pnodereporter_line_and_json_form() {
        let v = read_node_report(
            "NAME=alpha,X=0,Y=-20,SPD=1.5,HDG=180,DEP=0,LAT=43.8,LON=-70.3,TYPE=kayak,COLOR=yellow,MODE=PARK,TIME=3590845246.47,LENGTH=4",
            1.0,
        )
        .unwrap();
        assert_eq!(
            (v.x, v.y, v.hdg, v.spd, v.length),
            (0.0, -20.0, 180.0, 1.5, 4.0)
        );
        assert_eq!((v.color.as_str(), v.mode.as_str()), ("yellow", "PARK"));
        let j = read_node_report(r#"{"NAME":"bob","X":3,"Y":4,"TYPE":"ship"}"#, 0.0).unwrap();
        assert_eq!((j.name.as_str(), j.x, j.length), ("bob", 3.0, 12.0));
        assert_eq!(
            read_node_report("X=1,Y=2", 0.0),
            Err(NodeError::MissingName)
        );
        assert_eq!(
            read_node_report("NAME=a,X=1,Y=nan", 0.0),
            Err(NodeError::MissingPosition)
        );
    }

    #[test]
    fn nav_samples_need_both_coordinates() {
        let mut n = NavVehicle::new("alpha");
        assert_eq!(n.apply("NAV_X", 1.0, 0.0), None);
        assert_eq!(n.apply("NAV_HEADING", 45.0, 0.0), None);
        let s = n.apply("NAV_Y", 2.0, 0.5).unwrap();
        assert_eq!((s.x, s.y, s.hdg, s.t), (1.0, 2.0, 45.0, 0.5));
    }
}
