//! LegRun's VIEW_* postings, BHV_SETTINGS and macros (behaviors-more.md §9.7, §9.8).

use std::collections::HashMap;

use behavior_api::flag::{expand_macros, has_macro};
use behavior_api::geometry::{
    dist, fmt_x, point_erase_spec, point_spec, project_point, rel_ang, seglist_erase_spec,
    seglist_spec, Attrs, Vertex,
};
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

    pub(super) fn post_steer_points(&self, ctx: &mut Ctx<'_>, track: Pt, next: Pt) {
        let own = ctx.ownship();
        let tlabel = format!("{own}'s track-point");
        let trk = if dist(track.0, track.1, next.0, next.1) > 5.0 {
            let mut a = Attrs {
                label: tlabel,
                ..Attrs::default()
            };
            self.hinted("nextpt", false, &mut a);
            point_spec(track.0, track.1, None, &a)
        } else {
            point_erase_spec(&tlabel)
        };
        ctx.post_message_key("VIEW_POINT", trk.as_str().into(), "trk");
        let mut a = Attrs {
            label: format!("{own}'s next waypoint"),
            ..Attrs::default()
        };
        self.hinted("nextpt", false, &mut a);
        let wpt = point_spec(next.0, next.1, None, &a);
        ctx.post_message_key("VIEW_POINT", wpt.as_str().into(), "wpt");
    }

    pub(super) fn erase_steer_points(&self, ctx: &mut Ctx<'_>) {
        let own = ctx.ownship();
        let trk = point_erase_spec(&format!("{own}'s track-point"));
        ctx.post_message_key("VIEW_POINT", trk.as_str().into(), "trk");
        let wpt = point_erase_spec(&format!("{own}'s next waypoint"));
        ctx.post_message_key("VIEW_POINT", wpt.as_str().into(), "wpt");
    }

    /// P1 and P2; `active` false is the reference's "erase", which posts the active
    /// spec without hints.
    pub(super) fn post_leg_points(&self, ctx: &mut Ctx<'_>, active: bool) {
        let own = ctx.ownship();
        for (i, p) in [self.leg.p1, self.leg.p2].into_iter().enumerate() {
            let Some(p) = p else { continue };
            let mut a = Attrs {
                label: format!("{own}_p{}", i + 1),
                ..Attrs::default()
            };
            if active {
                self.hinted("legpt", false, &mut a);
                if i == 0 {
                    a.vertex_size = a.vertex_size.map(|s: f64| s.trunc() * 1.5);
                }
            }
            let spec = point_spec(p.0, p.1, None, &a);
            let key = format!("p{}", i + 1);
            ctx.post_message_key("VIEW_POINT", spec.as_str().into(), &key);
        }
    }

    pub(super) fn post_turn_path(&self, ctx: &mut Ctx<'_>) {
        let mut a = Attrs {
            label: format!("{}_turn", ctx.ownship()),
            ..Attrs::default()
        };
        self.hinted("turn", true, &mut a);
        let spec = seglist_spec(&verts(&self.turn_engine.pts), 1, &a);
        ctx.post_message("VIEW_SEGLIST", &spec);
    }

    pub(super) fn erase_turn_path(&self, ctx: &mut Ctx<'_>) {
        let spec = seglist_erase_spec(&format!("{}_turn", ctx.ownship()));
        ctx.post_message("VIEW_SEGLIST", &spec);
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

    pub(super) fn erase_all(&self, ctx: &mut Ctx<'_>) {
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
