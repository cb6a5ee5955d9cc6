//! LegRun's VIEW_* postings, BHV_SETTINGS and macros (behaviors-more.md §9.7, §9.8).

use std::collections::HashMap;

use behavior_api::flag::{expand_macros, has_macro};
use behavior_api::geometry::{
    dist, fmt_x, point_erase_spec, point_spec, project_point, push_point_spec, push_pts_props_spec,
    rel_ang, seglist_erase_spec, seglist_spec, Attrs, Vertex,
};
use behavior_api::push_compact;
use behavior_api::sdk::Ctx;

use super::engine::Pt;
use super::LegRun;

pub(super) fn default_hints() -> HashMap<String, String> {
    [
        ("vertex_size", "3"),
        ("edge_size", "1"),
        ("vertex_color", "dodger_blue"),
        ("edge_color", "gray60"),
        ("label_color", "off"),
        ("nextpt_vertex_size", "3"),
        ("nextpt_vertex_color", "yellow"),
        ("nextpt_label_color", "aqua"),
        ("legpt_vertex_size", "7"),
        ("legpt_vertex_color", "orange"),
        ("legpt_label_color", "off"),
        ("turn_vertex_size", "2"),
        ("turn_edge_size", "1"),
        ("turn_vertex_color", "gray70"),
        ("turn_edge_color", "gray30"),
        ("turn_label_color", "off"),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v.to_string()))
    .collect()
}

fn verts(pts: &[Pt]) -> Vec<Vertex> {
    pts.iter().map(|p| Vertex::new(p.0, p.1)).collect()
}

/// `pointAt(d)` on a path: the point `d` along it and the bearing of its edge.
fn point_at(pts: &[Pt], d: f64) -> (Pt, f64) {
    let Some(first) = pts.first() else {
        return ((0.0, 0.0), 0.0);
    };
    if d <= 0.0 || pts.len() == 1 {
        return (*first, 0.0);
    }
    let mut left = d;
    for w in pts.windows(2) {
        let len = dist(w[0].0, w[0].1, w[1].0, w[1].1);
        if left <= len {
            if left == 0.0 {
                return (w[0], 0.0);
            }
            let ang = rel_ang(w[0].0, w[0].1, w[1].0, w[1].1);
            return (project_point(ang, left, w[0].0, w[0].1), ang);
        }
        left -= len;
    }
    (*pts.last().unwrap_or(first), 0.0)
}

fn length(pts: &[Pt]) -> f64 {
    pts.windows(2)
        .map(|w| dist(w[0].0, w[0].1, w[1].0, w[1].1))
        .sum()
}

/// The texts LegRun posts every iteration, kept so that an iteration builds no string:
/// the labels and hinted attributes are made once (the ownship's name does not change)
/// and again only after `visual_hints` changes; each spec is written into `spec`.
#[derive(Default)]
pub(super) struct Texts {
    /// False until built, and again after the hints change.
    pub(super) ready: bool,
    own: String,
    trk: Attrs,
    wpt: Attrs,
    /// P1 and P2 with the `legpt` hints (P1's vertex 1.5 times as big).
    leg: [Attrs; 2],
    /// P1 and P2 with their labels only.
    leg_plain: [Attrs; 2],
    turn: Attrs,
    trk_erase: Attrs,
    wpt_erase: Attrs,
    turn_erase: Attrs,
    /// The spec being posted.
    spec: String,
    /// P1's and P2's specs, and what they were written for (the points and whether
    /// active): the leg does not move between iterations, so they are written again
    /// only when it does.
    leg_specs: [String; 2],
    leg_key: Option<([Option<Pt>; 2], bool)>,
    /// The next waypoint's spec and the point it was written for (it moves only when
    /// the engine advances).
    wpt_spec: String,
    wpt_key: Option<Pt>,
    verts: Vec<Vertex>,
}

/// The posting keys of P1 and P2.
const LEG_KEYS: [&str; 2] = ["p1", "p2"];

/// The vertices of an erased seglist (`seglist_erase_spec`).
const ERASE_SEGLIST: [Vertex; 3] = [
    Vertex {
        x: 0.0,
        y: 0.0,
        z: None,
    },
    Vertex {
        x: 9.0,
        y: 0.0,
        z: None,
    },
    Vertex {
        x: 0.0,
        y: 9.0,
        z: None,
    },
];

/// `point_erase_spec(label)` appended to `out`, `erase` being the inactive attributes
/// with the label: `x=0,y=0,active=false,label=L`.
fn push_point_erase(out: &mut String, erase: &Attrs) {
    push_point_spec(out, 0.0, 0.0, None, erase);
}

/// `seglist_spec(pts, 1, attrs)` appended to `out`.
fn push_seglist_spec(out: &mut String, pts: &[Vertex], attrs: &Attrs) {
    push_pts_props_spec(out, pts, &[], 1);
    attrs.push_spec(out);
}

impl LegRun {
    /// The hints with prefix `p` applied to attributes (`p_<attr>` first, then `<attr>`).
    fn hinted(&self, prefix: &str, seglist: bool, attrs: &mut Attrs) {
        // One key buffer for the lookups (this runs for every VIEW_* posting).
        let key = std::cell::RefCell::new(String::with_capacity(prefix.len() + 24));
        let get = |a: &str| {
            let mut k = key.borrow_mut();
            k.clear();
            k.push_str(prefix);
            k.push('_');
            k.push_str(a);
            self.hints
                .get(k.as_str())
                .or_else(|| self.hints.get(a))
                .map(|v| {
                    if v == "off" {
                        "invisible".to_string()
                    } else {
                        v.clone()
                    }
                })
        };
        if let Some(c) = get("label_color") {
            attrs.label_color = c;
        }
        if let Some(c) = get("vertex_color") {
            attrs.vertex_color = c;
        }
        if seglist {
            if let Some(c) = get("edge_color") {
                attrs.edge_color = c;
            }
            if let Some(s) = get("edge_size").and_then(|s| s.parse().ok()) {
                attrs.edge_size = Some(s);
            }
        }
        if let Some(s) = get("vertex_size").and_then(|s| s.parse().ok()) {
            attrs.vertex_size = Some(s);
        }
    }

    /// Fills the kept texts when they are not ready (first use, or the hints changed).
    fn ready_texts(&mut self, ctx: &Ctx<'_>) {
        if self.texts.ready {
            return;
        }
        let mut t = std::mem::take(&mut self.texts);
        // The ownship's name never changes: read once.
        ctx.ownship_into(&mut t.own);
        let own = t.own.as_str();
        let labelled = |label: String| Attrs {
            label,
            ..Attrs::default()
        };
        t.trk = labelled(format!("{own}'s track-point"));
        self.hinted("nextpt", false, &mut t.trk);
        t.wpt = labelled(format!("{own}'s next waypoint"));
        self.hinted("nextpt", false, &mut t.wpt);
        for (i, n) in [1, 2].into_iter().enumerate() {
            t.leg_plain[i] = labelled(format!("{own}_p{n}"));
            let mut a = t.leg_plain[i].clone();
            self.hinted("legpt", false, &mut a);
            if i == 0 {
                a.vertex_size = a.vertex_size.map(|s: f64| s.trunc() * 1.5);
            }
            t.leg[i] = a;
        }
        t.turn = labelled(format!("{own}_turn"));
        self.hinted("turn", true, &mut t.turn);
        // The erase forms: inactive, with the label only.
        let erase = |label: &str| Attrs {
            active: Some(false),
            label: label.to_string(),
            ..Attrs::default()
        };
        t.trk_erase = erase(&t.trk.label);
        t.wpt_erase = erase(&t.wpt.label);
        t.turn_erase = erase(&t.turn.label);
        // Room for the usual specs at once (a turn path of ~40 vertices).
        t.spec.reserve(1024);
        t.leg_key = None;
        t.wpt_key = None;
        t.ready = true;
        self.texts = t;
    }

    /// `LR_MODE_REPORT = vname=<own>,mode=<mode>,utc=<time>`.
    pub(super) fn post_mode_report(&mut self, ctx: &mut Ctx<'_>) {
        self.ready_texts(ctx);
        let t = &mut self.texts;
        t.spec.clear();
        t.spec.push_str("vname=");
        t.spec.push_str(&t.own);
        t.spec.push_str(",mode=");
        t.spec.push_str(self.mode.name());
        t.spec.push_str(",utc=");
        push_compact(&mut t.spec, ctx.get_buffer_curr_time(), 5);
        ctx.post_message("LR_MODE_REPORT", &t.spec);
    }

    pub(super) fn post_steer_points(&mut self, ctx: &mut Ctx<'_>, track: Pt, next: Pt) {
        self.ready_texts(ctx);
        let t = &mut self.texts;
        t.spec.clear();
        if dist(track.0, track.1, next.0, next.1) > 5.0 {
            push_point_spec(&mut t.spec, track.0, track.1, None, &t.trk);
        } else {
            push_point_erase(&mut t.spec, &t.trk_erase);
        }
        ctx.post_message_key("VIEW_POINT", t.spec.as_str().into(), "trk");
        if t.wpt_key != Some(next) {
            t.wpt_spec.clear();
            push_point_spec(&mut t.wpt_spec, next.0, next.1, None, &t.wpt);
            t.wpt_key = Some(next);
        }
        ctx.post_message_key("VIEW_POINT", t.wpt_spec.as_str().into(), "wpt");
    }

    pub(super) fn erase_steer_points(&mut self, ctx: &mut Ctx<'_>) {
        self.ready_texts(ctx);
        let t = &mut self.texts;
        for (attrs, key) in [(&t.trk_erase, "trk"), (&t.wpt_erase, "wpt")] {
            t.spec.clear();
            push_point_erase(&mut t.spec, attrs);
            ctx.post_message_key("VIEW_POINT", t.spec.as_str().into(), key);
        }
    }

    /// P1 and P2; `active` false is the reference's "erase", which posts the active
    /// spec without hints.
    pub(super) fn post_leg_points(&mut self, ctx: &mut Ctx<'_>, active: bool) {
        self.ready_texts(ctx);
        let t = &mut self.texts;
        let pts = [self.leg.p1, self.leg.p2];
        let key = Some((pts, active));
        let written = t.leg_key == key;
        let attrs = if active { &t.leg } else { &t.leg_plain };
        for (i, p) in pts.into_iter().enumerate() {
            let Some(p) = p else { continue };
            let spec = &mut t.leg_specs[i];
            if !written {
                spec.clear();
                push_point_spec(spec, p.0, p.1, None, &attrs[i]);
            }
            ctx.post_message_key("VIEW_POINT", spec.as_str().into(), LEG_KEYS[i]);
        }
        t.leg_key = key;
    }

    pub(super) fn post_turn_path(&mut self, ctx: &mut Ctx<'_>) {
        self.ready_texts(ctx);
        let t = &mut self.texts;
        t.verts.clear();
        t.verts
            .extend(self.turn_engine.pts.iter().map(|p| Vertex::new(p.0, p.1)));
        t.spec.clear();
        push_seglist_spec(&mut t.spec, &t.verts, &t.turn);
        ctx.post_message("VIEW_SEGLIST", &t.spec);
    }

    pub(super) fn erase_turn_path(&mut self, ctx: &mut Ctx<'_>) {
        self.ready_texts(ctx);
        let t = &mut self.texts;
        t.spec.clear();
        push_seglist_spec(&mut t.spec, &ERASE_SEGLIST, &t.turn_erase);
        ctx.post_message("VIEW_SEGLIST", &t.spec);
    }

    pub(super) fn post_preview(&mut self, ctx: &mut Ctx<'_>) {
        let own = ctx.ownship();
        let t1 = self.leg.turn_path(0);
        let t2 = self.leg.turn_path(1);
        let legpts: Vec<Pt> = [self.leg.p1, self.leg.p2].into_iter().flatten().collect();
        for (pts, n, hint) in [(&t1, 1, "turn"), (&t2, 2, "turn"), (&legpts, 3, "legpt")] {
            if pts.is_empty() {
                continue;
            }
            let mut a = Attrs {
                label: format!("{own}_pview{n}"),
                ..Attrs::default()
            };
            self.hinted(hint, true, &mut a);
            ctx.post_message("VIEW_SEGLIST", &seglist_spec(&verts(pts), 1, &a));
        }
        // Both markers at 42% of turn 1's length (sic: turn 2's marker too).
        let at = 0.42 * length(&t1);
        let marks = [point_at(&t1, at), point_at(&t2, at)];
        let mut changed = false;
        for (i, (p, _)) in marks.iter().enumerate() {
            let moved = self.markers[i].is_none_or(|m| dist(m.0, m.1, p.0, p.1) > 1.0);
            if moved {
                self.markers[i] = Some(*p);
                changed = true;
            }
        }
        if changed {
            for (i, (_, z)) in marks.iter().enumerate() {
                let Some(m) = self.markers[i] else { continue };
                let a = Attrs {
                    label: format!("{own}_fpt{}", i + 1),
                    label_color: "invisible".into(),
                    vertex_color: "limegreen".into(),
                    duration: Some(600.0),
                    vertex_size: Some(8.0),
                    ..Attrs::default()
                };
                ctx.post_message("VIEW_POINT", &point_spec(m.0, m.1, Some(*z), &a));
            }
        }
    }

    fn erase_preview(&self, ctx: &mut Ctx<'_>) {
        let own = ctx.ownship();
        for n in 1..=3 {
            ctx.post_message(
                "VIEW_SEGLIST",
                &seglist_erase_spec(&format!("{own}_pview{n}")),
            );
        }
        for n in 1..=2 {
            ctx.post_message("VIEW_POINT", &point_erase_spec(&format!("{own}_fpt{n}")));
        }
    }

    pub(super) fn erase_all(&mut self, ctx: &mut Ctx<'_>) {
        self.erase_turn_path(ctx);
        self.erase_steer_points(ctx);
        self.post_leg_points(ctx, false);
        self.erase_preview(ctx);
    }

    pub(super) fn post_settings(&self, ctx: &mut Ctx<'_>) {
        let e = &self.leg_engine;
        let mut s = format!(
            "type=BHV_LegRun,name={},speed={},currix={},capture_radius={},slip_radius={}",
            ctx.name(),
            fmt_x(self.speed, 1),
            e.ix,
            fmt_x(e.capture_radius, 1),
            fmt_x(e.slip_radius, 1)
        );
        if e.capture_line {
            let absolute = e.capture_radius == 0.0 && e.slip_radius == 0.0;
            s.push_str(if absolute {
                ",capture_line=absolute"
            } else {
                ",capture_line=true"
            });
        }
        s.push_str(&format!(",patience={}", fmt_x(self.patience, 2)));
        ctx.post_repeatable_message("BHV_SETTINGS", s.as_str().into());
    }

    /// The type's macros (§9.8); `$[NY]` is never expanded, as in the reference.
    pub fn expand(&self, text: &str) -> String {
        if !has_macro(text) {
            return text.to_string();
        }
        let e = &self.leg_engine;
        let f3 = |v: f64| fmt_x(v, 3);
        let cycrem = if e.max_repeats < 0 {
            u64::MAX.to_string()
        } else {
            (e.max_repeats as u64).saturating_sub(e.repeats).to_string()
        };
        let subs: Vec<(&str, String)> = vec![
            ("SPEED", f3(self.speed)),
            ("NI", e.ix.to_string()),
            ("NX", f3(e.current().map_or(0.0, |p| p.0))),
            ("CYCLES", e.repeats.to_string()),
            ("CYCREM", cycrem),
            ("WPTS_HIT", e.hits.to_string()),
            ("MODE", self.mode.name().to_string()),
            ("DIST_NP", f3(e.dist_to_next(self.os))),
            ("DIST_PP", f3(e.dist_to_prev(self.os))),
            ("PCT_NP", f3(e.pct_to_next(self.os))),
            ("LEG_ODO", f3(self.odo.total())),
            ("LEG_ID", (self.leg_count1 + self.leg_count2).to_string()),
            ("WRAPS", self.wrap.wraps.to_string()),
        ];
        expand_macros(text, &subs)
    }
}
