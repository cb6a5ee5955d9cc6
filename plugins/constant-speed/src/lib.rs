//! BHV_ConstantSpeed (behaviors-plugins.md §2): a ZAIC_PEAK over `speed` around a
//! desired speed, every running iteration, plus an optional mismatch posting.
//!
//! The body is shared with the other Constant* value behaviors (`bhv-plugin-common`,
//! `plugins/common`); this crate names the variable and its defaults.

use bhv_plugin_common::constant::{ConstantValue, Kind};
use bhv_plugin_common::peak::PeakShape;

/// The speed variant.
pub struct SpeedKind;

impl Kind for SpeedKind {
    const PARAM: &'static str = "speed";
    const NAV: &'static str = "NAV_SPEED";
    const MISMATCH_PARAM: &'static str = "speed_mismatch_var";
    // peakwidth, basewidth, summitdelta
    const SHAPE: PeakShape = PeakShape::new(0.0, 0.2, 0.0);
}

/// BHV_ConstantSpeed.
pub type ConstantSpeed = ConstantValue<SpeedKind>;

behavior_api::export_behaviors! {
    "BHV_ConstantSpeed" => ConstantSpeed::new,
}

#[cfg(test)]
mod tests {
    use super::*;
    use behavior_api::sdk::{HelmDomain, IvpBehavior};
    use behavior_api::testing::MockHelm as MockHost;
    use bhv_plugin_common::testing::{configured, pieces};

    fn helm() -> HelmDomain {
        HelmDomain::new("course,0,359,360:speed,0,2,21")
    }

    fn bhv(params: &[(&str, &str)]) -> (ConstantSpeed, MockHost) {
        configured(ConstantSpeed::new(&helm()), "cs", params)
    }

    #[test]
    fn domain_and_name() {
        let b = ConstantSpeed::new(&helm());
        assert_eq!(b.domain(), "speed,0,2,21");
        assert_eq!(b.default_name(), "???");
        let b = ConstantSpeed::new(&HelmDomain::new("course,0,359,360"));
        assert_eq!(b.domain(), "");
    }

    #[test]
    fn parameters_are_validated_and_clipped() {
        let (mut b, mut host) = bhv(&[
            ("speed", "-1"),
            ("peakwidth", "-3"),
            ("basewidth", "-0.5"),
            ("summitdelta", "150"),
            ("speed_mismatch_var", "SPD_MM"),
        ]);
        assert_eq!(b.settings().value, 0.0);
        assert_eq!(b.settings().shape, PeakShape::new(0.0, 0.0, 100.0));
        assert_eq!(b.settings().mismatch_var, "SPD_MM");
        host.with(|ctx| {
            assert!(!b.set_param(ctx, "speed", "fast"));
            assert!(!b.set_param(ctx, "speed", "1e3"));
            assert!(!b.set_param(ctx, "summitdelta", ""));
            assert!(!b.set_param(ctx, "speed_mismatch_var", "A B"));
            assert!(!b.set_param(ctx, "Speed", "1"));
            assert!(!b.set_param(ctx, "heading", "1"));
            // complete_thresh is BHV_ConstantHeading's alone.
            assert!(!b.set_param(ctx, "complete_thresh", "1"));
            assert!(b.set_param(ctx, "summitdelta", "-4"));
            assert!(b.set_param(ctx, "speed", " +2.5 "));
        });
        assert_eq!(
            (b.settings().value, b.settings().shape.summitdelta),
            (2.5, 0.0)
        );
    }

    #[test]
    fn worked_example_speed_1() {
        let (mut b, mut host) = bhv(&[("speed", "1.0")]);
        host.set("NAV_SPEED", 0.5);
        let f = host.with(|ctx| b.on_run(ctx)).unwrap();
        assert_eq!(f.pwt, 100.0);
        assert_eq!(f.domain.as_str(), "speed,0,2,21");
        assert_eq!(
            pieces(&f),
            vec![
                (0, 8, 0.0, 0.0),
                (9, 10, 50.0, -400.0),
                (11, 12, -50.0, 600.0),
                (13, 20, 0.0, 0.0)
            ]
        );
        assert!(host.posts.is_empty());
    }

    #[test]
    fn worked_examples_summit_insist_and_plateau() {
        let (mut b, mut host) = bhv(&[("speed", "2.5")]);
        host.set("NAV_SPEED", 0.0);
        let f = host.with(|ctx| b.on_run(ctx)).unwrap();
        assert_eq!(pieces(&f), vec![(20, 20, 0.0, 100.0), (0, 19, 0.0, 0.0)]);

        let (mut b, mut host) = bhv(&[("speed", "1.0"), ("peakwidth", "0.3")]);
        host.set("NAV_SPEED", 0.0);
        let f = host.with(|ctx| b.on_run(ctx)).unwrap();
        assert_eq!(
            pieces(&f),
            vec![
                (0, 5, 0.0, 0.0),
                (6, 7, 50.0, -250.0),
                (8, 13, 0.0, 100.0),
                (14, 15, -50.0, 750.0),
                (16, 20, 0.0, 0.0)
            ]
        );
    }

    #[test]
    fn worked_example_five_pieces_and_mismatch() {
        let (mut b, mut host) = bhv(&[
            ("peakwidth", "0.1"),
            ("basewidth", "0.5"),
            ("summitdelta", "10"),
            ("speed", "1.3"),
            ("speed_mismatch_var", "SPD_MISMATCH"),
        ]);
        host.set("NAV_SPEED", 0.5);
        let f = host.with(|ctx| b.on_run(ctx)).unwrap();
        assert_eq!(
            pieces(&f),
            vec![
                (0, 7, 0.0, 0.0),
                (8, 12, 18.0, -126.0),
                (13, 14, -10.0, 230.0),
                (20, 20, 0.0, 0.0),
                (15, 19, -18.0, 342.0)
            ]
        );
        let mm: f64 = host.last("SPD_MISMATCH").unwrap().parse().unwrap();
        assert!((mm - 0.8).abs() < 1e-12);
        assert_eq!(host.posts[0].2, "", "default key");
    }

    #[test]
    fn missing_nav_speed_warns_in_idle_and_run() {
        let (mut b, mut host) = bhv(&[("speed", "1"), ("speed_mismatch_var", "MM")]);
        host.with(|ctx| b.on_idle_state(ctx));
        assert_eq!(
            host.posted("BHV_WARNING"),
            vec![
                "cs: NAV_SPEED dbl info not found in helm info_buffer",
                "cs: No ownship SPEED info in info_buffer."
            ]
        );
        assert!(host.posts.iter().all(|p| p.2 == "repeatable"));
        assert!(host.posted("MM").is_empty());
        host.clear();
        // Running: the function is produced regardless of the read.
        assert!(host.with(|ctx| b.on_run(ctx)).is_some());
        assert_eq!(host.posted("BHV_WARNING").len(), 2);
        host.clear();
        host.set("NAV_SPEED", 3.0);
        host.with(|ctx| b.on_idle_state(ctx));
        assert_eq!(host.posted("MM"), vec!["2"]);
    }

    #[test]
    fn missing_domain_variable_is_an_error() {
        let mut b = ConstantSpeed::new(&HelmDomain::new("course,0,359,360"));
        let mut host = MockHost::new("cs");
        host.set("NAV_SPEED", 1.0);
        assert!(host.with(|ctx| b.on_run(ctx)).is_none());
        assert_eq!(
            host.posted("BHV_ERROR"),
            vec!["cs: No 'speed' variable in the helm domain"]
        );
    }
}
