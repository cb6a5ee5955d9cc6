//! BHV_Trail (behaviors-contacts.md §3): hold a point fixed relative to a moving
//! contact (default 50 m astern): a CPA-based function when far, heading and speed
//! peaks when near or arrived.

use std::f64::consts::PI;

use behavior_api::contact::ContactBase;
use behavior_api::geometry::{angle180, angle360, project_point};
use behavior_api::ivp::{Domain, IvpFunction, Reflector};
use behavior_api::params::parse_bool;
use behavior_api::sdk::{function_data, Ctx, HelmDomain, IvpBehavior};
use behavior_api::{atof, parse_number, push_compact, FunctionData, PostValue};

use crate::aof::CutRangeAof;
use behavior_api::kept::CoupledPeaks;
use behavior_api::zaic::Peak;

pub struct Trail {
    base: ContactBase,
    domain: Option<Domain>,
    domain_spec: String,
    trail_range: f64,
    trail_angle: f64,
    relative: bool,
    radius: f64,
    nm_radius: f64,
    pwt_outer_dist: f64,
    post_trail_dist_on_idle: bool,
    /// The ownship's name, read on the first run (`own_read`).
    own: String,
    own_read: bool,
    /// The trail point's VIEW_POINT text, kept between iterations.
    view: String,
    /// The near function's kept parts.
    peaks: CoupledPeaks,
}

/// Degrees clockwise from north to radians counter-clockwise from east, in [−π, π].
fn math_angle(compass: f64) -> f64 {
    let mut t = (90.0 - compass) * PI / 180.0;
    while t > PI {
        t -= 2.0 * PI;
    }
    while t < -PI {
        t += 2.0 * PI;
    }
    t
}

impl Trail {
    pub fn new(helm: &HelmDomain) -> Self {
        let mut base = ContactBase::new(60.0);
        base.no_alert_request = true;
        Trail {
            base,
            domain: helm.ivp_domain(&["course", "speed"]),
            domain_spec: helm.sub_domain(&["course", "speed"]),
            trail_range: 50.0,
            trail_angle: 180.0,
            relative: true,
            radius: 5.0,
            nm_radius: 20.0,
            pwt_outer_dist: 0.0,
            post_trail_dist_on_idle: true,
            own: String::new(),
            own_read: false,
            view: String::with_capacity(128),
            peaks: CoupledPeaks::default(),
        }
    }

    /// The trail point from the last contact read (§3.2).
    pub fn trail_point(&self) -> (f64, f64) {
        let cn = self.base.cn;
        if self.relative {
            let t = math_angle(angle360(cn.hdg + self.trail_angle));
            (
                cn.x + self.trail_range * t.cos(),
                cn.y + self.trail_range * t.sin(),
            )
        } else {
            project_point(self.trail_angle, self.trail_range, cn.x, cn.y)
        }
    }

    fn trail_distance(&self, tp: (f64, f64)) -> f64 {
        (self.base.os.x - tp.0).hypot(self.base.os.y - tp.1)
    }

    /// The coupled course and speed peaks, normalized to [0, 100].
    fn peaks(&mut self, hdg: f64, spd: f64) -> Option<IvpFunction> {
        let domain = self.domain.as_ref()?;
        let crs = Peak {
            summit: hdg,
            peak_width: 30.0,
            base_width: 150.0,
            summit_delta: 50.0,
            value_wrap: true,
            ..Peak::default()
        };
        let spd = Peak {
            summit: spd,
            peak_width: 0.1,
            base_width: 2.0,
            summit_delta: 50.0,
            ..Peak::default()
        };
        let mut f = self.peaks.build(domain, &crs, &spd)?;
        f.normalize(0.0, 100.0);
        Some(f)
    }

    /// The cut-range function toward the trail point, normalized to [0, 100] (twice,
    /// as the reference does: the reflector's, then the behavior's).
    fn far(&self, ctx: &mut Ctx<'_>, tp: (f64, f64)) -> Option<IvpFunction> {
        let domain = self.domain.as_ref()?;
        let vmax = domain.var(domain.index_of("speed")?).high;
        let cn = self.base.cn;
        let Some(aof) = CutRangeAof::new(
            (tp.0, tp.1, cn.hdg, cn.spd),
            (self.base.os.x, self.base.os.y),
            self.base.time_on_leg,
            100.0,
            vmax,
        ) else {
            ctx.post_wmessage("Error in initializing AOF_CutRangeCPA.");
            return None;
        };
        let mut refl = Reflector::new(domain, &aof);
        refl.set_uniform(
            &[("course", 3), ("speed", 2)],
            &[("course", 9), ("speed", 6)],
        );
        refl.create(None, None);
        refl.into_function_normalized_twice()
    }

    /// `VIEW_POINT = x=<x>,y=<y>,label=<own>_trailpoint,vertex_color=gray50,time=<t>,
    /// vertex_size=8`, written into the kept `view` (every iteration, no new string).
    fn post_trail_point(&mut self, ctx: &mut Ctx<'_>, tp: (f64, f64)) {
        if !self.own_read {
            // The ownship's name never changes: read once.
            ctx.ownship_into(&mut self.own);
            self.own_read = true;
        }
        let v = &mut self.view;
        v.clear();
        v.push_str("x=");
        push_compact(v, tp.0, 2);
        v.push_str(",y=");
        push_compact(v, tp.1, 2);
        v.push_str(",label=");
        v.push_str(&self.own);
        v.push_str("_trailpoint,vertex_color=gray50,time=");
        push_compact(v, ctx.get_buffer_curr_time(), 2);
        v.push_str(",vertex_size=8");
        ctx.post_message("VIEW_POINT", v);
    }

    fn set_num(&mut self, param: &str, v: f64) -> bool {
        let field = match param {
            "trail_range" => &mut self.trail_range,
            "radius" => &mut self.radius,
            "nm_radius" => &mut self.nm_radius,
            _ => &mut self.pwt_outer_dist,
        };
        if v < 0.0 {
            return false;
        }
        *field = v;
        true
    }
}

impl IvpBehavior for Trail {
    fn domain(&self) -> String {
        self.domain_spec.clone()
    }

    fn default_name(&self) -> String {
        "(d)trail".into()
    }

    fn set_param(&mut self, ctx: &mut Ctx<'_>, param: &str, value: &str) -> bool {
        let param = param.to_ascii_lowercase();
        if let Some(ok) = self.base.set_param_with(ctx, &param, value) {
            return ok;
        }
        let v = value.trim();
        match param.as_str() {
            "trail_range" | "radius" | "nm_radius" | "pwt_outer_dist" => {
                parse_number(v).is_some_and(|n| self.set_num(&param, n))
            }
            "trail_angle" => match parse_number(v) {
                Some(a) => {
                    self.trail_angle = angle180(a);
                    true
                }
                None => false,
            },
            "trail_angle_type" => match v.to_ascii_lowercase().as_str() {
                "relative" => {
                    self.relative = true;
                    true
                }
                "absolute" => {
                    self.relative = false;
                    true
                }
                _ => false,
            },
            "mod_trail_range" => {
                self.trail_range = (self.trail_range + atof(v)).max(10.0);
                true
            }
            "mod_trail_range_pct" => {
                let p = atof(v);
                if p <= 0.0 {
                    return false;
                }
                self.trail_range = (self.trail_range * p / 100.0).max(10.0);
                true
            }
            "post_trail_dist_on_idle" => match parse_bool(v, self.post_trail_dist_on_idle) {
                Some(b) => {
                    self.post_trail_dist_on_idle = b;
                    true
                }
                None => false,
            },
            "no_alert_request" => match parse_bool(v, self.base.no_alert_request) {
                Some(b) => {
                    self.base.no_alert_request = b;
                    true
                }
                None => false,
            },
            _ => false,
        }
    }

    fn on_helm_start(&mut self, ctx: &mut Ctx<'_>) {
        let name = ctx.name();
        let outer = self.pwt_outer_dist;
        if let Some(req) = self.base.alert_request(&name, outer, outer + 5.0) {
            ctx.post_message("BCM_ALERT_REQUEST", &req);
        }
    }

    fn on_spawn(&mut self, _ctx: &mut Ctx<'_>) {
        self.base.spawned();
    }

    fn on_every_state(&mut self, ctx: &mut Ctx<'_>) {
        self.base.every_state(ctx);
    }

    fn on_complete(&mut self, _ctx: &mut Ctx<'_>) {
        self.base.on_complete();
    }

    fn on_run_to_idle(&mut self, ctx: &mut Ctx<'_>) {
        ctx.post_message_num("PURSUIT", 0.0);
    }

    fn on_idle_state(&mut self, ctx: &mut Ctx<'_>) {
        if self.post_trail_dist_on_idle && self.base.has_relation() {
            let d = self.trail_distance(self.trail_point());
            ctx.post_int_message("TRAIL_DISTANCE", d);
        }
    }

    fn on_run(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        if !self.base.update_ok {
            return None;
        }
        self.base.handle_cnflags(ctx);
        let tp = self.trail_point();
        self.post_trail_point(ctx, tp);
        let r = self.base.range();
        let relevance = if self.pwt_outer_dist == 0.0 {
            1.0
        } else {
            ctx.post_int_message("TRAIL_RANGE", r);
            if r < self.pwt_outer_dist {
                1.0
            } else {
                0.0
            }
        };
        ctx.post_repeatable_message("TRAIL_RELEVANCE", PostValue::Num(relevance));
        ctx.post_repeatable_message("TRAIL_CTR", PostValue::Num(1.0));
        if relevance <= 0.0 {
            ctx.post_message_num("PURSUIT", 0.0);
            return None;
        }
        ctx.post_message_num("PURSUIT", 1.0);
        let cn = self.base.cn;
        let d = self.trail_distance(tp);
        ctx.post_int_message("TRAIL_DISTANCE", d);
        let th = math_angle(angle360(cn.hdg));
        let (hx, hy) = (th.cos(), th.sin());
        let os = self.base.os;
        // Each branch's function comes normalized to [0, 100].
        let mut f = if d > self.radius && d > self.nm_radius {
            ctx.post_message("REGION", "Outside nm_radius");
            self.far(ctx, tp)?
        } else if d > self.radius {
            ctx.post_message("REGION", "Inside nm_radius");
            let ahead = hx * (os.x - tp.0) + hy * (os.y - tp.1);
            let (px, py) = (tp.0 + self.nm_radius * hx, tp.1 + self.nm_radius * hy);
            let (bx, by) = (px - os.x, py - os.y);
            let len = bx.hypot(by);
            let modh = angle360(90.0 - (by / len).atan2(bx / len).to_degrees());
            ctx.post_int_message("TRAIL_HEADING", modh);
            let mut modv = cn.spd * (1.0 - 0.5 * ahead / self.nm_radius);
            if modv < 0.0 || !self.base.extrapolate {
                modv = 0.0;
            }
            ctx.post_message_num("TRAIL_SPEED", (modv * 10.0).round() / 10.0);
            self.peaks(modh, modv)?
        } else {
            ctx.post_message("REGION", "Inside radius");
            let mut modv = cn.spd;
            if modv < 0.0 || !self.base.extrapolate {
                modv = 0.0;
            }
            ctx.post_message_num("TRAIL_SPEED", modv);
            self.peaks(angle360(cn.hdg), modv)?
        };
        f.set_pwt(relevance * ctx.priority());
        Some(function_data(f))
    }

    fn expand_macros(&self, text: &str) -> Option<String> {
        self.base.expand_macros(text)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use behavior_api::testing::MockHelm;

    fn trail() -> (Trail, MockHelm) {
        let mut b = Trail::new(&HelmDomain::new("course,0,359,360:speed,0,4,41"));
        let mut helm = MockHelm::new("trail_abe");
        for (p, v) in [
            ("contact", "abe"),
            ("trail_range", "30"),
            ("nm_radius", "15"),
            ("radius", "5"),
            ("pwt_outer_dist", "200"),
        ] {
            assert!(helm.with(|ctx| b.set_param(ctx, p, v)), "{p}");
        }
        (b, helm)
    }

    #[test]
    fn trail_point_astern_relative_and_absolute() {
        let (mut b, mut helm) = trail();
        helm.nav(0.0, 0.0, 0.0, 0.0);
        helm.contact("abe", 100.0, 50.0, 90.0, 1.5, "kayak");
        helm.with(|ctx| b.on_every_state(ctx));
        let (x, y) = b.trail_point();
        // 30 m astern of a contact heading east: 30 m west of it.
        assert!((x - 70.0).abs() < 1e-9 && (y - 50.0).abs() < 1e-9);
        assert!(helm.with(|ctx| b.set_param(ctx, "trail_angle_type", "absolute")));
        assert!(helm.with(|ctx| b.set_param(ctx, "trail_angle", "270")));
        assert_eq!(b.trail_angle, -90.0);
        assert_eq!(b.trail_point(), (70.0, 50.0));
        assert!(helm.with(|ctx| b.set_param(ctx, "mod_trail_range", "-25")));
        assert_eq!(b.trail_range, 10.0); // floor of 10
    }

    #[test]
    fn regions_by_distance() {
        let (mut b, mut helm) = trail();
        helm.contact("abe", 100.0, 50.0, 90.0, 1.5, "kayak");
        for (osx, region, pieces) in [
            (0.0, "Outside nm_radius", Some(2520)),
            (60.0, "Inside nm_radius", None),
            (68.0, "Inside radius", None),
        ] {
            helm.nav(osx, 50.0, 90.0, 1.5);
            helm.with(|ctx| b.on_every_state(ctx));
            let f = helm.with(|ctx| b.on_run(ctx)).unwrap();
            assert_eq!(helm.last("REGION").as_deref(), Some(region));
            if let Some(p) = pieces {
                assert_eq!(f.piece_count(), Some(p));
            }
        }
        // 8 m behind the trail point, aim 15 m ahead of it: heading east, speed
        // 1.5 × (1 + 0.5 × 8/15) = 1.9.
        helm.nav(62.0, 50.0, 90.0, 1.5);
        helm.with(|ctx| b.on_every_state(ctx));
        helm.with(|ctx| b.on_run(ctx)).unwrap();
        assert_eq!(helm.last("TRAIL_HEADING").as_deref(), Some("90"));
        assert_eq!(helm.last("TRAIL_SPEED").as_deref(), Some("1.9"));
        assert_eq!(helm.last("TRAIL_DISTANCE").as_deref(), Some("8"));
        assert_eq!(helm.last("TRAIL_RANGE").as_deref(), Some("38"));
    }
}
