//! VIEW_* postings (VIEW_POINT, VIEW_SEGLIST, VIEW_POLYGON, VIEW_CIRCLE, VIEW_MARKER)
//! read into shapes the page draws. Points, seglists and polygons go through the
//! `geometry` readers (every format a mission writes, geometry-formats.md); circles and
//! markers are `key=value` lists (`x=,y=,radius=` / `x=,y=,type=,scale=`). A shape is
//! named by its kind and label, as pMarineViewer keys them: a later posting with the
//! same label replaces it, `active=false` erases it.

use serde::Serialize;

use geometry::Attrs;

/// The VIEW_* variables this module reads.
pub const VIEW_VARS: [&str; 5] = [
    "VIEW_POINT",
    "VIEW_SEGLIST",
    "VIEW_POLYGON",
    "VIEW_CIRCLE",
    "VIEW_MARKER",
];

/// What one VIEW_* posting does to the picture.
#[derive(Clone, Debug, PartialEq)]
pub enum ViewChange {
    /// Draw (or replace) the shape under its key (boxed: a shape is large, an erase small).
    Draw(Box<Shape>),
    /// Erase the shape under this key (`active=false`).
    Erase(String),
}

/// Why a VIEW_* posting was skipped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ViewError {
    /// The geometry readers found no vertex / no position.
    Unreadable,
    /// A coordinate or size is not finite.
    NotFinite,
    /// More vertices than anyone draws ([`MAX_VERTICES`]).
    TooManyVertices,
}

/// A seglist or polygon with more vertices is skipped: nothing real posts that many,
/// and the page would stall drawing it.
pub const MAX_VERTICES: usize = 20_000;

/// A drawable shape, as sent to the page (JSON). Every text is data: the page shows it
/// with `textContent`/`setAttribute`, never as markup.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Shape {
    /// `kind:label`, the identity a later posting replaces or erases.
    pub key: String,
    /// `point`, `seglist`, `polygon`, `circle` or `marker`.
    pub kind: &'static str,
    /// Vertices (seglist, polygon) or the one position (point, circle, marker).
    pub pts: Vec<[f64; 2]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// Marker type (`circle`, `square`, `triangle`, `diamond`, ...).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub marker: Option<String>,
    pub label: String,
    /// CSS colours (`none` for invisible), `None` when the posting gave none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub label_color: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub edge_color: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub vertex_color: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fill_color: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fill_transparency: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub vertex_size: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub edge_size: Option<f64>,
    /// Marker scale (default 1).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scale: Option<f64>,
    /// `duration=` (seconds, > 0): the shape is gone that long after it was posted, as
    /// pMarineViewer draws it; none (or 0, or negative) keeps it until replaced or erased.
    #[serde(skip)]
    pub duration: Option<f64>,
}

impl Shape {
    /// Whether a shape posted at `posted` is still drawn at `t`.
    pub fn alive(&self, posted: f64, t: f64) -> bool {
        self.duration.is_none_or(|d| t < posted + d)
    }
}

/// Read one VIEW_* posting. `var` must be one of [`VIEW_VARS`].
///
/// ```
/// use viewer::view::{read_view, ViewChange};
/// let Ok(ViewChange::Draw(s)) = read_view("VIEW_POINT", "x=3,y=-4,label=home") else {
///     panic!()
/// };
/// assert_eq!((s.key.as_str(), s.pts[0]), ("point:home", [3.0, -4.0]));
/// assert_eq!(
///     read_view("VIEW_POINT", "x=0,y=0,active=false,label=home"),
///     Ok(ViewChange::Erase("point:home".into()))
/// );
/// assert!(read_view("VIEW_POLYGON", "pts={garbage").is_err());
/// ```
pub fn read_view(var: &str, value: &str) -> Result<ViewChange, ViewError> {
    let (kind, pts, attrs, extra) = match var {
        "VIEW_POINT" => {
            let p = geometry::parse_point(value).ok_or(ViewError::Unreadable)?;
            ("point", vec![[p.x, p.y]], p.attrs, Extra::default())
        }
        "VIEW_POLYGON" => {
            let p = geometry::parse_polygon(value).ok_or(ViewError::Unreadable)?;
            let pts = p.vertices().iter().map(|v| [v.x, v.y]).collect();
            ("polygon", pts, p.attrs, Extra::default())
        }
        "VIEW_SEGLIST" => {
            let s = geometry::parse_seglist(value).ok_or(ViewError::Unreadable)?;
            let pts = s.pts.iter().map(|v| [v.x, v.y]).collect();
            ("seglist", pts, s.attrs, Extra::default())
        }
        "VIEW_CIRCLE" => {
            let (pts, attrs, extra) = keyed(value, "circle")?;
            ("circle", pts, attrs, extra)
        }
        "VIEW_MARKER" => {
            let (pts, attrs, extra) = keyed(value, "marker")?;
            ("marker", pts, attrs, extra)
        }
        _ => return Err(ViewError::Unreadable),
    };
    let key = format!("{kind}:{}", attrs.label);
    if attrs.active == Some(false) {
        return Ok(ViewChange::Erase(key));
    }
    if pts.is_empty() {
        return Err(ViewError::Unreadable);
    }
    if pts.len() > MAX_VERTICES {
        return Err(ViewError::TooManyVertices);
    }
    let finite = |v: Option<f64>| v.is_none_or(f64::is_finite);
    if !pts.iter().flatten().all(|v| v.is_finite()) || !finite(extra.radius) {
        return Err(ViewError::NotFinite);
    }
    let color = |c: &str| (!c.is_empty()).then(|| css_color(c)).flatten();
    Ok(ViewChange::Draw(Box::new(Shape {
        key,
        kind,
        pts,
        radius: extra.radius,
        marker: extra.marker,
        label: attrs.label.clone(),
        label_color: color(&attrs.label_color),
        edge_color: color(&attrs.edge_color).or(extra.color.clone()),
        vertex_color: color(&attrs.vertex_color),
        fill_color: color(&attrs.fill_color).or(extra.color),
        fill_transparency: attrs.fill_transparency,
        vertex_size: attrs.vertex_size,
        edge_size: attrs.edge_size,
        scale: extra.scale,
        duration: attrs.duration.filter(|d| *d > 0.0 && d.is_finite()),
    })))
}

/// What circles and markers carry beyond the common attributes.
#[derive(Default)]
struct Extra {
    radius: Option<f64>,
    marker: Option<String>,
    scale: Option<f64>,
    color: Option<String>,
}

/// `x=..,y=..,radius=..|type=..,scale=..,color=..` plus the common attributes.
fn keyed(value: &str, kind: &str) -> Result<(Vec<[f64; 2]>, Attrs, Extra), ViewError> {
    let mut attrs = Attrs::default();
    let mut extra = Extra::default();
    let (mut x, mut y) = (None, None);
    let num = |v: &str| mbutil::parse_number(v).filter(|v| v.is_finite());
    for field in value.split(',') {
        let Some((k, v)) = field.split_once('=') else {
            continue;
        };
        let (k, v) = (k.trim().to_ascii_lowercase(), v.trim());
        match k.as_str() {
            "x" => x = num(v),
            "y" => y = num(v),
            "radius" | "rad" if kind == "circle" => extra.radius = num(v).filter(|r| *r >= 0.0),
            "type" if kind == "marker" => extra.marker = Some(v.to_owned()),
            "scale" | "width" if kind == "marker" => extra.scale = num(v).filter(|s| *s > 0.0),
            "color" | "primary_color" => extra.color = css_color(v),
            _ => {
                attrs.set(&k, v);
            }
        }
    }
    if attrs.active == Some(false) {
        return Ok((Vec::new(), attrs, extra));
    }
    let (Some(x), Some(y)) = (x, y) else {
        return Err(ViewError::Unreadable);
    };
    if kind == "circle" && extra.radius.is_none() {
        return Err(ViewError::Unreadable);
    }
    Ok((vec![[x, y]], attrs, extra))
}

/// A MOOS-IvP colour (mbutil's parser: names, `hex:`, decimal triples) as a CSS colour
/// the page can use; `none` for the invisible words; `None` when not a colour. MOOS-IvP
/// names that CSS lacks (`gray05`..`grey95`, misspellings) get their own value or, failing
/// that, reach the page as the name and the page falls back to its default.
pub fn css_color(s: &str) -> Option<String> {
    use mbutil::Color;
    match mbutil::parse_color(s)? {
        Color::Named("empty" | "off" | "invisible") => Some("none".into()),
        Color::Named(n) => {
            let grey = n
                .strip_prefix("gray")
                .or_else(|| n.strip_prefix("grey"))
                .and_then(|d| d.parse::<u8>().ok());
            Some(match grey {
                Some(p) if p <= 100 => {
                    let v = (u32::from(p) * 255 + 50) / 100;
                    format!("rgb({v},{v},{v})")
                }
                _ => n.to_owned(),
            })
        }
        Color::Rgb(r, g, b) => Some(format!(
            "rgb({},{},{})",
            (r * 255.0).round(),
            (g * 255.0).round(),
            (b * 255.0).round()
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn draw(var: &str, v: &str) -> Shape {
        match read_view(var, v) {
            Ok(ViewChange::Draw(s)) => *s,
            other => panic!("{var} {v}: {other:?}"),
        }
    }

    #[test]
    fn every_kind_reads_with_colours_and_label() {
        let p = draw(
            "VIEW_POLYGON",
            "pts={0,0:10,0:10,10},label=box,edge_color=Dark_Khaki,fill_color=hex:ff,00,80",
        );
        assert_eq!(p.key, "polygon:box");
        assert_eq!(p.pts.len(), 3);
        assert_eq!(p.edge_color.as_deref(), Some("darkkhaki"));
        // `hex:ff,00,80` cannot survive the comma-separated form: only `hex:ff` reaches
        // the colour parser, which refuses it (geometry-formats.md §3.2).
        assert_eq!(p.fill_color, None);
        let s = draw(
            "VIEW_SEGLIST",
            "pts={0,-40:60,-40},label=wpt,edge_color=gray50",
        );
        assert_eq!(s.edge_color.as_deref(), Some("rgb(128,128,128)"));
        let r = draw(
            "VIEW_POLYGON",
            "format=radial, x=5, y=5, radius=10, pts=8, label=ring",
        );
        assert_eq!(r.pts.len(), 8);
        let c = draw("VIEW_CIRCLE", "x=1,y=2,radius=30,label=c1,edge_color=off");
        assert_eq!(
            (c.radius, c.edge_color.as_deref()),
            (Some(30.0), Some("none"))
        );
        let m = draw(
            "VIEW_MARKER",
            "x=1,y=2,type=diamond,scale=2,color=red,label=m",
        );
        assert_eq!(m.marker.as_deref(), Some("diamond"));
        assert_eq!(m.fill_color.as_deref(), Some("red"));
    }

    #[test]
    fn erase_and_malformed() {
        assert_eq!(
            read_view("VIEW_POLYGON", "pts={0,0:9,0:0,9},active=false,label=box"),
            Ok(ViewChange::Erase("polygon:box".into()))
        );
        assert_eq!(
            read_view("VIEW_CIRCLE", "x=1,y=2,active=false,label=c"),
            Ok(ViewChange::Erase("circle:c".into()))
        );
        for (var, v) in [
            ("VIEW_POINT", "x=1"),
            ("VIEW_POINT", ""),
            ("VIEW_POLYGON", "label=only"),
            ("VIEW_SEGLIST", "pts={"),
            ("VIEW_CIRCLE", "x=1,y=2"),
            ("VIEW_MARKER", "y=2,type=circle"),
            ("VIEW_ELSE", "x=1,y=2"),
        ] {
            assert!(read_view(var, v).is_err(), "{var} {v}");
        }
        assert_eq!(
            read_view("VIEW_POINT", "x=1e999,y=0"),
            Err(ViewError::NotFinite)
        );
    }

    #[test]
    fn labels_are_kept_verbatim_as_data() {
        let p = draw("VIEW_POINT", "x=1,y=2,label=<script>alert(1)</script>");
        assert_eq!(p.label, "<script>alert(1)</script>");
        let json = serde_json::to_string(&p).expect("json");
        assert!(json.contains("<script>alert(1)</script>"));
    }
}
