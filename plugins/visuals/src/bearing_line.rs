//! BHV_BearingLine (behaviors-more.md §2): a line from ownship toward a fixed point,
//! `line_pct` percent of the way, and the point itself.

use behavior_api::geometry::{
    dist, parse_point, point_spec, rel_ang, seglist_spec, Attrs, Point, Vertex,
};
use behavior_api::params::parse_bool;
use behavior_api::parse_number;
use behavior_api::sdk::{Ctx, HelmDomain, IvpBehavior};
use behavior_api::FunctionData;

pub struct BearingLine {
    domain: String,
    point: Point,
    line_pct: f64,
    show_pt: bool,
    line: Vec<Vertex>,
    /// Label of the line once it ran (`<ownship>_<name>`).
    label: String,
}

/// The point `d` away at bearing `deg`, always through sin/cos (no axis special cases:
/// the reference's raw projection, which differs from the axis-exact one in the last bit).
pub fn project_raw(deg: f64, d: f64, x: f64, y: f64) -> (f64, f64) {
    let rad = behavior_api::geometry::angle360(deg).to_radians();
    (x + rad.sin() * d, y + rad.cos() * d)
}

impl BearingLine {
    pub fn new(helm_domain: &HelmDomain) -> Self {
        let names: Vec<&str> = helm_domain.vars().iter().map(|v| v.name.as_str()).collect();
        BearingLine {
            domain: helm_domain.sub_domain(&names),
            point: Point {
                x: 0.0,
                y: 0.0,
                z: None,
                attrs: Attrs::default(),
            },
            line_pct: 50.0,
            show_pt: true,
            line: Vec::new(),
            label: String::new(),
        }
    }

    fn post_point(&mut self, ctx: &mut Ctx<'_>, active: bool) {
        // The point spec prints `active` only when false.
        self.point.attrs.active = if active { None } else { Some(false) };
        let spec = point_spec(self.point.x, self.point.y, self.point.z, &self.point.attrs);
        ctx.post_message("VIEW_POINT", &spec);
    }

    fn erase(&mut self, ctx: &mut Ctx<'_>) {
        let attrs = Attrs {
            active: Some(false),
            label: self.label.clone(),
            ..Attrs::default()
        };
        let spec = seglist_spec(&self.line, 1, &attrs);
        // An empty seglist prints just its attributes.
        let spec = spec.strip_prefix("pts={},").unwrap_or(&spec).to_string();
        ctx.post_message("VIEW_SEGLIST", &spec);
        self.post_point(ctx, false);
    }
}

impl IvpBehavior for BearingLine {
    fn domain(&self) -> String {
        self.domain.clone()
    }

    fn default_name(&self) -> String {
        "bhv_bngline".into()
    }

    fn set_param(&mut self, _ctx: &mut Ctx<'_>, param: &str, value: &str) -> bool {
        match param {
            "bearing_point" => match parse_point(value) {
                Some(mut p) => {
                    p.attrs.label = format!("{:.0},{:.0}", p.x, p.y);
                    self.point = p;
                    true
                }
                None => false,
            },
            "line_pct" => parse_number(value)
                .map(|v| self.line_pct = v.clamp(0.0, 100.0))
                .is_some(),
            "show_pt" => parse_bool(value, self.show_pt)
                .map(|v| self.show_pt = v)
                .is_some(),
            _ => false,
        }
    }

    fn on_params_complete(&mut self, ctx: &mut Ctx<'_>) {
        ctx.add_info_vars("NAV_X, NAV_Y");
    }

    fn on_idle_state(&mut self, ctx: &mut Ctx<'_>) {
        self.erase(ctx);
    }

    fn on_complete(&mut self, ctx: &mut Ctx<'_>) {
        self.erase(ctx);
    }

    fn on_run(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        let x = ctx.get_buffer_double_val("NAV_X");
        let y = ctx.get_buffer_double_val("NAV_Y");
        if x.is_none() {
            ctx.post_wmessage("No NAV_X info in the info_buffer");
        }
        if y.is_none() {
            ctx.post_wmessage("No NAV_Y info in the info_buffer");
        }
        let (x, y) = (x.unwrap_or(0.0), y.unwrap_or(0.0));
        let (bx, by) = (self.point.x, self.point.y);
        let d = dist(x, y, bx, by);
        let theta = rel_ang(x, y, bx, by);
        let (ex, ey) = project_raw(theta, (self.line_pct / 100.0) * d, x, y);
        self.line.clear();
        self.line.push(Vertex::new(x, y));
        self.line.push(Vertex::new(ex, ey));
        self.label = format!("{}_{}", ctx.ownship(), ctx.name());
        let attrs = Attrs {
            label: self.label.clone(),
            ..Attrs::default()
        };
        ctx.post_message("VIEW_SEGLIST", &seglist_spec(&self.line, 1, &attrs));
        let show = self.show_pt;
        self.post_point(ctx, show);
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use behavior_api::testing::MockHelm;

    fn bngline(params: &[(&str, &str)]) -> (BearingLine, MockHelm) {
        let mut b = BearingLine::new(&HelmDomain::new("course,0,359,360:speed,0,4,41"));
        let mut helm = MockHelm::new("bngl");
        for (p, v) in params {
            assert!(helm.with(|ctx| b.set_param(ctx, p, v)), "{p}");
        }
        (b, helm)
    }

    #[test]
    fn parameters() {
        let (mut b, mut helm) = bngline(&[("line_pct", "150"), ("show_pt", "off")]);
        assert_eq!(b.default_name(), "bhv_bngline");
        assert_eq!((b.line_pct, b.show_pt), (100.0, false));
        helm.with(|ctx| {
            assert!(!b.set_param(ctx, "bearing_point", "nowhere"));
            assert!(!b.set_param(ctx, "line_pct", "half"));
            assert!(!b.set_param(ctx, "show_pt", "maybe"));
            assert!(b.set_param(ctx, "show_pt", "toggle"));
            assert!(b.set_param(ctx, "line_pct", "-5"));
            assert!(b.set_param(ctx, "bearing_point", "-3.2,7.6"));
        });
        assert_eq!((b.line_pct, b.show_pt), (0.0, true));
        assert_eq!(b.point.attrs.label, "-3,8");
    }

    #[test]
    fn line_halfway_and_the_point() {
        let (mut b, mut helm) = bngline(&[("bearing_point", "100,-100")]);
        helm.nav(0.0, 0.0, 0.0, 0.0);
        assert!(helm.with(|ctx| b.on_run(ctx)).is_none());
        assert_eq!(
            helm.last("VIEW_SEGLIST").unwrap(),
            "pts={0,0:50,-50},label=abe_bngl"
        );
        assert_eq!(
            helm.last("VIEW_POINT").unwrap(),
            "x=100,y=-100,label=100,-100"
        );
        helm.clear();
        helm.with(|ctx| b.on_idle_state(ctx));
        assert_eq!(
            helm.last("VIEW_SEGLIST").unwrap(),
            "pts={0,0:50,-50},active=false,label=abe_bngl"
        );
        assert_eq!(
            helm.last("VIEW_POINT").unwrap(),
            "x=100,y=-100,active=false,label=100,-100"
        );
    }

    #[test]
    fn idle_before_running_and_missing_nav() {
        let (mut b, mut helm) = bngline(&[]);
        helm.with(|ctx| b.on_idle_state(ctx));
        assert_eq!(helm.last("VIEW_SEGLIST").unwrap(), "active=false");
        assert_eq!(helm.last("VIEW_POINT").unwrap(), "x=0,y=0,active=false");
        helm.clear();
        helm.with(|ctx| b.on_run(ctx));
        let w = helm.posted("BHV_WARNING");
        assert_eq!(w.len(), 4);
        assert_eq!(w[2], "bngl: No NAV_X info in the info_buffer");
    }
}
