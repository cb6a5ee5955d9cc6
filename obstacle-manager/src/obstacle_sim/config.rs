//! uFldObstacleSim's configuration block (obstacles.md §3.1) and its obstacle styling.

use geometry::Polygon;

/// Most sensor points per obstacle, vehicle and step (the reference has no limit).
pub const MAX_RATE_POINTS: f64 = 1000.0;

/// A refused configuration line.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum SimConfigError {
    #[error("unknown parameter: {0}")]
    Unknown(String),
    #[error("{param}: not a colour: {value}")]
    BadColor { param: String, value: String },
    #[error("{param}: not a boolean (true/false): {value}")]
    BadBool { param: String, value: String },
    #[error("{param}: not a number {rule}: {value}")]
    BadNumber {
        param: String,
        value: String,
        rule: &'static str,
    },
}

/// The configuration; defaults are uFldObstacleSim's.
#[derive(Clone, Debug, PartialEq)]
pub struct SimConfig {
    pub obstacle_file: Option<String>,
    pub poly_vert_color: String,
    pub poly_fill_color: String,
    pub poly_edge_color: String,
    pub poly_label_color: String,
    pub poly_vert_size: f64,
    pub poly_edge_size: f64,
    pub poly_transparency: f64,
    pub draw_region: bool,
    pub region_edge_color: String,
    pub region_vert_color: String,
    pub post_points: bool,
    pub rate_points: f64,
    pub point_size: f64,
    pub sensor_range: f64,
    pub min_duration: f64,
    pub max_duration: f64,
    pub refresh_interval: f64,
    pub reset_interval: f64,
    pub reset_range: f64,
    pub reuse_ids: bool,
    pub post_visuals: bool,
}

impl Default for SimConfig {
    fn default() -> Self {
        SimConfig {
            obstacle_file: None,
            poly_vert_color: "gray50".into(),
            poly_fill_color: "white".into(),
            poly_edge_color: "gray50".into(),
            poly_label_color: "invisible".into(),
            poly_vert_size: 1.0,
            poly_edge_size: 1.0,
            poly_transparency: 0.15,
            draw_region: true,
            region_edge_color: "gray50".into(),
            region_vert_color: "white".into(),
            post_points: false,
            rate_points: 5.0,
            point_size: 2.0,
            sensor_range: 50.0,
            min_duration: -1.0,
            max_duration: -1.0,
            refresh_interval: -1.0,
            reset_interval: -1.0,
            reset_range: 10.0,
            reuse_ids: true,
            post_visuals: true,
        }
    }
}

fn color(param: &str, v: &str) -> Result<String, SimConfigError> {
    if !mbutil::is_color(v) {
        return Err(SimConfigError::BadColor {
            param: param.into(),
            value: v.into(),
        });
    }
    // The three spellings of "invisible" print as `invisible`.
    Ok(match v.to_ascii_lowercase().as_str() {
        "invisible" | "empty" | "off" => "invisible".into(),
        _ => v.to_string(),
    })
}

fn number(param: &str, v: &str, nonneg: bool) -> Result<f64, SimConfigError> {
    mbutil::parse_number(v)
        .filter(|n| n.is_finite() && (!nonneg || *n >= 0.0))
        .ok_or_else(|| SimConfigError::BadNumber {
            param: param.into(),
            value: v.into(),
            rule: if nonneg { ">= 0" } else { "(finite)" },
        })
}

fn boolean(param: &str, v: &str) -> Result<bool, SimConfigError> {
    match v.to_ascii_lowercase().as_str() {
        "true" => Ok(true),
        "false" => Ok(false),
        _ => Err(SimConfigError::BadBool {
            param: param.into(),
            value: v.into(),
        }),
    }
}

impl SimConfig {
    /// Apply one block line (names in any case). A refused line changes nothing.
    pub fn set(&mut self, param: &str, value: &str) -> Result<(), SimConfigError> {
        let p = param.trim().to_ascii_lowercase();
        let v = value.trim();
        match p.as_str() {
            "obstacle_file" => self.obstacle_file = Some(v.to_string()),
            "poly_vert_color" => self.poly_vert_color = color(&p, v)?,
            "poly_fill_color" => self.poly_fill_color = color(&p, v)?,
            "poly_edge_color" => self.poly_edge_color = color(&p, v)?,
            "poly_label_color" => self.poly_label_color = color(&p, v)?,
            "region_edge_color" => self.region_edge_color = color(&p, v)?,
            "region_vert_color" => self.region_vert_color = color(&p, v)?,
            "poly_vert_size" => self.poly_vert_size = number(&p, v, true)?,
            "poly_edge_size" => self.poly_edge_size = number(&p, v, true)?,
            "poly_transparency" => self.poly_transparency = number(&p, v, true)?,
            // Capped: the points are drawn in a loop per obstacle per vehicle per step.
            "rate_points" => self.rate_points = number(&p, v, true)?.min(MAX_RATE_POINTS),
            "point_size" => self.point_size = number(&p, v, true)?,
            "sensor_range" => self.sensor_range = number(&p, v, true)?,
            "refresh_interval" => self.refresh_interval = number(&p, v, true)?,
            "reset_interval" => self.reset_interval = number(&p, v, true)?,
            "reset_range" => self.reset_range = number(&p, v, true)?,
            "draw_region" => self.draw_region = boolean(&p, v)?,
            "post_points" => self.post_points = boolean(&p, v)?,
            "reuse_ids" => self.reuse_ids = boolean(&p, v)?,
            "post_visuals" => self.post_visuals = boolean(&p, v)?,
            "min_duration" => {
                self.min_duration = number(&p, v, false)?;
                if self.min_duration > self.max_duration {
                    self.max_duration = self.min_duration;
                }
            }
            "max_duration" => {
                self.max_duration = number(&p, v, false)?;
                if self.max_duration < self.min_duration {
                    self.min_duration = self.max_duration;
                }
                if self.min_duration < 0.0 && self.max_duration >= 0.0 {
                    self.min_duration = 0.0;
                }
            }
            _ => return Err(SimConfigError::Unknown(p)),
        }
        Ok(())
    }

    /// An obstacle as the simulator draws it (§3.2).
    pub fn style_obstacle(&self, p: &Polygon) -> Polygon {
        let mut o = p.clone();
        let a = &mut o.attrs;
        a.edge_color.clone_from(&self.poly_edge_color);
        a.vertex_color.clone_from(&self.poly_vert_color);
        a.fill_color.clone_from(&self.poly_fill_color);
        a.label_color.clone_from(&self.poly_label_color);
        a.vertex_size = Some(self.poly_vert_size);
        a.edge_size = Some(self.poly_edge_size);
        a.fill_transparency = Some(self.poly_transparency);
        o
    }

    /// The region as the simulator draws it.
    pub fn style_region(&self, p: &Polygon) -> Polygon {
        let mut r = p.clone();
        r.attrs.label = "obs_region".into();
        r.attrs.edge_color.clone_from(&self.region_edge_color);
        r.attrs.vertex_color.clone_from(&self.region_vert_color);
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn m34_block_and_durations() {
        let mut c = SimConfig::default();
        for (p, v) in [
            ("obstacle_file", "obstacles.txt"),
            ("draw_region", "true"),
            ("region_edge_color", "gray50"),
            ("poly_fill_color", "invisible"),
            ("poly_vert_color", "green"),
            ("poly_edge_color", "white"),
            ("poly_vert_size", "2"),
            ("poly_edge_size", "2"),
            ("min_duration", "400"),
            ("max_duration", "500"),
            ("refresh_interval", "200"),
            ("post_points", "false"),
            ("point_size", "4"),
            ("reuse_ids", "false"),
        ] {
            c.set(p, v).unwrap_or_else(|e| panic!("{p}: {e}"));
        }
        assert_eq!((c.min_duration, c.max_duration), (400.0, 500.0));
        let mut d = SimConfig::default();
        d.set("max_duration", "50").unwrap();
        assert_eq!((d.min_duration, d.max_duration), (0.0, 50.0));
        d.set("min_duration", "80").unwrap();
        assert_eq!((d.min_duration, d.max_duration), (80.0, 80.0));
        assert!(d.set("poly_vert_color", "nocolour").is_err());
        assert!(d.set("colour", "red").is_err());
    }

    #[test]
    fn styled_as_the_reference_posts() {
        let c = SimConfig::default();
        let mut p = Polygon::from_xy(&[(0.0, 0.0), (0.0, 10.0), (10.0, 10.0)]);
        p.attrs.label = "ob_0".into();
        assert_eq!(
            c.style_obstacle(&p).spec(2),
            "pts={0,0:0,10:10,10},label=ob_0,label_color=invisible,edge_color=gray50,vertex_color=gray50,fill_color=white,vertex_size=1,edge_size=1,fill_transparency=0.15"
        );
        assert_eq!(
            c.style_region(&p).spec(1),
            "pts={0,0:0,10:10,10},label=obs_region,edge_color=gray50,vertex_color=white"
        );
    }
}
