//! A fleet's `scenario.toml`: the `[[vehicle]]` entries, the comms model, the collision
//! ranges, pokes and end conditions.
//!
//! ```toml
//! [[vehicle]]
//! name = "abe"              # unique; the NODE_REPORT name and the contact manager's ownship
//! mission = "abe.moos"      # relative to this file; several vehicles may share one
//! bhv = ["abe-extra.bhv"]   # optional extra behavior files (per vehicle)
//! x = 0                     # optional start overrides of the mission's simulator block
//! y = -20
//! heading = 90
//! speed = 0
//! color = "dodger_blue"     # a MOOS colour (default: one of a palette)
//! type = "kayak"            # the NODE_REPORT TYPE (default: pNodeReporter's platform_type, else kayak)
//!
//! [comms]                   # uFldNodeComms' rules
//! range = 100               # m (default 100)
//! drop = 0                  # percent of reports lost (default 0)
//! latency = 0               # s (default 0: the next step)
//! seed = 1                  # of the drops (Monte Carlo adds the run's seed)
//!
//! [collision]               # uFldCollisionDetect's ranges (m)
//! encounter = 20
//! near_miss = 6
//! collision = 3
//!
//! [picture]
//! tick = 60                 # s between the time ticks on each track
//!
//! [[poke]]                  # as for one vehicle; `vehicle = "abe"` pokes one, else all
//! [end]                     # as for one vehicle; mission_over: every helm is over
//!
//! obstacle_file = "..."     # obstacles: see [`super::obstacles`] (also [[obstacle]],
//!                           # [obstacle_sim], [obstacle_collision])
//! ```
//!
//! Everything is checked before anything runs: an unknown key, a missing mission file,
//! two vehicles of one name, a negative range are errors with the file and line.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use serde::Deserialize;
use toml::Spanned;

use crate::scenario::fields::{EndDoc, Fields};
use crate::scenario::{parse_toml, read_text, Poke, ScenarioError, When};

/// Colours of vehicles that name none, in order.
pub const PALETTE: [&str; 10] = [
    "dodgerblue",
    "orangered",
    "forestgreen",
    "darkorchid",
    "goldenrod",
    "deeppink",
    "teal",
    "saddlebrown",
    "slategray",
    "olive",
];

/// One `[[vehicle]]`.
#[derive(Clone, Debug, PartialEq)]
pub struct VehicleSpec {
    pub name: String,
    pub mission: PathBuf,
    pub bhv: Vec<PathBuf>,
    pub x: Option<f64>,
    pub y: Option<f64>,
    pub heading: Option<f64>,
    pub speed: Option<f64>,
    /// An SVG colour (`#rrggbb` or a CSS name).
    pub color: String,
    /// The MOOS spelling of the colour (for NODE_REPORT COLOR).
    pub moos_color: String,
    pub vtype: Option<String>,
}

/// uFldNodeComms' rules for delivering node reports.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Comms {
    pub range: f64,
    pub drop_pct: f64,
    pub latency: f64,
    pub seed: u64,
}

impl Default for Comms {
    fn default() -> Self {
        Comms {
            range: 100.0,
            drop_pct: 0.0,
            latency: 0.0,
            seed: 1,
        }
    }
}

/// uFldCollisionDetect's ranges.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Ranges {
    pub encounter: f64,
    pub near_miss: f64,
    pub collision: f64,
}

impl Default for Ranges {
    fn default() -> Self {
        Ranges {
            encounter: 20.0,
            near_miss: 6.0,
            collision: 3.0,
        }
    }
}

/// A poke for one vehicle (`Some(index)`) or all.
#[derive(Clone, Debug, PartialEq)]
pub struct FleetPoke {
    pub poke: Poke,
    pub vehicle: Option<usize>,
}

/// A fleet scenario, read and checked.
#[derive(Clone, Debug, PartialEq)]
pub struct FleetScenario {
    pub vehicles: Vec<VehicleSpec>,
    pub comms: Comms,
    pub ranges: Ranges,
    pub tick: f64,
    pub pokes: Vec<FleetPoke>,
    pub max_time: f64,
    pub mission_over: bool,
    pub when: Vec<When>,
    pub path: PathBuf,
    /// Obstacles (issue 22; see [`super::obstacles`]).
    pub obstacles: Option<super::obstacles::ObstacleSetup>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Doc {
    vehicle: Vec<VehicleDoc>,
    comms: Option<CommsDoc>,
    collision: Option<CollisionDoc>,
    picture: Option<PictureDoc>,
    #[serde(default)]
    poke: Vec<PokeDoc>,
    end: Option<EndDoc>,
    #[serde(default)]
    obstacle: Vec<super::obstacles::ObstacleDoc>,
    obstacle_file: Option<Spanned<String>>,
    obstacle_sim: Option<std::collections::BTreeMap<String, Spanned<toml::Value>>>,
    obstacle_collision: Option<std::collections::BTreeMap<String, Spanned<toml::Value>>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct VehicleDoc {
    name: Spanned<String>,
    mission: Spanned<String>,
    #[serde(default)]
    bhv: Vec<Spanned<String>>,
    x: Option<Spanned<f64>>,
    y: Option<Spanned<f64>>,
    heading: Option<Spanned<f64>>,
    speed: Option<Spanned<f64>>,
    #[serde(alias = "colour")]
    color: Option<Spanned<String>>,
    #[serde(rename = "type")]
    vtype: Option<Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CommsDoc {
    range: Option<Spanned<f64>>,
    drop: Option<Spanned<f64>>,
    latency: Option<Spanned<f64>>,
    seed: Option<u64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CollisionDoc {
    encounter: Option<Spanned<f64>>,
    near_miss: Option<Spanned<f64>>,
    collision: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PictureDoc {
    tick: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PokeDoc {
    at: Spanned<f64>,
    var: Spanned<String>,
    value: Spanned<toml::Value>,
    vehicle: Option<Spanned<String>>,
}

/// Whether `text` is a fleet scenario (`vehicle` is an array of tables). Text that is
/// not TOML is not: the one-vehicle reader reports it.
pub fn is_fleet(text: &str) -> bool {
    text.parse::<toml::Table>()
        .ok()
        .and_then(|t| t.get("vehicle").map(toml::Value::is_array))
        .unwrap_or(false)
}

/// `s` as an SVG colour, if it is a MOOS colour.
pub fn svg_color(s: &str) -> Option<String> {
    Some(match mbutil::parse_color(s)? {
        mbutil::Color::Named(n) => n.to_string(),
        mbutil::Color::Rgb(r, g, b) => {
            let c = |v: f64| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
            format!("#{:02x}{:02x}{:02x}", c(r), c(g), c(b))
        }
    })
}

impl FleetScenario {
    pub fn read(path: &Path) -> Result<FleetScenario, ScenarioError> {
        FleetScenario::parse(&read_text(path)?, path)
    }

    /// Parse and check `text`, read from `path` (mission files are relative to it).
    pub fn parse(text: &str, path: &Path) -> Result<FleetScenario, ScenarioError> {
        let f = Fields::new(path, text);
        let bad = |span, message| f.bad(span, message);
        let doc: Doc = parse_toml(text, path)?;
        let opt =
            |v: &Option<Spanned<f64>>, what: &str, min: Option<f64>| f.opt_number(v, what, min);
        let dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
        let file = |s: &Spanned<String>, what: &str| {
            let p = dir.join(s.get_ref().trim());
            if p.is_file() {
                Ok(p)
            } else {
                Err(bad(
                    s.span(),
                    format!("{what} `{}`: no such file ({})", s.get_ref(), p.display()),
                ))
            }
        };
        if doc.vehicle.is_empty() {
            return Err(bad(0..0, "no [[vehicle]] entries".into()));
        }
        let mut names = HashSet::new();
        let mut vehicles = Vec::new();
        for (i, v) in doc.vehicle.iter().enumerate() {
            let name = v.name.get_ref().trim().to_string();
            if name.is_empty() || name.contains(|c: char| c.is_whitespace() || c == ',') {
                return Err(bad(
                    v.name.span(),
                    format!("`{name}`: a vehicle name is one word without commas"),
                ));
            }
            if !names.insert(name.to_ascii_lowercase()) {
                return Err(bad(
                    v.name.span(),
                    format!("two vehicles named `{name}` (names are compared ignoring case)"),
                ));
            }
            let (color, moos_color) = match &v.color {
                Some(c) => {
                    let svg = svg_color(c.get_ref()).ok_or_else(|| {
                        bad(c.span(), format!("`{}` is not a colour", c.get_ref()))
                    })?;
                    (svg, c.get_ref().trim().to_string())
                }
                None => {
                    let c = PALETTE[i % PALETTE.len()];
                    (c.to_string(), c.to_string())
                }
            };
            let bhv = v
                .bhv
                .iter()
                .map(|b| file(b, "behavior file"))
                .collect::<Result<Vec<_>, _>>()?;
            vehicles.push(VehicleSpec {
                name,
                mission: file(&v.mission, "mission")?,
                bhv,
                x: opt(&v.x, "x", None)?,
                y: opt(&v.y, "y", None)?,
                heading: opt(&v.heading, "heading", None)?,
                speed: opt(&v.speed, "speed", Some(0.0))?,
                color,
                moos_color,
                vtype: v.vtype.as_ref().map(|t| t.get_ref().trim().to_string()),
            });
        }
        let mut comms = Comms::default();
        if let Some(c) = &doc.comms {
            comms.range = opt(&c.range, "range", Some(0.0))?.unwrap_or(comms.range);
            comms.latency = opt(&c.latency, "latency", Some(0.0))?.unwrap_or(0.0);
            comms.drop_pct = opt(&c.drop, "drop", Some(0.0))?.unwrap_or(0.0);
            if let Some(d) = &c.drop {
                if comms.drop_pct > 100.0 {
                    return Err(bad(d.span(), "`drop` is a percentage, 0..100".into()));
                }
            }
            comms.seed = c.seed.unwrap_or(comms.seed);
        }
        let mut ranges = Ranges::default();
        if let Some(c) = &doc.collision {
            let r =
                |v, what, dflt| Ok::<_, ScenarioError>(opt(v, what, Some(0.0))?.unwrap_or(dflt));
            ranges.encounter = r(&c.encounter, "encounter", ranges.encounter)?;
            ranges.near_miss = r(&c.near_miss, "near_miss", ranges.near_miss)?;
            ranges.collision = r(&c.collision, "collision", ranges.collision)?;
            if !(ranges.collision <= ranges.near_miss && ranges.near_miss <= ranges.encounter) {
                let span = c
                    .collision
                    .as_ref()
                    .or(c.near_miss.as_ref())
                    .or(c.encounter.as_ref())
                    .map_or(0..0, |s| s.span());
                return Err(bad(
                    span,
                    "ranges must be collision <= near_miss <= encounter".into(),
                ));
            }
        }
        let tick = match doc.picture.as_ref().and_then(|p| p.tick.as_ref()) {
            Some(t) => f.seconds(t, "tick")?,
            None => 60.0,
        };
        let mut pokes = Vec::new();
        for p in &doc.poke {
            let vehicle = match &p.vehicle {
                None => None,
                Some(n) => Some(
                    vehicles
                        .iter()
                        .position(|v| v.name.eq_ignore_ascii_case(n.get_ref().trim()))
                        .ok_or_else(|| bad(n.span(), format!("no vehicle `{}`", n.get_ref())))?,
                ),
            };
            pokes.push(FleetPoke {
                poke: f.poke(&p.at, &p.var, &p.value)?,
                vehicle,
            });
        }
        pokes.sort_by(|a, b| a.poke.at.total_cmp(&b.poke.at));
        let end = f.end(doc.end.as_ref())?;
        let obstacles = super::obstacles::read_setup(
            &super::obstacles::Docs {
                obstacle: &doc.obstacle,
                obstacle_file: doc.obstacle_file.as_ref(),
                obstacle_sim: doc.obstacle_sim.as_ref(),
                obstacle_collision: doc.obstacle_collision.as_ref(),
            },
            &dir,
            &bad,
        )?;
        Ok(FleetScenario {
            obstacles,
            vehicles,
            comms,
            ranges,
            tick,
            pokes,
            max_time: end.max_time,
            mission_over: end.mission_over,
            when: end.when,
            path: path.to_path_buf(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir() -> PathBuf {
        let d = std::env::temp_dir().join(format!("fleet-spec-{}", std::process::id()));
        std::fs::create_dir_all(&d).expect("temp dir");
        std::fs::write(d.join("m.moos"), "Community = x\n").expect("write");
        d
    }

    fn parse(t: &str) -> Result<FleetScenario, ScenarioError> {
        FleetScenario::parse(t, &dir().join("scenario.toml"))
    }

    #[test]
    fn reads_vehicles_comms_and_ranges() {
        let s = parse(
            "[[vehicle]]\nname = \"abe\"\nmission = \"m.moos\"\nx = 5\ncolor = \"dodger_blue\"\n\
             [[vehicle]]\nname = \"ben\"\nmission = \"m.moos\"\n\
             [comms]\nrange = 150\ndrop = 10\n[collision]\nnear_miss = 8\n\
             [[poke]]\nat = 1\nvar = \"DEPLOY\"\nvalue = true\nvehicle = \"ben\"\n",
        )
        .expect("parses");
        assert!(is_fleet("[[vehicle]]\nname = \"a\"\n"));
        assert!(!is_fleet("[vehicle]\nx = 1\n"));
        assert_eq!(s.vehicles.len(), 2);
        assert_eq!(s.vehicles[0].color, "dodgerblue");
        assert_eq!(s.vehicles[1].color, PALETTE[1]);
        assert_eq!(s.vehicles[0].x, Some(5.0));
        assert_eq!((s.comms.range, s.comms.drop_pct), (150.0, 10.0));
        assert_eq!(s.ranges.near_miss, 8.0);
        assert_eq!(s.ranges.encounter, 20.0);
        assert_eq!(s.pokes[0].vehicle, Some(1));
    }

    #[test]
    fn bad_input_names_the_line() {
        let v = "[[vehicle]]\nname = \"abe\"\nmission = \"m.moos\"\n";
        let cases = [
            (format!("{v}speed_max = 3\n"), 4, "unknown field"),
            (
                "[[vehicle]]\nname = \"abe\"\nmission = \"nope.moos\"\n".to_string(),
                3,
                "no such file",
            ),
            (
                format!("{v}\n[[vehicle]]\nname = \"ABE\"\nmission = \"m.moos\"\n"),
                6,
                "two vehicles",
            ),
            (format!("{v}[comms]\nrange = -5\n"), 5, "range"),
            (format!("{v}[comms]\ndrop = 120\n"), 5, "percentage"),
            (format!("{v}color = \"notacolour\"\n"), 4, "colour"),
            (
                format!("{v}x = inf\n"),
                4,
                "`x = inf`: must be a finite number",
            ),
            (
                format!("{v}[collision]\ncollision = 30\n"),
                5,
                "collision <=",
            ),
        ];
        for (text, line, has) in cases {
            let e = parse(&text).expect_err(&text).to_string();
            assert!(
                e.contains(&format!("scenario.toml:{line}: ")),
                "{text:?} -> {e}"
            );
            assert!(e.contains(has), "{text:?} -> {e}");
        }
    }
}
