//! BHV_ConstantHeading (behaviors-plugins.md §3): a wrapping ZAIC_PEAK over `course`
//! around a desired heading snapped to the course grid, an optional mismatch posting and
//! an optional completion threshold.
//!
//! The body is shared with the other Constant* value behaviors (`bhv-plugin-common`,
//! `plugins/common`); this crate names the variable and its defaults, and how a heading
//! is snapped and compared.

use behavior_api::geometry::angles::{angle180, angle360};
use behavior_api::ivp::{Domain, Snap};
use bhv_plugin_common::constant::{ConstantValue, Kind};
use bhv_plugin_common::peak::PeakShape;

/// The heading variant.
pub struct HeadingKind;

impl Kind for HeadingKind {
    const PARAM: &'static str = "heading";
    const VAR: &'static str = "course";
    const DOMAIN_NAME: &'static str = "heading/course";
    const NAV: &'static str = "NAV_HEADING";
    const MISMATCH_PARAM: &'static str = "heading_mismatch_var";
    // peakwidth, basewidth, summitdelta
    const SHAPE: PeakShape = PeakShape::new(10.0, 170.0, 25.0);
    const WRAP: bool = true;
    const COMPLETE_THRESH: bool = true;

    /// Snap a heading onto the course grid (§3.2): angle360, nearest index (ties down),
    /// `low + delta*index`. `None` without a course variable.
    fn desired(domain: Option<&Domain>, h: f64) -> Option<f64> {
        let dom = domain?;
        let idx = dom.snap(0, angle360(h), Snap::Nearest);
        Some(dom.value(0, idx))
    }

    /// The angle between ownship's heading and the desired one, in [0, 180].
    fn mismatch(os: f64, desired: f64) -> f64 {
        angle180(os - desired).abs()
    }
}

/// BHV_ConstantHeading.
pub type ConstantHeading = ConstantValue<HeadingKind>;

behavior_api::export_behaviors! {
    "BHV_ConstantHeading" => ConstantHeading::new,
}

#[cfg(test)]
mod tests {
    use super::*;
    use behavior_api::sdk::{HelmDomain, IvpBehavior};
    use behavior_api::testing::MockHelm as MockHost;
    use bhv_plugin_common::testing::{configured, pieces};

    const HELM: &str = "course,0,359,360:speed,0,2,21";

    fn bhv_in(domain: &str, params: &[(&str, &str)]) -> (ConstantHeading, MockHost) {
        configured(ConstantHeading::new(&HelmDomain::new(domain)), "ch", params)
    }

    fn bhv(params: &[(&str, &str)]) -> (ConstantHeading, MockHost) {
        bhv_in(HELM, params)
    }

    #[test]
    fn domain_and_name() {
        let b = ConstantHeading::new(&HelmDomain::new(HELM));
        assert_eq!(b.domain(), "course,0,359,360");
        assert_eq!(b.default_name(), "???");
        assert_eq!(b.settings().shape, PeakShape::new(10.0, 170.0, 25.0));
        assert_eq!(b.settings().complete_thresh, -1.0);
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
            assert_eq!(b.settings().value, want, "{given}");
        }
        let (b, _) = bhv_in("course,0,359,72", &[("heading", "90")]);
        assert_eq!(b.settings().value, 91.014_084_507_042_26);
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
        assert_eq!(b.settings().shape, PeakShape::new(0.0, 0.0, 100.0));
        assert_eq!(b.settings().complete_thresh, -7.0);
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

    #[test]
    fn missing_course_variable_is_an_error() {
        let (mut b, mut host) = bhv_in("speed,0,2,21", &[("complete_thresh", "0")]);
        host.set("NAV_HEADING", 90.0);
        assert!(host.with(|ctx| b.on_run(ctx)).is_none());
        assert_eq!(
            host.posted("BHV_ERROR"),
            vec!["ch: No 'heading/course' variable in the helm domain"]
        );
        assert_eq!(host.completes, 0);
    }
}
