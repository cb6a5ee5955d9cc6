//! The SDK: write a behavior as a plain Rust type implementing [`IvpBehavior`], talk to the
//! helm through [`Ctx`], and export it with [`crate::export_behaviors!`].
//!
//! The adapter here turns an [`IvpBehavior`] into the ABI trait object and catches any
//! panic at the boundary, returning its message to the host instead of unwinding.

use std::cell::Cell;
use std::panic::{catch_unwind, AssertUnwindSafe};

use abi_stable::sabi_trait::TD_Opaque;
use abi_stable::std_types::{ROption, RResult, RStr, RString};

use crate::behavior::{Behavior, BehaviorBox, Behavior_TO, CallResult};
use crate::context::HelmCtx;
use crate::function::FunctionData;
use crate::value::{ContactState, PostValue};

/// One variable of the helm's decision domain.
#[derive(Clone, Debug, PartialEq)]
pub struct DomainVar {
    pub name: String,
    pub low: f64,
    pub high: f64,
    pub points: u32,
}

/// The helm's decision domain as handed to a behavior at creation.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HelmDomain {
    vars: Vec<DomainVar>,
}

impl HelmDomain {
    /// Parse `name,low,high,points` joined by `:` (the form the host sends). Malformed
    /// entries are skipped: the host only ever sends what it validated itself.
    pub fn new(spec: &str) -> Self {
        let vars = spec
            .split(':')
            .filter_map(|v| {
                let f: Vec<&str> = v.split(',').collect();
                if f.len() != 4 {
                    return None;
                }
                Some(DomainVar {
                    name: f[0].to_string(),
                    low: f[1].parse().ok()?,
                    high: f[2].parse().ok()?,
                    points: f[3].parse().ok()?,
                })
            })
            .collect();
        HelmDomain { vars }
    }

    pub fn vars(&self) -> &[DomainVar] {
        &self.vars
    }

    pub fn var(&self, name: &str) -> Option<&DomainVar> {
        self.vars.iter().find(|v| v.name == name)
    }

    /// The sub-domain with exactly `names` in that order, as `name,low,high,points`
    /// joined by `:`; empty if any is missing (the helm's subDomain rule).
    pub fn sub_domain(&self, names: &[&str]) -> String {
        let mut out = String::new();
        for (i, n) in names.iter().enumerate() {
            let Some(v) = self.var(n) else {
                return String::new();
            };
            if i > 0 {
                out.push(':');
            }
            out.push_str(&format!("{},{},{},{}", v.name, v.low, v.high, v.points));
        }
        out
    }
}

/// The helm, as seen from inside a behavior call.
pub struct Ctx<'a> {
    inner: HelmCtx<'a>,
}

impl<'a> Ctx<'a> {
    pub fn new(inner: HelmCtx<'a>) -> Self {
        Ctx { inner }
    }

    /// Subscribe to comma-separated variables (`addInfoVars`).
    pub fn add_info_vars(&mut self, vars: &str) {
        self.inner.add_info_vars(vars.into(), false);
    }
    /// Subscribe without missing-value warnings (`addInfoVars(vars, "no_warning")`).
    pub fn add_info_vars_no_warning(&mut self, vars: &str) {
        self.inner.add_info_vars(vars.into(), true);
    }
    /// `getBufferDoubleVal`: posts the standard BHV_WARNING when missing.
    pub fn get_buffer_double_val(&mut self, var: &str) -> Option<f64> {
        self.inner.double_val(var.into(), true).into_option()
    }
    /// Like [`Ctx::get_buffer_double_val`] but silent when missing.
    pub fn get_buffer_double_val_quiet(&mut self, var: &str) -> Option<f64> {
        self.inner.double_val(var.into(), false).into_option()
    }
    /// `getBufferStringVal`: posts the standard BHV_WARNING when missing.
    pub fn get_buffer_string_val(&mut self, var: &str) -> Option<String> {
        self.inner
            .string_val(var.into(), true)
            .into_option()
            .map(String::from)
    }
    /// Like [`Ctx::get_buffer_string_val`] but silent when missing.
    pub fn get_buffer_string_val_quiet(&mut self, var: &str) -> Option<String> {
        self.inner
            .string_val(var.into(), false)
            .into_option()
            .map(String::from)
    }
    /// [`Ctx::get_buffer_string_val`] written into `out` (false, `out` empty, when
    /// missing): no new string once `out` has grown, for a value read every iteration.
    pub fn get_buffer_string_val_into(&mut self, var: &str, out: &mut String) -> bool {
        let inner = &mut self.inner;
        with_spare(out, |buf| inner.string_val_into(var.into(), true, buf))
    }
    /// [`Ctx::get_buffer_string_val_into`], silent when missing.
    pub fn get_buffer_string_val_quiet_into(&mut self, var: &str, out: &mut String) -> bool {
        let inner = &mut self.inner;
        with_spare(out, |buf| inner.string_val_into(var.into(), false, buf))
    }
    pub fn get_buffer_time_val(&self, var: &str) -> f64 {
        self.inner.time_val(var.into())
    }
    pub fn get_buffer_msg_time_val(&self, var: &str) -> f64 {
        self.inner.msg_time_val(var.into())
    }
    pub fn get_buffer_is_known(&self, var: &str) -> bool {
        self.inner.is_known(var.into())
    }
    pub fn get_buffer_var_updated(&self, var: &str) -> bool {
        self.inner.is_known(var.into()) && self.inner.time_val(var.into()) == 0.0
    }
    pub fn get_buffer_curr_time(&self) -> f64 {
        self.inner.curr_time()
    }
    pub fn get_buffer_local_time(&self) -> f64 {
        self.inner.local_time()
    }
    pub fn get_buffer_string_vector(&self, var: &str) -> Vec<String> {
        self.inner
            .string_deltas(var.into())
            .into_iter()
            .map(String::from)
            .collect()
    }
    pub fn get_buffer_double_vector(&self, var: &str) -> Vec<f64> {
        self.inner.double_deltas(var.into()).into_vec()
    }
    pub fn helm_iteration(&self) -> u64 {
        self.inner.helm_iteration()
    }
    pub fn ownship(&self) -> String {
        self.inner.ownship().into()
    }
    pub fn name(&self) -> String {
        self.inner.name().into()
    }
    /// [`Ctx::ownship`] written into `out`: no new string once `out` has grown.
    pub fn ownship_into(&self, out: &mut String) {
        with_spare(out, |buf| self.inner.ownship_into(buf));
    }
    /// [`Ctx::name`] written into `out`: no new string once `out` has grown.
    pub fn name_into(&self, out: &mut String) {
        with_spare(out, |buf| self.inner.name_into(buf));
    }
    pub fn priority(&self) -> f64 {
        self.inner.priority()
    }
    pub fn perpetual(&self) -> bool {
        self.inner.perpetual()
    }
    pub fn set_perpetual(&mut self, perpetual: bool) {
        self.inner.set_perpetual(perpetual)
    }
    pub fn dur_run_time(&self) -> f64 {
        self.inner.dur_run_time()
    }
    pub fn dur_idle_time(&self) -> f64 {
        self.inner.dur_idle_time()
    }

    /// `postMessage(var, string)` with the default key.
    pub fn post_message(&mut self, var: &str, value: &str) {
        self.inner
            .post(var.into(), PostValue::from(value), "".into());
    }
    /// `postMessage(var, double)` with the default key.
    pub fn post_message_num(&mut self, var: &str, value: f64) {
        self.inner
            .post(var.into(), PostValue::Num(value), "".into());
    }
    /// `postMessage(var, value, key)`: the key is appended to the default key.
    pub fn post_message_key(&mut self, var: &str, value: PostValue<'_>, key: &str) {
        self.inner.post(var.into(), value, key.into());
    }
    /// `postBoolMessage`: the string `true` / `false`.
    pub fn post_bool_message(&mut self, var: &str, value: bool) {
        self.post_message(var, if value { "true" } else { "false" });
    }
    /// `postIntMessage`: `trunc(value + 0.5)` as a number.
    pub fn post_int_message(&mut self, var: &str, value: f64) {
        self.post_message_num(var, (value + 0.5).trunc());
    }
    /// `postRepeatableMessage`: bypasses the duplicate filter.
    pub fn post_repeatable_message(&mut self, var: &str, value: PostValue<'_>) {
        self.inner.post(var.into(), value, "repeatable".into());
    }
    /// `postWMessage`: `BHV_WARNING = <name>: <msg>` (empty messages are ignored).
    pub fn post_wmessage(&mut self, msg: &str) {
        if msg.is_empty() {
            return;
        }
        self.with_prefixed(msg, |ctx, text| {
            ctx.post_repeatable_message("BHV_WARNING", PostValue::from(text));
        });
    }
    /// `postRetractWMessage`: retracts the app warning; the text is still posted.
    pub fn post_retract_wmessage(&mut self, msg: &str) {
        self.with_prefixed(msg, |ctx, text| {
            ctx.inner.post(
                "BHV_WARNING".into(),
                PostValue::from(text),
                "retract".into(),
            );
        });
    }
    /// `postEMessage`: `BHV_ERROR = <name>: <msg>`; halts the helm for this iteration.
    pub fn post_emessage(&mut self, msg: &str) {
        self.with_prefixed(msg, |ctx, text| {
            ctx.post_repeatable_message("BHV_ERROR", PostValue::from(text));
        });
    }
    /// `postEventMessage`: `BHV_EVENT = <name>: <msg>`.
    pub fn post_event_message(&mut self, msg: &str) {
        self.with_prefixed(msg, |ctx, text| ctx.post_message("BHV_EVENT", text));
    }
    /// Post a flag in `.bhv` flag syntax; common macros are expanded by the host.
    pub fn post_flag(&mut self, flag: &str, repeatable: bool) {
        self.inner.post_flag(flag.into(), repeatable)
    }
    pub fn expand_common_macros(&mut self, text: &str) -> String {
        self.inner.expand_common_macros(text.into()).into()
    }
    /// Evaluate a logic condition on the info buffer; `Err` if it does not parse.
    pub fn eval_condition(&mut self, condition: &str) -> Result<bool, String> {
        self.inner
            .eval_condition(condition.into())
            .into_result()
            .map_err(String::from)
    }
    /// `setComplete`: posts endflags; the behavior is removed unless perpetual.
    pub fn set_complete(&mut self) {
        self.inner.set_complete()
    }
    /// Record ownship as read by the platform update (`$[OSX]`, `$[OSY]`, ...).
    pub fn set_platform(&mut self, osx: f64, osy: f64, osh: f64, osv: f64) {
        self.inner.set_platform(osx, osy, osh, osv)
    }
    pub fn log(&mut self, message: &str) {
        self.inner.log(2, message.into())
    }

    /// How many contacts the helm sees this iteration.
    pub fn contact_count(&self) -> usize {
        self.inner.contact_count() as usize
    }
    /// The contacts' names, in byte order.
    pub fn contact_names(&self) -> Vec<String> {
        (0..self.inner.contact_count())
            .filter_map(|i| self.inner.contact_name(i).into_option().map(String::from))
            .collect()
    }
    /// One contact's state this iteration (`None`: not in the ledger).
    pub fn contact(&self, name: &str) -> Option<ContactState> {
        self.inner.contact(name.into()).into_option()
    }
    /// A contact's `type` (after type fixing), `group` or `vsource`; "" if unknown.
    pub fn contact_text(&self, name: &str, field: &str) -> String {
        self.inner.contact_text(name.into(), field.into()).into()
    }
    /// [`Ctx::contact_text`] written into `out`: no new string once `out` has grown
    /// (what a contact behavior reads every iteration).
    pub fn contact_text_into(&self, name: &str, field: &str, out: &mut String) {
        with_spare(out, |buf| {
            self.inner.contact_text_into(name.into(), field.into(), buf)
        });
    }
    /// The `index`-th contact's name (byte order) written into `out`; false past the end.
    pub fn contact_name_into(&self, index: usize, out: &mut String) -> bool {
        let Ok(index) = u32::try_from(index) else {
            out.clear();
            return false;
        };
        with_spare(out, |buf| self.inner.contact_name_into(index, buf))
    }
    /// Tell the helm which contact this behavior is about (`IVPHELM_CONTACT_SUMMARY`).
    pub fn set_contact(&mut self, name: &str) {
        self.inner.set_contact(name.into())
    }

    /// `<name>: <msg>` (just `msg` without a name) handed to `post`, written into this
    /// thread's kept string: a behavior may warn every iteration.
    fn with_prefixed(&mut self, msg: &str, post: impl FnOnce(&mut Self, &str)) {
        // Taken out while in use: a nested message (none is expected) gets a new one.
        let mut text = PREFIXED.with(Cell::take);
        self.name_into(&mut text);
        if !text.is_empty() {
            text.push_str(": ");
        }
        text.push_str(msg);
        post(self, &text);
        PREFIXED.with(|s| s.set(text));
    }
}

thread_local! {
    /// The text of the last prefixed message ([`Ctx::with_prefixed`]), kept.
    static PREFIXED: Cell<String> = const { Cell::new(String::new()) };
}

thread_local! {
    /// The string the helm writes an `_into` answer into before it is copied to the
    /// caller's `String`: this library's own `RString`, kept, so the helm refills it in
    /// place and grows it (through this library's allocator) only for a longer text.
    static SPARE: Cell<RString> = const { Cell::new(RString::new()) };
}

/// `fill` writes into the spare `RString`; `out` becomes a copy of it, in its own storage.
fn with_spare<R>(out: &mut String, fill: impl FnOnce(&mut RString) -> R) -> R {
    // Taken out of the cell while the helm writes: a nested call (none is expected)
    // would find an empty spare, not a borrowed one.
    let mut buf = SPARE.with(Cell::take);
    let r = fill(&mut buf);
    out.clear();
    out.push_str(buf.as_str());
    SPARE.with(|s| s.set(buf));
    r
}

/// A behavior, written as plain Rust. Only the hooks a type needs have to be written.
pub trait IvpBehavior: Send + 'static {
    /// The decision domain this behavior works on (see [`HelmDomain::sub_domain`]).
    fn domain(&self) -> String;
    /// Name used when the block has no `name =` line (e.g. `bhv_waypoint`).
    fn default_name(&self) -> String;
    /// A type-specific parameter (name lower-cased from `.bhv`, as given from updates).
    fn set_param(&mut self, ctx: &mut Ctx<'_>, param: &str, value: &str) -> bool;
    fn on_params_complete(&mut self, _ctx: &mut Ctx<'_>) {}
    fn on_helm_start(&mut self, _ctx: &mut Ctx<'_>) {}
    fn on_every_state(&mut self, _ctx: &mut Ctx<'_>) {}
    fn on_idle_state(&mut self, _ctx: &mut Ctx<'_>) {}
    fn on_idle_to_run(&mut self, _ctx: &mut Ctx<'_>) {}
    fn on_run_to_idle(&mut self, _ctx: &mut Ctx<'_>) {}
    fn on_complete(&mut self, _ctx: &mut Ctx<'_>) {}
    fn on_inactive(&mut self, _ctx: &mut Ctx<'_>) {}
    fn on_spawn(&mut self, _ctx: &mut Ctx<'_>) {}
    /// The running state: return the objective function, or `None`.
    fn on_run(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData>;
    /// Expand type-specific macros in a flag value; `None` leaves it as is.
    fn expand_macros(&self, _text: &str) -> Option<String> {
        None
    }
    /// Default of the common `duration` parameter for this type (`None`: no limit).
    /// BHV_ConstantSpeed and friends default to 0.
    fn default_duration(&self) -> Option<f64> {
        None
    }
    /// Collective check after configuration: an error message, or empty when fine.
    fn collective_check(&mut self) -> String {
        String::new()
    }
}

/// Run `f`, turning a panic into its message.
fn catching<T>(f: impl FnOnce() -> T) -> CallResult<T> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(v) => RResult::ROk(v),
        Err(payload) => {
            let msg = if let Some(s) = payload.downcast_ref::<&str>() {
                (*s).to_string()
            } else if let Some(s) = payload.downcast_ref::<String>() {
                s.clone()
            } else {
                "panic with a non-string payload".to_string()
            };
            RResult::RErr(RString::from(msg))
        }
    }
}

/// Wraps an [`IvpBehavior`] as the ABI trait object.
pub struct Adapter<B>(pub B);

macro_rules! hook {
    ($name:ident) => {
        fn $name(&mut self, ctx: HelmCtx<'_>) -> CallResult<()> {
            let b = &mut self.0;
            catching(move || b.$name(&mut Ctx::new(ctx)))
        }
    };
}

impl<B: IvpBehavior> Behavior for Adapter<B> {
    fn domain(&self) -> RString {
        // A panic here is caught and reported as an empty domain (the helm then
        // reports "Null IvPDomain").
        catching(|| self.0.domain()).unwrap_or_default().into()
    }
    fn default_name(&self) -> RString {
        catching(|| self.0.default_name())
            .unwrap_or_else(|_| "???".to_string())
            .into()
    }
    fn set_param(
        &mut self,
        ctx: HelmCtx<'_>,
        param: RStr<'_>,
        value: RStr<'_>,
    ) -> CallResult<bool> {
        let b = &mut self.0;
        catching(move || b.set_param(&mut Ctx::new(ctx), param.as_str(), value.as_str()))
    }
    hook!(on_params_complete);
    hook!(on_helm_start);
    hook!(on_every_state);
    hook!(on_idle_state);
    hook!(on_idle_to_run);
    hook!(on_run_to_idle);
    hook!(on_complete);
    hook!(on_inactive);
    hook!(on_spawn);
    fn on_run(&mut self, ctx: HelmCtx<'_>) -> CallResult<ROption<FunctionData>> {
        let b = &mut self.0;
        catching(move || ROption::from(b.on_run(&mut Ctx::new(ctx))))
    }
    fn expand_macros(&self, text: RStr<'_>) -> CallResult<RString> {
        catching(|| match self.0.expand_macros(text.as_str()) {
            Some(s) => RString::from(s),
            None => RString::from(text.as_str()),
        })
    }
    fn default_duration(&self) -> CallResult<f64> {
        catching(|| self.0.default_duration().unwrap_or(-1.0))
    }
    fn collective_check(&mut self) -> CallResult<RString> {
        let b = &mut self.0;
        catching(move || RString::from(b.collective_check()))
    }
}

/// Box a behavior as the ABI trait object (how built-in behaviors are created).
pub fn boxed<B: IvpBehavior>(b: B) -> BehaviorBox {
    Behavior_TO::from_value(Adapter(b), TD_Opaque)
}

/// Construct and box a behavior; a panicking constructor gives its message.
pub fn boxed_catching<B: IvpBehavior>(ctor: impl FnOnce() -> B) -> RResult<BehaviorBox, RString> {
    catching(ctor).map(boxed)
}

/// Convert a function built with the `ivp` builders into the ABI form (no deep copy).
pub fn function_data(f: ivp::IvpFunction) -> FunctionData {
    FunctionData::from_ivp(f)
}

/// A copy of `f` in this thread's spare storage (no allocation once the spares hold
/// room; the context is not copied): for a behavior that keeps a function depending
/// only on its parameters and hands out copies while they stay (the Constant* plugins).
pub fn copy_function(f: &ivp::IvpFunction) -> Result<ivp::IvpFunction, ivp::IvpError> {
    crate::function::copied_function(
        ivp::Domain::from_var_refs(f.domain().vars().iter())?,
        f.bounds(),
        f.weights(),
        f.gelbox(),
        f.grid_bounds(),
        f.pwt(),
    )
}

/// [`copy_function`] then [`function_data`], without the `ivp` function between them:
/// the copy's buffers go straight into the ABI form, in this thread's spare storage,
/// and no domain (with its name strings) or context is made only to be dropped again.
/// The result is the same, bit for bit; `pwt` replaces the function's own.
pub fn copy_function_data(f: &ivp::IvpFunction, pwt: f64) -> FunctionData {
    let (bounds, weights, gelbox, grid) = ivp::zaic::spare::function_buffers_from(
        f.bounds(),
        f.weights(),
        f.gelbox(),
        f.grid_bounds(),
    );
    FunctionData {
        domain: crate::function::domain_text(f.domain()),
        bounds: bounds.into(),
        weights: weights.into(),
        pwt,
        gelbox: gelbox.into(),
        grid: grid.into(),
    }
}

impl HelmDomain {
    /// The `ivp` domain with exactly `names` (in that order); `None` if one is missing.
    pub fn ivp_domain(&self, names: &[&str]) -> Option<ivp::Domain> {
        let mut d = ivp::Domain::new();
        for n in names {
            let v = self.var(n)?;
            d.add_var(&v.name, v.low, v.high, v.points).ok()?;
        }
        Some(d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `copy_function_data` gives what `copy_function`, a new pwt and `function_data`
    /// give, with and without a grid.
    #[test]
    fn copy_function_data_is_copy_then_function_data() {
        let d = ivp::Domain::parse("course:0:359:360,speed:0:4:41").unwrap();
        let pieces = [
            (vec![(0, 99), (0, 40)], vec![0.5, -0.0, 3.0]),
            (vec![(100, 359), (0, 40)], vec![-0.25, 1.5, 7.0]),
        ];
        let mut f = ivp::IvpFunction::from_pieces(d, &pieces).unwrap();
        for grid in [false, true] {
            if grid {
                f.build_grid();
            }
            let direct = copy_function_data(&f, 42.5);
            let mut copy = copy_function(&f).unwrap();
            copy.set_pwt(42.5);
            let via = function_data(copy);
            let bits = crate::testing::function_data_bits;
            assert_eq!(bits(&direct), bits(&via), "grid {grid}");
            assert_eq!(direct.grid.is_empty(), !grid);
        }
    }
}
