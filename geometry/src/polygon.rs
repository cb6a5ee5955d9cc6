//! Convex polygons (behaviors-std.md §1.3).

use crate::angles::rel_ang;
use crate::points::{dist, dist_point_to_seg, project_point, segments_cross};
use crate::spec::{object_spec, Attrs, Vertex};

/// Which side of the line through (x1,y1)-(x2,y2) the point lies on: 0, 1, or -1 when on
/// the line, as geometry-formats.md §3.4 defines it: a degenerate edge (two equal
/// points) has every point on its line; vertical edges: right = 0, left = 1; otherwise
/// the line `y = m x + b` with `b = y2 - m x2`, above = 1, below = 0.
fn side(x1: f64, y1: f64, x2: f64, y2: f64, px: f64, py: f64) -> i8 {
    if x1 == x2 {
        return if y1 == y2 || px == x1 {
            -1
        } else if px > x1 {
            0
        } else {
            1
        };
    }
    let m = (y2 - y1) / (x2 - x1);
    let b = y2 - m * x2;
    let yl = m * px + b;
    if yl > py {
        0
    } else if yl < py {
        1
    } else {
        -1
    }
}

/// A polygon (vertex list) with its convexity determined as in the reference.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Polygon {
    pts: Vec<Vertex>,
    /// Per-vertex property texts: empty, or one per vertex (geometry-formats.md §3.3).
    props: Vec<String>,
    /// The "inside" side of each edge (-1 if the edge is not valid).
    sides: Vec<i8>,
    convex: bool,
    pub attrs: Attrs,
}

impl Polygon {
    pub fn new(pts: Vec<Vertex>) -> Self {
        let mut p = Polygon {
            pts,
            props: Vec::new(),
            sides: Vec::new(),
            convex: false,
            attrs: Attrs::default(),
        };
        p.determine_convexity();
        p
    }

    /// A polygon whose vertices carry property texts (`props` empty or one per vertex).
    pub fn with_props(pts: Vec<Vertex>, props: Vec<String>) -> Self {
        let mut p = Polygon::new(pts);
        if p.pts.len() == props.len() {
            p.props = props;
        }
        p
    }

    /// The per-vertex property texts: empty, or one per vertex.
    pub fn props(&self) -> &[String] {
        &self.props
    }

    pub fn from_xy(pts: &[(f64, f64)]) -> Self {
        Polygon::new(pts.iter().map(|&(x, y)| Vertex::new(x, y)).collect())
    }

    pub fn vertices(&self) -> &[Vertex] {
        &self.pts
    }
    pub fn size(&self) -> usize {
        self.pts.len()
    }
    pub fn is_empty(&self) -> bool {
        self.pts.is_empty()
    }
    pub fn is_convex(&self) -> bool {
        self.convex
    }
    pub fn vx(&self, i: usize) -> f64 {
        self.pts.get(i).map_or(0.0, |p| p.x)
    }
    pub fn vy(&self, i: usize) -> f64 {
        self.pts.get(i).map_or(0.0, |p| p.y)
    }

    fn determine_convexity(&mut self) {
        let n = self.pts.len();
        self.sides = vec![-1; n];
        if n < 3 {
            self.convex = false;
            return;
        }
        let mut all_valid = true;
        for i in 0..n {
            let a = self.pts[i];
            let b = self.pts[(i + 1) % n];
            let mut s: i8 = -1;
            let mut valid = true;
            for (j, p) in self.pts.iter().enumerate() {
                if j == i || j == (i + 1) % n {
                    continue;
                }
                let sj = side(a.x, a.y, b.x, b.y, p.x, p.y);
                if sj == -1 {
                    continue;
                }
                if s == -1 {
                    s = sj;
                } else if s != sj {
                    valid = false;
                }
            }
            if s == -1 || !valid {
                all_valid = false;
                self.sides[i] = -1;
            } else {
                self.sides[i] = s;
            }
        }
        self.convex = all_valid;
    }

    /// Inside test (convex polygons only; else false). Points on an edge line count.
    pub fn contains(&self, x: f64, y: f64) -> bool {
        if !self.convex {
            return false;
        }
        if self.pts.iter().any(|p| p.x == x && p.y == y) {
            return true;
        }
        let n = self.pts.len();
        for i in 0..n {
            let a = self.pts[i];
            let b = self.pts[(i + 1) % n];
            let s = side(a.x, a.y, b.x, b.y, x, y);
            if s != -1 && s != self.sides[i] {
                return false;
            }
        }
        true
    }

    /// Minimum distance from the point to any edge.
    pub fn dist_to_poly(&self, x: f64, y: f64) -> f64 {
        let n = self.pts.len();
        match n {
            0 => -1.0,
            1 => dist(self.pts[0].x, self.pts[0].y, x, y),
            2 => dist_point_to_seg(
                self.pts[0].x,
                self.pts[0].y,
                self.pts[1].x,
                self.pts[1].y,
                x,
                y,
            ),
            _ => (0..n)
                .map(|i| {
                    let a = self.pts[i];
                    let b = self.pts[(i + 1) % n];
                    dist_point_to_seg(a.x, a.y, b.x, b.y, x, y)
                })
                .fold(f64::INFINITY, f64::min),
        }
    }

    fn extremes(&self) -> (f64, f64, f64, f64) {
        let mut minx = f64::INFINITY;
        let mut maxx = f64::NEG_INFINITY;
        let mut miny = f64::INFINITY;
        let mut maxy = f64::NEG_INFINITY;
        for p in &self.pts {
            minx = minx.min(p.x);
            maxx = maxx.max(p.x);
            miny = miny.min(p.y);
            maxy = maxy.max(p.y);
        }
        (minx, maxx, miny, maxy)
    }

    /// Center of the extremes box (0,0 when empty).
    pub fn center(&self) -> (f64, f64) {
        if self.pts.is_empty() {
            return (0.0, 0.0);
        }
        let (minx, maxx, miny, maxy) = self.extremes();
        ((minx + maxx) / 2.0, (miny + maxy) / 2.0)
    }

    /// Largest vertex distance from the extremes-box center.
    pub fn max_radius(&self) -> f64 {
        let (cx, cy) = self.center();
        self.pts
            .iter()
            .map(|p| dist(cx, cy, p.x, p.y))
            .fold(0.0, f64::max)
    }

    pub fn is_clockwise(&self) -> bool {
        let n = self.pts.len();
        if n < 3 {
            return false;
        }
        let (cx, cy) = self.center();
        let mut up = 0;
        let mut down = 0;
        for i in 0..n {
            let a = self.pts[i];
            let b = self.pts[(i + 1) % n];
            if rel_ang(cx, cy, b.x, b.y) > rel_ang(cx, cy, a.x, a.y) {
                up += 1;
            } else {
                down += 1;
            }
        }
        up > down
    }

    pub fn reverse(&mut self) {
        self.pts.reverse();
        self.props.reverse();
        self.determine_convexity();
    }

    /// Shift all vertices so the extremes-box center moves to (cx, cy).
    pub fn new_center(&mut self, cx: f64, cy: f64) {
        let (ox, oy) = self.center();
        let (dx, dy) = (cx - ox, cy - oy);
        for p in &mut self.pts {
            p.x += dx;
            p.y += dy;
        }
        self.determine_convexity();
    }

    /// Move each vertex along its ray from the center by `amt` (radius at least 5).
    pub fn grow_radius(&mut self, amt: f64) {
        let (cx, cy) = self.center();
        for p in &mut self.pts {
            let r = dist(cx, cy, p.x, p.y);
            let nr = (r + amt).max(5.0);
            let (x, y) = project_point(rel_ang(cx, cy, p.x, p.y), nr, cx, cy);
            p.x = x;
            p.y = y;
        }
        self.determine_convexity();
    }

    /// Round x and y of every vertex to a multiple of `s` (never z); undone if it
    /// breaks convexity (geometry-formats.md §2.5, §3.5).
    pub fn apply_snap(&mut self, s: f64) {
        if s <= 0.0 || !s.is_finite() {
            return;
        }
        let saved = self.clone();
        for p in &mut self.pts {
            p.x = crate::points::snap(p.x, s);
            p.y = crate::points::snap(p.y, s);
        }
        self.determine_convexity();
        if saved.convex && !self.convex {
            *self = saved;
        }
    }

    /// Whether vertex `i` can be "seen" from (x, y) without crossing the polygon.
    pub fn vertex_is_viewable(&self, i: usize, x: f64, y: f64) -> bool {
        let n = self.pts.len();
        if i >= n {
            return false;
        }
        let v = self.pts[i];
        if v.x == x && v.y == y {
            return true;
        }
        if self.contains(x, y) {
            return false;
        }
        let mut count = 0;
        for k in 0..n {
            let a = self.pts[k];
            let b = self.pts[(k + 1) % n];
            if segments_cross(x, y, v.x, v.y, a.x, a.y, b.x, b.y) {
                count += 1;
            }
        }
        count <= 2
    }

    /// The polygon spec (geometry-formats.md §3.6): `pts={..}` at `precision` (only
    /// if there are vertices) then the attributes.
    pub fn spec(&self, precision: usize) -> String {
        object_spec(&self.pts, &self.props, &[], &self.attrs, precision)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> Polygon {
        Polygon::from_xy(&[(0.0, 0.0), (0.0, 10.0), (10.0, 10.0), (10.0, 0.0)])
    }

    #[test]
    fn convexity_and_contains() {
        let p = square();
        assert!(p.is_convex());
        assert!(p.contains(5.0, 5.0));
        assert!(p.contains(0.0, 5.0));
        assert!(p.contains(10.0, 10.0));
        assert!(!p.contains(11.0, 5.0));
        assert!(!p.contains(5.0, -0.1));
        let c = Polygon::from_xy(&[(0.0, 0.0), (5.0, 2.0), (10.0, 0.0), (5.0, 10.0)]);
        assert!(!c.is_convex());
        assert!(!c.contains(5.0, 5.0));
        assert!(!Polygon::from_xy(&[(0.0, 0.0), (1.0, 1.0)]).is_convex());
    }

    #[test]
    fn orientation_and_distance() {
        let mut p = square();
        assert!(p.is_clockwise());
        p.reverse();
        assert!(!p.is_clockwise());
        assert!(p.is_convex());
        assert!((p.dist_to_poly(15.0, 5.0) - 5.0).abs() < 1e-12);
        assert!((p.dist_to_poly(5.0, 4.0) - 4.0).abs() < 1e-12);
        p.new_center(100.0, 100.0);
        assert_eq!(p.center(), (100.0, 100.0));
        assert!((p.max_radius() - 50f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn snap_and_view() {
        let mut p = Polygon::from_xy(&[(0.04, 0.06), (0.0, 10.0), (10.0, 10.0), (9.96, -0.04)]);
        p.apply_snap(0.1);
        assert_eq!(p.vx(0), 0.0);
        assert!((p.vy(0) - 0.1).abs() < 1e-12);
        assert!((p.vy(3) - 0.0).abs() < 1e-12);
        let s = square();
        // From the far side vertex (10,10) is hidden behind the square.
        assert!(s.vertex_is_viewable(0, -5.0, -5.0));
        assert!(!s.vertex_is_viewable(2, -5.0, -5.0));
        assert!(!s.vertex_is_viewable(0, 5.0, 5.0));
    }
}
