//! The shared body of BHV_ConstantSpeed and BHV_ConstantDepth (behaviors-plugins.md §2,
//! §4): a ZAIC_PEAK over one variable around a desired value, every running iteration,
//! plus an optional mismatch posting. Each plugin names its variable through [`Kind`].

use std::marker::PhantomData;

use behavior_api::ivp::{self, zaic::ZaicPeak};
use behavior_api::sdk::{function_data, Ctx, HelmDomain, IvpBehavior};
use behavior_api::FunctionData;

use super::util::{no_white, parse_number};

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
    const PEAKWIDTH: f64;
    const BASEWIDTH: f64;
    const SUMMITDELTA: f64;
}

/// A behavior that holds one decision variable at a value.
pub struct ConstantValue<K: Kind> {
    domain: String,
    ivp_domain: Option<ivp::Domain>,
    pub(crate) value: f64,
    pub(crate) peakwidth: f64,
    pub(crate) basewidth: f64,
    pub(crate) summitdelta: f64,
    pub(crate) mismatch_var: String,
    kind: PhantomData<K>,
}

impl<K: Kind> ConstantValue<K> {
    pub fn new(helm_domain: &HelmDomain) -> Self {
        ConstantValue {
            domain: helm_domain.sub_domain(&[K::VAR]),
            ivp_domain: helm_domain.ivp_domain(&[K::VAR]),
            value: 0.0,
            peakwidth: K::PEAKWIDTH,
            basewidth: K::BASEWIDTH,
            summitdelta: K::SUMMITDELTA,
            mismatch_var: String::new(),
            kind: PhantomData,
        }
    }

    /// Read the navigation variable (idle and running iterations): a warning when it is
    /// missing, else the mismatch posting.
    fn read_ownship(&mut self, ctx: &mut Ctx<'_>) {
        match ctx.get_buffer_double_val(K::NAV) {
            None => ctx.post_wmessage(&format!("No ownship {} info in info_buffer.", K::WHAT)),
            Some(os) => {
                if !self.mismatch_var.is_empty() {
                    let mut delta = os - self.value;
                    if delta < 0.0 {
                        delta = -delta;
                    }
                    ctx.post_message_num(&self.mismatch_var, delta);
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
        let err = || format!("Unable to generate constant-{} IvP function", K::VAR);
        let mut z = ZaicPeak::new(dom, K::VAR).map_err(|_| err())?;
        z.set_summit(self.value, 0);
        z.set_base_width(self.basewidth, 0);
        z.set_peak_width(self.peakwidth, 0);
        z.set_summit_delta(self.summitdelta, 0);
        z.extract(true).ok_or_else(err)
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
        if param == K::VAR {
            return parse_number(value)
                .map(|v| self.value = v.max(0.0))
                .is_some();
        }
        if param == K::MISMATCH_PARAM {
            return no_white(value)
                .map(|v| self.mismatch_var = v.to_string())
                .is_some();
        }
        match param {
            "peakwidth" => parse_number(value).map(|v| self.peakwidth = v.max(0.0)),
            "basewidth" => parse_number(value).map(|v| self.basewidth = v.max(0.0)),
            "summitdelta" => parse_number(value).map(|v| self.summitdelta = v.clamp(0.0, 100.0)),
            _ => None,
        }
        .is_some()
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
