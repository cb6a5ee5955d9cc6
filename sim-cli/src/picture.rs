//! The SVG picture of a run: the track, the `VIEW_*` objects the behaviors posted
//! (waypoint paths, polygons, points, circles), start and end marks, a scale bar, a
//! legend and a title line. Plain SVG 1.1, x east, y north, equal scales.

use std::fmt::Write as _;

use super::canvas::{esc, poly_points, scale_bar, View, H, MARGIN, W};
use super::labels::{Placed, Placer, Rect, Style};
use helm_sim::observe::{Observer, ViewKind};

const TRACK: &str = "#1f6fd1";
const PATH: &str = "#e07b00";
const POLY: &str = "#8e44ad";
const POINT: &str = "#2b2b2b";
const CIRCLE: &str = "#7f8c8d";
const OTHERS: &str = "#6baed6";
const START: &str = "#1e9e46";
const END: &str = "#d62728";

/// A drawable object parsed from a `VIEW_*` spec.
enum Shape {
    Path(Vec<(f64, f64)>, String),
    Polygon(Vec<(f64, f64)>, String),
    Point(f64, f64, String),
    Circle(f64, f64, f64, String),
}

fn field(spec: &str, key: &str) -> Option<f64> {
    spec.split(',')
        .filter_map(|f| f.split_once('='))
        .find(|(k, _)| k.trim().eq_ignore_ascii_case(key))
        .and_then(|(_, v)| v.trim().parse().ok())
        .filter(|v: &f64| v.is_finite())
}

/// A posted colour of the object (`edge_color`, or `vertex_color` for a point), as SVG.
fn posted_color(spec: &str, kind: ViewKind) -> Option<String> {
    let key = if kind == ViewKind::Point {
        "vertex_color"
    } else {
        "edge_color"
    };
    spec.split(',')
        .filter_map(|f| f.split_once('='))
        .find(|(k, _)| k.trim().eq_ignore_ascii_case(key))
        .and_then(|(_, v)| helm_sim::fleet::spec::svg_color(v))
}

/// Colour of a path or polygon its behavior erased (a finished plan, still worth seeing).
const ERASED: &str = "#b8b8b8";

/// The objects to draw, each with its posted colour if any. Erased markers (points,
/// circles) are left out; erased paths and polygons are drawn in grey.
fn shapes(obs: &Observer) -> Vec<(Shape, Option<String>)> {
    let mut out = Vec::new();
    let mut colors = Vec::new();
    for ((kind, label), spec) in &obs.views {
        let erased = obs.erased.contains(&(*kind, label.clone()));
        if erased && matches!(kind, ViewKind::Point | ViewKind::Circle) {
            continue;
        }
        let color = if erased {
            Some(ERASED.to_string())
        } else {
            posted_color(spec, *kind)
        };
        let at = out.len();
        let label = label.clone();
        match kind {
            ViewKind::Seglist => {
                if let Some(s) = geometry::parse_seglist(spec) {
                    out.push(Shape::Path(
                        s.pts.iter().map(|v| (v.x, v.y)).collect(),
                        label,
                    ));
                }
            }
            ViewKind::Polygon => {
                if let Some(p) = geometry::parse_polygon(spec) {
                    let pts = p.vertices().iter().map(|v| (v.x, v.y)).collect();
                    out.push(Shape::Polygon(pts, label));
                }
            }
            ViewKind::Point => {
                if let Some(p) = geometry::parse_point(spec) {
                    out.push(Shape::Point(p.x, p.y, label));
                }
            }
            ViewKind::Circle => {
                if let (Some(x), Some(y), Some(r)) =
                    (field(spec, "x"), field(spec, "y"), field(spec, "radius"))
                {
                    out.push(Shape::Circle(x, y, r, label));
                }
            }
        }
        if out.len() > at {
            colors.push(color);
        }
    }
    out.into_iter().zip(colors).collect()
}

/// The picture, as SVG text. `title` is the first line (mission, end reason, time).
pub fn svg(obs: &Observer, title: &str, subtitle: &str) -> String {
    svg_with_tracks(obs, &[], title, subtitle)
}

/// [`svg`] with other runs' tracks drawn thin under this run's (Monte Carlo).
pub fn svg_with_tracks(
    obs: &Observer,
    others: &[Vec<(f64, f64)>],
    title: &str,
    subtitle: &str,
) -> String {
    let shapes = shapes(obs);
    let track = obs.track.points();
    let mut all: Vec<(f64, f64)> = track.clone();
    for t in others {
        all.extend(t);
    }
    for (s, _) in &shapes {
        match s {
            Shape::Path(p, _) | Shape::Polygon(p, _) => all.extend(p),
            Shape::Point(x, y, _) => all.push((*x, *y)),
            Shape::Circle(x, y, r, _) => {
                all.push((x - r, y - r));
                all.push((x + r, y + r));
            }
        }
    }
    let v = View::fit(&all);
    let mut o = String::new();
    let height = H + depth_strip_height(obs);
    let _ = writeln!(
        o,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{height}" viewBox="0 0 {W} {height}" font-family="Helvetica, Arial, sans-serif">"#
    );
    let _ = writeln!(
        o,
        r##"<rect width="{W}" height="{height}" fill="#ffffff"/>"##
    );
    let _ = writeln!(
        o,
        r##"<text x="{MARGIN}" y="28" font-size="18" font-weight="bold" fill="#222">{}</text>"##,
        esc(title)
    );
    let _ = writeln!(
        o,
        r##"<text x="{MARGIN}" y="48" font-size="13" fill="#555">{}</text>"##,
        esc(subtitle)
    );
    super::decor::grid(&mut o, &v);
    let labels = place_labels(&v, &shapes, obs);
    // Polygons and circles first (areas), then paths, then the track on top.
    for (s, c) in &shapes {
        match s {
            Shape::Polygon(p, _) => {
                let col = c.as_deref().unwrap_or(POLY);
                let _ = writeln!(
                    o,
                    r#"<polygon points="{}" fill="{col}" fill-opacity="0.08" stroke="{col}" stroke-width="1.5"/>"#,
                    poly_points(&v, p)
                );
            }
            Shape::Circle(x, y, r, _) => {
                let col = c.as_deref().unwrap_or(CIRCLE);
                let (px, py) = v.p(*x, *y);
                let _ = writeln!(
                    o,
                    r#"<circle cx="{px:.1}" cy="{py:.1}" r="{:.1}" fill="none" stroke="{col}" stroke-width="1.2" stroke-dasharray="3,3"/>"#,
                    r * v.scale
                );
            }
            _ => {}
        }
    }
    for (s, c) in &shapes {
        if let Shape::Path(p, _) = s {
            let path_color = c.as_deref().unwrap_or(PATH);
            let _ = writeln!(
                o,
                r#"<polyline points="{}" fill="none" stroke="{path_color}" stroke-width="1.5" stroke-dasharray="6,4"/>"#,
                poly_points(&v, p)
            );
            for &(x, y) in p {
                let (px, py) = v.p(x, y);
                let _ = writeln!(
                    o,
                    r##"<circle cx="{px:.1}" cy="{py:.1}" r="5" fill="#fff" stroke="{path_color}" stroke-width="2"/>"##
                );
            }
        }
    }
    // Thinned so that a thousand runs stay well under 1 MB of SVG.
    let keep = (40_000 / others.len().max(1)).clamp(8, 400);
    for t in others.iter().filter(|t| t.len() > 1) {
        let _ = writeln!(
            o,
            r#"<polyline points="{}" fill="none" stroke="{OTHERS}" stroke-opacity="0.25" stroke-width="0.8"/>"#,
            poly_points(&v, &super::decor::thin(t, keep))
        );
    }
    super::decor::clouds(&mut o, &v, others, START, END);
    if track.len() > 1 {
        let _ = writeln!(
            o,
            r#"<polyline points="{}" fill="none" stroke="{TRACK}" stroke-width="2.2" stroke-linejoin="round"/>"#,
            poly_points(&v, &track)
        );
    }
    for (s, c) in &shapes {
        if let Shape::Point(x, y, _) = s {
            let col = c.as_deref().unwrap_or(POINT);
            let (px, py) = v.p(*x, *y);
            let _ = writeln!(
                o,
                r#"<path d="M{:.1},{py:.1} L{px:.1},{:.1} L{:.1},{py:.1} L{px:.1},{:.1} Z" fill="{col}"/>"#,
                px - 4.0,
                py - 4.0,
                px + 4.0,
                py + 4.0
            );
        }
    }
    if let Some((x, y)) = obs.track.last() {
        let (px, py) = v.p(x, y);
        let _ = writeln!(
            o,
            r##"<rect x="{:.1}" y="{:.1}" width="12" height="12" fill="{END}" stroke="#fff" stroke-width="1.5"/>"##,
            px - 6.0,
            py - 6.0
        );
    }
    if let Some((x, y)) = obs.track.first() {
        let (px, py) = v.p(x, y);
        let _ = writeln!(
            o,
            r##"<circle cx="{px:.1}" cy="{py:.1}" r="9" fill="none" stroke="{START}" stroke-width="3"/>"##
        );
    }
    if let (Some((h0, h1)), Some(a), Some(b)) = (obs.headings, obs.track.first(), obs.track.last())
    {
        super::decor::heading_arrow(&mut o, &v, a, h0, START);
        super::decor::heading_arrow(&mut o, &v, b, h1, END);
    }
    // On top of everything, each with a white halo.
    for (at, text, color) in &labels {
        if let Some((a, b)) = at.leader {
            let _ = writeln!(
                o,
                r#"<path d="M{:.1},{:.1} L{:.1},{:.1}" stroke="{color}" stroke-width="0.8" stroke-opacity="0.7"/>"#,
                a.0, a.1, b.0, b.1
            );
        }
        let _ = writeln!(
            o,
            r##"<text x="{:.1}" y="{:.1}" font-size="11" fill="{color}" {}>{}</text>"##,
            at.x,
            at.y,
            super::canvas::halo(color),
            esc(text)
        );
    }
    scale_bar(&mut o, &v);
    let erased = shapes.iter().any(|(_, c)| c.as_deref() == Some(ERASED));
    let only: Vec<Shape> = shapes.into_iter().map(|(s, _)| s).collect();
    legend(&mut o, &only, !others.is_empty(), erased);
    if obs.depth.enabled {
        crate::depth_strip::draw(&mut o, &obs.depth, H, W);
    }
    o.push_str("</svg>\n");
    o
}

/// The objects' labels and the waypoint numbers (1, 2, …), placed by
/// [`crate::labels`] off each other and off the track, the paths, the polygon and circle
/// edges, the marks (waypoints, points, start, end, origin) and the heading arrows,
/// inside the grid area. Object labels first, then waypoint numbers; each with its
/// colour.
fn place_labels(
    v: &View,
    shapes: &[(Shape, Option<String>)],
    obs: &Observer,
) -> Vec<(Placed, String, String)> {
    const STYLE: Style = Style {
        size: 11.0,
        bold: false,
        leader: true,
    };
    let mut placer = Placer::new(Rect {
        x: MARGIN,
        y: MARGIN,
        w: W - 2.0 * MARGIN - 170.0,
        h: H - 2.0 * MARGIN,
    });
    let screen = |pts: &[(f64, f64)]| pts.iter().map(|&(x, y)| v.p(x, y)).collect::<Vec<_>>();
    placer.add_polyline(&screen(&obs.track.points()));
    for (s, _) in shapes {
        match s {
            Shape::Path(p, _) => {
                placer.add_polyline(&screen(p));
                for &(px, py) in &screen(p) {
                    placer.add_mark(Rect::around(px, py, 6.0));
                }
            }
            Shape::Polygon(p, _) => {
                let mut ring = screen(p);
                ring.extend(ring.first().copied());
                placer.add_polyline(&ring);
            }
            Shape::Point(x, y, _) => {
                let (px, py) = v.p(*x, *y);
                placer.add_mark(Rect::around(px, py, 4.5));
            }
            Shape::Circle(x, y, r, _) => {
                let ring: Vec<(f64, f64)> = (0..=24)
                    .map(|i| {
                        let a = i as f64 * std::f64::consts::TAU / 24.0;
                        v.p(x + r * a.cos(), y + r * a.sin())
                    })
                    .collect();
                placer.add_polyline(&ring);
            }
        }
    }
    let (ox, oy) = v.p(0.0, 0.0);
    // The origin's cross and its "0,0" (see decor::grid).
    placer.add_mark(Rect {
        x: ox - 7.0,
        y: oy - 7.0,
        w: 28.0,
        h: 20.0,
    });
    let ends = [
        (obs.track.first(), 10.5, obs.headings.map(|h| h.0)),
        (obs.track.last(), 6.75, obs.headings.map(|h| h.1)),
    ];
    for (at, r, heading) in ends {
        if let Some((x, y)) = at {
            let (px, py) = v.p(x, y);
            placer.add_mark(Rect::around(px, py, r));
            if let Some(h) = heading {
                let h = h.to_radians();
                placer.add_polyline(&[(px, py), (px + 24.0 * h.sin(), py - 24.0 * h.cos())]);
            }
        }
    }
    let mut out = Vec::new();
    let mut put = |(x, y): (f64, f64), clear: f64, text: String, color: &str| {
        if !text.is_empty() {
            let at = placer.place(v.p(x, y), clear, &text, STYLE);
            out.push((at, text, color.to_string()));
        }
    };
    for (s, c) in shapes {
        match s {
            Shape::Polygon(p, label) => {
                if let Some(&first) = p.first() {
                    put(first, 2.0, label.clone(), c.as_deref().unwrap_or(POLY));
                }
            }
            Shape::Circle(x, y, r, label) => {
                put(
                    (*x, y + r),
                    2.0,
                    label.clone(),
                    c.as_deref().unwrap_or(CIRCLE),
                );
            }
            Shape::Path(p, label) => {
                if let Some(&first) = p.first() {
                    put(first, 6.0, label.clone(), c.as_deref().unwrap_or(PATH));
                }
            }
            Shape::Point(x, y, label) => {
                put((*x, *y), 4.5, label.clone(), c.as_deref().unwrap_or(POINT));
            }
        }
    }
    for (s, c) in shapes {
        if let Shape::Path(p, _) = s {
            for (i, &q) in p.iter().enumerate() {
                put(q, 6.0, (i + 1).to_string(), c.as_deref().unwrap_or(PATH));
            }
        }
    }
    out
}

/// Extra height under the map for the depth strip (0 without depth in the domain).
fn depth_strip_height(obs: &Observer) -> f64 {
    if obs.depth.enabled {
        crate::depth_strip::STRIP_H
    } else {
        0.0
    }
}

/// `erased`: some shape is drawn grey because its behavior erased it (say so, or a
/// reader matches the grey plan to the coloured legend entry and is misled).
fn legend(o: &mut String, shapes: &[Shape], others: bool, erased: bool) {
    let x = W - 200.0;
    let top = MARGIN + 10.0;
    let has = |f: fn(&Shape) -> bool| shapes.iter().any(f);
    type Sym = fn(f64, f64) -> String;
    let mut items: Vec<(Sym, &str)> = vec![
        (
            |x, y| format!(r#"<path d="M{x},{y} h22" stroke="{TRACK}" stroke-width="2.2"/>"#),
            "vehicle track",
        ),
        (
            |x, y| {
                format!(
                    r#"<circle cx="{:.0}" cy="{y}" r="6" fill="{START}"/>"#,
                    x + 11.0
                )
            },
            "start (ring)",
        ),
        (
            |x, y| {
                format!(
                    r#"<rect x="{:.0}" y="{:.0}" width="12" height="12" fill="{END}"/>"#,
                    x + 5.0,
                    y - 6.0
                )
            },
            "end",
        ),
    ];
    if others {
        items[0].1 = "track, unperturbed run";
        items.push((
            |x, y| format!(r#"<path d="M{x},{y} h22" stroke="{OTHERS}" stroke-width="1.5"/>"#),
            "tracks, perturbed runs",
        ));
    }
    if has(|s| matches!(s, Shape::Path(..))) {
        items.push((
            |x, y| {
                format!(
                    r#"<path d="M{x},{y} h22" stroke="{PATH}" stroke-width="1.5" stroke-dasharray="6,4"/>"#
                )
            },
            "waypoints (VIEW_SEGLIST)",
        ));
    }
    if erased {
        items.push((
            |x, y| {
                format!(
                    r#"<path d="M{x},{y} h22" stroke="{ERASED}" stroke-width="1.5" stroke-dasharray="6,4"/>"#
                )
            },
            "erased by its behavior",
        ));
    }
    if has(|s| matches!(s, Shape::Polygon(..))) {
        items.push((
            |x, y| {
                format!(
                    r#"<rect x="{x}" y="{:.0}" width="22" height="12" fill="{POLY}" fill-opacity="0.1" stroke="{POLY}"/>"#,
                    y - 6.0
                )
            },
            "polygon (VIEW_POLYGON)",
        ));
    }
    if has(|s| matches!(s, Shape::Point(..))) {
        items.push((
            |x, y| {
                format!(
                    r#"<circle cx="{:.0}" cy="{y}" r="4" fill="{POINT}"/>"#,
                    x + 11.0
                )
            },
            "point (VIEW_POINT)",
        ));
    }
    if has(|s| matches!(s, Shape::Circle(..))) {
        items.push((
            |x, y| {
                format!(
                    r#"<circle cx="{:.0}" cy="{y}" r="6" fill="none" stroke="{CIRCLE}" stroke-dasharray="3,3"/>"#,
                    x + 11.0
                )
            },
            "circle (VIEW_CIRCLE)",
        ));
    }
    let _ = writeln!(
        o,
        r##"<rect x="{:.0}" y="{:.0}" width="185" height="{}" fill="#fafafa" stroke="#ccc"/>"##,
        x - 10.0,
        top - 18.0,
        22.0 * items.len() as f64 + 14.0
    );
    for (i, (sym, text)) in items.iter().enumerate() {
        let y = top + 22.0 * i as f64;
        let _ = writeln!(
            o,
            r##"{}<text x="{:.0}" y="{:.0}" font-size="12" fill="#222">{text}</text>"##,
            sym(x, y),
            x + 30.0,
            y + 4.0
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use helm_engine::posting::Value;

    #[test]
    fn draws_every_kind_and_the_track() {
        let mut o = Observer::new(0.0, Vec::new());
        let s = |v: &str| Value::Str(v.into());
        o.on_posting(
            "VIEW_SEGLIST",
            &s("pts={0,0:100,0:100,-50},label=survey"),
            1.0,
        );
        o.on_posting(
            "VIEW_POLYGON",
            &s("pts={10,10:20,10:20,20},label=zone"),
            1.0,
        );
        o.on_posting("VIEW_POINT", &s("x=5,y=5,label=next"), 1.0);
        o.on_posting("VIEW_CIRCLE", &s("x=50,y=-20,radius=10,label=station"), 1.0);
        for i in 0..10 {
            o.track.push(i as f64 * 10.0, 0.0);
        }
        let svg = svg(&o, "t & <title>", "sub");
        for has in [
            "<polyline",
            "<polygon",
            "station",
            "zone",
            "survey",
            "20 m</text>",
            "t &amp; &lt;title&gt;",
            "VIEW_CIRCLE",
        ] {
            assert!(svg.contains(has), "{has} missing");
        }
        assert!(svg.ends_with("</svg>\n"));
    }

    #[test]
    fn erased_not_drawn_colours_grid_arrows() {
        let mut o = Observer::new(0.0, Vec::new());
        let s = |v: &str| Value::Str(v.into());
        o.on_posting("VIEW_POINT", &s("x=5,y=5,label=gone"), 1.0);
        o.on_posting("VIEW_POINT", &s("x=5,y=5,active=false,label=gone"), 2.0);
        o.on_posting(
            "VIEW_POLYGON",
            &s("pts={10,10:20,10:20,20},label=zone,edge_color=dodger_blue"),
            1.0,
        );
        o.on_posting("VIEW_SEGLIST", &s("pts={0,0:9,9},label=done"), 1.0);
        o.on_posting(
            "VIEW_SEGLIST",
            &s("pts={0,0:9,9},active=false,label=done"),
            2.0,
        );
        for i in 0..10 {
            o.track.push(i as f64 * 10.0, 0.0);
        }
        o.headings = Some((90.0, 180.0));
        let svg = svg(&o, "t", "sub");
        assert!(!svg.contains(">gone<"), "an erased marker is not drawn");
        assert!(svg.contains(r#"stroke="dodgerblue""#), "the posted colour");
        assert!(
            svg.contains(&format!(r#"stroke="{ERASED}""#)),
            "a finished path, grey"
        );
        assert!(
            svg.contains("erased by its behavior"),
            "the legend says what grey means"
        );
        assert!(svg.contains(">0,0</text>"), "the origin");
        assert!(
            svg.contains(r#"text-anchor="middle">40</text>"#),
            "metre labels"
        );
        // The start arrow points east (+x on screen), the end arrow south (+y).
        assert!(svg.matches("Z\" fill=").count() >= 2, "two arrow heads");
    }

    #[test]
    fn a_thousand_runs_stay_under_a_megabyte() {
        let mut o = Observer::new(0.0, Vec::new());
        for i in 0..2000 {
            o.track.push(i as f64 * 0.3, (i as f64 * 0.01).sin() * 50.0);
        }
        let tracks: Vec<Vec<(f64, f64)>> = (0..1000)
            .map(|r| {
                (0..400)
                    .map(|i| {
                        (
                            i as f64 * 1.5 + r as f64 * 0.01,
                            (i as f64 * 0.02).cos() * 40.0,
                        )
                    })
                    .collect()
            })
            .collect();
        let svg = svg_with_tracks(&o, &tracks, "t", "s");
        assert!(svg.len() < 1_000_000, "{} bytes", svg.len());
        assert!(
            svg.matches("fill-opacity=\"0.45\"").count() >= 2000,
            "start and end clouds"
        );
    }

    /// alpha's case: a path (with its label and numbers) starting where the track
    /// starts and ends, at the origin. No label covers another, the start ring or the
    /// track, and every one is drawn with its halo.
    #[test]
    fn labels_clear_the_start_the_track_and_each_other() {
        let mut o = Observer::new(0.0, Vec::new());
        let s = |v: &str| Value::Str(v.into());
        o.on_posting(
            "VIEW_SEGLIST",
            &s("pts={0,0:60,-20:60,-140:150,-140},label=waypt_survey"),
            1.0,
        );
        o.on_posting("VIEW_POINT", &s("x=1,y=1,label=return_point"), 1.0);
        for i in 0..=60 {
            o.track.push(i as f64, -i as f64 / 3.0);
        }
        for i in 0..=120 {
            o.track.push(60.0, -20.0 - i as f64);
        }
        o.headings = Some((0.0, 90.0));
        let shapes = shapes(&o);
        let v = View::fit(&[(0.0, 0.0), (150.0, -140.0)]);
        let labels = place_labels(&v, &shapes, &o);
        assert_eq!(labels.len(), 2 + 4, "two labels, four waypoint numbers");
        let (sx, sy) = v.p(0.0, 0.0);
        let ring = Rect::around(sx, sy, 10.5);
        let track: Vec<(f64, f64)> = o.track.points().iter().map(|&(x, y)| v.p(x, y)).collect();
        for (i, (a, text, _)) in labels.iter().enumerate() {
            assert_eq!(a.rect.overlap(&ring), 0.0, "{text} on the start");
            for w in track.windows(2) {
                assert_eq!(a.rect.clip_len(w[0], w[1]), 0.0, "{text} on the track");
            }
            for (b, other, _) in &labels[..i] {
                assert_eq!(a.rect.overlap(&b.rect), 0.0, "{text} on {other}");
            }
        }
        let svg = svg(&o, "t", "s");
        assert_eq!(svg.matches(r#"paint-order="stroke""#).count(), labels.len());
    }
}
