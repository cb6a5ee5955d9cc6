//! The parsed objects that are not polygons: a seglist and a point. The parser (the
//! `parse` module) and the format generators both make them.

use crate::polygon::Polygon;
use crate::spec::{object_spec, point_spec, Attrs, EdgeTag, Vertex};

/// A parsed seglist: vertices (with optional property texts), edge tags, attributes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Seglist {
    pub pts: Vec<Vertex>,
    /// Per-vertex property texts: empty, or one per vertex.
    pub props: Vec<String>,
    pub tags: Vec<EdgeTag>,
    pub attrs: Attrs,
}

impl Seglist {
    /// Append a vertex with its property text (usually empty).
    pub fn push(&mut self, v: Vertex, prop: &str) {
        if !prop.is_empty() && self.props.len() < self.pts.len() {
            self.props.resize(self.pts.len(), String::new());
        }
        self.pts.push(v);
        if !prop.is_empty() || !self.props.is_empty() {
            self.props.push(prop.to_string());
        }
    }

    /// Valid in the real parser's sense: a vertex, or inactive (§1).
    pub fn is_valid(&self) -> bool {
        !self.pts.is_empty() || self.attrs.active == Some(false)
    }

    /// The printed form at vertex precision `precision` (§3.6).
    pub fn spec(&self, precision: usize) -> String {
        object_spec(&self.pts, &self.props, &self.tags, &self.attrs, precision)
    }

    /// The vertices as a polygon (convexity computed), keeping properties and attributes.
    pub fn into_polygon(self) -> Polygon {
        let mut p = Polygon::with_props(self.pts, self.props);
        p.attrs = self.attrs;
        p
    }
}

/// A parsed point.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    pub x: f64,
    pub y: f64,
    /// z, only when it is not 0.
    pub z: Option<f64>,
    pub attrs: Attrs,
}

impl Point {
    /// The printed form (§3.7).
    pub fn spec(&self) -> String {
        point_spec(self.x, self.y, self.z, &self.attrs)
    }
}
