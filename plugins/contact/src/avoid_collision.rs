//! BHV_AvoidCollision (contacts-appcast.md §3): keep the closest point of approach to
//! one contact above a distance, with a priority that grows as the range shrinks.

use behavior_api::contact::ContactBase;
use behavior_api::contacts::CpaEngine;
use behavior_api::ivp::{Domain, Reflector};
use behavior_api::params::parse_bool;
use behavior_api::sdk::{function_data, Ctx, HelmDomain, IvpBehavior};
use behavior_api::{parse_number, push_fixed, FunctionData};

use crate::aof::AvoidAof;

/// The relevance curve (`pwt_grade`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Grade {
    Linear,
    Quadratic,
    Quasi,
}

pub struct AvoidCollision {
    base: ContactBase,
    domain: Option<Domain>,
    domain_spec: String,
    pwt_outer_dist: f64,
    pwt_inner_dist: f64,
    completed_dist: f64,
    min_util_cpa_dist: f64,
    max_util_cpa_dist: f64,
    grade: Grade,
    /// The `AVD_DEBUG` text of the last run, kept so that the next one is written
    /// without allocating.
    debug_text: String,
}

impl AvoidCollision {
    pub fn new(helm: &HelmDomain) -> Self {
        let mut base = ContactBase::new(120.0);
        base.can_disable = false;
        AvoidCollision {
            base,
            domain: helm.ivp_domain(&["course", "speed"]),
            domain_spec: helm.sub_domain(&["course", "speed"]),
            pwt_outer_dist: 200.0,
            pwt_inner_dist: 50.0,
            completed_dist: 500.0,
            min_util_cpa_dist: 10.0,
            max_util_cpa_dist: 75.0,
            grade: Grade::Quasi,
            debug_text: String::new(),
        }
    }

    /// Relevance by range (§3.5): 0 beyond `pwt_outer_dist`, else the graded
    /// `(outer − r)/(outer − inner)`, deliberately not clamped at 1 inside inner.
    pub fn relevance(&self, r: f64) -> f64 {
        if r >= self.pwt_outer_dist {
            return 0.0;
        }
        let d = (self.pwt_outer_dist - r) / (self.pwt_outer_dist - self.pwt_inner_dist);
        match self.grade {
            Grade::Linear => d,
            Grade::Quadratic => d * d,
            Grade::Quasi => d.powf(1.5),
        }
    }

    /// Complete when the contact fails an exit filter or is past 1.1 × completed_dist.
    fn check_complete(&mut self, ctx: &mut Ctx<'_>) -> bool {
        if self.base.exit_filter_fails() || self.base.range() >= 1.1 * self.completed_dist {
            self.base.complete(ctx);
            return true;
        }
        false
    }

    fn build(&self, ctx: &mut Ctx<'_>, r: f64) -> Option<behavior_api::ivp::IvpFunction> {
        let domain = self.domain.as_ref()?;
        let cd = if r <= self.min_util_cpa_dist {
            r / 2.0
        } else {
            self.min_util_cpa_dist
        };
        if cd > self.max_util_cpa_dist {
            ctx.post_emessage("Unable to init AOF_AvoidCollision.");
            return None;
        }
        let cn = self.base.cn;
        let aof = AvoidAof {
            engine: CpaEngine::new(cn.x, cn.y, cn.hdg, cn.spd, self.base.os.x, self.base.os.y),
            tol: self.base.time_on_leg,
            cd,
            acd: self.max_util_cpa_dist,
        };
        let mut refl = Reflector::new(domain, &aof);
        refl.set_uniform(
            &[("course", 3), ("speed", 3)],
            &[("course", 9), ("speed", 6)],
        );
        refl.create(None, None);
        if !refl.warnings().is_empty() {
            ctx.post_message("AVD_DEBUG", refl.warnings());
        }
        // The reference normalizes the reflector's normalized function once more.
        refl.into_function_normalized_twice()
    }

    fn set_dist(&mut self, param: &str, v: f64) {
        match param {
            "pwt_outer_dist" => {
                self.pwt_outer_dist = v;
                self.pwt_inner_dist = self.pwt_inner_dist.min(v);
            }
            "pwt_inner_dist" => {
                self.pwt_inner_dist = v;
                self.pwt_outer_dist = self.pwt_outer_dist.max(v);
            }
            "completed_dist" => self.completed_dist = v,
            "min_util_cpa_dist" => {
                self.min_util_cpa_dist = v;
                self.max_util_cpa_dist = self.max_util_cpa_dist.max(v);
            }
            _ => {
                self.max_util_cpa_dist = v;
                self.min_util_cpa_dist = self.min_util_cpa_dist.min(v);
            }
        }
    }
}

impl IvpBehavior for AvoidCollision {
    fn domain(&self) -> String {
        self.domain_spec.clone()
    }

    fn default_name(&self) -> String {
        "avoid_collision".into()
    }

    fn set_param(&mut self, ctx: &mut Ctx<'_>, param: &str, value: &str) -> bool {
        let param = param.to_ascii_lowercase();
        if let Some(ok) = self.base.set_param_with(ctx, &param, value) {
            return ok;
        }
        let v = value.trim();
        match param.as_str() {
            "pwt_outer_dist" | "pwt_inner_dist" | "completed_dist" | "min_util_cpa_dist"
            | "max_util_cpa_dist" => match parse_number(v) {
                Some(n) if n >= 0.0 => {
                    self.set_dist(&param, n);
                    true
                }
                _ => false,
            },
            // `active_grade` is the older name m3_casar still uses.
            "pwt_grade" | "active_grade" => {
                self.grade = match v.to_ascii_lowercase().as_str() {
                    "linear" => Grade::Linear,
                    "quadratic" => Grade::Quadratic,
                    "quasi" => Grade::Quasi,
                    _ => return false,
                };
                true
            }
            "no_alert_request" => bool_into(&mut self.base.no_alert_request, v),
            "can_disable" => bool_into(&mut self.base.can_disable, v),
            // The refinery (plateau refinement) is not described by the spec: refusing
            // `true` makes the helm name this line (MALCONFIG) instead of guessing.
            "use_refinery" => parse_bool(v, false) == Some(false),
            // The depth variant is not built: refused, so the line is named.
            "collision_depth" => parse_number(v) == Some(0.0),
            "check_plateaus" | "check_validity" | "verbose" => parse_bool(v, false).is_some(),
            "pcheck_thresh" => parse_number(v).is_some_and(|n| n >= 0.0),
            "roc_max_heighten" | "roc_max_dampen" => parse_number(v).is_some(),
            _ => false,
        }
    }

    fn on_params_complete(&mut self, ctx: &mut Ctx<'_>) {
        self.base.subscribe_able_filter(ctx);
    }

    fn on_helm_start(&mut self, ctx: &mut Ctx<'_>) {
        let name = ctx.name();
        if let Some(req) = self
            .base
            .alert_request(&name, self.pwt_outer_dist, self.completed_dist)
        {
            ctx.post_message("BCM_ALERT_REQUEST", &req);
        }
    }

    fn on_spawn(&mut self, _ctx: &mut Ctx<'_>) {
        self.base.spawned();
    }

    fn on_every_state(&mut self, ctx: &mut Ctx<'_>) {
        self.base.every_state(ctx);
    }

    fn on_idle_state(&mut self, ctx: &mut Ctx<'_>) {
        if self.base.update_ok {
            self.check_complete(ctx);
        }
    }

    fn on_inactive(&mut self, ctx: &mut Ctx<'_>) {
        self.base.post_inactive_bearing_line(ctx);
    }

    fn on_complete(&mut self, ctx: &mut Ctx<'_>) {
        self.base.on_complete();
        self.base.post_inactive_bearing_line(ctx);
    }

    fn on_run(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        if !self.base.update_ok {
            return None;
        }
        let able = self.base.able_filter(ctx, "BHV_AvoidCollision");
        if able.expunge {
            self.base.complete(ctx);
            return None;
        }
        self.base.handle_cnflags(ctx);
        if self.check_complete(ctx) || self.base.disabled {
            return None;
        }
        let r = self.base.range();
        self.debug_text.clear();
        self.debug_text.push_str("In getRelevance: ");
        push_fixed(&mut self.debug_text, r, 5);
        ctx.post_message("AVD_DEBUG", &self.debug_text);
        let relevance = self.relevance(r);
        if relevance <= 0.0 {
            return None;
        }
        let mut f = self.build(ctx, r)?;
        f.set_pwt(relevance * ctx.priority());
        self.base.post_bearing_line(ctx, relevance);
        Some(function_data(f))
    }

    fn expand_macros(&self, text: &str) -> Option<String> {
        self.base.expand_macros(text)
    }
}

fn bool_into(field: &mut bool, v: &str) -> bool {
    match parse_bool(v, *field) {
        Some(b) => {
            *field = b;
            true
        }
        None => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use behavior_api::testing::MockHelm;

    fn avd() -> (AvoidCollision, MockHelm) {
        let mut b = AvoidCollision::new(&HelmDomain::new("course,0,359,360:speed,0,4,41"));
        let mut helm = MockHelm::new("avd_bob");
        for (p, v) in [
            ("contact", "bob"),
            ("pwt_outer_dist", "50"),
            ("pwt_inner_dist", "20"),
            ("completed_dist", "75"),
            ("min_util_cpa_dist", "8"),
            ("max_util_cpa_dist", "25"),
            ("pwt_grade", "linear"),
        ] {
            assert!(helm.with(|ctx| b.set_param(ctx, p, v)), "{p}");
        }
        (b, helm)
    }

    #[test]
    fn relevance_by_hand() {
        let (mut b, _) = avd();
        assert_eq!(b.relevance(50.0), 0.0);
        assert_eq!(b.relevance(35.0), 0.5); // (50 − 35) / 30
        assert_eq!(b.relevance(5.0), 1.5); // not clamped inside inner
        b.grade = Grade::Quadratic;
        assert_eq!(b.relevance(35.0), 0.25);
        b.grade = Grade::Quasi;
        assert!((b.relevance(35.0) - 0.5f64.powf(1.5)).abs() < 1e-12);
    }

    #[test]
    fn distance_pairs_move_together() {
        let (mut b, mut helm) = avd();
        assert!(helm.with(|ctx| b.set_param(ctx, "pwt_outer_dist", "10")));
        assert_eq!((b.pwt_outer_dist, b.pwt_inner_dist), (10.0, 10.0));
        assert!(helm.with(|ctx| b.set_param(ctx, "pwt_inner_dist", "60")));
        assert_eq!((b.pwt_outer_dist, b.pwt_inner_dist), (60.0, 60.0));
        assert!(helm.with(|ctx| b.set_param(ctx, "max_util_cpa_dist", "5")));
        assert_eq!((b.min_util_cpa_dist, b.max_util_cpa_dist), (5.0, 5.0));
        assert!(!helm.with(|ctx| b.set_param(ctx, "pwt_grade", "cubic")));
        assert!(!helm.with(|ctx| b.set_param(ctx, "use_refinery", "true")));
        assert!(helm.with(|ctx| b.set_param(ctx, "use_refinery", "false")));
    }

    #[test]
    fn active_inside_outer_with_weighted_priority() {
        let (mut b, mut helm) = avd();
        helm.priority = 300.0;
        helm.nav(0.0, 0.0, 0.0, 2.0);
        helm.contact("bob", 0.0, 35.0, 180.0, 2.0, "kayak");
        helm.with(|ctx| b.on_every_state(ctx));
        let f = helm.with(|ctx| b.on_run(ctx)).unwrap();
        // relevance 0.5 × pwt 300.
        assert_eq!(f.pwt, 150.0);
        assert_eq!(f.piece_count(), Some(1680));
        assert_eq!(
            helm.last("AVD_DEBUG").as_deref(),
            Some("In getRelevance: 35.00000")
        );
    }

    #[test]
    fn completes_past_one_point_one_completed_dist() {
        let (mut b, mut helm) = avd();
        helm.nav(0.0, 0.0, 0.0, 2.0);
        helm.contact("bob", 0.0, 82.4, 0.0, 2.0, "kayak");
        helm.with(|ctx| b.on_every_state(ctx));
        assert!(helm.with(|ctx| b.on_run(ctx)).is_none());
        assert_eq!(helm.completes, 0);
        helm.contact("bob", 0.0, 82.5, 0.0, 2.0, "kayak");
        helm.with(|ctx| b.on_every_state(ctx));
        assert!(helm.with(|ctx| b.on_run(ctx)).is_none());
        assert_eq!(helm.completes, 1);
        assert_eq!(
            b.expand_macros("$[BHV_POST_MORTEM]").as_deref(),
            Some("rng=82.5#bng=0")
        );
    }
}
