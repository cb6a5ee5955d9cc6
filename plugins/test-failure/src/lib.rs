//! BHV_TestFailure: a behavior that fails on purpose, to test the helm's isolation
//! (the real helm has a static type of the same name for the same purpose).
//!
//! Parameters (type parameters; everything common is the helm's):
//!
//! * `failure = none | panic_on_run | panic_on_param | panic_on_create | panic_on_helm_start
//!   | nan | bad_pieces | bad_bounds | unknown_var` (default `none`):
//!   * `panic_on_run`: `on_run` panics from the `fail_at`-th running iteration on;
//!   * `panic_on_param`: the `set_param` call that receives this value panics;
//!   * `panic_on_create`: creation panics once all parameters are given (the collective
//!     parameter check that ends configuration);
//!   * `panic_on_helm_start`: `on_helm_start` panics;
//!   * `nan`: the function has a NaN weight;
//!   * `bad_pieces`: the function's buffers do not match its domain (a 1-D domain with
//!     bounds and weights laid out for 2 dimensions);
//!   * `bad_bounds`: a piece's bounds lie outside the domain (index `points`);
//!   * `unknown_var`: the function is over a variable the helm domain does not have.
//! * `fail_at = N`: the running iteration (1-based, counted by this behavior) from which the
//!   run-time failures happen, every iteration after too (default 1).
//! * `speed = V` (default 1), `tolerance = W` (default 0.5): the valid function produced
//!   while not failing, a ZAIC_PEAK on speed.
//!
//! Also exported: `BHV_TestFailureCtor`, whose constructor always panics, and
//! `BHV_WaypointLib`, the standard BHV_Waypoint (`behaviors-std`) served from this library
//! (the `plugin_vs_builtin` bench compares it with the built-in one).

use behavior_api::abi_stable::std_types::RVec;
use behavior_api::ivp;
use behavior_api::sdk::{function_data, Ctx, HelmDomain, IvpBehavior};
use behavior_api::FunctionData;
use bhv_plugin_common::peak::PeakShape;

/// What goes wrong, and when.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Failure {
    None,
    PanicOnRun,
    PanicOnParam,
    PanicOnCreate,
    PanicOnHelmStart,
    Nan,
    BadPieces,
    BadBounds,
    UnknownVar,
}

impl Failure {
    pub fn parse(s: &str) -> Option<Failure> {
        Some(match s.trim().to_ascii_lowercase().as_str() {
            "none" => Failure::None,
            "panic_on_run" => Failure::PanicOnRun,
            "panic_on_param" => Failure::PanicOnParam,
            "panic_on_create" => Failure::PanicOnCreate,
            "panic_on_helm_start" => Failure::PanicOnHelmStart,
            "nan" => Failure::Nan,
            "bad_pieces" => Failure::BadPieces,
            "bad_bounds" => Failure::BadBounds,
            "unknown_var" => Failure::UnknownVar,
            _ => return None,
        })
    }
}

pub struct TestFailure {
    domain: String,
    ivp_domain: Option<ivp::Domain>,
    failure: Failure,
    fail_at: u64,
    runs: u64,
    speed: f64,
    tolerance: f64,
}

impl TestFailure {
    pub fn new(helm_domain: &HelmDomain) -> Self {
        TestFailure {
            domain: helm_domain.sub_domain(&["speed"]),
            ivp_domain: helm_domain.ivp_domain(&["speed"]),
            failure: Failure::None,
            fail_at: 1,
            runs: 0,
            speed: 1.0,
            tolerance: 0.5,
        }
    }

    pub fn failure(&self) -> Failure {
        self.failure
    }

    /// The valid function: a ZAIC_PEAK at `speed`, base width `tolerance`, no peak width
    /// or summit delta.
    fn good_function(&self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        let dom = self.ivp_domain.as_ref()?;
        let shape = PeakShape::new(0.0, self.tolerance, 0.0);
        let mut f = shape.function(dom, "speed", self.speed, false)?;
        f.set_pwt(ctx.priority());
        Some(function_data(f))
    }
}

fn number(s: &str) -> Option<f64> {
    // The helm's own number test: what the helm calls a number, nothing else.
    behavior_api::parse_number(s)
}

/// The message of every deliberate panic starts with this.
pub const PANIC_PREFIX: &str = "BHV_TestFailure deliberate panic";

impl IvpBehavior for TestFailure {
    fn domain(&self) -> String {
        self.domain.clone()
    }

    fn default_name(&self) -> String {
        "bhv_test_failure".into()
    }

    fn set_param(&mut self, _ctx: &mut Ctx<'_>, param: &str, value: &str) -> bool {
        match param {
            "failure" => match Failure::parse(value) {
                Some(Failure::PanicOnParam) => {
                    panic!("{PANIC_PREFIX} in set_param(failure = {})", value.trim())
                }
                Some(f) => {
                    self.failure = f;
                    true
                }
                None => false,
            },
            "fail_at" => match value.trim().parse::<u64>() {
                Ok(n) if n >= 1 => {
                    self.fail_at = n;
                    true
                }
                _ => false,
            },
            "speed" => number(value).map(|v| self.speed = v.max(0.0)).is_some(),
            "tolerance" => number(value).map(|v| self.tolerance = v.max(0.0)).is_some(),
            _ => false,
        }
    }

    fn collective_check(&mut self) -> String {
        if self.failure == Failure::PanicOnCreate {
            panic!("{PANIC_PREFIX} while being created");
        }
        String::new()
    }

    fn on_helm_start(&mut self, _ctx: &mut Ctx<'_>) {
        if self.failure == Failure::PanicOnHelmStart {
            panic!("{PANIC_PREFIX} in on_helm_start");
        }
    }

    fn on_run(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        self.runs += 1;
        let good = self.good_function(ctx)?;
        if self.runs < self.fail_at {
            return Some(good);
        }
        let n = self.runs;
        match self.failure {
            Failure::PanicOnRun => panic!("{PANIC_PREFIX} in on_run (run {n})"),
            Failure::Nan => {
                let mut f = good;
                let k = f.weights.len() / 2;
                f.weights[k] = f64::NAN;
                Some(f)
            }
            Failure::BadPieces => {
                // Laid out for 2 dimensions over a 1-D domain.
                let mut f = good;
                f.bounds = RVec::from(vec![0, 1, 0, 1, 2, 3, 2, 3]);
                f.weights = RVec::from(vec![0.0, 0.0, 10.0, 0.0, 0.0, 20.0]);
                Some(f)
            }
            Failure::BadBounds => {
                // One piece beyond the last index of the speed variable.
                let mut f = good;
                let points = self.ivp_domain.as_ref().map_or(1, |d| d.var(0).points) as i32;
                f.bounds = RVec::from(vec![0, points]);
                f.weights = RVec::from(vec![0.0, 50.0]);
                Some(f)
            }
            Failure::UnknownVar => {
                let mut f = good;
                let rest = f
                    .domain
                    .as_str()
                    .split_once(',')
                    .map_or(String::new(), |(_, r)| r.to_string());
                f.domain = format!("warp_factor,{rest}").into();
                Some(f)
            }
            _ => Some(good),
        }
    }
}

/// A type whose constructor always panics.
pub struct PanickingCtor;

impl PanickingCtor {
    pub fn new(_helm_domain: &HelmDomain) -> Self {
        panic!("BHV_TestFailureCtor deliberate panic in the constructor");
    }
}

impl IvpBehavior for PanickingCtor {
    fn domain(&self) -> String {
        String::new()
    }
    fn default_name(&self) -> String {
        "bhv_test_failure_ctor".into()
    }
    fn set_param(&mut self, _ctx: &mut Ctx<'_>, _param: &str, _value: &str) -> bool {
        false
    }
    fn on_run(&mut self, _ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        None
    }
}

behavior_api::export_behaviors! {
    "BHV_TestFailure" => TestFailure::new,
    "BHV_TestFailureCtor" => PanickingCtor::new,
    "BHV_WaypointLib" => behaviors_std::BhvWaypoint::new,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_every_failure_kind() {
        for (s, f) in [
            ("none", Failure::None),
            ("panic_on_run", Failure::PanicOnRun),
            ("PANIC_ON_PARAM", Failure::PanicOnParam),
            ("panic_on_create", Failure::PanicOnCreate),
            ("panic_on_helm_start", Failure::PanicOnHelmStart),
            ("nan", Failure::Nan),
            ("bad_pieces", Failure::BadPieces),
            ("bad_bounds", Failure::BadBounds),
            (" unknown_var ", Failure::UnknownVar),
        ] {
            assert_eq!(Failure::parse(s), Some(f), "{s}");
        }
        assert_eq!(Failure::parse("sometimes"), None);
    }

    /// Without a failure: the ZAIC_PEAK of `speed` and `tolerance` alone, at priority pwt.
    #[test]
    fn good_function_is_the_speed_peak() {
        use behavior_api::ivp::zaic::ZaicPeak;
        use behavior_api::testing::MockHelm;

        let helm_domain = HelmDomain::new("course,0,359,360:speed,0,4,41");
        let mut b = TestFailure::new(&helm_domain);
        let mut helm = MockHelm::new("tf");
        helm.with(|ctx| {
            assert!(b.set_param(ctx, "speed", "1.5"));
            assert!(b.set_param(ctx, "tolerance", "0.3"));
        });
        let got = helm.with(|ctx| b.on_run(ctx)).unwrap();

        let dom = helm_domain.ivp_domain(&["speed"]).unwrap();
        let mut z = ZaicPeak::new(&dom, "speed").unwrap();
        z.set_summit(1.5, 0);
        z.set_base_width(0.3, 0);
        let mut want = z.extract(true).unwrap();
        want.set_pwt(100.0);
        assert_eq!(got, function_data(want));
    }

    #[test]
    fn exported_root_module() {
        let lib = ivp_behaviors_root_module();
        let types: Vec<String> = (lib.behavior_types())()
            .into_iter()
            .map(String::from)
            .collect();
        assert_eq!(
            types,
            ["BHV_TestFailure", "BHV_TestFailureCtor", "BHV_WaypointLib"]
        );
        let dom = "course,0,359,360:speed,0,4,41";
        let b = (lib.create())("BHV_TestFailure".into(), dom.into())
            .unwrap()
            .unwrap();
        assert_eq!(b.domain().as_str(), "speed,0,4,41");
        // The panicking constructor is caught inside the library.
        let ctor = (lib.create())("BHV_TestFailureCtor".into(), dom.into()).unwrap();
        assert!(
            ctor.into_result().is_err(),
            "a panicking constructor gives its message"
        );
        let w = (lib.create())("BHV_WaypointLib".into(), dom.into())
            .unwrap()
            .unwrap();
        assert_eq!(w.default_name().as_str(), "bhv_waypoint");
    }
}
