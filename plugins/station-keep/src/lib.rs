//! BHV_StationKeep (behaviors-plugins.md §5): hold a station point with a coupled
//! course × speed function, a speed ramp between an inner and an outer ring and an
//! optional hibernation state machine.

use std::collections::VecDeque;

use behavior_api::geometry::angles::{angle360, rel_ang};
use behavior_api::geometry::spec::{fmt_x, is_color};
use behavior_api::ivp;
use behavior_api::kept::CoupledPeaks;
use behavior_api::mbutil::push_fixed;
use behavior_api::sdk::{function_data, Ctx, HelmDomain, IvpBehavior};
use behavior_api::zaic::Peak;
use behavior_api::{parse_number, FunctionData, PostValue};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mode {
    Disabled,
    Hibernating,
    SeekingStation,
}

impl Mode {
    fn label(self) -> &'static str {
        match self {
            Mode::Disabled => "DISABLED",
            Mode::Hibernating => "HIBERNATING",
            Mode::SeekingStation => "SEEKING_STATION",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Transit {
    Disabled,
    Hibernating,
    PendingProgressStart,
    NotedProgressStart,
    NotedProgressEnd,
}

/// (label, radius bits, active, station x bits, station y bits)
type CircleKey = (&'static str, u64, bool, u64, u64);

/// BHV_StationKeep.
pub struct StationKeep {
    /// Circle specs already formatted, by (label, radius, active, station): they change
    /// only when the station or a parameter does (parameters clear it).
    circle_cache: std::cell::RefCell<Vec<(CircleKey, String)>>,
    domain: String,
    ivp_domain: Option<ivp::Domain>,
    // station actually held
    station: (f64, f64),
    station_set: bool,
    // static point from station_pt
    static_pt: (f64, f64),
    static_defined: bool,
    pending: bool,
    center_activate: bool,
    hibernation_radius: f64,
    mode: Mode,
    transit: Transit,
    outer_radius: f64,
    inner_radius: f64,
    outer_speed: f64,
    extra_speed: f64,
    swing_time: f64,
    dist: f64,
    mark_time: f64,
    /// (distance, time), newest first.
    history: VecDeque<(f64, f64)>,
    // visual hints
    vertex_color: String,
    edge_color: String,
    label_color: String,
    vertex_size: f64,
    edge_size: f64,
    /// Course and speed summits of the last function (for tests and logs).
    last_summits: (f64, f64),
    /// The speed function and course builder kept between iterations.
    peaks: CoupledPeaks,
}

impl StationKeep {
    pub fn new(helm_domain: &HelmDomain) -> Self {
        StationKeep {
            circle_cache: Default::default(),
            domain: helm_domain.sub_domain(&["course", "speed"]),
            ivp_domain: helm_domain.ivp_domain(&["course", "speed"]),
            station: (0.0, 0.0),
            station_set: false,
            static_pt: (0.0, 0.0),
            static_defined: false,
            pending: false,
            center_activate: false,
            hibernation_radius: -1.0,
            mode: Mode::Disabled,
            transit: Transit::Disabled,
            outer_radius: 15.0,
            inner_radius: 4.0,
            outer_speed: 1.2,
            extra_speed: 2.5,
            swing_time: 0.0,
            dist: -1.0,
            mark_time: -1.0,
            history: VecDeque::new(),
            vertex_color: "red".into(),
            edge_color: "light_blue".into(),
            label_color: "white".into(),
            vertex_size: 1.0,
            edge_size: 1.0,
            last_summits: (0.0, 0.0),
            peaks: CoupledPeaks::default(),
        }
    }

    fn settings(&self, name: &str) -> String {
        format!(
            "type=BHV_StationKeep,name={name},x={:.2},y={:.2},inner_radius={:.1},outer_radius={:.1},hibernation_radius={:.1},outer_speed={:.1},center_activate={}",
            self.static_pt.0,
            self.static_pt.1,
            self.inner_radius,
            self.outer_radius,
            self.hibernation_radius,
            self.outer_speed,
            self.center_activate
        )
    }

    fn post_settings(&self, ctx: &mut Ctx<'_>) {
        let s = self.settings(&ctx.name());
        ctx.post_repeatable_message("BHV_SETTINGS", PostValue::from(s.as_str()));
    }

    fn set_visual_hints(&mut self, value: &str) {
        for field in split_top(value, ',') {
            let Some((k, v)) = field.split_once('=') else {
                continue;
            };
            let (k, v) = (k.trim().to_ascii_lowercase(), v.trim());
            match k.as_str() {
                "vertex_color" | "edge_color" | "label_color" if is_color(v) => {
                    let slot = match k.as_str() {
                        "vertex_color" => &mut self.vertex_color,
                        "edge_color" => &mut self.edge_color,
                        _ => &mut self.label_color,
                    };
                    *slot = v.to_string();
                }
                "vertex_size" => {
                    if let Some(n) = parse_number(v) {
                        self.vertex_size = n;
                    }
                }
                "edge_size" => {
                    if let Some(n) = parse_number(v) {
                        self.edge_size = n;
                    }
                }
                _ => {}
            }
        }
    }

    /// One `VIEW_POLYGON` radial spec (§5.7), written piece by piece: `{:.1}`'s text
    /// by `push_fixed` (the same text) instead of `format!` (the first decision, and
    /// each new station, formats these).
    fn circle(&self, ctx: &Ctx<'_>, label: &str, radius: f64, active: bool) -> String {
        let own = ctx.ownship();
        let mut s = String::with_capacity(256);
        s.push_str("radial:: x=");
        push_fixed(&mut s, self.station.0, 1);
        s.push_str(",y=");
        push_fixed(&mut s, self.station.1, 1);
        s.push_str(",source=");
        s.push_str(&own);
        s.push(':');
        s.push_str(&ctx.name());
        s.push_str(",pts=32");
        if self.edge_size >= 0.0 {
            s.push_str(",edge_size=");
            s.push_str(&fmt_x(self.edge_size, 5));
        }
        if self.vertex_size >= 0.0 {
            s.push_str(",vertex_size=");
            s.push_str(&fmt_x(self.vertex_size, 5));
        }
        for (key, value) in [
            (",edge_color=", &self.edge_color),
            (",label_color=", &self.label_color),
            (",vertex_color=", &self.vertex_color),
        ] {
            s.push_str(key);
            s.push_str(value);
        }
        s.push_str(",label=");
        s.push_str(&own);
        s.push_str(":station-keep-");
        s.push_str(label);
        s.push_str(",radius=");
        push_fixed(&mut s, radius, 1);
        if !active {
            s.push_str(",active=false");
        }
        s
    }

    fn post_circle(
        &self,
        ctx: &mut Ctx<'_>,
        label: &'static str,
        key: &str,
        radius: f64,
        active: bool,
    ) {
        // The labels are fixed texts: the key is made without a new string.
        let ck: CircleKey = (
            label,
            radius.to_bits(),
            active,
            self.station.0.to_bits(),
            self.station.1.to_bits(),
        );
        let mut cache = self.circle_cache.borrow_mut();
        // The numbers first: the label's text is compared only where they all match.
        let same = |k: &CircleKey| (k.1, k.3, k.4, k.2) == (ck.1, ck.3, ck.4, ck.2) && k.0 == ck.0;
        let idx = match cache.iter().position(|(k, _)| same(k)) {
            Some(i) => i,
            None => {
                let spec = self.circle(ctx, label, radius, active);
                cache.push((ck, spec));
                if cache.len() > 8 {
                    cache.remove(0);
                }
                cache.len() - 1
            }
        };
        ctx.post_message_key("VIEW_POLYGON", PostValue::from(cache[idx].1.as_str()), key);
    }

    fn post_visuals(&self, ctx: &mut Ctx<'_>) {
        self.post_circle(ctx, "out", "outer", self.outer_radius, true);
        if self.inner_radius < self.outer_radius {
            self.post_circle(ctx, "in", "inner", self.inner_radius, true);
        }
        if self.hibernation_radius > self.outer_radius {
            self.post_circle(ctx, "hiber", "hiber", self.hibernation_radius, true);
        }
    }

    fn erase_visuals(&self, ctx: &mut Ctx<'_>) {
        self.post_circle(ctx, "out", "outer", self.outer_radius, false);
        self.post_circle(ctx, "in", "inner", self.inner_radius, false);
        self.post_circle(ctx, "hiber", "hiber", self.hibernation_radius, false);
    }

    /// History test: `None` when the span is ≤ 5 s, else the rate of change.
    fn history_rate(&self) -> Option<f64> {
        let (dn, tn) = *self.history.front()?;
        let (d0, t0) = *self.history.back()?;
        let span = tn - t0;
        if span <= 5.0 {
            return None;
        }
        Some((dn - d0) / span)
    }

    /// The hibernation state machine (§5.5).
    fn update_hibernation(&mut self) {
        if self.mode == Mode::Disabled {
            return;
        }
        let (d, r) = (self.dist, self.hibernation_radius);
        match self.transit {
            Transit::PendingProgressStart
                if d <= r && self.history_rate().is_some_and(|rate| rate <= 0.0) =>
            {
                self.history.clear();
                self.transit = Transit::NotedProgressStart;
            }
            Transit::NotedProgressStart if self.history_rate().is_some_and(|rate| rate >= 0.0) => {
                self.transit = Transit::NotedProgressEnd;
            }
            _ => {}
        }
        if self.mode == Mode::Hibernating {
            if d > r {
                self.mode = Mode::SeekingStation;
                self.history.clear();
                self.transit = Transit::PendingProgressStart;
            }
            return;
        }
        if self.mode == Mode::SeekingStation
            && (d <= self.inner_radius || (self.transit == Transit::NotedProgressEnd && d <= r))
        {
            self.mode = Mode::Hibernating;
            self.transit = Transit::Hibernating;
            self.history.clear();
        }
    }

    /// The speed summit (§5.4 step 9).
    fn speed_summit(&self) -> f64 {
        let d = self.dist;
        if self.mode == Mode::Hibernating || d <= self.inner_radius {
            0.0
        } else if d < self.outer_radius {
            let range = self.outer_radius - self.inner_radius;
            let pct = (d - self.inner_radius) / range;
            pct * self.outer_speed
        } else {
            self.extra_speed
        }
    }

    /// The coupled course × speed function (§5.6), without pwt: a course peak 180°
    /// wide and a speed peak 0.4 wide of utility 0 to 25, coupled 50/50.
    fn build(&mut self, course: f64, speed: f64) -> Option<ivp::IvpFunction> {
        let dom = self.ivp_domain.as_ref()?;
        let crs = Peak {
            summit: course,
            base_width: 180.0,
            value_wrap: true,
            ..Peak::default()
        };
        let spd = Peak {
            summit: speed,
            base_width: 0.4,
            max_util: 25.0,
            ..Peak::default()
        };
        self.peaks.build(dom, &crs, &spd)
    }
}

/// Split on `sep` outside double quotes and braces.
fn split_top(s: &str, sep: char) -> Vec<String> {
    let mut out = Vec::new();
    let (mut cur, mut depth, mut quoted) = (String::new(), 0i32, false);
    for c in s.chars() {
        match c {
            '"' => quoted = !quoted,
            '{' if !quoted => depth += 1,
            '}' if !quoted => depth -= 1,
            _ => {}
        }
        if c == sep && !quoted && depth <= 0 {
            out.push(std::mem::take(&mut cur));
        } else {
            cur.push(c);
        }
    }
    out.push(cur);
    out
}

/// The station point of `station_pt` (§5.1): any point string the real `string2Point`
/// accepts (geometry-formats.md §6); z and attributes are not used.
fn parse_station_point(s: &str) -> Option<(f64, f64)> {
    behavior_api::geometry::parse_point(s).map(|p| (p.x, p.y))
}

fn positive(value: &str) -> Option<f64> {
    parse_number(value).filter(|v| *v > 0.0)
}

impl IvpBehavior for StationKeep {
    fn domain(&self) -> String {
        self.domain.clone()
    }

    fn default_name(&self) -> String {
        "station_keep".into()
    }

    fn set_param(&mut self, _ctx: &mut Ctx<'_>, param: &str, value: &str) -> bool {
        // Colors, sizes and radii may change what the circles look like.
        self.circle_cache.borrow_mut().clear();
        let param = param.to_ascii_lowercase();
        let value = value.trim();
        match param.as_str() {
            "station_pt" | "point" => parse_station_point(value).map(|p| {
                self.static_pt = p;
                self.static_defined = true;
                self.pending = true;
            }),
            "center_activate" => match value.to_ascii_lowercase().as_str() {
                "true" => Some(true),
                "false" => Some(false),
                _ => None,
            }
            .map(|b| {
                self.center_activate = b;
                self.pending = true;
            }),
            "hibernation_radius" => {
                if value.eq_ignore_ascii_case("off") || value == "-1" {
                    self.hibernation_radius = -1.0;
                    self.mode = Mode::Disabled;
                    Some(())
                } else {
                    positive(value).map(|r| {
                        self.hibernation_radius = r;
                        if self.mode == Mode::Disabled {
                            self.mode = Mode::Hibernating;
                        }
                    })
                }
            }
            "outer_radius" => positive(value).map(|v| self.outer_radius = v),
            "inner_radius" => positive(value).map(|v| self.inner_radius = v),
            "outer_speed" => positive(value).map(|v| {
                self.outer_speed = v;
                if self.extra_speed < v {
                    self.extra_speed = v;
                }
            }),
            "extra_speed" | "transit_speed" => positive(value).map(|v| self.extra_speed = v),
            "swing_time" => parse_number(value).map(|v| self.swing_time = v.clamp(0.0, 60.0)),
            "visual_hints" => {
                self.set_visual_hints(value);
                Some(())
            }
            _ => None,
        }
        .is_some()
    }

    fn on_params_complete(&mut self, ctx: &mut Ctx<'_>) {
        ctx.add_info_vars("NAV_X, NAV_Y");
        self.post_settings(ctx);
    }

    fn on_idle_to_run(&mut self, ctx: &mut Ctx<'_>) {
        self.post_settings(ctx);
    }

    fn on_run_to_idle(&mut self, ctx: &mut Ctx<'_>) {
        self.history.clear();
        self.erase_visuals(ctx);
        if self.center_activate {
            self.pending = true;
        }
        self.mark_time = -1.0;
    }

    fn on_complete(&mut self, ctx: &mut Ctx<'_>) {
        self.erase_visuals(ctx);
    }

    fn on_run(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        // 1. Platform update.
        let x = ctx.get_buffer_double_val("NAV_X");
        let y = ctx.get_buffer_double_val("NAV_Y");
        let (Some(osx), Some(osy)) = (x, y) else {
            ctx.post_emessage("No ownship X/Y info in info_buffer.");
            return None;
        };
        let Some(h) = ctx.get_buffer_double_val("NAV_HEADING") else {
            ctx.post_emessage("No ownship heading info in info_buffer.");
            return None;
        };
        let osh = angle360(h);
        let osv = ctx.get_buffer_double_val("NAV_SPEED").unwrap_or(0.0);
        ctx.set_platform(osx, osy, osh, osv);

        // 2-4. Refresh: station assignment or distance/history update.
        let now = ctx.get_buffer_curr_time();
        if self.mark_time == -1.0 {
            self.mark_time = now;
        }
        let mut changed = false;
        if self.pending {
            if self.center_activate {
                self.station = (osx, osy);
                self.station_set = true;
                changed = true;
                if now >= self.mark_time + self.swing_time {
                    self.pending = false;
                }
            } else if self.static_defined {
                self.station = self.static_pt;
                self.station_set = true;
                self.pending = false;
                changed = true;
            }
        }
        if changed {
            self.mode = Mode::Hibernating;
            self.transit = Transit::Hibernating;
        } else {
            self.dist = (osx - self.station.0).hypot(osy - self.station.1);
            self.history.push_front((self.dist, now));
            let k = self.history.iter().filter(|(_, t)| now - t > 10.0).count();
            for _ in 0..k {
                self.history.pop_back();
            }
        }

        ctx.post_message_num("DIST_TO_STATION", self.dist);
        if !self.station_set {
            ctx.post_wmessage("STATION_POINT_NOT_SET");
            self.erase_visuals(ctx);
            return None;
        }
        if self.inner_radius > self.outer_radius {
            self.outer_radius = self.inner_radius;
        }
        self.update_hibernation();
        ctx.post_message("PSKEEP_MODE", self.mode.label());
        self.post_visuals(ctx);

        let course = if self.pending {
            osh
        } else {
            rel_ang(osx, osy, self.station.0, self.station.1)
        };
        let speed = self.speed_summit();
        self.last_summits = (course, speed);
        let mut f = self.build(course, speed)?;
        f.set_pwt(ctx.priority());
        Some(function_data(f))
    }
}

behavior_api::export_behaviors! {
    "BHV_StationKeep" => StationKeep::new,
}

#[cfg(test)]
mod tests;
