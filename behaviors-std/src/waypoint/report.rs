//! BHV_Waypoint's status postings and visuals (behaviors-std.md §2.5): WPT_STAT,
//! WPT_INDEX, the distances, and the path, next point and track point views.

use behavior_api::push_compact;
use behavior_api::sdk::Ctx;
use behavior_api::PostValue;
use geometry::{dist, point_spec, seglist_spec, Attrs, Polygon};

use super::BhvWaypoint;
use crate::common::push_f0;

impl BhvWaypoint {
    pub(super) fn nextpt_attrs(&self, ownship: &str, active: bool) -> Attrs {
        Attrs {
            active: Some(active),
            label: format!("{ownship}'s nextpt"),
            label_color: self.hints.nextpt_label_color.clone(),
            vertex_color: self.hints.nextpt_color.clone(),
            vertex_size: Some(self.hints.nextpt_vertex_size),
            ..Attrs::default()
        }
    }

    pub(super) fn post_nextpt_inactive(&self, ctx: &mut Ctx<'_>) {
        let label = format!("{}'s nextpt", ctx.ownship());
        let spec = geometry::point_erase_spec(&label);
        ctx.post_message_key("VIEW_POINT", PostValue::from(spec.as_str()), "wpt");
    }

    pub(super) fn erase_visuals(&self, ctx: &mut Ctx<'_>) {
        let own = ctx.ownship();
        let trk = geometry::point_erase_spec(&format!("{own}'s trackpt"));
        ctx.post_message_key("VIEW_POINT", PostValue::from(trk.as_str()), "trk");
        self.post_nextpt_inactive(ctx);
        let attrs = Attrs {
            active: Some(false),
            label: format!("{own}_{}", ctx.name()),
            ..Attrs::default()
        };
        let seg = seglist_spec(self.engine.points(), 1, &attrs);
        ctx.post_message("VIEW_SEGLIST", &seg);
    }

    pub(super) fn post_status_report(&mut self, ctx: &mut Ctx<'_>) {
        let ix = self.engine.index();
        if !Self::silent(&self.var_report) {
            let (nx, ny) = self.nextpt.unwrap_or((0.0, 0.0));
            let d = dist(self.plat.x, self.plat.y, nx, ny);
            let cap = self.engine.capture_hits();
            let tot = cap + self.engine.slip_hits();
            let key = (ix, cap, tot, self.engine.cycles());
            let v = &mut self.stat;
            match self.stat_head {
                Some((k, head)) if k == key => v.truncate(head),
                _ => {
                    v.clear();
                    v.push_str("vname=");
                    v.push_str(&self.own);
                    v.push_str(",behavior-name=");
                    v.push_str(&self.me);
                    v.push_str(",index=");
                    behavior_api::push_u64(v, ix as u64);
                    v.push_str(",hits=");
                    behavior_api::push_u64(v, cap as u64);
                    v.push('/');
                    behavior_api::push_u64(v, tot as u64);
                    v.push_str(",cycles=");
                    behavior_api::push_u64(v, key.3 as u64);
                    v.push_str(",dist=");
                    self.stat_head = Some((key, v.len()));
                }
            }
            push_f0(v, d);
            v.push_str(",eta=");
            push_f0(v, d / self.plat.speed);
            ctx.post_message(&self.sfx(&self.var_report), &self.stat);
        }
        if !Self::silent(&self.var_index) && ix as i64 != self.prev_waypt_index {
            ctx.post_message_num(&self.sfx(&self.var_index), ix as f64);
        }
        if !self.eager_prev_index {
            self.prev_waypt_index = ix as i64;
        }
    }

    pub(super) fn post_views(&mut self, ctx: &mut Ctx<'_>) {
        let (own, name) = (&self.own, &self.me);
        let edge = &self.hints.edge_color;
        if edge.eq_ignore_ascii_case("off") || edge.eq_ignore_ascii_case("inactive") {
            let seg = geometry::seglist_erase_spec(&format!("{own}_{name}"));
            ctx.post_message("VIEW_SEGLIST", &seg);
        } else {
            let version = self.engine.points_version();
            if self.seg_view.as_ref().is_none_or(|(v, _)| *v != version) {
                let hints = &self.hints;
                let attrs = Attrs {
                    label: format!("{own}_{name}"),
                    label_color: hints.label_color.clone(),
                    edge_color: hints.edge_color.clone(),
                    vertex_color: hints.vertex_color.clone(),
                    vertex_size: Some(hints.vertex_size),
                    edge_size: Some(hints.edge_size),
                    ..Attrs::default()
                };
                let (pts, tags) = (self.engine.points(), &self.path_tags);
                let spec = if tags.is_empty() || pts.is_empty() {
                    seglist_spec(pts, 3, &attrs)
                } else {
                    geometry::object_spec(pts, &[], tags, &attrs, 3)
                };
                self.seg_view = Some((version, spec));
            }
            if let Some((_, seg)) = &self.seg_view {
                ctx.post_message("VIEW_SEGLIST", seg);
            }
        }
        if self.draw_path_loop {
            let mut poly = Polygon::new(self.engine.points().to_vec());
            if poly.is_convex() {
                poly.attrs = Attrs {
                    label: format!("{own}_{name}_loop"),
                    edge_color: self.hints.edge_color.clone(),
                    vertex_color: self.hints.vertex_color.clone(),
                    ..Attrs::default()
                };
                ctx.post_message("VIEW_POLYGON", &poly.spec(1));
            }
        }
        let (nx, ny) = self.nextpt.unwrap_or((0.0, 0.0));
        let key = (nx.to_bits(), ny.to_bits());
        if self.nextpt_spec.as_ref().is_none_or(|(k, _)| *k != key) {
            let spec = point_spec(nx, ny, None, &self.nextpt_attrs(&self.own, true));
            self.nextpt_spec = Some((key, spec));
        }
        if let Some((_, np)) = &self.nextpt_spec {
            ctx.post_message_key("VIEW_POINT", PostValue::from(np.as_str()), "wpt");
        }
        let (tx, ty) = self.trackpt;
        // Without a lead the trackpt is the next point (distance 0: no hypot).
        if (tx, ty) != (nx, ny) && dist(tx, ty, nx, ny) > 5.0 {
            // `point_spec` written into the kept text buffer (the point moves every
            // iteration), its attribute fields formatted once.
            if self.trk_attrs.is_empty() {
                let attrs = Attrs {
                    active: Some(true),
                    label: format!("{}'s trackpt", self.own),
                    label_color: self.hints.nextpt_color.clone(),
                    vertex_color: self.hints.nextpt_color.clone(),
                    vertex_size: Some(4.0),
                    ..Attrs::default()
                };
                self.trk_attrs = attrs.spec();
            }
            let mut trk = std::mem::take(&mut self.text);
            trk.clear();
            trk.push_str("x=");
            push_compact(&mut trk, tx, 2);
            trk.push_str(",y=");
            push_compact(&mut trk, ty, 2);
            trk.push_str(&self.trk_attrs);
            ctx.post_message_key("VIEW_POINT", PostValue::from(trk.as_str()), "trk");
            self.text = trk;
        } else {
            let own = &self.own;
            let trk = self
                .trk_erase_spec
                .get_or_insert_with(|| geometry::point_erase_spec(&format!("{own}'s trackpt")));
            ctx.post_message_key("VIEW_POINT", PostValue::from(trk.as_str()), "trk");
        }
    }

    pub(super) fn post_distances(&self, ctx: &mut Ctx<'_>) {
        let (x, y) = (self.plat.x, self.plat.y);
        if !self.var_dist_to_prev.is_empty() {
            let ix = self.engine.index();
            let d = if let Some((px, py)) = self.engine.prev_point() {
                dist(x, y, px, py)
            } else if ix > 0 {
                self.engine
                    .point(ix - 1)
                    .map_or(-1.0, |p| dist(x, y, p.x, p.y))
            } else {
                -1.0
            };
            ctx.post_message_num(&self.var_dist_to_prev, d);
        }
        if !self.var_dist_to_next.is_empty() {
            let d = self.engine.current().map_or(-1.0, |p| dist(x, y, p.x, p.y));
            ctx.post_message_num(&self.var_dist_to_next, d);
        }
    }
}
