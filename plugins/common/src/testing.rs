//! Helpers for the plugins' unit tests; the behaviors themselves do not use them.

use behavior_api::sdk::IvpBehavior;
use behavior_api::testing::MockHelm;
use behavior_api::FunctionData;

/// `behavior` given `params` (name, value), in order, inside a [`MockHelm`] whose
/// behavior is called `name`. Panics when a parameter is refused.
pub fn configured<B: IvpBehavior>(
    mut behavior: B,
    name: &str,
    params: &[(&str, &str)],
) -> (B, MockHelm) {
    let mut helm = MockHelm::new(name);
    for (p, v) in params {
        assert!(helm.with(|ctx| behavior.set_param(ctx, p, v)), "{p}={v}");
    }
    (behavior, helm)
}

/// (low index, high index, slope, intercept) per piece of a one-variable function, the
/// weights rounded to 4 decimals (and -0 made 0) to compare with worked examples.
/// Panics on a function whose buffers do not fit its domain.
pub fn pieces(f: &FunctionData) -> Vec<(i32, i32, f64, f64)> {
    let r = |x: f64| (x * 1e4).round() / 1e4 + 0.0;
    let count = f.piece_count().expect("buffers that fit the domain");
    (0..count)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::peak::PeakShape;
    use behavior_api::sdk::{function_data, HelmDomain};

    #[test]
    fn pieces_of_a_peak() {
        let dom = HelmDomain::new("speed,0,2,21")
            .ivp_domain(&["speed"])
            .unwrap();
        let f = PeakShape::new(0.0, 0.2, 0.0)
            .function(&dom, "speed", 1.0, false)
            .unwrap();
        assert_eq!(
            pieces(&function_data(f)),
            vec![
                (0, 8, 0.0, 0.0),
                (9, 10, 50.0, -400.0),
                (11, 12, -50.0, 600.0),
                (13, 20, 0.0, 0.0)
            ]
        );
    }
}
