//! The picture of a fleet run: every vehicle's track in its colour with its start
//! (circle and name) and end (square), a dot on each track every `tick` seconds with the
//! time (so one sees where each was at the same moment), and each encounter's closest
//! approach as a line between the two vehicles with the distance. Each layer is a
//! function, so more (obstacles, COLREGS states) can be added.

use std::fmt::Write as _;

use crate::canvas::{esc, nice_length, poly_points, View, H, MARGIN, W};
use helm_sim::fleet::collide::PairRecord;
use helm_sim::fleet::run::FleetOutcome;

const CPA: &str = "#c0392b";

/// The SVG text.
pub fn svg(o: &FleetOutcome, title: &str, subtitle: &str) -> String {
    let mut all = Vec::new();
    for v in &o.vehicles {
        all.extend(v.observer.track.points());
    }
    if let Some(ob) = &o.obstacles {
        all.extend(helm_sim::fleet::obstacles::picture_points(ob));
    }
    let view = View::fit(&all);
    let mut s = String::new();
    header(&mut s, title, subtitle);
    if let Some(ob) = &o.obstacles {
        super::obstacle_layer::picture_layer(&mut s, &view, ob);
    }
    tracks(&mut s, &view, o);
    time_ticks(&mut s, &view, o);
    closest_approaches(&mut s, &view, o);
    starts_and_ends(&mut s, &view, o);
    scale_bar(&mut s, &view);
    legend(&mut s, o);
    s.push_str("</svg>\n");
    s
}

fn header(s: &mut String, title: &str, subtitle: &str) {
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" viewBox="0 0 {W} {H}" font-family="Helvetica, Arial, sans-serif">"#
    );
    let _ = writeln!(s, r##"<rect width="{W}" height="{H}" fill="#ffffff"/>"##);
    let _ = writeln!(
        s,
        r##"<text x="{MARGIN}" y="28" font-size="18" font-weight="bold" fill="#222">{}</text>"##,
        esc(title)
    );
    let _ = writeln!(
        s,
        r##"<text x="{MARGIN}" y="48" font-size="13" fill="#555">{}</text>"##,
        esc(subtitle)
    );
}

fn tracks(s: &mut String, v: &View, o: &FleetOutcome) {
    for veh in &o.vehicles {
        let pts = veh.observer.track.points();
        if pts.len() > 1 {
            let _ = writeln!(
                s,
                r#"<polyline points="{}" fill="none" stroke="{}" stroke-width="2" stroke-linejoin="round"/>"#,
                poly_points(v, &pts),
                esc(&veh.color)
            );
        }
    }
}

fn time_ticks(s: &mut String, v: &View, o: &FleetOutcome) {
    for veh in &o.vehicles {
        for &(t, x, y) in &veh.ticks {
            let (px, py) = v.p(x, y);
            let _ = writeln!(
                s,
                r##"<circle cx="{px:.1}" cy="{py:.1}" r="3" fill="#fff" stroke="{c}" stroke-width="1.5"/><text x="{:.1}" y="{:.1}" font-size="9" fill="{c}">{}</text>"##,
                px + 4.0,
                py + 10.0,
                clock(t),
                c = esc(&veh.color)
            );
        }
    }
}

/// `m:ss` of `t` seconds.
fn clock(t: f64) -> String {
    let t = t.round() as u64;
    format!("{}:{:02}", t / 60, t % 60)
}

/// The pairs worth marking: those that came within the encounter range, and the pair
/// that came closest of all.
fn marked(o: &FleetOutcome) -> Vec<&PairRecord> {
    let closest = o
        .pairs
        .iter()
        .min_by(|a, b| a.closest_m.total_cmp(&b.closest_m));
    o.pairs
        .iter()
        .filter(|p| {
            p.closest_m <= o.ranges.encounter || closest.is_some_and(|c| std::ptr::eq(c, *p))
        })
        .collect()
}

fn closest_approaches(s: &mut String, v: &View, o: &FleetOutcome) {
    for p in marked(o) {
        let (ax, ay) = v.p(p.closest_a.0, p.closest_a.1);
        let (bx, by) = v.p(p.closest_b.0, p.closest_b.1);
        let _ = writeln!(
            s,
            r#"<path d="M{ax:.1},{ay:.1} L{bx:.1},{by:.1}" stroke="{CPA}" stroke-width="1.5" stroke-dasharray="3,2"/><circle cx="{ax:.1}" cy="{ay:.1}" r="2.5" fill="{CPA}"/><circle cx="{bx:.1}" cy="{by:.1}" r="2.5" fill="{CPA}"/>"#
        );
        let (mx, my) = ((ax + bx) / 2.0, (ay + by) / 2.0);
        let _ = writeln!(
            s,
            r##"<text x="{:.1}" y="{:.1}" font-size="11" font-weight="bold" fill="{CPA}" stroke="#fff" stroke-width="3" paint-order="stroke">{:.1} m {}-{} at {}</text>"##,
            mx + 6.0,
            my - 6.0,
            p.closest_m,
            esc(&p.a),
            esc(&p.b),
            clock(p.closest_time_s)
        );
    }
}

fn starts_and_ends(s: &mut String, v: &View, o: &FleetOutcome) {
    for veh in &o.vehicles {
        let c = esc(&veh.color);
        if let Some((x, y)) = veh.observer.track.last() {
            let (px, py) = v.p(x, y);
            let _ = writeln!(
                s,
                r##"<rect x="{:.1}" y="{:.1}" width="10" height="10" fill="{c}" stroke="#fff" stroke-width="1.5"/>"##,
                px - 5.0,
                py - 5.0
            );
        }
        if let Some((x, y)) = veh.observer.track.first() {
            let (px, py) = v.p(x, y);
            let _ = writeln!(
                s,
                r##"<circle cx="{px:.1}" cy="{py:.1}" r="7" fill="none" stroke="{c}" stroke-width="3"/><text x="{:.1}" y="{:.1}" font-size="12" font-weight="bold" fill="{c}">{}</text>"##,
                px + 9.0,
                py - 9.0,
                esc(&veh.name)
            );
        }
    }
}

fn scale_bar(s: &mut String, v: &View) {
    let width_m = (W - 2.0 * MARGIN - 170.0) / v.scale;
    let len = nice_length(width_m);
    let (bx, by) = (MARGIN, H - 25.0);
    let bw = len * v.scale;
    let _ = writeln!(
        s,
        r##"<path d="M{bx},{by} h{bw:.1} M{bx},{:.1} v10 M{:.1},{:.1} v10" stroke="#222" stroke-width="2"/><text x="{:.1}" y="{:.1}" font-size="12" fill="#222">{len} m</text>"##,
        by - 5.0,
        bx + bw,
        by - 5.0,
        bx + bw + 8.0,
        by + 4.0
    );
}

fn legend(s: &mut String, o: &FleetOutcome) {
    let x = W - 200.0;
    let mut y = MARGIN + 10.0;
    for veh in &o.vehicles {
        let _ = writeln!(
            s,
            r#"<path d="M{x},{y} h22" stroke="{c}" stroke-width="3"/><text x="{:.1}" y="{:.1}" font-size="12" fill="{c}">{}</text>"#,
            x + 30.0,
            y + 4.0,
            esc(&veh.name),
            c = esc(&veh.color)
        );
        y += 18.0;
    }
    y += 6.0;
    let items = [
        ("start: circle, end: square", "#555"),
        ("dot: time m:ss on the track", "#555"),
        ("closest approach (m)", CPA),
    ];
    for (text, c) in items {
        let _ = writeln!(
            s,
            r#"<text x="{x}" y="{y:.1}" font-size="11" fill="{c}">{text}</text>"#
        );
        y += 16.0;
    }
}
