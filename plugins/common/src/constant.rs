//! The shared body of BHV_ConstantSpeed and BHV_ConstantDepth (behaviors-plugins.md §2,
//! §4): a ZAIC_PEAK over one variable around a desired value, every running iteration,
//! plus an optional mismatch posting. Each plugin names its variable through [`Kind`].

use std::marker::PhantomData;

use behavior_api::ivp;
use behavior_api::parse_number;
use behavior_api::sdk::{function_data, Ctx, HelmDomain, IvpBehavior};
use behavior_api::FunctionData;

use crate::no_white;
use crate::peak::PeakShape;

/// What distinguishes one Constant* type from another.
pub trait Kind: Send + 'static {
    /// The decision variable and the parameter holding the desired value.
    const VAR: &'static str;
    /// The navigation variable compared with the desired value.
    const NAV: &'static str;
    /// Upper-case name in the missing-navigation warning.
    const WHAT: &'static str;
    /// The parameter naming the mismatch variable.
    const MISMATCH_PARAM: &'static str;
    /// Default ZAIC_PEAK shape.
    const SHAPE: PeakShape;
}

/// The type parameters of a Constant* behavior, as configured.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// The desired value.
    pub value: f64,
    pub shape: PeakShape,
    /// Where the distance from the desired value is posted (empty: nowhere).
    pub mismatch_var: String,
}

/// A behavior that holds one decision variable at a value.
pub struct ConstantValue<K: Kind> {
    domain: String,
    ivp_domain: Option<ivp::Domain>,
    settings: Settings,
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
                mismatch_var: String::new(),
            },
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
            None => ctx.post_wmessage(&format!("No ownship {} info in info_buffer.", K::WHAT)),
            Some(os) => {
                if !self.settings.mismatch_var.is_empty() {
                    let mut delta = os - self.settings.value;
                    if delta < 0.0 {
                        delta = -delta;
                    }
                    ctx.post_message_num(&self.settings.mismatch_var, delta);
                }
            }
        }
    }

    /// The objective function, without pwt.
    fn build(&self) -> Result<ivp::IvpFunction, String> {
        let dom = self
            .ivp_domain
            .as_ref()
            .ok_or_else(|| format!("No '{}' variable in the helm domain", K::VAR))?;
        self.settings
            .shape
            .function(dom, K::VAR, self.settings.value, false)
            .ok_or_else(|| format!("Unable to generate constant-{} IvP function", K::VAR))
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
        if param == K::VAR {
            return parse_number(value).map(|v| s.value = v.max(0.0)).is_some();
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
        match self.build() {
            Ok(mut f) => {
                f.set_pwt(ctx.priority());
                Some(function_data(f))
            }
            Err(msg) => {
                ctx.post_emessage(&msg);
                None
            }
        }
    }
}
