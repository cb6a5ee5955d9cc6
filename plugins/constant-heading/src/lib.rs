//! BHV_ConstantHeading (behaviors-plugins.md §3): a wrapping ZAIC_PEAK over `course`
//! around a desired heading snapped to the course grid, an optional mismatch posting and
//! an optional completion threshold.
//!
//! The host handles the common parameters; note that this type's duration default is 0
//! (§1.2), which the host must apply for it.

use behavior_api::geometry::angles::{angle180, angle360};
use behavior_api::ivp::{self, domain::Snap, zaic::ZaicPeak};
use behavior_api::sdk::{function_data, Ctx, HelmDomain, IvpBehavior};
use behavior_api::{parse_number, FunctionData};
use bhv_plugin_common::no_white;

/// BHV_ConstantHeading.
pub struct ConstantHeading {
    domain: String,
    ivp_domain: Option<ivp::Domain>,
    heading: f64,
    peakwidth: f64,
    basewidth: f64,
    summitdelta: f64,
    complete_thresh: f64,
    mismatch_var: String,
    /// |angle180(NAV_HEADING - heading)| from the last successful read (0 initially).
    heading_delta: f64,
}

impl ConstantHeading {
    pub fn new(helm_domain: &HelmDomain) -> Self {
        ConstantHeading {
            domain: helm_domain.sub_domain(&["course"]),
            ivp_domain: helm_domain.ivp_domain(&["course"]),
            heading: 0.0,
            peakwidth: 10.0,
            basewidth: 170.0,
            summitdelta: 25.0,
            complete_thresh: -1.0,
            mismatch_var: String::new(),
            heading_delta: 0.0,
        }
    }

    /// Snap a heading onto the course grid (§3.2): angle360, nearest index (ties down),
    /// `low + delta*index`. `None` without a course variable.
    fn snap_heading(&self, h: f64) -> Option<f64> {
        let dom = self.ivp_domain.as_ref()?;
        let idx = dom.snap(0, angle360(h), Snap::Nearest);
        Some(dom.value(0, idx))
    }

    /// Read NAV_HEADING (idle and running iterations).
    fn read_ownship(&mut self, ctx: &mut Ctx<'_>) {
        match ctx.get_buffer_double_val("NAV_HEADING") {
            None => ctx.post_wmessage("No ownship HEADING info in info_buffer."),
            Some(os) => {
                self.heading_delta = angle180(os - self.heading).abs();
                if !self.mismatch_var.is_empty() {
                    ctx.post_message_num(&self.mismatch_var, self.heading_delta);
                }
            }
        }
    }

    /// The objective function (§3.4), without pwt.
    fn build(&self) -> Result<ivp::IvpFunction, &'static str> {
        let dom = self
            .ivp_domain
            .as_ref()
            .ok_or("No 'heading/course' variable in the helm domain")?;
        let err = "Unable to generate constant-heading IvP function";
        let mut z = ZaicPeak::new(dom, "course").map_err(|_| err)?;
        z.set_summit(self.heading, 0);
        z.set_base_width(self.basewidth, 0);
        z.set_peak_width(self.peakwidth, 0);
        z.set_summit_delta(self.summitdelta, 0);
        z.set_value_wrap(true);
        z.extract(true).ok_or(err)
    }
}

impl IvpBehavior for ConstantHeading {
    /// The Constant* types default the common `duration` to 0 (behaviors-plugins.md
    /// §1.2): without a `duration` line they complete on their first run.
    fn default_duration(&self) -> Option<f64> {
        Some(0.0)
    }

    fn domain(&self) -> String {
        self.domain.clone()
    }

    fn default_name(&self) -> String {
        // The reference's attempt to set a descriptor fails silently (§1.3).
        "???".into()
    }

    fn set_param(&mut self, _ctx: &mut Ctx<'_>, param: &str, value: &str) -> bool {
        match param {
            "heading" => parse_number(value)
                .and_then(|v| self.snap_heading(v))
                .map(|h| self.heading = h),
            "peakwidth" => parse_number(value).map(|v| self.peakwidth = v.max(0.0)),
            "basewidth" => parse_number(value).map(|v| self.basewidth = v.max(0.0)),
            "summitdelta" => parse_number(value).map(|v| self.summitdelta = v.clamp(0.0, 100.0)),
            "complete_thresh" => parse_number(value).map(|v| self.complete_thresh = v),
            "heading_mismatch_var" => no_white(value).map(|v| self.mismatch_var = v.to_string()),
            _ => None,
        }
        .is_some()
    }

    fn on_idle_state(&mut self, ctx: &mut Ctx<'_>) {
        self.read_ownship(ctx);
    }

    fn on_run(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        self.read_ownship(ctx);
        if self.heading_delta < self.complete_thresh {
            ctx.set_complete();
            return None;
        }
        match self.build() {
            Ok(mut f) => {
                f.set_pwt(ctx.priority());
                Some(function_data(f))
            }
            Err(msg) => {
                ctx.post_emessage(msg);
                None
            }
        }
    }
}

behavior_api::export_behaviors! {
    "BHV_ConstantHeading" => ConstantHeading::new,
}

#[cfg(test)]
mod tests {
    use super::*;
    use behavior_api::testing::MockHelm as MockHost;

    const HELM: &str = "course,0,359,360:speed,0,2,21";

    fn bhv_in(domain: &str, params: &[(&str, &str)]) -> (ConstantHeading, MockHost) {
        let mut b = ConstantHeading::new(&HelmDomain::new(domain));
        let mut host = MockHost::new("ch");
        for (p, v) in params {
            assert!(host.with(|ctx| b.set_param(ctx, p, v)), "{p}={v}");
        }
        (b, host)
    }

    fn bhv(params: &[(&str, &str)]) -> (ConstantHeading, MockHost) {
        bhv_in(HELM, params)
    }

    fn pieces(f: &FunctionData) -> Vec<(i32, i32, f64, f64)> {
        let r = |x: f64| (x * 1e4).round() / 1e4 + 0.0;
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
    fn domain_and_name() {
        let b = ConstantHeading::new(&HelmDomain::new(HELM));
        assert_eq!(b.domain(), "course,0,359,360");
        assert_eq!(b.default_name(), "???");
    }

    #[test]
    fn heading_snapping() {
        for (given, want) in [
            ("10.5", 10.0),
            ("10.6", 11.0),
            ("359.7", 359.0),
            ("-90", 270.0),
            ("725", 5.0),
            ("0", 0.0),
        ] {
            let (b, _) = bhv(&[("heading", given)]);
            assert_eq!(b.heading, want, "{given}");
        }
        let (b, _) = bhv_in("course,0,359,72", &[("heading", "90")]);
        assert_eq!(b.heading, 91.014_084_507_042_26);
        // Without a course variable the heading is rejected.
        let mut b = ConstantHeading::new(&HelmDomain::new("speed,0,2,21"));
        let mut host = MockHost::new("ch");
        assert!(!host.with(|ctx| b.set_param(ctx, "heading", "90")));
        assert_eq!(b.domain(), "");
    }

    #[test]
    fn parameter_validation() {
        let (mut b, mut host) = bhv(&[
            ("peakwidth", "-1"),
            ("basewidth", "-1"),
            ("summitdelta", "101"),
            ("complete_thresh", "-7"),
            ("heading_mismatch_var", "HM"),
        ]);
        assert_eq!(
            (b.peakwidth, b.basewidth, b.summitdelta, b.complete_thresh),
            (0.0, 0.0, 100.0, -7.0)
        );
        host.with(|ctx| {
            assert!(!b.set_param(ctx, "heading", "east"));
            assert!(!b.set_param(ctx, "complete_thresh", "x"));
            assert!(!b.set_param(ctx, "heading_mismatch_var", "H M"));
            assert!(!b.set_param(ctx, "speed", "1"));
        });
    }

    #[test]
    fn default_function_summit_359() {
        let (mut b, mut host) = bhv(&[("heading", "359.7")]);
        host.set("NAV_HEADING", 90.0);
        let f = host.with(|ctx| b.on_run(ctx)).unwrap();
        assert_eq!(
            pieces(&f),
            vec![
                (0, 9, -2.5, 97.5),
                (10, 179, -0.4412, 78.9706),
                (180, 349, 0.4412, -78.9706),
                (350, 359, 2.5, -797.5)
            ]
        );
        assert_eq!(f.pwt, 100.0);
    }

    #[test]
    fn worked_examples_pieces() {
        let (mut b, mut host) =
            bhv(&[("heading", "10.6"), ("peakwidth", "0"), ("basewidth", "90")]);
        host.set("NAV_HEADING", 0.0);
        let f = host.with(|ctx| b.on_run(ctx)).unwrap();
        assert_eq!(
            pieces(&f),
            vec![
                (0, 11, 1.1111, 87.7778),
                (12, 101, -1.1111, 112.2222),
                (102, 281, 0.0, 0.0),
                (282, 359, 1.1111, -312.2222)
            ]
        );
        let (mut b, mut host) = bhv(&[("heading", "90"), ("summitdelta", "0")]);
        host.set("NAV_HEADING", 0.0);
        let f = host.with(|ctx| b.on_run(ctx)).unwrap();
        assert_eq!(
            pieces(&f),
            vec![
                (0, 80, 0.5882, 52.9412),
                (81, 100, 0.0, 100.0),
                (101, 270, -0.5882, 158.8235),
                (271, 359, 0.5882, -158.8235)
            ]
        );
        host.with(|ctx| assert!(b.set_param(ctx, "basewidth", "0")));
        let f = host.with(|ctx| b.on_run(ctx)).unwrap();
        assert_eq!(
            pieces(&f),
            vec![
                (0, 79, 0.0, 0.0),
                (80, 100, 0.0, 100.0),
                (101, 359, 0.0, 0.0)
            ]
        );
    }

    #[test]
    fn mismatch_and_completion() {
        let (mut b, mut host) = bhv(&[
            ("heading", "359.7"),
            ("complete_thresh", "5"),
            ("heading_mismatch_var", "HDG_MISMATCH"),
        ]);
        host.set("NAV_HEADING", 90.0);
        assert!(host.with(|ctx| b.on_run(ctx)).is_some());
        assert_eq!(host.posted("HDG_MISMATCH"), vec!["91"]);
        assert_eq!(host.completes, 0);
        host.set("NAV_HEADING", 3.0);
        assert!(host.with(|ctx| b.on_run(ctx)).is_none());
        assert_eq!(host.last("HDG_MISMATCH").unwrap(), "4");
        assert_eq!(host.completes, 1);
    }

    #[test]
    fn strict_threshold_and_missing_heading() {
        // complete_thresh 0 never fires, even exactly on heading.
        let (mut b, mut host) = bhv(&[("heading", "72.4"), ("complete_thresh", "0")]);
        host.set("NAV_HEADING", 72.0);
        assert!(host.with(|ctx| b.on_run(ctx)).is_some());
        assert_eq!(host.completes, 0);

        // Without NAV_HEADING the delta stays 0 (initial), so a positive threshold
        // completes at once; warnings in idle and running iterations.
        let (mut b, mut host) = bhv(&[("heading", "90"), ("complete_thresh", "1")]);
        host.with(|ctx| b.on_idle_state(ctx));
        assert_eq!(
            host.posted("BHV_WARNING"),
            vec![
                "ch: NAV_HEADING dbl info not found in helm info_buffer",
                "ch: No ownship HEADING info in info_buffer."
            ]
        );
        assert!(host.with(|ctx| b.on_run(ctx)).is_none());
        assert_eq!(host.completes, 1);
    }
}
