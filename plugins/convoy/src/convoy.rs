//! BHV_Convoy's parameters, run iteration and objective function (behaviors-more.md
//! §10.1–§10.5).

use std::collections::VecDeque;

use behavior_api::contact::ContactBase;
use behavior_api::geometry::{angle360, dist, rel_ang};
use behavior_api::ivp::{Domain, ZaicPeak};
use behavior_api::params::parse_bool;
use behavior_api::sdk::{function_data, Ctx, HelmDomain, IvpBehavior};
use behavior_api::{compact, parse_number, FunctionData};

use crate::marks::{Mark, Marks};

pub struct Convoy {
    base: ContactBase,
    domain: Option<Domain>,
    domain_spec: String,
    radius: f64,
    nm_radius: f64,
    inter_mark_range: f64,
    max_mark_range: f64,
    cruise_speed: f64,
    spd_max: f64,
    spd_slower: f64,
    spd_faster: f64,
    rng_estop: f64,
    rng_tgating: f64,
    rng_lagging: f64,
    rng_safety: bool,
    marks_up_bound: u64,
    marks: Marks,
    /// Contact speeds (value, time), newest first.
    history: VecDeque<(f64, f64)>,
    avg2: f64,
    avg5: f64,
    wpt: (f64, f64),
    set_speed: f64,
}

impl Convoy {
    pub fn new(helm: &HelmDomain) -> Self {
        Convoy {
            base: ContactBase::new(60.0),
            domain: helm.ivp_domain(&["course", "speed"]),
            domain_spec: helm.sub_domain(&["course", "speed"]),
            radius: 5.0,
            nm_radius: 20.0,
            inter_mark_range: 10.0,
            max_mark_range: 150.0,
            cruise_speed: -1.0,
            spd_max: 2.0,
            spd_slower: 0.5,
            spd_faster: 1.5,
            rng_estop: 15.0,
            rng_tgating: 30.0,
            rng_lagging: 70.0,
            rng_safety: true,
            marks_up_bound: 16,
            marks: Marks::default(),
            history: VecDeque::new(),
            avg2: 0.0,
            avg5: 0.0,
            wpt: (0.0, 0.0),
            set_speed: 0.0,
        }
    }

    /// (estop, tailgating, lagging) ranges after the safety adjustment.
    pub fn ranges(&self) -> (f64, f64, f64) {
        (self.rng_estop, self.rng_tgating, self.rng_lagging)
    }

    /// The speed the last run iteration asked for.
    pub fn set_speed(&self) -> f64 {
        self.set_speed
    }

    pub fn marks(&self) -> &Marks {
        &self.marks
    }

    fn label(&self, ctx: &Ctx<'_>, id: u64) -> String {
        format!("{}_{}_{id}", ctx.ownship(), self.base.contact)
    }

    fn post_mark(&self, ctx: &mut Ctx<'_>, m: Mark) {
        let spec = format!(
            "x={},y={},label={},label_color=invisible,vertex_color=white",
            compact(m.x, 2),
            compact(m.y, 2),
            self.label(ctx, m.id)
        );
        ctx.post_message("VIEW_POINT", &spec);
    }

    fn erase_mark(&self, ctx: &mut Ctx<'_>, m: Mark) {
        let spec = format!("x=0,y=0,active=false,label={}", self.label(ctx, m.id));
        ctx.post_message("VIEW_POINT", &spec);
    }

    fn pop(&mut self, ctx: &mut Ctx<'_>) -> Option<Mark> {
        let m = self.marks.oldest()?;
        self.erase_mark(ctx, m);
        self.marks.pop()
    }

    /// Step 3: the contact-speed history and its 2 s and 5 s means.
    fn speeds(&mut self, cnv: f64, now: f64) {
        self.history.push_front((cnv, now));
        while self.history.back().is_some_and(|(_, t)| now - t > 5.0) {
            self.history.pop_back();
        }
        if !self.history.is_empty() {
            self.avg5 = self.history.iter().map(|h| h.0).sum::<f64>() / self.history.len() as f64;
        }
        let recent: Vec<f64> = self
            .history
            .iter()
            .filter(|(_, t)| now - t <= 2.0)
            .map(|h| h.0)
            .collect();
        if !recent.is_empty() {
            self.avg2 = recent.iter().sum::<f64>() / recent.len() as f64;
        }
    }

    /// Step 8.
    fn speed_for(&self, range: f64) -> f64 {
        if range < self.rng_estop {
            0.0
        } else if self.cruise_speed > 0.0 {
            self.cruise_speed
        } else if range > self.rng_lagging {
            self.avg2 * self.spd_faster
        } else if range > self.rng_tgating {
            self.avg2
        } else {
            self.avg2 * self.spd_slower
        }
    }

    /// §10.4, pwt left at the library default.
    fn function(&self, course: f64, heading: f64) -> Option<behavior_api::ivp::IvpFunction> {
        let dom = self.domain.as_ref()?;
        let mut zs = ZaicPeak::new(dom, "speed").ok()?;
        zs.set_params(
            self.set_speed,
            self.set_speed / 2.0,
            1.6,
            20.0,
            0.0,
            100.0,
            0,
        );
        let mut zc = ZaicPeak::new(dom, "course").ok()?;
        zc.set_value_wrap(true);
        zc.set_params(course, 0.0, 180.0, 50.0, 0.0, 100.0, 0);
        let i = zc.add_component();
        zc.set_params(angle360(heading), 30.0, 180.0, 5.0, 0.0, 20.0, i);
        // couple(course, speed, 0.5, 0.5, true) bit for bit, the course pieces coupled
        // straight from the builder (both extractions fail or not on their own).
        let mut fs = zs.extract(true)?;
        fs.normalize(0.0, 0.5);
        let f = zc.try_extract_coupled(false, &fs, (0.5, 0.5), true);
        fs.recycle();
        f.ok()?.ok()
    }
}

/// A number > 0.
fn pos(value: &str) -> Option<f64> {
    parse_number(value).filter(|v| *v > 0.0)
}

impl IvpBehavior for Convoy {
    fn domain(&self) -> String {
        self.domain_spec.clone()
    }

    fn default_name(&self) -> String {
        "???".into()
    }

    fn set_param(&mut self, ctx: &mut Ctx<'_>, param: &str, value: &str) -> bool {
        if let Some(ok) = self.base.set_param_with(ctx, param, value) {
            return ok;
        }
        let value = value.trim();
        let non_neg = parse_number(value).filter(|v| *v >= 0.0);
        match param {
            "radius" => non_neg.map(|v| self.radius = v).is_some(),
            "nm_radius" => non_neg.map(|v| self.nm_radius = v).is_some(),
            "inter_mark_range" => pos(value).map(|v| self.inter_mark_range = v).is_some(),
            "max_mark_range" => pos(value).map(|v| self.max_mark_range = v).is_some(),
            "cruise_speed" => pos(value).map(|v| self.cruise_speed = v).is_some(),
            "spd_max" => pos(value).map(|v| self.spd_max = v).is_some(),
            // Quirk (§10.1): a positive value out of range is stored, then refused.
            "spd_slower" => match pos(value) {
                Some(v) => {
                    self.spd_slower = v;
                    v <= 1.0
                }
                None => false,
            },
            "spd_faster" => match pos(value) {
                Some(v) => {
                    self.spd_faster = v;
                    (1.0..=3.0).contains(&v)
                }
                None => false,
            },
            "rng_estop" | "range_estop" => pos(value).map(|v| self.rng_estop = v).is_some(),
            "rng_tgating" | "range_tailgating" => {
                pos(value).map(|v| self.rng_tgating = v).is_some()
            }
            "rng_lagging" | "range_lagging" => pos(value).map(|v| self.rng_lagging = v).is_some(),
            "rng_safety" => parse_bool(value, self.rng_safety)
                .map(|b| self.rng_safety = b)
                .is_some(),
            _ => false,
        }
    }

    fn on_params_complete(&mut self, ctx: &mut Ctx<'_>) {
        ctx.add_info_vars("NAV_X, NAV_Y, NAV_SPEED, NAV_HEADING");
        self.marks_up_bound = (self.max_mark_range / self.inter_mark_range + 1.0) as u64;
        if self.rng_safety {
            let before = self.ranges();
            self.rng_estop = self.rng_estop.max(5.0);
            self.rng_tgating = self.rng_tgating.max(self.rng_estop + 10.0);
            self.rng_lagging = self.rng_lagging.max(self.rng_tgating + 10.0);
            if self.ranges() != before {
                ctx.post_wmessage("Safety ranges were auto-adusted bigger.");
            }
        }
        if self.cruise_speed > self.spd_max {
            self.cruise_speed = self.spd_max;
            ctx.post_wmessage("Cruise speed auto-capped at max speed.");
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
        let marks: Vec<Mark> = self.marks.iter().copied().collect();
        for m in marks {
            self.erase_mark(ctx, m);
        }
        self.marks.clear();
    }

    fn expand_macros(&self, text: &str) -> Option<String> {
        self.base.expand_macros(text)
    }

    fn on_run(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        if !self.base.update_ok {
            return None;
        }
        self.base.handle_cnflags(ctx);
        if !self.base.update(ctx) {
            return None;
        }
        ctx.post_message_num("TLEN", self.marks.total);
        ctx.post_message_num("QLEN", self.marks.len() as f64);
        ctx.post_message_num("MXRNG", self.max_mark_range);

        let now = ctx.get_buffer_curr_time();
        let cn = self.base.cn;
        self.speeds(cn.spd, now);
        ctx.post_message_num("AVG2", self.avg2);
        ctx.post_message_num("AVG5", self.avg5);

        let far = self
            .marks
            .newest()
            .is_none_or(|n| dist(cn.x, cn.y, n.x, n.y) > self.inter_mark_range);
        if far {
            let m = self.marks.push(cn.x, cn.y, self.marks_up_bound);
            self.post_mark(ctx, m);
        }
        if !self.marks.is_empty() && self.marks.total > self.max_mark_range {
            self.pop(ctx);
        }

        let os = self.base.os;
        let mut have_wpt = false;
        if let Some(mut w) = self.marks.oldest() {
            have_wpt = true;
            while dist(os.x, os.y, w.x, w.y) < self.radius {
                self.pop(ctx);
                match self.marks.oldest() {
                    Some(next) => w = next,
                    None => {
                        have_wpt = false;
                        break;
                    }
                }
            }
            self.wpt = (w.x, w.y);
        }
        ctx.post_message_num("WPTX", self.wpt.0);
        ctx.post_message_num("WPTY", self.wpt.1);
        if !have_wpt {
            return None;
        }

        self.set_speed = self.speed_for(self.base.range());
        let course = rel_ang(os.x, os.y, self.wpt.0, self.wpt.1);
        match self.function(course, os.heading) {
            Some(f) => Some(function_data(f)),
            None => {
                ctx.post_emessage("Unable to generate the convoy IvP function");
                None
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use behavior_api::testing::MockHelm;

    fn convoy() -> (Convoy, MockHelm) {
        let mut b = Convoy::new(&HelmDomain::new("course,0,359,360:speed,0,4,41"));
        let mut helm = MockHelm::new("cnv");
        for (p, v) in [
            ("contact", "abe"),
            ("radius", "8"),
            ("inter_mark_range", "5"),
        ] {
            assert!(helm.with(|ctx| b.set_param(ctx, p, v)), "{p}");
        }
        helm.with(|ctx| b.on_params_complete(ctx));
        (b, helm)
    }

    fn step(b: &mut Convoy, helm: &mut MockHelm) -> Option<FunctionData> {
        helm.with(|ctx| b.on_every_state(ctx));
        helm.with(|ctx| b.on_run(ctx))
    }

    /// The function is the reference's (both peaks made into functions, then
    /// coupled) bit for bit, over courses, headings and speeds.
    #[test]
    fn function_equals_extract_then_couple() {
        let (mut b, _) = convoy();
        let bits = behavior_api::testing::function_bits;
        for (k, speed) in [1.0, 0.0, 2.5, 4.0, 7.0].into_iter().enumerate() {
            b.set_speed = speed;
            for (course, heading) in [(0.0, 0.0), (45.5, 300.0), (359.0, -20.0), (180.0, 720.5)] {
                let dom = b.domain.as_ref().unwrap();
                let mut zs = ZaicPeak::new(dom, "speed").unwrap();
                zs.set_params(speed, speed / 2.0, 1.6, 20.0, 0.0, 100.0, 0);
                let mut zc = ZaicPeak::new(dom, "course").unwrap();
                zc.set_value_wrap(true);
                zc.set_params(course, 0.0, 180.0, 50.0, 0.0, 100.0, 0);
                let i = zc.add_component();
                zc.set_params(angle360(heading), 30.0, 180.0, 5.0, 0.0, 20.0, i);
                let (fc, fs) = (zc.extract(false).unwrap(), zs.extract(true).unwrap());
                let want = behavior_api::ivp::couple(fc, fs, 0.5, 0.5, true).unwrap();
                let got = b.function(course, heading).unwrap();
                assert_eq!(bits(&got), bits(&want), "{k} {course} {heading}");
            }
        }
    }

    #[test]
    fn marks_trail_the_contact_and_are_popped_when_reached() {
        let (mut b, mut helm) = convoy();
        helm.nav(0.0, 0.0, 0.0, 1.0);
        for i in 0..10 {
            helm.time = 1000.0 + i as f64;
            helm.contact("abe", 0.0, 25.0 + 2.0 * i as f64, 0.0, 2.0, "kayak");
            assert!(step(&mut b, &mut helm).is_some());
        }
        // Contact moved 18 m in 2 m steps: a mark each time the gap passed 5 m.
        assert_eq!(b.marks().len(), 4);
        assert_eq!(
            helm.posted("VIEW_POINT")[0],
            "x=0,y=25,label=abe_abe_0,label_color=invisible,vertex_color=white"
        );
        assert_eq!(helm.last("WPTY").as_deref(), Some("25"));
        assert_eq!(helm.last("AVG2").as_deref(), Some("2"));
        // Ownship reaches the first mark: it is erased and the next one is the target.
        helm.nav(0.0, 20.0, 0.0, 1.0);
        step(&mut b, &mut helm);
        assert!(helm
            .posted("VIEW_POINT")
            .contains(&"x=0,y=0,active=false,label=abe_abe_0".to_string()));
        assert_eq!(helm.last("WPTY").as_deref(), Some("31"));
        // Range 23 < tailgating 30: the contact's speed times spd_slower.
        assert_eq!(b.set_speed(), 1.0);
        helm.with(|ctx| b.on_run_to_idle(ctx));
        assert!(b.marks().is_empty());
    }

    #[test]
    fn safety_ranges_and_refusals() {
        let mut b = Convoy::new(&HelmDomain::new("course,0,359,360:speed,0,4,41"));
        let mut helm = MockHelm::new("cnv");
        assert!(helm.with(|ctx| b.set_param(ctx, "rng_estop", "2")));
        assert!(helm.with(|ctx| b.set_param(ctx, "cruise_speed", "5")));
        assert!(!helm.with(|ctx| b.set_param(ctx, "spd_faster", "4")));
        assert!(!helm.with(|ctx| b.set_param(ctx, "spd_slower", "0")));
        assert!(!helm.with(|ctx| b.set_param(ctx, "rng_safety", "maybe")));
        assert!(!helm.with(|ctx| b.set_param(ctx, "radius", "-1")));
        helm.with(|ctx| b.on_params_complete(ctx));
        assert_eq!(b.ranges(), (5.0, 30.0, 70.0));
        assert_eq!(
            helm.posted("BHV_WARNING"),
            [
                "cnv: Safety ranges were auto-adusted bigger.",
                "cnv: Cruise speed auto-capped at max speed."
            ]
        );
        assert_eq!(b.spd_faster, 4.0, "stored although refused (quirk)");
    }
}
