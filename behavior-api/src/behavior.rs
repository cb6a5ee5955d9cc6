//! The behavior trait object: what the host calls, built-in and plugin alike.
//!
//! Every call returns [`CallResult`]: `Err` carries the message of a panic caught inside
//! the behavior (the SDK adapter catches it, so no unwinding crosses the boundary).

use abi_stable::sabi_trait;
use abi_stable::std_types::{RBox, ROption, RResult, RStr, RString};

use crate::context::HelmCtx;
use crate::function::FunctionData;

/// Result of a behavior call: `Err(message)` when the behavior panicked.
pub type CallResult<T> = RResult<T, RString>;

/// A behavior instance, as the helm engine sees it.
#[sabi_trait]
pub trait Behavior: Send {
    /// The behavior's decision domain (`name,low,high,points` joined by `:`); empty means
    /// the helm domain lacks what it needs ("Null IvPDomain given to Behavior").
    fn domain(&self) -> RString;
    /// The name used when the `.bhv` block has no `name =` line.
    fn default_name(&self) -> RString;
    /// A type-specific parameter; `Ok(false)` means not accepted.
    fn set_param(&mut self, ctx: HelmCtx<'_>, param: RStr<'_>, value: RStr<'_>)
        -> CallResult<bool>;
    /// After all parameters (and after each successful update).
    fn on_params_complete(&mut self, ctx: HelmCtx<'_>) -> CallResult<()>;
    /// Once at helm start-up; anything posted becomes a helm-start message.
    fn on_helm_start(&mut self, ctx: HelmCtx<'_>) -> CallResult<()>;
    /// Every iteration, before the run state is acted on.
    fn on_every_state(&mut self, ctx: HelmCtx<'_>) -> CallResult<()>;
    fn on_idle_state(&mut self, ctx: HelmCtx<'_>) -> CallResult<()>;
    fn on_idle_to_run(&mut self, ctx: HelmCtx<'_>) -> CallResult<()>;
    fn on_run_to_idle(&mut self, ctx: HelmCtx<'_>) -> CallResult<()>;
    fn on_complete(&mut self, ctx: HelmCtx<'_>) -> CallResult<()>;
    fn on_inactive(&mut self, ctx: HelmCtx<'_>) -> CallResult<()>;
    fn on_spawn(&mut self, ctx: HelmCtx<'_>) -> CallResult<()>;
    /// The running state: the objective function, if the behavior has one this iteration.
    fn on_run(&mut self, ctx: HelmCtx<'_>) -> CallResult<ROption<FunctionData>>;
    /// Expand the type's own macros in a flag value (`$[NI]`, ...).
    fn expand_macros(&self, text: RStr<'_>) -> CallResult<RString>;
    /// The type's default for the common `duration` parameter (negative: no limit).
    fn default_duration(&self) -> CallResult<f64>;
    /// Collective parameter check after configuration: `Ok("")` when fine.
    #[sabi(last_prefix_field)]
    fn collective_check(&mut self) -> CallResult<RString>;
}

/// An owned behavior trait object.
pub type BehaviorBox = Behavior_TO<'static, RBox<()>>;
