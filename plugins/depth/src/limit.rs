//! BHV_MaxSpeed and BHV_MaxDepth (behaviors-more.md §4, §5): a ZAIC_LEQ over one
//! variable (everything at or below the limit flat, a ramp of `basewidth` above it) and
//! an optional slack posting `limit − NAV_<VAR>` in idle and running iterations.

use std::marker::PhantomData;

use behavior_api::ivp::{self, ZaicLeq};
use behavior_api::kept::Kept;
use behavior_api::params::no_white;
use behavior_api::parse_number;
use behavior_api::sdk::{copy_function_data, Ctx, HelmDomain, IvpBehavior};
use behavior_api::FunctionData;

/// What distinguishes MaxSpeed from MaxDepth.
pub trait LimitKind: Send + 'static {
    /// The decision variable.
    const VAR: &'static str;
    /// The parameter holding the limit.
    const PARAM: &'static str;
    /// Its default.
    const LIMIT: f64;
    const BASEWIDTH: f64;
    const SLACK_PARAM: &'static str;
    const NAV: &'static str;
    /// The warning when the navigation variable is missing.
    const NO_NAV: &'static str;
    /// The error when the builder fails.
    const NO_FUNCTION: &'static str;
}

pub struct SpeedKind;
impl LimitKind for SpeedKind {
    const VAR: &'static str = "speed";
    const PARAM: &'static str = "max_speed";
    const LIMIT: f64 = 1.0;
    const BASEWIDTH: f64 = 0.5;
    const SLACK_PARAM: &'static str = "speed_slack_var";
    const NAV: &'static str = "NAV_SPEED";
    const NO_NAV: &'static str = "No ownship SPEED info in info_buffer.";
    const NO_FUNCTION: &'static str = "Unable to generate max-speed IvP function";
}

pub struct DepthKind;
impl LimitKind for DepthKind {
    const VAR: &'static str = "depth";
    const PARAM: &'static str = "max_depth";
    const LIMIT: f64 = 0.0;
    const BASEWIDTH: f64 = 100.0;
    const SLACK_PARAM: &'static str = "depth_slack_var";
    const NAV: &'static str = "NAV_DEPTH";
    const NO_NAV: &'static str = "No ownship DEPTH info in info_buffer.";
    // The reference's text (it was copied from ConstantDepth).
    const NO_FUNCTION: &'static str = "Unable to generate constant-depth IvP function";
}

/// A cap on one decision variable.
pub struct Limit<K: LimitKind> {
    domain: String,
    ivp_domain: Option<ivp::Domain>,
    limit: f64,
    basewidth: f64,
    slack_var: String,
    /// The function of the last (limit, basewidth), by their bits, without pwt: it only
    /// changes with an update, so it is built once, not every iteration.
    last: Kept<(u64, u64)>,
    kind: PhantomData<K>,
}

/// BHV_MaxSpeed.
pub type MaxSpeed = Limit<SpeedKind>;
/// BHV_MaxDepth.
pub type MaxDepth = Limit<DepthKind>;

impl<K: LimitKind> Limit<K> {
    pub fn new(helm_domain: &HelmDomain) -> Self {
        Limit {
            domain: helm_domain.sub_domain(&[K::VAR]),
            ivp_domain: helm_domain.ivp_domain(&[K::VAR]),
            limit: K::LIMIT,
            basewidth: K::BASEWIDTH,
            slack_var: String::new(),
            last: Kept::default(),
            kind: PhantomData,
        }
    }

    /// (limit, basewidth, slack variable) as configured.
    pub fn settings(&self) -> (f64, f64, &str) {
        (self.limit, self.basewidth, &self.slack_var)
    }

    fn read_ownship(&self, ctx: &mut Ctx<'_>) {
        match ctx.get_buffer_double_val(K::NAV) {
            None => ctx.post_wmessage(K::NO_NAV),
            Some(v) => {
                if !self.slack_var.is_empty() {
                    ctx.post_message_num(&self.slack_var, self.limit - v);
                }
            }
        }
    }
}

impl<K: LimitKind> IvpBehavior for Limit<K> {
    fn domain(&self) -> String {
        self.domain.clone()
    }

    fn default_name(&self) -> String {
        "???".into()
    }

    fn set_param(&mut self, _ctx: &mut Ctx<'_>, param: &str, value: &str) -> bool {
        if param == K::PARAM {
            return parse_number(value)
                .map(|v| self.limit = v.max(0.0))
                .is_some();
        }
        if param == K::SLACK_PARAM {
            return no_white(value.trim())
                .map(|v| self.slack_var = v.to_string())
                .is_some();
        }
        match param {
            "basewidth" | "tolerance" => parse_number(value)
                .map(|v| self.basewidth = v.max(0.0))
                .is_some(),
            _ => false,
        }
    }

    fn on_idle_state(&mut self, ctx: &mut Ctx<'_>) {
        self.read_ownship(ctx);
    }

    fn on_run(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        self.read_ownship(ctx);
        let Some(dom) = self.ivp_domain.as_ref() else {
            ctx.post_emessage(K::NO_FUNCTION);
            return None;
        };
        let var = dom.var(0);
        if self.limit < var.low || self.limit > var.high {
            ctx.post_wmessage("given summit value out of domain range (suspicious):");
        }
        let (limit, basewidth) = (self.limit, self.basewidth);
        let key = (limit.to_bits(), basewidth.to_bits());
        match self
            .last
            .get(key, || build::<K>(dom, limit, basewidth).ok_or(()))
        {
            Ok(f) => Some(copy_function_data(f, ctx.priority())),
            Err(()) => {
                ctx.post_emessage(K::NO_FUNCTION);
                None
            }
        }
    }
}

/// The ZAIC_LEQ of `limit` and `basewidth` over `dom`, without pwt.
fn build<K: LimitKind>(dom: &ivp::Domain, limit: f64, basewidth: f64) -> Option<ivp::IvpFunction> {
    let mut z = ZaicLeq::new(dom, K::VAR).ok()?;
    z.set_summit(limit);
    z.set_base_width(basewidth);
    z.extract()
}

#[cfg(test)]
mod tests {
    use super::*;
    use behavior_api::testing::{function_data_bits, MockHelm};

    fn helm() -> HelmDomain {
        HelmDomain::new("course,0,359,360:speed,0,4,21:depth,0,100,101")
    }

    /// (lo, hi, slope, intercept) per piece, rounded.
    fn pieces(f: &FunctionData) -> Vec<(i32, i32, f64, f64)> {
        let r = |x: f64| (x * 1e5).round() / 1e5 + 0.0;
        (0..f.piece_count().unwrap())
            .map(|k| {
                (
                    f.bounds[2 * k],
                    f.bounds[2 * k + 1],
                    r(f.weights[2 * k]),
                    r(f.weights[2 * k + 1]),
                )
            })
            .collect()
    }

    #[test]
    fn defaults_domains_and_refusals() {
        let mut s = MaxSpeed::new(&helm());
        let d = MaxDepth::new(&helm());
        assert_eq!(
            (s.domain().as_str(), d.domain().as_str()),
            ("speed,0,4,21", "depth,0,100,101")
        );
        assert_eq!(s.settings(), (1.0, 0.5, ""));
        assert_eq!(d.settings(), (0.0, 100.0, ""));
        assert_eq!(s.default_name(), "???");
        assert_eq!(MaxDepth::new(&HelmDomain::new("speed,0,4,21")).domain(), "");
        let mut h = MockHelm::new("cap");
        h.with(|ctx| {
            assert!(s.set_param(ctx, "max_speed", "-2"));
            assert!(s.set_param(ctx, "tolerance", "-1"));
            assert!(!s.set_param(ctx, "max_speed", "fast"));
            assert!(!s.set_param(ctx, "basewidth", ""));
            assert!(!s.set_param(ctx, "speed_slack_var", "A B"));
            assert!(!s.set_param(ctx, "max_depth", "3"));
            assert!(s.set_param(ctx, "speed_slack_var", "SLK"));
        });
        assert_eq!(s.settings(), (0.0, 0.0, "SLK"));
    }

    #[test]
    fn max_speed_worked_example() {
        // speed:0:4:21, max 2.1, tolerance 0.2 -> i1 = 11, i2 = 12, ib = 1.
        let mut s = MaxSpeed::new(&helm());
        let mut h = MockHelm::new("cap");
        h.with(|ctx| {
            s.set_param(ctx, "max_speed", "2.1");
            s.set_param(ctx, "tolerance", "0.2");
            s.set_param(ctx, "speed_slack_var", "SPD_SLACK");
        });
        h.set("NAV_SPEED", 0.0);
        let f = h.with(|ctx| s.on_run(ctx)).unwrap();
        assert_eq!(
            pieces(&f),
            vec![
                (0, 11, 0.00001, 100.0),
                (12, 12, -100.0, 1200.0),
                (13, 20, -0.00001, 0.0)
            ]
        );
        assert_eq!(f.pwt, 100.0);
        assert_eq!(h.last("SPD_SLACK").as_deref(), Some("2.1"));
    }

    #[test]
    fn max_depth_worked_example_and_warnings() {
        let mut d = MaxDepth::new(&helm());
        let mut h = MockHelm::new("cap");
        h.with(|ctx| {
            d.set_param(ctx, "max_depth", "6.3");
            d.set_param(ctx, "tolerance", "1");
        });
        let f = h.with(|ctx| d.on_run(ctx)).unwrap();
        assert_eq!(
            pieces(&f),
            vec![
                (0, 6, 0.00001, 100.0),
                (7, 7, -100.0, 700.0),
                (8, 100, -0.00001, 0.0)
            ]
        );
        assert_eq!(
            h.posted("BHV_WARNING"),
            vec![
                "cap: NAV_DEPTH dbl info not found in helm info_buffer",
                "cap: No ownship DEPTH info in info_buffer."
            ]
        );
        h.clear();
        h.set("NAV_DEPTH", 1.0);
        h.with(|ctx| d.set_param(ctx, "max_depth", "150"));
        assert!(h.with(|ctx| d.on_run(ctx)).is_some());
        assert_eq!(
            h.posted("BHV_WARNING"),
            vec!["cap: given summit value out of domain range (suspicious):"]
        );
    }

    /// The function handed out (copied from the kept one while limit and basewidth
    /// hold) is bit for bit a fresh build's, over updates that change, repeat and come
    /// back, and with the priority changing in between.
    #[test]
    fn kept_function_equals_a_fresh_build() {
        let mut d = MaxDepth::new(&helm());
        let mut h = MockHelm::new("cap");
        let settings = [
            ("6.3", "1"),
            ("6.3", "1"),
            ("20", "1"),
            ("20", "4"),
            ("6.3", "1"),
        ];
        let mut builds = std::collections::HashSet::new();
        for round in 0..40 {
            let (limit, width) = settings[round % settings.len()];
            h.with(|ctx| {
                assert!(d.set_param(ctx, "max_depth", limit));
                assert!(d.set_param(ctx, "tolerance", width));
            });
            h.priority = 100.0 + round as f64;
            let got = h.with(|ctx| d.on_run(ctx)).unwrap();
            let fresh = build::<DepthKind>(d.ivp_domain.as_ref().unwrap(), d.limit, d.basewidth);
            let mut want = fresh.unwrap();
            want.set_pwt(h.with(|ctx| ctx.priority()));
            let want = behavior_api::sdk::function_data(want);
            assert_eq!(
                function_data_bits(&got),
                function_data_bits(&want),
                "round {round}"
            );
            builds.insert((d.limit.to_bits(), d.basewidth.to_bits()));
        }
        assert_eq!(builds.len(), 3);
    }
}
