//! The ABI of `behavior-api` 0.1.1 (contacts), frozen, so that a library built against it
//! still loads and runs in this helm; the same device as [`crate::abi_v1`] for 0.1.0.
//!
//! 0.1.2 appended to [`crate::context::HelmContext`] the methods that write into a
//! caller's string (issue 19). abi_stable refuses a host context vtable with more methods
//! than the library knew, so a 0.1.1 library is loaded through [`module::BehaviorLibRef`]
//! below, whose types are byte for byte those of 0.1.1, and [`adapt`] turns its behavior
//! into a current [`crate::BehaviorBox`] that hands it a 0.1.1 context built over the
//! current one.
//!
//! Nothing here may change: the names, order and signatures are the 0.1.1 ones. A plugin
//! author never uses this module; the helm's loader does.

use abi_stable::sabi_trait::TD_Opaque;
use abi_stable::sabi_types::RMut;
use abi_stable::std_types::{ROption, RResult, RStr, RString, RVec};

use crate::behavior::{Behavior as CurrentBehavior, BehaviorBox as CurrentBox, CallResult};
use crate::context::HelmCtx as CurrentCtx;
use crate::function::FunctionData;
use crate::value::{ContactState, PostValue};

/// `HelmContext` as 0.1.1 had it.
pub mod context {
    use abi_stable::sabi_trait;
    use abi_stable::sabi_types::RMut;
    use abi_stable::std_types::{ROption, RResult, RStr, RString, RVec};

    use crate::value::{ContactState, PostValue};

    #[sabi_trait]
    pub trait HelmContext {
        fn curr_time(&self) -> f64;
        fn local_time(&self) -> f64;
        fn helm_iteration(&self) -> u64;
        fn ownship(&self) -> RString;
        fn name(&self) -> RString;
        fn priority(&self) -> f64;
        fn perpetual(&self) -> bool;
        fn set_perpetual(&mut self, perpetual: bool);
        fn dur_run_time(&self) -> f64;
        fn dur_idle_time(&self) -> f64;

        fn double_val(&mut self, var: RStr<'_>, warn: bool) -> ROption<f64>;
        fn string_val(&mut self, var: RStr<'_>, warn: bool) -> ROption<RString>;
        fn time_val(&self, var: RStr<'_>) -> f64;
        fn msg_time_val(&self, var: RStr<'_>) -> f64;
        fn is_known(&self, var: RStr<'_>) -> bool;
        fn string_deltas(&self, var: RStr<'_>) -> RVec<RString>;
        fn double_deltas(&self, var: RStr<'_>) -> RVec<f64>;
        fn add_info_vars(&mut self, vars: RStr<'_>, no_warning: bool);

        fn post(&mut self, var: RStr<'_>, value: PostValue<'_>, key: RStr<'_>);
        fn post_flag(&mut self, flag: RStr<'_>, repeatable: bool);
        fn expand_common_macros(&mut self, text: RStr<'_>) -> RString;
        fn eval_condition(&mut self, condition: RStr<'_>) -> RResult<bool, RString>;
        fn set_complete(&mut self);
        fn set_platform(&mut self, osx: f64, osy: f64, osh: f64, osv: f64);
        #[sabi(last_prefix_field)]
        fn log(&mut self, level: u8, message: RStr<'_>);

        fn contact_count(&self) -> u32;
        fn contact_name(&self, index: u32) -> ROption<RString>;
        fn contact(&self, name: RStr<'_>) -> ROption<ContactState>;
        fn contact_text(&self, name: RStr<'_>, field: RStr<'_>) -> RString;
        fn set_contact(&mut self, name: RStr<'_>);
    }

    pub type HelmCtx<'a> = HelmContext_TO<'a, RMut<'a, ()>>;
}

/// `Behavior` as 0.1.1 had it (its methods take the 0.1.1 context).
pub mod behavior {
    use abi_stable::sabi_trait;
    use abi_stable::std_types::{RBox, ROption, RStr, RString};

    use super::context::HelmCtx;
    use crate::behavior::CallResult;
    use crate::function::FunctionData;

    #[sabi_trait]
    pub trait Behavior: Send {
        fn domain(&self) -> RString;
        fn default_name(&self) -> RString;
        fn set_param(
            &mut self,
            ctx: HelmCtx<'_>,
            param: RStr<'_>,
            value: RStr<'_>,
        ) -> CallResult<bool>;
        fn on_params_complete(&mut self, ctx: HelmCtx<'_>) -> CallResult<()>;
        fn on_helm_start(&mut self, ctx: HelmCtx<'_>) -> CallResult<()>;
        fn on_every_state(&mut self, ctx: HelmCtx<'_>) -> CallResult<()>;
        fn on_idle_state(&mut self, ctx: HelmCtx<'_>) -> CallResult<()>;
        fn on_idle_to_run(&mut self, ctx: HelmCtx<'_>) -> CallResult<()>;
        fn on_run_to_idle(&mut self, ctx: HelmCtx<'_>) -> CallResult<()>;
        fn on_complete(&mut self, ctx: HelmCtx<'_>) -> CallResult<()>;
        fn on_inactive(&mut self, ctx: HelmCtx<'_>) -> CallResult<()>;
        fn on_spawn(&mut self, ctx: HelmCtx<'_>) -> CallResult<()>;
        fn on_run(&mut self, ctx: HelmCtx<'_>) -> CallResult<ROption<FunctionData>>;
        fn expand_macros(&self, text: RStr<'_>) -> CallResult<RString>;
        fn default_duration(&self) -> CallResult<f64>;
        #[sabi(last_prefix_field)]
        fn collective_check(&mut self) -> CallResult<RString>;
    }

    pub type BehaviorBox = Behavior_TO<'static, RBox<()>>;
}

/// The root module as 0.1.1 libraries export it.
pub mod module {
    use abi_stable::library::RootModule;
    use abi_stable::package_version_strings;
    use abi_stable::sabi_types::VersionStrings;
    use abi_stable::std_types::{ROption, RResult, RStr, RString, RVec};
    use abi_stable::StableAbi;

    use super::behavior::BehaviorBox;

    #[repr(C)]
    #[derive(StableAbi)]
    #[sabi(kind(Prefix(prefix_ref = BehaviorLibRef)))]
    #[sabi(missing_field(panic))]
    pub struct BehaviorLib {
        pub api_version: extern "C" fn() -> RStr<'static>,
        pub behavior_types: extern "C" fn() -> RVec<RString>,
        #[sabi(last_prefix_field)]
        pub create: extern "C" fn(
            type_name: RStr<'_>,
            helm_domain: RStr<'_>,
        ) -> ROption<RResult<BehaviorBox, RString>>,
    }

    impl RootModule for BehaviorLibRef {
        abi_stable::declare_root_module_statics! {BehaviorLibRef}
        const BASE_NAME: &'static str = "ivp_behaviors";
        const NAME: &'static str = "ivp_behaviors";
        const VERSION_STRINGS: VersionStrings = package_version_strings!();
    }
}

/// Whether a library built against behavior-api `version` speaks this frozen ABI.
pub fn speaks_v2(version: &str) -> bool {
    version == "0.1.1"
}

/// A 0.1.1 behavior as a current one.
pub fn adapt(old: behavior::BehaviorBox) -> CurrentBox {
    crate::behavior::Behavior_TO::from_value(Adapter { old }, TD_Opaque)
}

struct Adapter {
    old: behavior::BehaviorBox,
}

/// The 0.1.1 context over the current one: every 0.1.1 call is a current call.
struct Bridge<'c, 'a> {
    ctx: &'c mut CurrentCtx<'a>,
}

impl context::HelmContext for Bridge<'_, '_> {
    fn curr_time(&self) -> f64 {
        self.ctx.curr_time()
    }
    fn local_time(&self) -> f64 {
        self.ctx.local_time()
    }
    fn helm_iteration(&self) -> u64 {
        self.ctx.helm_iteration()
    }
    fn ownship(&self) -> RString {
        self.ctx.ownship()
    }
    fn name(&self) -> RString {
        self.ctx.name()
    }
    fn priority(&self) -> f64 {
        self.ctx.priority()
    }
    fn perpetual(&self) -> bool {
        self.ctx.perpetual()
    }
    fn set_perpetual(&mut self, perpetual: bool) {
        self.ctx.set_perpetual(perpetual)
    }
    fn dur_run_time(&self) -> f64 {
        self.ctx.dur_run_time()
    }
    fn dur_idle_time(&self) -> f64 {
        self.ctx.dur_idle_time()
    }
    fn double_val(&mut self, var: RStr<'_>, warn: bool) -> ROption<f64> {
        self.ctx.double_val(var, warn)
    }
    fn string_val(&mut self, var: RStr<'_>, warn: bool) -> ROption<RString> {
        self.ctx.string_val(var, warn)
    }
    fn time_val(&self, var: RStr<'_>) -> f64 {
        self.ctx.time_val(var)
    }
    fn msg_time_val(&self, var: RStr<'_>) -> f64 {
        self.ctx.msg_time_val(var)
    }
    fn is_known(&self, var: RStr<'_>) -> bool {
        self.ctx.is_known(var)
    }
    fn string_deltas(&self, var: RStr<'_>) -> RVec<RString> {
        self.ctx.string_deltas(var)
    }
    fn double_deltas(&self, var: RStr<'_>) -> RVec<f64> {
        self.ctx.double_deltas(var)
    }
    fn add_info_vars(&mut self, vars: RStr<'_>, no_warning: bool) {
        self.ctx.add_info_vars(vars, no_warning)
    }
    fn post(&mut self, var: RStr<'_>, value: PostValue<'_>, key: RStr<'_>) {
        self.ctx.post(var, value, key)
    }
    fn post_flag(&mut self, flag: RStr<'_>, repeatable: bool) {
        self.ctx.post_flag(flag, repeatable)
    }
    fn expand_common_macros(&mut self, text: RStr<'_>) -> RString {
        self.ctx.expand_common_macros(text)
    }
    fn eval_condition(&mut self, condition: RStr<'_>) -> RResult<bool, RString> {
        self.ctx.eval_condition(condition)
    }
    fn set_complete(&mut self) {
        self.ctx.set_complete()
    }
    fn set_platform(&mut self, osx: f64, osy: f64, osh: f64, osv: f64) {
        self.ctx.set_platform(osx, osy, osh, osv)
    }
    fn log(&mut self, level: u8, message: RStr<'_>) {
        self.ctx.log(level, message)
    }
    fn contact_count(&self) -> u32 {
        self.ctx.contact_count()
    }
    fn contact_name(&self, index: u32) -> ROption<RString> {
        self.ctx.contact_name(index)
    }
    fn contact(&self, name: RStr<'_>) -> ROption<ContactState> {
        self.ctx.contact(name)
    }
    fn contact_text(&self, name: RStr<'_>, field: RStr<'_>) -> RString {
        self.ctx.contact_text(name, field)
    }
    fn set_contact(&mut self, name: RStr<'_>) {
        self.ctx.set_contact(name)
    }
}

/// Call `f` on the old behavior with a 0.1.1 context over `ctx`.
fn with_old<R>(mut ctx: CurrentCtx<'_>, f: impl FnOnce(context::HelmCtx<'_>) -> R) -> R {
    let mut bridge = Bridge { ctx: &mut ctx };
    f(context::HelmContext_TO::from_ptr(
        RMut::new(&mut bridge),
        TD_Opaque,
    ))
}

impl CurrentBehavior for Adapter {
    fn domain(&self) -> RString {
        self.old.domain()
    }
    fn default_name(&self) -> RString {
        self.old.default_name()
    }
    fn set_param(
        &mut self,
        ctx: CurrentCtx<'_>,
        param: RStr<'_>,
        value: RStr<'_>,
    ) -> CallResult<bool> {
        with_old(ctx, |c| self.old.set_param(c, param, value))
    }
    fn on_params_complete(&mut self, ctx: CurrentCtx<'_>) -> CallResult<()> {
        with_old(ctx, |c| self.old.on_params_complete(c))
    }
    fn on_helm_start(&mut self, ctx: CurrentCtx<'_>) -> CallResult<()> {
        with_old(ctx, |c| self.old.on_helm_start(c))
    }
    fn on_every_state(&mut self, ctx: CurrentCtx<'_>) -> CallResult<()> {
        with_old(ctx, |c| self.old.on_every_state(c))
    }
    fn on_idle_state(&mut self, ctx: CurrentCtx<'_>) -> CallResult<()> {
        with_old(ctx, |c| self.old.on_idle_state(c))
    }
    fn on_idle_to_run(&mut self, ctx: CurrentCtx<'_>) -> CallResult<()> {
        with_old(ctx, |c| self.old.on_idle_to_run(c))
    }
    fn on_run_to_idle(&mut self, ctx: CurrentCtx<'_>) -> CallResult<()> {
        with_old(ctx, |c| self.old.on_run_to_idle(c))
    }
    fn on_complete(&mut self, ctx: CurrentCtx<'_>) -> CallResult<()> {
        with_old(ctx, |c| self.old.on_complete(c))
    }
    fn on_inactive(&mut self, ctx: CurrentCtx<'_>) -> CallResult<()> {
        with_old(ctx, |c| self.old.on_inactive(c))
    }
    fn on_spawn(&mut self, ctx: CurrentCtx<'_>) -> CallResult<()> {
        with_old(ctx, |c| self.old.on_spawn(c))
    }
    fn on_run(&mut self, ctx: CurrentCtx<'_>) -> CallResult<ROption<FunctionData>> {
        with_old(ctx, |c| self.old.on_run(c))
    }
    fn expand_macros(&self, text: RStr<'_>) -> CallResult<RString> {
        self.old.expand_macros(text)
    }
    fn default_duration(&self) -> CallResult<f64> {
        self.old.default_duration()
    }
    fn collective_check(&mut self) -> CallResult<RString> {
        self.old.collective_check()
    }
}
