//! The picture of a fleet run: every vehicle's track in its colour with its start
//! (circle and name) and end (square), a dot on each track every `tick` seconds with the
//! time (so one sees where each was at the same moment), and each encounter's closest
//! approach as a line between the two vehicles with the distance. Each layer is a
//! function, so more (obstacles, COLREGS states) can be added.

use std::fmt::Write as _;

use crate::canvas::{esc, poly_points, scale_bar, View, H, MARGIN, W};
use crate::labels::{Placed, Placer, Rect, Style};
use helm_sim::fleet::collide::PairRecord;
use helm_sim::fleet::run::FleetOutcome;

const CPA: &str = "#c0392b";
const NAME: Style = Style {
    size: 12.0,
    bold: true,
    leader: true,
};
/// No leader: it would run along the dashed line; the colour and the pair say enough.
const CPA_TEXT: Style = Style {
    size: 11.0,
    bold: true,
    leader: false,
};
const TICK: Style = Style {
    size: 9.0,
    bold: false,
    leader: true,
};

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
    let labels = labels(&view, o);
    for l in &labels {
        if let Some((a, b)) = l.at.leader {
            let _ = writeln!(
                s,
                r#"<path d="M{:.1},{:.1} L{:.1},{:.1}" stroke="{}" stroke-width="0.8" stroke-opacity="0.7"/>"#,
                a.0,
                a.1,
                b.0,
                b.1,
                esc(&l.color)
            );
        }
    }
    for l in &labels {
        let weight = if l.style.bold {
            r#" font-weight="bold""#
        } else {
            ""
        };
        let _ = writeln!(
            s,
            r##"<text x="{:.1}" y="{:.1}" font-size="{}"{weight} fill="{}" {}>{}</text>"##,
            l.at.x,
            l.at.y,
            l.style.size,
            esc(&l.color),
            crate::canvas::halo(&l.color),
            esc(&l.text)
        );
    }
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
        for &(_, x, y) in &veh.ticks {
            let (px, py) = v.p(x, y);
            let _ = writeln!(
                s,
                r##"<circle cx="{px:.1}" cy="{py:.1}" r="3" fill="#fff" stroke="{}" stroke-width="1.5"/>"##,
                esc(&veh.color)
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
    }
}

/// A text of the picture, placed.
struct Label {
    text: String,
    style: Style,
    color: String,
    at: Placed,
}

/// The labels, placed so that they cover neither each other nor the tracks, the
/// closest-approach lines, the marks or the legend (see [`crate::labels`]): vehicle
/// names at the starts first, then the closest approaches, then the time ticks. In the
/// order to draw them (the most important last, on top).
fn labels(v: &View, o: &FleetOutcome) -> Vec<Label> {
    // Below the subtitle, above the scale bar.
    let mut placer = Placer::new(Rect {
        x: 4.0,
        y: 54.0,
        w: W - 8.0,
        h: H - 34.0 - 54.0,
    });
    let n = o.vehicles.len() as f64;
    placer.add_mark(Rect {
        x: W - 204.0,
        y: MARGIN - 2.0,
        w: 204.0,
        h: 18.0 * n + 6.0 + 3.0 * 16.0 + 4.0,
    });
    if let Some(ob) = &o.obstacles {
        super::obstacle_layer::keep_clear(&mut placer, v, ob);
    }
    let pairs = marked(o);
    for veh in &o.vehicles {
        let pts: Vec<(f64, f64)> = veh.observer.track.points();
        placer.add_polyline(&pts.iter().map(|&(x, y)| v.p(x, y)).collect::<Vec<_>>());
        for &(_, x, y) in &veh.ticks {
            let (px, py) = v.p(x, y);
            placer.add_mark(Rect::around(px, py, 3.75));
        }
        if let Some((x, y)) = veh.observer.track.first() {
            let (px, py) = v.p(x, y);
            placer.add_mark(Rect::around(px, py, 8.5));
        }
        if let Some((x, y)) = veh.observer.track.last() {
            let (px, py) = v.p(x, y);
            placer.add_mark(Rect::around(px, py, 5.75));
        }
    }
    let cpa_ends = |p: &PairRecord| {
        (
            v.p(p.closest_a.0, p.closest_a.1),
            v.p(p.closest_b.0, p.closest_b.1),
        )
    };
    for p in &pairs {
        let (a, b) = cpa_ends(p);
        placer.add_polyline(&[a, b]);
        placer.add_mark(Rect::around(a.0, a.1, 2.5));
        placer.add_mark(Rect::around(b.0, b.1, 2.5));
    }
    let mut out = Vec::new();
    let mut put = |anchor: (f64, f64), clear: f64, text: String, style: Style, color: &str| {
        let at = placer.place(anchor, clear, &text, style);
        out.push(Label {
            text,
            style,
            color: color.to_string(),
            at,
        });
    };
    for veh in &o.vehicles {
        if let Some((x, y)) = veh.observer.track.first() {
            put(v.p(x, y), 8.5, veh.name.clone(), NAME, &veh.color);
        }
    }
    for p in &pairs {
        let (a, b) = cpa_ends(p);
        let text = format!(
            "{:.1} m {}-{} at {}",
            p.closest_m,
            p.a,
            p.b,
            clock(p.closest_time_s)
        );
        put(
            ((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0),
            2.0,
            text,
            CPA_TEXT,
            CPA,
        );
    }
    for veh in &o.vehicles {
        let end = veh.observer.track.last().map(|(x, y)| v.p(x, y));
        for &(t, x, y) in &veh.ticks {
            let p = v.p(x, y);
            // A tick at the end is drawn under the end square: clear the square.
            let on_end = end.is_some_and(|e| (e.0 - p.0).hypot(e.1 - p.1) < 3.0);
            let clear = if on_end { 7.5 } else { 3.75 };
            put(p, clear, clock(t), TICK, &veh.color);
        }
    }
    out.reverse();
    out
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
                r##"<circle cx="{px:.1}" cy="{py:.1}" r="7" fill="none" stroke="{c}" stroke-width="3"/>"##
            );
        }
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use helm_sim::fleet::run::{FleetOptions, FleetPlan};

    /// missions/encounter without the avoidance plugin (so that the crate's tests need no
    /// behavior library): abe still goes north, ben goes west and then bends north-west
    /// across abe's track, as in the real encounter's picture.
    fn crossing_outcome() -> FleetOutcome {
        let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../missions/encounter");
        let dir = std::env::temp_dir().join(format!("helm-labels-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        for f in ["abe.bhv", "encounter.moos", "scenario.toml"] {
            std::fs::copy(src.join(f), dir.join(f)).expect("copy the mission");
        }
        std::fs::write(dir.join("encounter.bhv"), "initialize DEPLOY = true\n").expect("bhv");
        let ben = std::fs::read_to_string(src.join("ben.bhv")).expect("ben.bhv");
        let ben = ben.replace("points         = -150,0", "points = 30,0 : -120,70");
        assert!(ben.contains("-120,70"), "ben.bhv changed: {ben}");
        std::fs::write(dir.join("ben.bhv"), ben).expect("ben.bhv");
        let plan = FleetPlan::load(&dir.join("scenario.toml")).expect("the mission loads");
        let o = plan.run(&[], &FleetOptions::default()).expect("it runs");
        let _ = std::fs::remove_dir_all(&dir);
        o
    }

    #[test]
    fn labels_of_a_crossing_cover_neither_each_other_nor_the_tracks() {
        let o = crossing_outcome();
        assert!(
            o.vehicles.iter().all(|v| v.ticks.len() >= 5),
            "ticks to label"
        );
        let mut all = Vec::new();
        for v in &o.vehicles {
            all.extend(v.observer.track.points());
        }
        let view = View::fit(&all);
        let labels = labels(&view, &o);
        let ticks: usize = o.vehicles.iter().map(|v| v.ticks.len()).sum();
        let cpa = marked(&o).len();
        assert!(cpa >= 1, "the closest approach is marked");
        assert_eq!(labels.len(), ticks + cpa + 2, "no label dropped");
        for (i, a) in labels.iter().enumerate() {
            for b in &labels[..i] {
                assert_eq!(
                    a.at.rect.overlap(&b.at.rect),
                    0.0,
                    "{:?} and {:?} overlap",
                    a.text,
                    b.text
                );
            }
            for v in &o.vehicles {
                let pts: Vec<(f64, f64)> = v
                    .observer
                    .track
                    .points()
                    .iter()
                    .map(|&(x, y)| view.p(x, y))
                    .collect();
                for w in pts.windows(2) {
                    assert_eq!(
                        a.at.rect.clip_len(w[0], w[1]),
                        0.0,
                        "{:?} on {}'s track",
                        a.text,
                        v.name
                    );
                }
            }
        }
        // Same outcome, same bytes.
        let title = "encounter";
        assert_eq!(svg(&o, title, "x"), svg(&o, title, "x"));
        let s = svg(&o, title, "x");
        assert_eq!(s.matches(r#"paint-order="stroke""#).count(), labels.len());
    }
}
