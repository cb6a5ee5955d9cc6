//! BHV_CutRange (behaviors-contacts.md §2): pursue a contact, blending the rate of
//! closure with the CPA as a fraction of the range; the weight grows with the range.

use behavior_api::contact::ContactBase;
use behavior_api::flag::FlagList;
use behavior_api::ivp::{Domain, Reflector};
use behavior_api::sdk::{function_data, Ctx, HelmDomain, IvpBehavior};
use behavior_api::{parse_number, FunctionData};

use crate::aof::CutRangeAof;

pub struct CutRange {
    base: ContactBase,
    domain: Option<Domain>,
    domain_spec: String,
    pwt_outer_dist: f64,
    pwt_inner_dist: f64,
    giveup_dist: f64,
    patience: f64,
    max_patience: f64,
    pursueflags: FlagList,
    giveupflags: FlagList,
    in_pursuit: bool,
}

impl CutRange {
    pub fn new(helm: &HelmDomain) -> Self {
        CutRange {
            base: ContactBase::new(15.0),
            domain: helm.ivp_domain(&["course", "speed"]),
            domain_spec: helm.sub_domain(&["course", "speed"]),
            pwt_outer_dist: 0.0,
            pwt_inner_dist: 0.0,
            giveup_dist: 0.0,
            patience: 0.0,
            max_patience: 85.0,
            pursueflags: FlagList::default(),
            giveupflags: FlagList::default(),
            in_pursuit: false,
        }
    }

    /// Relevance (§2.3): 0 without a pursuit or a priority range; 1 beyond outer, 0
    /// inside inner, linear between.
    pub fn relevance(&self, r: f64) -> f64 {
        let span = self.pwt_outer_dist - self.pwt_inner_dist;
        if span == 0.0 || !self.in_pursuit {
            return 0.0;
        }
        if r >= self.pwt_outer_dist {
            1.0
        } else if r < self.pwt_inner_dist {
            0.0
        } else {
            (r - self.pwt_inner_dist) / span
        }
    }

    /// Entering the pursuit window posts the pursue flags, leaving it the give-up flags.
    fn pursuit_check(&mut self, ctx: &mut Ctx<'_>) {
        if self.giveup_dist <= 0.0 {
            return;
        }
        let now = self.base.range() <= self.giveup_dist + 1.0;
        let base = &self.base;
        let expand = |s: &str| base.expand_macros(s).unwrap_or_else(|| s.to_string());
        if now && !self.in_pursuit {
            self.pursueflags.post(ctx, false, expand);
        } else if !now && self.in_pursuit {
            self.giveupflags.post(ctx, false, expand);
        }
        self.in_pursuit = now;
    }

    fn build(&self, ctx: &mut Ctx<'_>) -> Option<behavior_api::ivp::IvpFunction> {
        let domain = self.domain.as_ref()?;
        let vmax = domain.var(domain.index_of("speed")?).high;
        let cn = self.base.cn;
        let Some(aof) = CutRangeAof::new(
            (cn.x, cn.y, cn.hdg, cn.spd),
            (self.base.os.x, self.base.os.y),
            self.base.time_on_leg,
            self.patience,
            vmax,
        ) else {
            ctx.post_wmessage("Error in initializing AOF_CutRangeCPA.");
            return None;
        };
        let mut refl = Reflector::new(domain, &aof);
        refl.set_uniform(
            &[("course", 2), ("speed", 3)],
            &[("course", 8), ("speed", 6)],
        );
        refl.create(None, None);
        if !refl.warnings().is_empty() {
            let w = refl.warnings().to_string();
            ctx.post_wmessage(&w);
            return None;
        }
        refl.into_function(true)
    }
}

impl IvpBehavior for CutRange {
    fn domain(&self) -> String {
        self.domain_spec.clone()
    }

    fn default_name(&self) -> String {
        "bhv_cutrange".into()
    }

    fn set_param(&mut self, ctx: &mut Ctx<'_>, param: &str, value: &str) -> bool {
        let param = param.to_ascii_lowercase();
        if let Some(ok) = self.base.set_param_with(ctx, &param, value) {
            return ok;
        }
        let num = parse_number(value);
        match param.as_str() {
            "pwt_outer_dist" => match num {
                Some(v) if v >= 0.0 => {
                    self.pwt_outer_dist = v;
                    self.pwt_inner_dist = self.pwt_inner_dist.min(v);
                    true
                }
                _ => false,
            },
            "pwt_inner_dist" => match num {
                Some(v) if v >= 0.0 => {
                    self.pwt_inner_dist = v;
                    self.pwt_outer_dist = self.pwt_outer_dist.max(v);
                    true
                }
                _ => false,
            },
            "giveup_dist" | "giveup_range" => match num {
                Some(v) if v >= 0.0 => {
                    self.giveup_dist = v;
                    true
                }
                _ => false,
            },
            "patience" | "max_patience" => match num {
                Some(v) if (0.0..=100.0).contains(&v) => {
                    if param == "patience" {
                        self.patience = v;
                    } else {
                        self.max_patience = v;
                    }
                    true
                }
                _ => false,
            },
            "pursueflag" => self.pursueflags.set(value),
            "giveupflag" => self.giveupflags.set(value),
            _ => false,
        }
    }

    fn on_params_complete(&mut self, _ctx: &mut Ctx<'_>) {
        self.patience = self.patience.min(self.max_patience);
    }

    fn on_helm_start(&mut self, ctx: &mut Ctx<'_>) {
        let name = ctx.name();
        let outer = self.pwt_outer_dist;
        if let Some(req) = self.base.alert_request(&name, outer, outer + 1.0) {
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

    fn on_run(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        if !self.base.update_ok {
            return None;
        }
        self.base.handle_cnflags(ctx);
        // The reference refreshes a second time at the start of its run hook.
        if !self.base.update(ctx) {
            return None;
        }
        self.pursuit_check(ctx);
        let relevance = self.relevance(self.base.range());
        if relevance <= 0.0 {
            return None;
        }
        let mut f = self.build(ctx)?;
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

    fn cut() -> (CutRange, MockHelm) {
        let mut b = CutRange::new(&HelmDomain::new("course,0,359,360:speed,0,4,41"));
        let mut helm = MockHelm::new("cut_eve");
        for (p, v) in [
            ("contact", "eve"),
            ("pwt_outer_dist", "100"),
            ("pwt_inner_dist", "10"),
            ("giveup_dist", "120"),
            ("patience", "60"),
            ("pursueflag", "PURSUIT = true"),
            ("giveupflag", "PURSUIT = false"),
        ] {
            assert!(helm.with(|ctx| b.set_param(ctx, p, v)), "{p}");
        }
        assert!(!helm.with(|ctx| b.set_param(ctx, "patience", "101")));
        assert!(!helm.with(|ctx| b.set_param(ctx, "no_alert_request", "true")));
        (b, helm)
    }

    #[test]
    fn pursuit_window_and_relevance() {
        let (mut b, mut helm) = cut();
        helm.nav(0.0, 0.0, 0.0, 1.0);
        helm.contact("eve", 0.0, 130.0, 250.0, 1.2, "kayak");
        helm.with(|ctx| b.on_every_state(ctx));
        assert!(helm.with(|ctx| b.on_run(ctx)).is_none()); // 130 > 121: no pursuit
        assert!(helm.flags.is_empty());
        helm.contact("eve", 0.0, 55.0, 250.0, 1.2, "kayak");
        helm.with(|ctx| b.on_every_state(ctx));
        let f = helm.with(|ctx| b.on_run(ctx)).unwrap();
        // (55 − 10) / 90 = 0.5 of pwt 100.
        assert!((f.pwt - 50.0).abs() < 1e-9);
        assert_eq!(f.piece_count(), Some(2520));
        assert_eq!(helm.flags, vec![("PURSUIT = true".to_string(), false)]);
        helm.contact("eve", 0.0, 5.0, 250.0, 1.2, "kayak");
        helm.with(|ctx| b.on_every_state(ctx));
        assert!(helm.with(|ctx| b.on_run(ctx)).is_none()); // inside inner
    }

    #[test]
    fn giveup_never_produces_with_zero_giveup_dist() {
        let mut b = CutRange::new(&HelmDomain::new("course,0,359,360:speed,0,4,41"));
        let mut helm = MockHelm::new("c");
        for (p, v) in [("contact", "eve"), ("pwt_outer_dist", "100")] {
            assert!(helm.with(|ctx| b.set_param(ctx, p, v)));
        }
        helm.nav(0.0, 0.0, 0.0, 1.0);
        helm.contact("eve", 0.0, 50.0, 0.0, 1.0, "kayak");
        helm.with(|ctx| b.on_every_state(ctx));
        assert!(helm.with(|ctx| b.on_run(ctx)).is_none());
    }
}
