//! The fleet picture's obstacle layer (issue 22): what `helm_sim::fleet::obstacles`
//! counted, drawn.

use std::fmt::Write as _;

use helm_sim::fleet::obstacles::ObstacleOutcome;

use crate::canvas::{esc, poly_points, View};
use crate::labels::{text_size, Placer, Rect};

/// The picture's obstacle layer: the region dashed, each obstacle filled grey with its
/// label and the closest any vehicle came to it (red when a collision was counted).
pub fn picture_layer(s: &mut String, v: &View, o: &ObstacleOutcome) {
    if let Some(r) = &o.region {
        let _ = writeln!(
            s,
            r##"<polygon points="{}" fill="none" stroke="#999" stroke-width="1" stroke-dasharray="6,4"/>"##,
            poly_points(v, &pts(r))
        );
    }
    for p in &o.polygons {
        let hit = o
            .pairs
            .iter()
            .any(|q| q.obstacle == p.attrs.label && q.collisions > 0);
        let (fill, stroke) = if hit {
            ("#f5b7b1", "#c0392b")
        } else {
            ("#d5d8dc", "#566573")
        };
        let _ = writeln!(
            s,
            r#"<polygon points="{}" fill="{fill}" stroke="{stroke}" stroke-width="1.5"/>"#,
            poly_points(v, &pts(p))
        );
    }
    for (px, py, text, hit) in labels(v, o) {
        let stroke = if hit { "#c0392b" } else { "#566573" };
        let _ = writeln!(
            s,
            r##"<text x="{px:.1}" y="{py:.1}" font-size="10" text-anchor="middle" fill="{stroke}">{}</text>"##,
            esc(&text)
        );
    }
}

fn pts(p: &geometry::Polygon) -> Vec<(f64, f64)> {
    p.vertices().iter().map(|q| (q.x, q.y)).collect()
}

/// Each obstacle's label and the closest any vehicle came, at its centre (screen,
/// `text-anchor="middle"`), and whether a collision was counted.
fn labels(v: &View, o: &ObstacleOutcome) -> Vec<(f64, f64, String, bool)> {
    let mut out = Vec::new();
    for p in &o.polygons {
        let label = &p.attrs.label;
        let hit = o
            .pairs
            .iter()
            .any(|q| &q.obstacle == label && q.collisions > 0);
        let ps = pts(p);
        let n = ps.len().max(1) as f64;
        let (cx, cy) = ps
            .iter()
            .fold((0.0, 0.0), |a, q| (a.0 + q.0 / n, a.1 + q.1 / n));
        let (px, py) = v.p(cx, cy);
        let closest = o
            .obstacles
            .iter()
            .find(|r| &r.label == label)
            .filter(|r| r.closest_m >= 0.0)
            .map_or(String::new(), |r| format!(" {:.1} m", r.closest_m));
        out.push((px, py, format!("{label}{closest}"), hit));
    }
    out
}

/// What the picture's other labels must not cover: the obstacles' edges and their
/// labels' boxes (estimated as [`crate::labels`] does).
pub fn keep_clear(placer: &mut Placer, v: &View, o: &ObstacleOutcome) {
    for p in &o.polygons {
        let mut ring: Vec<(f64, f64)> = pts(p).iter().map(|&(x, y)| v.p(x, y)).collect();
        ring.extend(ring.first().copied());
        placer.add_polyline(&ring);
    }
    for (px, py, text, _) in labels(v, o) {
        let (w, h) = text_size(&text, 10.0, false);
        placer.add_mark(Rect {
            x: px - w / 2.0,
            y: py - 0.75 * 10.0 - 1.5,
            w,
            h,
        });
    }
}
