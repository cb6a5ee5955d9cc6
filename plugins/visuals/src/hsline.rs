//! BHV_HSLine (behaviors-more.md §1): a line from ownship along the helm's last desired
//! heading, its length the desired speed (scaled by the largest seen) times
//! `time_on_leg`.

use behavior_api::geometry::{project_point, push_pts_props_spec, Attrs, Vertex};
use behavior_api::parse_number;
use behavior_api::sdk::{Ctx, HelmDomain, IvpBehavior};
use behavior_api::FunctionData;

pub struct HsLine {
    domain: String,
    time_on_leg: f64,
    /// Largest desired speed seen so far (-1 before any).
    max_seen: f64,
    /// The last line drawn (empty before the first run).
    line: Vec<Vertex>,
    /// The line's attributes' text (`,active=...,label=<ownship>_<name>`), inactive and
    /// active, made once: the label is fixed for a behavior's life (asking for it costs
    /// strings across the ABI) and the line is posted every iteration.
    attrs: Option<[String; 2]>,
    /// The posted text, kept: the line is posted every iteration.
    text: String,
}

impl HsLine {
    pub fn new(helm_domain: &HelmDomain) -> Self {
        let names: Vec<&str> = helm_domain.vars().iter().map(|v| v.name.as_str()).collect();
        HsLine {
            domain: helm_domain.sub_domain(&names),
            time_on_leg: 60.0,
            max_seen: -1.0,
            line: Vec::new(),
            attrs: None,
            text: String::new(),
        }
    }

    /// Post the line as `VIEW_SEGLIST`, active or not (`seglist_spec`'s text).
    fn post(&mut self, ctx: &mut Ctx<'_>, active: bool) {
        let attrs = self.attrs.get_or_insert_with(|| {
            let mut attrs = Attrs {
                label: format!("{}_{}", ctx.ownship(), ctx.name()),
                ..Attrs::default()
            };
            [false, true].map(|a| {
                attrs.active = Some(a);
                let mut text = String::new();
                attrs.push_spec(&mut text);
                text
            })
        });
        self.text.clear();
        push_pts_props_spec(&mut self.text, &self.line, &[], 1);
        self.text.push_str(&attrs[usize::from(active)]);
        ctx.post_message("VIEW_SEGLIST", &self.text);
    }

    /// Post the last line inactive (idle and complete); nothing if it never ran.
    fn erase(&mut self, ctx: &mut Ctx<'_>) {
        if !self.line.is_empty() {
            self.post(ctx, false);
        }
    }
}

impl IvpBehavior for HsLine {
    fn domain(&self) -> String {
        self.domain.clone()
    }

    fn default_name(&self) -> String {
        "bhv_hsline".into()
    }

    fn set_param(&mut self, _ctx: &mut Ctx<'_>, param: &str, value: &str) -> bool {
        match param {
            "time_on_leg" => match parse_number(value) {
                Some(v) if v > 0.0 => {
                    self.time_on_leg = v;
                    true
                }
                _ => false,
            },
            _ => false,
        }
    }

    fn on_params_complete(&mut self, ctx: &mut Ctx<'_>) {
        ctx.add_info_vars("NAV_X, NAV_Y, DESIRED_HEADING, DESIRED_SPEED");
    }

    fn on_idle_state(&mut self, ctx: &mut Ctx<'_>) {
        self.erase(ctx);
    }

    fn on_complete(&mut self, ctx: &mut Ctx<'_>) {
        self.erase(ctx);
    }

    fn on_run(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        const VARS: [&str; 4] = ["DESIRED_HEADING", "DESIRED_SPEED", "NAV_X", "NAV_Y"];
        let mut vals = [0.0; 4];
        let mut found = [false; 4];
        for (i, var) in VARS.iter().enumerate() {
            if let Some(v) = ctx.get_buffer_double_val(var) {
                vals[i] = v;
                found[i] = true;
            }
        }
        for (i, var) in VARS.iter().enumerate() {
            if !found[i] {
                ctx.post_wmessage(&format!("No {var} info in the info_buffer"));
            }
        }
        let [h, s, x, y] = vals;
        if s > self.max_seen {
            self.max_seen = s;
        }
        let pct = if self.max_seen > 0.0 {
            s / self.max_seen
        } else {
            1.0
        };
        let d = s * pct * self.time_on_leg;
        let (x2, y2) = project_point(h, d, x, y);
        self.line.clear();
        self.line.push(Vertex::new(x, y));
        self.line.push(Vertex::new(x2, y2));
        self.post(ctx, true);
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use behavior_api::testing::MockHelm;

    fn hsline() -> (HsLine, MockHelm) {
        let b = HsLine::new(&HelmDomain::new("course,0,359,360:speed,0,4,41"));
        (b, MockHelm::new("hsline"))
    }

    #[test]
    fn domain_name_and_parameters() {
        let (mut b, mut helm) = hsline();
        assert_eq!(b.domain(), "course,0,359,360:speed,0,4,41");
        assert_eq!(b.default_name(), "bhv_hsline");
        assert_eq!(b.time_on_leg, 60.0);
        helm.with(|ctx| {
            assert!(!b.set_param(ctx, "time_on_leg", "0"));
            assert!(!b.set_param(ctx, "time_on_leg", "-3"));
            assert!(!b.set_param(ctx, "time_on_leg", "long"));
            assert!(!b.set_param(ctx, "speed", "1"));
            assert!(b.set_param(ctx, "time_on_leg", "8"));
        });
        assert_eq!(b.time_on_leg, 8.0);
    }

    #[test]
    fn first_iteration_warns_and_draws_a_point() {
        let (mut b, mut helm) = hsline();
        helm.set("NAV_X", 0.0);
        helm.set("NAV_Y", 0.0);
        assert!(helm.with(|ctx| b.on_run(ctx)).is_none());
        let w = helm.posted("BHV_WARNING");
        assert_eq!(w.len(), 4);
        assert_eq!(w[2], "hsline: No DESIRED_HEADING info in the info_buffer");
        assert_eq!(w[3], "hsline: No DESIRED_SPEED info in the info_buffer");
        assert_eq!(
            helm.last("VIEW_SEGLIST").unwrap(),
            "pts={0,0:0,0},active=true,label=abe_hsline"
        );
    }

    #[test]
    fn length_scales_with_the_largest_speed_seen() {
        let (mut b, mut helm) = hsline();
        helm.with(|ctx| b.set_param(ctx, "time_on_leg", "10"));
        helm.nav(10.0, 5.0, 0.0, 0.0);
        helm.set("DESIRED_HEADING", 90.0);
        helm.set("DESIRED_SPEED", 2.0);
        helm.with(|ctx| b.on_run(ctx));
        assert_eq!(
            helm.last("VIEW_SEGLIST").unwrap(),
            "pts={10,5:30,5},active=true,label=abe_hsline"
        );
        // Half the max speed: (1 * 0.5) * 10 = 5 m.
        helm.set("DESIRED_SPEED", 1.0);
        helm.with(|ctx| b.on_run(ctx));
        assert_eq!(
            helm.last("VIEW_SEGLIST").unwrap(),
            "pts={10,5:15,5},active=true,label=abe_hsline"
        );
        helm.clear();
        helm.with(|ctx| b.on_idle_state(ctx));
        assert_eq!(
            helm.last("VIEW_SEGLIST").unwrap(),
            "pts={10,5:15,5},active=false,label=abe_hsline"
        );
    }

    #[test]
    fn idle_before_any_run_posts_nothing() {
        let (mut b, mut helm) = hsline();
        helm.with(|ctx| b.on_idle_state(ctx));
        helm.with(|ctx| b.on_complete(ctx));
        assert!(helm.posts.is_empty());
    }
}
