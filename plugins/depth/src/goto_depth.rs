//! BHV_GoToDepth (behaviors-more.md §6): drive through a list of depth levels, holding
//! each for its time, `repeat` extra passes, then complete.

use behavior_api::ivp::{self, ZaicPeak};
use behavior_api::kept::Kept;
use behavior_api::sdk::{copy_function_data, Ctx, HelmDomain, IvpBehavior};
use behavior_api::FunctionData;
use behavior_api::{atof, is_number};

/// One level: depth and seconds to hold it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Level {
    pub depth: f64,
    pub time: f64,
}

pub struct GoToDepth {
    domain: String,
    ivp_domain: Option<ivp::Domain>,
    levels: Vec<Level>,
    repeat: i64,
    arrival_delta: f64,
    /// The arrival variable (`GTD_<flag>`), empty when no flag was given.
    arrival_var: Option<String>,
    ix: usize,
    arrivals: u32,
    prior: f64,
    plateau: bool,
    plateau_start: f64,
    first: bool,
    /// The function of the last level's depth (by its bits), without pwt: it depends on
    /// nothing else, so while the level holds it is copied, not built again.
    last: Kept<u64>,
}

/// What an advance to the next level did.
enum Advance {
    Advanced,
    Finished,
}

impl GoToDepth {
    pub fn new(helm_domain: &HelmDomain) -> Self {
        GoToDepth {
            domain: helm_domain.sub_domain(&["depth"]),
            ivp_domain: helm_domain.ivp_domain(&["depth"]),
            levels: Vec::new(),
            repeat: 0,
            arrival_delta: 1.0,
            arrival_var: None,
            ix: 0,
            arrivals: 0,
            prior: 0.0,
            plateau: false,
            plateau_start: 0.0,
            first: true,
            last: Kept::default(),
        }
    }

    pub fn levels(&self) -> &[Level] {
        &self.levels
    }

    /// Append the `D[,T]` elements of `value` one by one; a bad element refuses the
    /// line but keeps those appended before it (the reference's behavior).
    fn add_levels(&mut self, value: &str) -> bool {
        if value.is_empty() {
            return true;
        }
        for elem in value.split(':') {
            let fields: Vec<&str> = elem.split(',').collect();
            if fields.len() > 2 || !fields.iter().all(|f| is_number(f)) {
                return false;
            }
            let depth = atof(fields[0]);
            let time = fields.get(1).map_or(0.0, |t| atof(t));
            if depth < 0.0 || time < 0.0 {
                return false;
            }
            self.levels.push(Level { depth, time });
        }
        true
    }

    fn advance(&mut self, ctx: &mut Ctx<'_>) -> Advance {
        self.ix += 1;
        if self.ix >= self.levels.len() {
            if self.repeat == 0 {
                ctx.set_complete();
                if ctx.perpetual() {
                    self.ix = 0;
                    self.first = true;
                    self.arrivals = 0;
                }
                return Advance::Finished;
            }
            self.repeat -= 1;
            self.ix = 0;
        }
        ctx.post_message_num("LEVEL_DEPTH", self.levels[self.ix].depth);
        Advance::Advanced
    }

    fn function(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        let depth = self.levels[self.ix].depth;
        let dom = &self.ivp_domain;
        let kept = self
            .last
            .get(depth.to_bits(), || build(dom, depth).ok_or(()));
        Some(copy_function_data(kept.ok()?, ctx.priority()))
    }
}

/// The function of holding `depth`, without pwt.
fn build(dom: &Option<ivp::Domain>, depth: f64) -> Option<ivp::IvpFunction> {
    let mut z = ZaicPeak::new(dom.as_ref()?, "depth").ok()?;
    z.set_summit(depth, 0);
    z.set_base_width(5.0, 0);
    z.set_peak_width(0.0, 0);
    z.extract(true)
}

impl IvpBehavior for GoToDepth {
    fn domain(&self) -> String {
        self.domain.clone()
    }

    fn default_name(&self) -> String {
        "bhv_goto_depth".into()
    }

    fn set_param(&mut self, _ctx: &mut Ctx<'_>, param: &str, value: &str) -> bool {
        match param {
            "depth" => self.add_levels(value),
            "repeat" => {
                if !is_number(value) {
                    return false;
                }
                // The reference takes the integer part (atoi).
                let v = atof(value).trunc();
                if v < 0.0 {
                    return false;
                }
                self.repeat = v.min(i64::MAX as f64) as i64;
                true
            }
            "arrival_delta" | "capture_delta" => match behavior_api::params::non_negative(value) {
                Some(v) => {
                    self.arrival_delta = v;
                    true
                }
                None => false,
            },
            "arrival_flag" | "capture_flag" => {
                self.arrival_var = Some(format!("GTD_{value}"));
                true
            }
            _ => false,
        }
    }

    fn on_params_complete(&mut self, ctx: &mut Ctx<'_>) {
        ctx.add_info_vars("NAV_DEPTH");
    }

    fn on_run(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        let Some(v) = ctx.get_buffer_double_val("NAV_DEPTH") else {
            ctx.post_emessage("No ownship Depth info in Helm info_buffer.");
            return None;
        };
        if self.levels.is_empty() {
            // The reference reads past its empty list here; we refuse to steer instead.
            ctx.post_wmessage("No depth levels given");
            return None;
        }
        let now = ctx.get_buffer_curr_time();
        let mut test_arrival = true;
        if self.plateau {
            if now - self.plateau_start >= self.levels[self.ix].time {
                self.plateau = false;
                if let Advance::Finished = self.advance(ctx) {
                    self.first = false;
                    return None;
                }
            } else {
                test_arrival = false;
            }
        }
        if test_arrival {
            let d = self.levels[self.ix].depth;
            let arrived = (v - d).abs() <= self.arrival_delta
                || (!self.first && v >= d && d >= self.prior)
                || (!self.first && v <= d && d <= self.prior);
            if arrived {
                self.arrivals += 1;
                if let Some(var) = &self.arrival_var {
                    ctx.post_message_num(var, f64::from(self.arrivals));
                }
                self.plateau = true;
                self.plateau_start = now;
            }
            self.prior = v;
        }
        self.first = false;
        self.function(ctx)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use behavior_api::testing::{function_data_bits, MockHelm};

    fn gtd(params: &[(&str, &str)]) -> (GoToDepth, MockHelm) {
        let mut b = GoToDepth::new(&HelmDomain::new("speed,0,4,41:depth,0,50,51"));
        let mut helm = MockHelm::new("levels");
        for (p, v) in params {
            assert!(helm.with(|ctx| b.set_param(ctx, p, v)), "{p}={v}");
        }
        (b, helm)
    }

    /// The depth index with the highest utility.
    fn best(f: &FunctionData) -> i32 {
        let mut best = (f64::NEG_INFINITY, 0);
        for k in 0..f.piece_count().unwrap() {
            for i in f.bounds[2 * k]..=f.bounds[2 * k + 1] {
                let v = f.weights[2 * k] * f64::from(i) + f.weights[2 * k + 1];
                if v > best.0 {
                    best = (v, i);
                }
            }
        }
        best.1
    }

    #[test]
    fn level_lists_append_and_bad_elements_refuse_the_line() {
        let (mut b, mut helm) = gtd(&[("depth", "12,6:24,10"), ("depth", "")]);
        assert_eq!(b.default_name(), "bhv_goto_depth");
        assert_eq!(b.domain(), "depth,0,50,51");
        helm.with(|ctx| {
            assert!(!b.set_param(ctx, "depth", "6:-1,3:8"));
            assert!(!b.set_param(ctx, "depth", "1,2,3"));
            assert!(!b.set_param(ctx, "depth", "deep"));
            assert!(!b.set_param(ctx, "repeat", "-1"));
            assert!(!b.set_param(ctx, "capture_delta", "-1"));
            assert!(b.set_param(ctx, "repeat", "2.7"));
            assert!(b.set_param(ctx, "arrival_flag", ""));
        });
        let depths: Vec<f64> = b.levels().iter().map(|l| l.depth).collect();
        // "6" was appended before "-1,3" refused the line.
        assert_eq!(depths, vec![12.0, 24.0, 6.0]);
        assert_eq!(b.repeat, 2);
        assert_eq!(b.arrival_var.as_deref(), Some("GTD_"));
    }

    #[test]
    fn arrive_hold_advance_and_complete() {
        let (mut b, mut helm) = gtd(&[("depth", "6,10:3"), ("capture_flag", "ACH")]);
        helm.set("NAV_DEPTH", 0.0);
        let f = helm.with(|ctx| b.on_run(ctx)).unwrap();
        assert_eq!(best(&f), 6);
        assert!(helm.posted("GTD_ACH").is_empty());
        // Crossing the level counts as arrival.
        helm.set("NAV_DEPTH", 7.5);
        helm.time += 1.0;
        helm.with(|ctx| b.on_run(ctx)).unwrap();
        assert_eq!(helm.posted("GTD_ACH"), vec!["1"]);
        // Held for 10 s, then the next level.
        helm.time += 9.0;
        helm.with(|ctx| b.on_run(ctx)).unwrap();
        assert!(helm.posted("LEVEL_DEPTH").is_empty());
        helm.time += 1.0;
        let f = helm.with(|ctx| b.on_run(ctx)).unwrap();
        assert_eq!(helm.posted("LEVEL_DEPTH"), vec!["3"]);
        assert_eq!(best(&f), 3);
        helm.set("NAV_DEPTH", 3.2);
        helm.time += 1.0;
        helm.with(|ctx| b.on_run(ctx)).unwrap();
        assert_eq!(helm.posted("GTD_ACH"), vec!["1", "2"]);
        // Hold time 0: done at the next iteration, no function.
        helm.time += 1.0;
        assert!(helm.with(|ctx| b.on_run(ctx)).is_none());
        assert_eq!(helm.completes, 1);
    }

    /// The function handed out while a level holds (copied from the kept one) is bit for
    /// bit the fresh build's, over levels that change, repeat and come back.
    #[test]
    fn kept_level_function_equals_a_fresh_build() {
        let (mut b, mut helm) = gtd(&[("depth", "12,6:24,10:6,0:24,0:0.5,1:-0,1")]);
        let mut seen = std::collections::HashSet::new();
        for round in 0..200 {
            b.ix = [0, 1, 1, 2, 3, 3, 4, 5, 0][round % 9] % b.levels.len();
            let depth = b.levels[b.ix].depth;
            seen.insert(depth.to_bits());
            let got = helm.with(|ctx| b.function(ctx)).unwrap();
            let mut want = build(&b.ivp_domain, depth).unwrap();
            want.set_pwt(helm.with(|ctx| ctx.priority()));
            let want = behavior_api::sdk::function_data(want);
            assert_eq!(
                function_data_bits(&got),
                function_data_bits(&want),
                "round {round}"
            );
        }
        assert_eq!(seen.len(), 5);
    }

    #[test]
    fn missing_depth_is_an_error_and_no_levels_a_warning() {
        let (mut b, mut helm) = gtd(&[]);
        assert!(helm.with(|ctx| b.on_run(ctx)).is_none());
        assert_eq!(
            helm.last("BHV_ERROR").as_deref(),
            Some("levels: No ownship Depth info in Helm info_buffer.")
        );
        helm.set("NAV_DEPTH", 1.0);
        assert!(helm.with(|ctx| b.on_run(ctx)).is_none());
        assert_eq!(
            helm.last("BHV_WARNING").as_deref(),
            Some("levels: No depth levels given")
        );
    }
}
