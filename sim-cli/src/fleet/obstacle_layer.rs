//! The fleet picture's obstacle layer (issue 22): what `helm_sim::fleet::obstacles`
//! counted, drawn.

use std::fmt::Write as _;

use helm_sim::fleet::obstacles::ObstacleOutcome;

use crate::canvas::{esc, poly_points, View};

/// The picture's obstacle layer: the region dashed, each obstacle filled grey with its
/// label and the closest any vehicle came to it (red when a collision was counted).
pub fn picture_layer(s: &mut String, v: &View, o: &ObstacleOutcome) {
    let pts = |p: &geometry::Polygon| -> Vec<(f64, f64)> {
        p.vertices().iter().map(|q| (q.x, q.y)).collect()
    };
    if let Some(r) = &o.region {
        let _ = writeln!(
            s,
            r##"<polygon points="{}" fill="none" stroke="#999" stroke-width="1" stroke-dasharray="6,4"/>"##,
            poly_points(v, &pts(r))
        );
    }
    for p in &o.polygons {
        let label = &p.attrs.label;
        let hit = o
            .pairs
            .iter()
            .any(|q| &q.obstacle == label && q.collisions > 0);
        let (fill, stroke) = if hit {
            ("#f5b7b1", "#c0392b")
        } else {
            ("#d5d8dc", "#566573")
        };
        let ps = pts(p);
        let _ = writeln!(
            s,
            r#"<polygon points="{}" fill="{fill}" stroke="{stroke}" stroke-width="1.5"/>"#,
            poly_points(v, &ps)
        );
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
        let _ = writeln!(
            s,
            r##"<text x="{px:.1}" y="{py:.1}" font-size="10" text-anchor="middle" fill="{stroke}">{}{}</text>"##,
            esc(label),
            closest
        );
    }
}
