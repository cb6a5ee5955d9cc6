//! What the host offers a behavior while it is being configured or run.
//!
//! The names follow the "IvP Behavior Utility Functions" a behavior author knows from
//! the C++ helm (`getBufferDoubleVal`, `postMessage`, ...); [`crate::sdk::Ctx`] wraps this
//! trait object with those names in snake case.

use abi_stable::sabi_trait;
use abi_stable::sabi_types::RMut;
use abi_stable::std_types::{ROption, RResult, RStr, RString, RVec};

use crate::value::{ContactState, PostValue};

/// The host side of one behavior call. Implemented by the helm; behaviors only call it.
#[sabi_trait]
pub trait HelmContext {
    /// The info buffer's current time (MOOS seconds).
    fn curr_time(&self) -> f64;
    /// Current time minus the helm's start time.
    fn local_time(&self) -> f64;
    /// The helm iteration counter (used in contexts and source-aux fields).
    fn helm_iteration(&self) -> u64;
    /// Ownship (MOOS community) name.
    fn ownship(&self) -> RString;
    /// This behavior's name (descriptor).
    fn name(&self) -> RString;
    /// This behavior's priority weight.
    fn priority(&self) -> f64;
    fn perpetual(&self) -> bool;
    fn set_perpetual(&mut self, perpetual: bool);
    /// Accumulated running / idle time (common state-duration bookkeeping).
    fn dur_run_time(&self) -> f64;
    fn dur_idle_time(&self) -> f64;

    /// Numeric value of `var`; with `warn`, a missing value posts the standard BHV_WARNING.
    fn double_val(&mut self, var: RStr<'_>, warn: bool) -> ROption<f64>;
    /// String value of `var` (a number is printed `%.6f`); with `warn` as above.
    fn string_val(&mut self, var: RStr<'_>, warn: bool) -> ROption<RString>;
    /// Seconds since `var` was last written to the buffer, -1 if never.
    fn time_val(&self, var: RStr<'_>) -> f64;
    /// Seconds since the timestamp of the message that last wrote `var`, -1 if never.
    fn msg_time_val(&self, var: RStr<'_>) -> f64;
    fn is_known(&self, var: RStr<'_>) -> bool;
    /// String values written to `var` during this iteration, in order.
    fn string_deltas(&self, var: RStr<'_>) -> RVec<RString>;
    /// Numeric values written to `var` during this iteration, in order.
    fn double_deltas(&self, var: RStr<'_>) -> RVec<f64>;
    /// Subscribe to comma-separated variables, optionally without missing-value warnings.
    fn add_info_vars(&mut self, vars: RStr<'_>, no_warning: bool);

    /// Queue a posting. `key` empty = default key (`<name><VAR>`), `repeatable` bypasses
    /// the duplicate filter, anything else is appended to the default key.
    fn post(&mut self, var: RStr<'_>, value: PostValue<'_>, key: RStr<'_>);
    /// Post a flag written in `.bhv` flag syntax (`VAR = VALUE [if] COND`), with the
    /// common macros expanded by the host. Type macros must already be expanded.
    fn post_flag(&mut self, flag: RStr<'_>, repeatable: bool);
    /// Expand the common macros (`$[OWNSHIP]`, `$[BHVNAME]`, `$[UTC]`, ...).
    fn expand_common_macros(&mut self, text: RStr<'_>) -> RString;
    /// Evaluate a logic condition against the info buffer; `Err` if it does not parse.
    fn eval_condition(&mut self, condition: RStr<'_>) -> RResult<bool, RString>;
    /// Complete the behavior: posts its endflags; it is removed unless perpetual.
    fn set_complete(&mut self);
    /// Ownship position as the platform update last read it (used by `$[OSX]` ...).
    fn set_platform(&mut self, osx: f64, osy: f64, osh: f64, osv: f64);
    /// A log line through the host's tracing (level 0 error .. 4 trace).
    #[sabi(last_prefix_field)]
    fn log(&mut self, level: u8, message: RStr<'_>);

    // Since 0.1.1 (contacts), after the last prefix field: a plugin built against 0.1.0
    // never calls them and still loads; a 0.1.0 host refuses a 0.1.1 plugin (the
    // loader's version rule), so a plugin never calls one its host lacks.

    /// How many contacts this iteration's ledger snapshot holds.
    fn contact_count(&self) -> u32;
    /// The `index`-th contact's name, in byte order of the names; None past the end.
    fn contact_name(&self, index: u32) -> ROption<RString>;
    /// One contact's state by exact (case-sensitive) name; None if it is not in this
    /// iteration's snapshot.
    fn contact(&self, name: RStr<'_>) -> ROption<ContactState>;
    /// A text field of a contact: `type` (after type fixing), `group`, `vsource`; ""
    /// for an unknown contact or field.
    fn contact_text(&self, name: RStr<'_>, field: RStr<'_>) -> RString;
    /// The contact this behavior is about (its `contact` parameter), so the helm keeps
    /// it in `IVPHELM_CONTACT_SUMMARY`; "" for none.
    fn set_contact(&mut self, name: RStr<'_>);

    // Since 0.1.2 (issue 19: nothing allocated on the decision path), appended the same
    // way: the texts above, written into a string the behavior keeps instead of a new
    // one per call. `out` is cleared first; growing it is the only allocation, and that
    // is the behavior's own (an `RString` frees and grows through the allocator that
    // made it). A 0.1.1 plugin is loaded through `abi_v2`, a 0.1.0 one through `abi_v1`.

    /// [`HelmContext::contact_text`] into `out`.
    fn contact_text_into(&self, name: RStr<'_>, field: RStr<'_>, out: &mut RString);
    /// [`HelmContext::name`] into `out`.
    fn name_into(&self, out: &mut RString);
    /// [`HelmContext::ownship`] into `out`.
    fn ownship_into(&self, out: &mut RString);
    /// [`HelmContext::string_val`] into `out`: false (and `out` empty) when missing,
    /// with the same warning.
    fn string_val_into(&mut self, var: RStr<'_>, warn: bool, out: &mut RString) -> bool;
    /// [`HelmContext::contact_name`] into `out`: false (and `out` empty) past the end.
    fn contact_name_into(&self, index: u32, out: &mut RString) -> bool;
}

/// The context handed to every behavior call.
pub type HelmCtx<'a> = HelmContext_TO<'a, RMut<'a, ()>>;
