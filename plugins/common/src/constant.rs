//! The shared body of BHV_ConstantSpeed, BHV_ConstantHeading and BHV_ConstantDepth
//! (behaviors-plugins.md §2-§4): a ZAIC_PEAK over one decision variable around a desired
//! value, every running iteration, an optional mismatch posting and, for the types that
//! take one, a completion threshold. Each plugin names its variable and defaults
//! through [`Kind`].

use std::marker::PhantomData;

use behavior_api::ivp;
use behavior_api::kept::Kept;
use behavior_api::parse_number;
use behavior_api::sdk::{copy_function_data, Ctx, HelmDomain, IvpBehavior};
use behavior_api::FunctionData;

use crate::no_white;
use crate::peak::PeakShape;

/// What distinguishes one Constant* type from another.
pub trait Kind: Send + 'static {
    /// The parameter holding the desired value; also names the type in the
    /// "Unable to generate constant-<PARAM> IvP function" error.
    const PARAM: &'static str;
    /// The decision variable.
    const VAR: &'static str = Self::PARAM;
    /// The variable's name in the "No '<...>' variable in the helm domain" error.
    const DOMAIN_NAME: &'static str = Self::VAR;
    /// The navigation variable compared with the desired value (`NAV_<WHAT>`: the
    /// missing-navigation warning names it by `<WHAT>`).
    const NAV: &'static str;
    /// The parameter naming the mismatch variable.
    const MISMATCH_PARAM: &'static str;
    /// Default ZAIC_PEAK shape.
    const SHAPE: PeakShape;
    /// Whether the peak wraps around the ends of the variable's range.
    const WRAP: bool = false;
    /// Whether the type takes `complete_thresh`.
    const COMPLETE_THRESH: bool = false;

    /// The desired value given the number in its parameter and the behavior's domain;
    /// `None` rejects the parameter. By default a negative value becomes 0.
    fn desired(_domain: Option<&ivp::Domain>, v: f64) -> Option<f64> {
        Some(v.max(0.0))
    }

    /// How far ownship's value `os` is from the desired value (posted as the mismatch,
    /// compared with `complete_thresh`).
    fn mismatch(os: f64, desired: f64) -> f64 {
        let mut delta = os - desired;
        if delta < 0.0 {
            delta = -delta;
        }
        delta
    }
}

/// The type parameters of a Constant* behavior, as configured.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// The desired value.
    pub value: f64,
    pub shape: PeakShape,
    /// Completes the behavior once the mismatch is below it (-1, the default: never).
    pub complete_thresh: f64,
    /// Where the distance from the desired value is posted (empty: nowhere).
    pub mismatch_var: String,
}

/// A behavior that holds one decision variable at a value.
pub struct ConstantValue<K: Kind> {
    domain: String,
    ivp_domain: Option<ivp::Domain>,
    settings: Settings,
    /// The mismatch at the last successful read of the navigation variable (0 before).
    mismatch: f64,
    /// The last function built and what it was built from (bit for bit): the function
    /// depends on nothing else, so while they stay it is copied, not built again (the
    /// ZAIC scans every point of the variable).
    last: Kept<[u64; 4]>,
    kind: PhantomData<K>,
}

impl<K: Kind> ConstantValue<K> {
    pub fn new(helm_domain: &HelmDomain) -> Self {
        ConstantValue {
            domain: helm_domain.sub_domain(&[K::VAR]),
            ivp_domain: helm_domain.ivp_domain(&[K::VAR]),
            settings: Settings {
                value: 0.0,
                shape: K::SHAPE,
                complete_thresh: -1.0,
                mismatch_var: String::new(),
            },
            mismatch: 0.0,
            last: Kept::default(),
            kind: PhantomData,
        }
    }

    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// Read the navigation variable (idle and running iterations): a warning when it is
    /// missing, else the mismatch posting.
    fn read_ownship(&mut self, ctx: &mut Ctx<'_>) {
        match ctx.get_buffer_double_val(K::NAV) {
            None => {
                let what = K::NAV.strip_prefix("NAV_").unwrap_or(K::NAV);
                ctx.post_wmessage(&format!("No ownship {what} info in info_buffer."));
            }
            Some(os) => {
                self.mismatch = K::mismatch(os, self.settings.value);
                if !self.settings.mismatch_var.is_empty() {
                    ctx.post_message_num(&self.settings.mismatch_var, self.mismatch);
                }
            }
        }
    }

    /// The objective function with priority `pwt`, in the ABI form: a copy of the last
    /// one while the desired value and the shape are unchanged.
    fn build_kept(&mut self, pwt: f64) -> Result<FunctionData, String> {
        let shape = &self.settings.shape;
        let key = [
            self.settings.value.to_bits(),
            shape.peakwidth.to_bits(),
            shape.basewidth.to_bits(),
            shape.summitdelta.to_bits(),
        ];
        let (dom, settings) = (&self.ivp_domain, &self.settings);
        let kept = self.last.get(key, || Self::build(dom, settings))?;
        Ok(copy_function_data(kept, pwt))
    }

    /// The objective function, without pwt.
    fn build(dom: &Option<ivp::Domain>, settings: &Settings) -> Result<ivp::IvpFunction, String> {
        let dom = dom
            .as_ref()
            .ok_or_else(|| format!("No '{}' variable in the helm domain", K::DOMAIN_NAME))?;
        settings
            .shape
            .function(dom, K::VAR, settings.value, K::WRAP)
            .ok_or_else(|| format!("Unable to generate constant-{} IvP function", K::PARAM))
    }
}

impl<K: Kind> IvpBehavior for ConstantValue<K> {
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
        let s = &mut self.settings;
        if param == K::PARAM {
            return parse_number(value)
                .and_then(|v| K::desired(self.ivp_domain.as_ref(), v))
                .map(|v| s.value = v)
                .is_some();
        }
        if K::COMPLETE_THRESH && param == "complete_thresh" {
            return parse_number(value).map(|v| s.complete_thresh = v).is_some();
        }
        if param == K::MISMATCH_PARAM {
            return no_white(value)
                .map(|v| s.mismatch_var = v.to_string())
                .is_some();
        }
        s.shape.set_param(param, value).unwrap_or(false)
    }

    fn on_idle_state(&mut self, ctx: &mut Ctx<'_>) {
        self.read_ownship(ctx);
    }

    fn on_run(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        self.read_ownship(ctx);
        // Strictly below: a threshold of 0 never completes (the default -1 neither).
        if self.mismatch < self.settings.complete_thresh {
            ctx.set_complete();
            return None;
        }
        match self.build_kept(ctx.priority()) {
            Ok(f) => Some(f),
            Err(msg) => {
                ctx.post_emessage(&msg);
                None
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Depth;
    impl Kind for Depth {
        const PARAM: &'static str = "depth";
        const NAV: &'static str = "NAV_DEPTH";
        const MISMATCH_PARAM: &'static str = "depth_mismatch_var";
        const SHAPE: PeakShape = PeakShape::new(3.0, 6.0, 50.0);
    }

    /// A kept function handed out again is bit for bit the one a fresh build gives, over
    /// random changes of the desired value and the shape (some repeated, -0.0 included).
    #[test]
    fn kept_function_equals_a_fresh_build() {
        let mut b = ConstantValue::<Depth>::new(&HelmDomain::new("depth,0,100,101"));
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = |n: u64| {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (seed >> 33) % n
        };
        let mut unchanged = 0;
        for _ in 0..600 {
            match next(6) {
                0 => b.settings.value = [0.0, -0.0, 12.5, 40.0, 99.0][next(5) as usize],
                1 => b.settings.shape.peakwidth = [0.0, -0.0, 3.0, 10.0][next(4) as usize],
                2 => b.settings.shape.basewidth = [0.0, 6.0, 20.0][next(3) as usize],
                3 => b.settings.shape.summitdelta = [0.0, 25.0, 50.0][next(3) as usize],
                _ => unchanged += 1,
            }
            let kept = b.build_kept(12.5).expect("builds");
            let mut fresh =
                ConstantValue::<Depth>::build(&b.ivp_domain, &b.settings).expect("builds");
            fresh.set_pwt(12.5);
            let fresh = FunctionData::from_ivp(fresh);
            let bits = behavior_api::testing::function_data_bits;
            assert_eq!(bits(&kept), bits(&fresh), "settings {:?}", b.settings);
            fresh.give_back();
            kept.give_back();
        }
        // Both paths ran: a third of the rounds change nothing, so the copy is used.
        assert!(unchanged > 100, "{unchanged}");
    }
}
