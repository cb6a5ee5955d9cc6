//! BHV_PModelView (behaviors-more.md §3): draws the helm's platform-model turn path (a
//! "seglr": vertices and a ray) toward the current DESIRED_HEADING. Never produces a
//! function.
//!
//! The helm's platform model is the default `holo` generator here (the seglr is the
//! single vertex NAV_X, NAV_Y): pHelmIvP's `pmgen` is accepted by our helm but not
//! handed to behaviors, so the `dubins` model of §3.4 is not drawn.

use behavior_api::params::non_negative;
use behavior_api::platform::platform_update;
use behavior_api::sdk::{Ctx, HelmDomain, IvpBehavior};
use behavior_api::{is_color, FunctionData};

pub struct PModelView {
    domain: String,
    /// Stored and checked, never used (as in the reference).
    edge_color: String,
    vertex_color: String,
    vertex_size: f64,
    /// The last desired heading read.
    last_hd: f64,
}

impl PModelView {
    pub fn new(helm_domain: &HelmDomain) -> Self {
        PModelView {
            domain: helm_domain.sub_domain(&["course", "speed"]),
            edge_color: "white".into(),
            vertex_color: "white".into(),
            vertex_size: 3.0,
            last_hd: 0.0,
        }
    }

    /// (edge colour, vertex colour, vertex size) as configured.
    pub fn settings(&self) -> (&str, &str, f64) {
        (&self.edge_color, &self.vertex_color, self.vertex_size)
    }

    /// The `pts={x,y}` part of the holo model's seglr; empty before any navigation.
    fn pts(ctx: &mut Ctx<'_>) -> String {
        match (
            ctx.get_buffer_double_val_quiet("NAV_X"),
            ctx.get_buffer_double_val_quiet("NAV_Y"),
        ) {
            (Some(x), Some(y)) => format!("pts={{{x:.1},{y:.1}}},"),
            _ => String::new(),
        }
    }
}

impl IvpBehavior for PModelView {
    fn domain(&self) -> String {
        self.domain.clone()
    }

    fn default_name(&self) -> String {
        "???".into()
    }

    fn set_param(&mut self, _ctx: &mut Ctx<'_>, param: &str, value: &str) -> bool {
        let v = value.trim();
        match param {
            "edge_color" | "vertex_color" if is_color(v) => {
                let slot = if param == "edge_color" {
                    &mut self.edge_color
                } else {
                    &mut self.vertex_color
                };
                *slot = v.to_string();
                true
            }
            "vertex_size" => non_negative(v).map(|n| self.vertex_size = n).is_some(),
            _ => false,
        }
    }

    fn on_params_complete(&mut self, ctx: &mut Ctx<'_>) {
        ctx.add_info_vars("NAV_X, NAV_Y, NAV_HEADING, NAV_SPEED, DESIRED_HEADING, DESIRED_SPEED");
    }

    fn on_run_to_idle(&mut self, ctx: &mut Ctx<'_>) {
        let spec = format!(
            "{}ray={:.1},active=false,label={}_seglr,ray_len=5,head_size=3",
            Self::pts(ctx),
            self.last_hd,
            ctx.ownship()
        );
        ctx.post_message("VIEW_SEGLR", &spec);
    }

    fn on_run(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        let p = platform_update(ctx)?;
        let hd = ctx.get_buffer_double_val("DESIRED_HEADING").unwrap_or(0.0);
        let sd = ctx.get_buffer_double_val("DESIRED_SPEED").unwrap_or(0.0);
        self.last_hd = hd;
        if sd == 0.0 {
            return None;
        }
        let spec = format!(
            "pts={{{:.1},{:.1}}},ray={hd:.1},label={}_seglr,vertex_color=lime_green,vertex_size=2,ray_len=20,head_size=1",
            p.x,
            p.y,
            ctx.ownship()
        );
        ctx.post_message("VIEW_SEGLR", &spec);
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use behavior_api::testing::MockHelm;

    fn view() -> (PModelView, MockHelm) {
        let b = PModelView::new(&HelmDomain::new("course,0,359,360:speed,0,4,41"));
        (b, MockHelm::new("pmv"))
    }

    #[test]
    fn draws_the_seglr_only_with_a_desired_speed() {
        let (mut b, mut helm) = view();
        assert_eq!(b.domain(), "course,0,359,360:speed,0,4,41");
        assert_eq!(b.default_name(), "???");
        helm.nav(0.0, 0.5, 0.0, 0.0);
        helm.set("DESIRED_HEADING", 0.0);
        helm.set("DESIRED_SPEED", 0.0);
        assert!(helm.with(|ctx| b.on_run(ctx)).is_none());
        assert!(helm.posted("VIEW_SEGLR").is_empty());
        helm.set("DESIRED_SPEED", 1.2);
        helm.set("DESIRED_HEADING", 45.25);
        helm.with(|ctx| b.on_run(ctx));
        let own = helm.with(|ctx| ctx.ownship());
        assert_eq!(
            helm.last("VIEW_SEGLR").unwrap(),
            format!("pts={{0.0,0.5}},ray=45.2,label={own}_seglr,vertex_color=lime_green,vertex_size=2,ray_len=20,head_size=1")
        );
        helm.with(|ctx| b.on_run_to_idle(ctx));
        assert_eq!(
            helm.last("VIEW_SEGLR").unwrap(),
            format!(
                "pts={{0.0,0.5}},ray=45.2,active=false,label={own}_seglr,ray_len=5,head_size=3"
            )
        );
    }

    #[test]
    fn missing_desired_values_warn_and_missing_nav_is_an_error() {
        let (mut b, mut helm) = view();
        helm.nav(1.0, 2.0, 90.0, 1.0);
        helm.with(|ctx| b.on_run(ctx));
        assert_eq!(helm.posted("BHV_WARNING").len(), 2);
        assert!(helm.posted("VIEW_SEGLR").is_empty());
        helm.unset("NAV_X");
        helm.with(|ctx| b.on_run(ctx));
        assert_eq!(helm.posted("BHV_ERROR").len(), 1);
    }

    #[test]
    fn parameters_refuse_bad_values() {
        let (mut b, mut helm) = view();
        assert!(helm.with(|ctx| b.set_param(ctx, "edge_color", "red")));
        assert!(!helm.with(|ctx| b.set_param(ctx, "vertex_color", "notacolor")));
        assert!(helm.with(|ctx| b.set_param(ctx, "vertex_size", "4")));
        assert!(!helm.with(|ctx| b.set_param(ctx, "vertex_size", "-1")));
        assert!(!helm.with(|ctx| b.set_param(ctx, "ray_len", "4")));
        assert_eq!(b.settings(), ("red", "white", 4.0));
    }
}
