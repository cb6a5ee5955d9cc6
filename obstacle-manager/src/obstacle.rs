//! One obstacle of the table, tracked points (obstacles.md §2.3) and given obstacles
//! (§2.4): reading them from mail, typed errors for what is refused.

use std::collections::VecDeque;

use geometry::{parse_polygon, pts_spec, Polygon};

/// A refused tracked point.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum PointError {
    #[error("missing or empty {0}")]
    Missing(&'static str),
    #[error("{0} is not a finite number")]
    NotFinite(&'static str),
    #[error("vsource contains white space")]
    VsourceSpace,
}

/// A refused given obstacle.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum GivenError {
    #[error("not a convex polygon")]
    NotAPolygon,
    #[error("polygon is not convex")]
    NotConvex,
    #[error("Incoming GIVEN_OBSTACLE has missing duration")]
    MissingDuration,
    #[error("Incoming GIVEN_OBSTACLE has duration exceeding max duration")]
    DurationTooLong,
    #[error("Reject given obst: already known as data obstacle")]
    KnownAsData,
}

/// One tracked point: `x=..,y=..,key=..|label=..[,vsource=..]`.
#[derive(Clone, Debug, PartialEq)]
pub struct TrackedPoint<'a> {
    pub x: f64,
    pub y: f64,
    pub key: &'a str,
    pub vsource: &'a str,
}

impl<'a> TrackedPoint<'a> {
    /// Fields are case-sensitive and trimmed; `key` or `label` names the obstacle (the
    /// later wins); other fields are ignored. x and y are read as C `atof` does, but a
    /// non-finite value is refused.
    ///
    /// ```
    /// use obstacle_manager::TrackedPoint;
    /// let p = TrackedPoint::parse("x=5,y=8,key=ob_3,vsource=lidar,color=red").unwrap();
    /// assert_eq!((p.x, p.y, p.key, p.vsource), (5.0, 8.0, "ob_3", "lidar"));
    /// assert!(TrackedPoint::parse("x=5,y=8").is_err());
    /// ```
    pub fn parse(s: &'a str) -> Result<TrackedPoint<'a>, PointError> {
        let (mut x, mut y, mut key, mut vsource) = ("", "", "", "");
        for part in s.split(',') {
            let Some((k, v)) = part.split_once('=') else {
                continue;
            };
            let v = v.trim();
            match k.trim() {
                "x" => x = v,
                "y" => y = v,
                "key" | "label" => key = v,
                "vsource" => vsource = v,
                _ => {}
            }
        }
        for (name, v) in [("x", x), ("y", y), ("key", key)] {
            if v.is_empty() {
                return Err(PointError::Missing(name));
            }
        }
        if vsource.chars().any(char::is_whitespace) {
            return Err(PointError::VsourceSpace);
        }
        let (x, y) = (mbutil::atof(x), mbutil::atof(y));
        if !x.is_finite() {
            return Err(PointError::NotFinite("x"));
        }
        if !y.is_finite() {
            return Err(PointError::NotFinite("y"));
        }
        Ok(TrackedPoint { x, y, key, vsource })
    }
}

/// A given obstacle read from its string: the convex polygon and the `duration` field
/// (−1 when absent or not a number).
#[derive(Clone, Debug, PartialEq)]
pub struct Given {
    pub poly: Polygon,
    pub duration: Option<f64>,
}

/// The value of a top-level `duration=` field (commas inside braces do not split).
fn duration_field(s: &str) -> Option<f64> {
    let mut depth = 0i32;
    let mut start = 0;
    let mut fields = Vec::new();
    for (i, c) in s.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                fields.push(&s[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    fields.push(&s[start..]);
    fields.iter().find_map(|f| {
        let (k, v) = f.split_once('=')?;
        (k.trim() == "duration")
            .then(|| mbutil::parse_number(v.trim()))
            .flatten()
            .filter(|d| d.is_finite())
    })
}

impl Given {
    /// ```
    /// use obstacle_manager::Given;
    /// let g = Given::parse("pts={0,0:9,0:0,9},label=obe,duration=20").unwrap();
    /// assert_eq!((g.poly.attrs.label.as_str(), g.duration), ("obe", Some(20.0)));
    /// assert!(Given::parse("pts={0,0:10,0:5,1:10,10:0,10},label=c").is_err());
    /// ```
    pub fn parse(s: &str) -> Result<Given, GivenError> {
        let poly = parse_polygon(s).ok_or(GivenError::NotAPolygon)?;
        if !poly.is_convex() {
            return Err(GivenError::NotConvex);
        }
        Ok(Given {
            poly,
            duration: duration_field(s),
        })
    }
}

/// How an obstacle came to be.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// From `given_obstacle` lines or `GIVEN_OBSTACLE` mail.
    Given,
    /// From tracked points (its polygon is their hull).
    Points,
}

/// One obstacle of the table.
#[derive(Clone, Debug, PartialEq)]
pub struct Obstacle {
    pub source: Source,
    /// (x, y, time), most recent first.
    pub points: VecDeque<(f64, f64, f64)>,
    /// The point limit; `None` until the first point was added.
    pub max_points: Option<usize>,
    pub poly: Polygon,
    /// Given: seconds to live from `timestamp`, < 0 none.
    pub duration: f64,
    pub timestamp: f64,
    pub changed: bool,
    pub vsource: String,
    /// Distance from ownship at the last iteration (−1 before the first).
    pub range: f64,
}

impl Obstacle {
    pub fn new(source: Source) -> Obstacle {
        Obstacle {
            source,
            points: VecDeque::new(),
            max_points: None,
            poly: Polygon::default(),
            duration: -1.0,
            timestamp: 0.0,
            changed: false,
            vsource: String::new(),
            range: -1.0,
        }
    }

    /// Replace the polygon unless it prints the same at 0.1 m with the same label;
    /// returns whether it was replaced.
    pub fn set_poly(&mut self, poly: Polygon) -> bool {
        let same = poly.attrs.label == self.poly.attrs.label
            && poly.attrs.active == self.poly.attrs.active
            && poly.size() == self.poly.size()
            && pts_spec(poly.vertices(), 1) == pts_spec(self.poly.vertices(), 1);
        if !same {
            self.poly = poly;
        }
        !same
    }

    pub fn xy(&self, out: &mut Vec<(f64, f64)>) {
        out.clear();
        out.extend(self.points.iter().map(|p| (p.0, p.1)));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points() {
        let p = TrackedPoint::parse(" x = 1.5 , y=-2 ,label=a,key=b ").unwrap();
        assert_eq!((p.x, p.y, p.key, p.vsource), (1.5, -2.0, "b", ""));
        // atof: a numeric prefix is enough, no number check.
        assert_eq!(TrackedPoint::parse("x=3m,y=abc,key=k").unwrap().x, 3.0);
        for (s, e) in [
            ("y=1,key=k", PointError::Missing("x")),
            ("x=1,y=,key=k", PointError::Missing("y")),
            ("x=1,y=1,Key=k", PointError::Missing("key")),
            ("x=1,y=1,key=k,vsource=a b", PointError::VsourceSpace),
            ("x=inf,y=1,key=k", PointError::NotFinite("x")),
        ] {
            assert_eq!(TrackedPoint::parse(s), Err(e), "{s}");
        }
    }

    #[test]
    fn given() {
        let g = Given::parse("pts={60,-12:60,6:80,6:80,-12},label=oba").unwrap();
        assert_eq!(g.duration, None);
        let g = Given::parse("pts={0,0:9,0:0,9},active=false,label=ob_1,duration=0").unwrap();
        assert_eq!((g.poly.attrs.active, g.duration), (Some(false), Some(0.0)));
        assert_eq!(
            Given::parse("pts={0,0:9,0:0,9},label=a,duration=soon")
                .unwrap()
                .duration,
            None
        );
        assert_eq!(Given::parse("nonsense"), Err(GivenError::NotAPolygon));
    }

    #[test]
    fn polygon_replaced_only_when_it_differs_at_a_decimetre() {
        let mut o = Obstacle::new(Source::Given);
        let mut p = Polygon::from_xy(&[(0.0, 0.0), (10.0, 0.0), (0.0, 10.0)]);
        p.attrs.label = "a".into();
        assert!(o.set_poly(p.clone()));
        let mut q = Polygon::from_xy(&[(0.01, 0.0), (10.0, 0.0), (0.0, 10.0)]);
        q.attrs.label = "a".into();
        assert!(!o.set_poly(q.clone()));
        q.attrs.label = "b".into();
        assert!(o.set_poly(q));
    }
}
