//! BHV_Timer (behaviors-std.md §4): no objective function; reports how long it has been
//! idle and running.

use behavior_api::sdk::{Ctx, HelmDomain, IvpBehavior};
use behavior_api::FunctionData;

use crate::common::no_white;

/// The BHV_Timer behavior.
pub struct BhvTimer {
    domain: String,
    var_idle: String,
    var_running: String,
    suffix: String,
}

impl BhvTimer {
    pub fn new(helm: &HelmDomain) -> Self {
        let names: Vec<&str> = helm.vars().iter().map(|v| v.name.as_str()).collect();
        BhvTimer {
            domain: helm.sub_domain(&names),
            var_idle: "TIMER_IDLE".into(),
            var_running: "TIMER_RUNNING".into(),
            suffix: String::new(),
        }
    }

    fn post_status(&self, ctx: &mut Ctx<'_>) {
        let idle = ctx.dur_idle_time();
        let run = ctx.dur_run_time();
        ctx.post_message_num(&suffixed(&self.var_idle, &self.suffix), idle);
        ctx.post_message_num(&suffixed(&self.var_running, &self.suffix), run);
    }
}

/// `var` with the suffix; without one, the name as it is (no string built per post).
fn suffixed<'a>(var: &'a str, suffix: &str) -> std::borrow::Cow<'a, str> {
    if suffix.is_empty() {
        var.into()
    } else {
        format!("{var}{suffix}").into()
    }
}

impl IvpBehavior for BhvTimer {
    fn domain(&self) -> String {
        self.domain.clone()
    }

    fn default_name(&self) -> String {
        "bhv_timer".into()
    }

    fn set_param(&mut self, _ctx: &mut Ctx<'_>, param: &str, value: &str) -> bool {
        match param {
            "var_status_idle" => match no_white(value) {
                Some(v) => self.var_idle = v.to_string(),
                None => return false,
            },
            "var_status_running" => match no_white(value) {
                Some(v) => self.var_running = v.to_string(),
                None => return false,
            },
            "status_suffix" => {
                let v = value.trim();
                self.suffix = if v.is_empty() || v.starts_with('_') {
                    v.to_string()
                } else {
                    format!("_{v}")
                };
            }
            _ => return false,
        }
        true
    }

    fn on_idle_state(&mut self, ctx: &mut Ctx<'_>) {
        self.post_status(ctx);
    }

    fn on_run(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        self.post_status(ctx);
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use behavior_api::testing::MockHelm as MockHost;

    #[test]
    fn timer_posts_durations() {
        let helm = HelmDomain::new("course,0,359,360:speed,0,2,21");
        let mut t = BhvTimer::new(&helm);
        assert_eq!(t.domain(), "course,0,359,360:speed,0,2,21");
        let mut h = MockHost::new("wpt");
        assert!(h.with(|c| t.set_param(c, "status_suffix", "a")));
        assert!(!h.with(|c| t.set_param(c, "var_status_idle", "A B")));
        assert!(h.with(|c| t.set_param(c, "var_status_running", "RUN")));
        assert!(!h.with(|c| t.set_param(c, "bogus", "1")));
        h.idle_time = 2.5;
        h.run_time = 0.25;
        h.with(|c| t.on_idle_state(c));
        assert!(h.with(|c| t.on_run(c)).is_none());
        assert_eq!(h.posted("TIMER_IDLE_a"), vec!["2.5", "2.5"]);
        assert_eq!(h.posted("RUN_a"), vec!["0.25", "0.25"]);
    }
}
