//! BHV_ConstantDepth (behaviors-plugins.md §4): a ZAIC_PEAK over `depth` around a
//! desired depth, every running iteration, plus an optional mismatch posting.
//!
//! The body is shared with the other Constant* value behaviors (`bhv-plugin-common`,
//! `plugins/common`); this crate names the variable and its defaults.

use bhv_plugin_common::constant::{ConstantValue, Kind};
use bhv_plugin_common::peak::PeakShape;

/// The depth variant.
pub struct DepthKind;

impl Kind for DepthKind {
    const PARAM: &'static str = "depth";
    const NAV: &'static str = "NAV_DEPTH";
    const MISMATCH_PARAM: &'static str = "depth_mismatch_var";
    // peakwidth, basewidth, summitdelta
    const SHAPE: PeakShape = PeakShape::new(3.0, 100.0, 50.0);
}

/// BHV_ConstantDepth.
pub type ConstantDepth = ConstantValue<DepthKind>;

behavior_api::export_behaviors! {
    "BHV_ConstantDepth" => ConstantDepth::new,
}

#[cfg(test)]
mod tests {
    use super::*;
    use behavior_api::sdk::{HelmDomain, IvpBehavior};
    use behavior_api::testing::MockHelm as MockHost;
    use behavior_api::FunctionData;
    use bhv_plugin_common::testing::{configured, pieces};

    fn helm() -> HelmDomain {
        HelmDomain::new("course,0,359,360:speed,0,2,21:depth,0,100,101")
    }

    fn bhv(params: &[(&str, &str)]) -> (ConstantDepth, MockHost) {
        configured(ConstantDepth::new(&helm()), "cd", params)
    }

    /// The best grid index, scaling by pwt like the helm (slope and intercept separately)
    /// and keeping the first piece on ties.
    fn best(f: &FunctionData) -> i32 {
        let mut best = (f64::NEG_INFINITY, 0);
        for k in 0..f.piece_count().unwrap() {
            let (lo, hi) = (f.bounds[2 * k], f.bounds[2 * k + 1]);
            let (m, b) = (f.weights[2 * k] * f.pwt, f.weights[2 * k + 1] * f.pwt);
            let i = if m > 0.0 { hi } else { lo };
            let v = b + m * f64::from(i);
            if v > best.0 {
                best = (v, i);
            }
        }
        best.1
    }

    #[test]
    fn domain_and_name() {
        let b = ConstantDepth::new(&helm());
        assert_eq!(b.domain(), "depth,0,100,101");
        assert_eq!(b.default_name(), "???");
        assert_eq!(
            ConstantDepth::new(&HelmDomain::new("speed,0,2,21")).domain(),
            ""
        );
    }

    #[test]
    fn parameters() {
        let (mut b, mut host) = bhv(&[]);
        assert_eq!(b.settings().value, 0.0);
        assert_eq!(b.settings().shape, PeakShape::new(3.0, 100.0, 50.0));
        host.with(|ctx| {
            assert!(ctx.name() == "cd");
            assert!(b.set_param(ctx, "depth", "-5"));
            assert!(b.set_param(ctx, "peakwidth", "-1"));
            assert!(b.set_param(ctx, "basewidth", "-1"));
            assert!(b.set_param(ctx, "summitdelta", "-1"));
            assert!(b.set_param(ctx, "depth_mismatch_var", "DERR"));
            assert!(!b.set_param(ctx, "depth", "deep"));
            assert!(!b.set_param(ctx, "depth_mismatch_var", "D ERR"));
            assert!(!b.set_param(ctx, "speed", "1"));
        });
        assert_eq!(b.settings().value, 0.0);
        assert_eq!(b.settings().shape, PeakShape::new(0.0, 0.0, 0.0));
        assert_eq!(b.settings().mismatch_var, "DERR");
    }

    #[test]
    fn worked_example_12_3() {
        let (mut b, mut host) = bhv(&[("depth", "12.3")]);
        host.set("NAV_DEPTH", 0.0);
        let f = host.with(|ctx| b.on_run(ctx)).unwrap();
        assert_eq!(
            pieces(&f),
            vec![
                (0, 9, 0.5, 45.35),
                (10, 12, 16.6667, -105.0),
                (13, 15, -16.6667, 305.0),
                (16, 100, -0.5, 57.65)
            ]
        );
        assert_eq!(best(&f), 12);
    }

    #[test]
    fn worked_example_decisions() {
        for (depth, want) in [
            ("12.5", 12),
            ("12.4999", 12),
            ("99.5", 100),
            ("150", 100),
            ("0", 0),
        ] {
            let (mut b, mut host) = bhv(&[("depth", depth)]);
            host.set("NAV_DEPTH", 0.0);
            let f = host.with(|ctx| b.on_run(ctx)).unwrap();
            assert_eq!(best(&f), want, "depth {depth}");
        }
        let (mut b, mut host) = bhv(&[("depth", "150")]);
        host.set("NAV_DEPTH", 0.0);
        let f = host.with(|ctx| b.on_run(ctx)).unwrap();
        assert_eq!(pieces(&f), vec![(0, 47, 0.0, 0.0), (48, 100, 0.5, -23.5)]);
    }

    #[test]
    fn mismatch_and_warnings() {
        let (mut b, mut host) = bhv(&[("depth", "20"), ("depth_mismatch_var", "DERR")]);
        host.set("NAV_DEPTH", 12.5);
        host.with(|ctx| b.on_idle_state(ctx));
        assert_eq!(host.posted("DERR"), vec!["7.5"]);
        host.clear();
        host.unset("NAV_DEPTH");
        assert!(host.with(|ctx| b.on_run(ctx)).is_some());
        assert_eq!(
            host.posted("BHV_WARNING"),
            vec![
                "cd: NAV_DEPTH dbl info not found in helm info_buffer",
                "cd: No ownship DEPTH info in info_buffer."
            ]
        );
        assert!(host.posted("DERR").is_empty());
    }
}
