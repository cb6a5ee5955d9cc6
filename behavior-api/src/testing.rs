//! A mock helm for unit-testing behaviors without the host: an info buffer of numbers
//! and strings you set, and a record of everything the behavior posts.
//!
//! ```
//! use behavior_api::testing::MockHelm;
//! let mut helm = MockHelm::new("my_bhv");
//! helm.nav(0.0, 0.0, 90.0, 1.5);
//! let speed = helm.with(|ctx| ctx.get_buffer_double_val("NAV_SPEED"));
//! assert_eq!(speed, Some(1.5));
//! helm.with(|ctx| ctx.post_message("DONE", "yes"));
//! assert_eq!(helm.last("DONE").as_deref(), Some("yes"));
//! ```

use std::collections::HashMap;

use crate::context::{HelmContext, HelmContext_TO};
use crate::sdk::Ctx;
use crate::{ContactState, PostValue};
use abi_stable::sabi_trait::TD_Opaque;
use abi_stable::sabi_types::RMut;
use abi_stable::std_types::{ROption, RResult, RStr, RString, RVec};

/// Ownship's name in the mock.
const OWNSHIP: &str = "abe";

/// The mock: fields are public so a test can set and inspect anything.
#[derive(Default)]
pub struct MockHelm {
    pub nums: HashMap<String, f64>,
    pub strs: HashMap<String, String>,
    pub posts: Vec<(String, String, String)>,
    pub flags: Vec<(String, bool)>,
    pub perpetual: bool,
    pub completes: u32,
    pub platform: (f64, f64, f64, f64),
    pub time: f64,
    pub run_time: f64,
    pub idle_time: f64,
    pub name: String,
    pub priority: f64,
    /// Contacts by name: state, type, group (see [`MockHelm::contact`]).
    pub contacts: std::collections::BTreeMap<String, (ContactState, String, String)>,
    /// What the behavior told the helm with `set_contact`.
    pub contact_set: String,
}

impl MockHelm {
    /// A mock helm for a behavior named `name` (priority 100, time 1000).
    pub fn new(name: &str) -> Self {
        MockHelm {
            name: name.into(),
            time: 1000.0,
            priority: 100.0,
            ..Default::default()
        }
    }
    /// Set a numeric variable.
    pub fn set(&mut self, var: &str, v: f64) {
        self.nums.insert(var.into(), v);
    }
    /// Forget a variable.
    pub fn unset(&mut self, var: &str) {
        self.nums.remove(var);
        self.strs.remove(var);
    }
    /// Set NAV_X, NAV_Y, NAV_HEADING, NAV_SPEED.
    pub fn nav(&mut self, x: f64, y: f64, h: f64, v: f64) {
        self.nums.insert("NAV_X".into(), x);
        self.nums.insert("NAV_Y".into(), y);
        self.nums.insert("NAV_HEADING".into(), h);
        self.nums.insert("NAV_SPEED".into(), v);
    }
    /// Put a contact in the ledger (or move it): position, heading, speed, type; its
    /// report time is the mock's `time`.
    pub fn contact(&mut self, name: &str, x: f64, y: f64, hdg: f64, spd: f64, vtype: &str) {
        let state = ContactState {
            x,
            y,
            hdg,
            spd,
            utc: self.time,
            utc_received: self.time,
            ..ContactState::default()
        };
        self.contacts
            .insert(name.into(), (state, vtype.into(), String::new()));
    }

    /// Run `f` with a behavior context backed by this mock.
    pub fn with<R>(&mut self, f: impl FnOnce(&mut Ctx<'_>) -> R) -> R {
        let to = HelmContext_TO::from_ptr(RMut::new(self), TD_Opaque);
        let mut ctx = Ctx::new(to);
        f(&mut ctx)
    }
    /// Values posted to `var`, in order.
    pub fn posted(&self, var: &str) -> Vec<String> {
        self.posts
            .iter()
            .filter(|p| p.0 == var)
            .map(|p| p.1.clone())
            .collect()
    }
    pub fn last(&self, var: &str) -> Option<String> {
        self.posted(var).last().cloned()
    }
    pub fn clear(&mut self) {
        self.posts.clear();
        self.flags.clear();
    }
}

impl HelmContext for MockHelm {
    fn curr_time(&self) -> f64 {
        self.time
    }
    fn local_time(&self) -> f64 {
        self.time - 1000.0
    }
    fn helm_iteration(&self) -> u64 {
        1
    }
    fn ownship(&self) -> RString {
        OWNSHIP.into()
    }
    fn name(&self) -> RString {
        self.name.as_str().into()
    }
    fn priority(&self) -> f64 {
        self.priority
    }
    fn perpetual(&self) -> bool {
        self.perpetual
    }
    fn set_perpetual(&mut self, perpetual: bool) {
        self.perpetual = perpetual;
    }
    fn dur_run_time(&self) -> f64 {
        self.run_time
    }
    fn dur_idle_time(&self) -> f64 {
        self.idle_time
    }
    fn double_val(&mut self, var: RStr<'_>, warn: bool) -> ROption<f64> {
        match self.nums.get(var.as_str()) {
            Some(v) => ROption::RSome(*v),
            None => {
                if warn {
                    let msg = format!(
                        "{}: {} dbl info not found in helm info_buffer",
                        self.name, var
                    );
                    self.posts
                        .push(("BHV_WARNING".into(), msg, "repeatable".into()));
                }
                ROption::RNone
            }
        }
    }
    fn string_val(&mut self, var: RStr<'_>, _warn: bool) -> ROption<RString> {
        self.strs
            .get(var.as_str())
            .map(|s| RString::from(s.as_str()))
            .into()
    }
    fn time_val(&self, _var: RStr<'_>) -> f64 {
        0.0
    }
    fn msg_time_val(&self, _var: RStr<'_>) -> f64 {
        0.0
    }
    fn is_known(&self, var: RStr<'_>) -> bool {
        self.nums.contains_key(var.as_str()) || self.strs.contains_key(var.as_str())
    }
    // Every string set in the mock counts as this iteration's mail.
    fn string_deltas(&self, var: RStr<'_>) -> RVec<RString> {
        self.strs
            .get(var.as_str())
            .map(|s| RString::from(s.as_str()))
            .into_iter()
            .collect()
    }
    fn double_deltas(&self, _var: RStr<'_>) -> RVec<f64> {
        RVec::new()
    }
    fn add_info_vars(&mut self, _vars: RStr<'_>, _no_warning: bool) {}
    fn post(&mut self, var: RStr<'_>, value: PostValue<'_>, key: RStr<'_>) {
        let v = match value {
            PostValue::Str(s) => s.to_string(),
            PostValue::Num(n) => format!("{n}"),
        };
        self.posts.push((var.to_string(), v, key.to_string()));
    }
    fn post_flag(&mut self, flag: RStr<'_>, repeatable: bool) {
        self.flags.push((flag.to_string(), repeatable));
    }
    fn expand_common_macros(&mut self, text: RStr<'_>) -> RString {
        text.into()
    }
    /// Only `VAR = value` (string equality) is understood; anything else, or a text
    /// containing `BAD`, fails to parse.
    fn eval_condition(&mut self, condition: RStr<'_>) -> RResult<bool, RString> {
        let c = condition.as_str();
        if c.contains("BAD") {
            return RResult::RErr("bad condition".into());
        }
        match c.split_once('=') {
            Some((var, val)) => {
                RResult::ROk(self.strs.get(var.trim()).map(String::as_str) == Some(val.trim()))
            }
            None => RResult::RErr("no operator".into()),
        }
    }
    fn set_complete(&mut self) {
        self.completes += 1;
    }
    fn set_platform(&mut self, osx: f64, osy: f64, osh: f64, osv: f64) {
        self.platform = (osx, osy, osh, osv);
    }
    fn log(&mut self, _level: u8, _message: RStr<'_>) {}

    fn contact_count(&self) -> u32 {
        u32::try_from(self.contacts.len()).unwrap_or(u32::MAX)
    }
    fn contact_name(&self, index: u32) -> ROption<RString> {
        self.contacts
            .keys()
            .nth(index as usize)
            .map(|n| RString::from(n.as_str()))
            .into()
    }
    fn contact(&self, name: RStr<'_>) -> ROption<ContactState> {
        self.contacts
            .get(name.as_str())
            .map(|(s, _, _)| ContactState {
                utc_age: self.time - s.utc,
                utc_age_received: self.time - s.utc_received,
                ..*s
            })
            .into()
    }
    fn contact_text(&self, name: RStr<'_>, field: RStr<'_>) -> RString {
        match (self.contacts.get(name.as_str()), field.as_str()) {
            (Some((_, t, _)), "type") => t.as_str().into(),
            (Some((_, _, g)), "group") => g.as_str().into(),
            _ => RString::new(),
        }
    }
    fn set_contact(&mut self, name: RStr<'_>) {
        // Into the kept string: a behavior sets its contact every iteration.
        self.contact_set.clear();
        self.contact_set.push_str(name.as_str());
    }

    // The `_into` forms: the answers above, written into `out` without a string of
    // their own (a behavior's allocation count in a test is then its own).
    fn contact_text_into(&self, name: RStr<'_>, field: RStr<'_>, out: &mut RString) {
        let text = match (self.contacts.get(name.as_str()), field.as_str()) {
            (Some((_, t, _)), "type") => t.as_str(),
            (Some((_, _, g)), "group") => g.as_str(),
            _ => "",
        };
        refill(out, text);
    }
    fn name_into(&self, out: &mut RString) {
        refill(out, &self.name);
    }
    fn ownship_into(&self, out: &mut RString) {
        refill(out, OWNSHIP);
    }
    fn string_val_into(&mut self, var: RStr<'_>, _warn: bool, out: &mut RString) -> bool {
        let v = self.strs.get(var.as_str());
        refill(out, v.map_or("", String::as_str));
        v.is_some()
    }
    fn contact_name_into(&self, index: u32, out: &mut RString) -> bool {
        let v = self.contacts.keys().nth(index as usize);
        refill(out, v.map_or("", String::as_str));
        v.is_some()
    }
}

fn refill(out: &mut RString, text: &str) {
    out.clear();
    out.push_str(text);
}

/// A global allocator for a profiling binary or test of a behavior: the system
/// allocator, counting allocations and reallocations per thread ([`allocations`]), so
/// one can see whether a build allocates in steady state. Install it in the binary:
/// `#[global_allocator] static GLOBAL: CountingAlloc = CountingAlloc;`
pub struct CountingAlloc;

thread_local! {
    /// This thread's count. Per thread, so that what the test harness's own thread
    /// allocates meanwhile (it may run late on a loaded machine) is not counted.
    static ALLOCATIONS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// Allocations and reallocations so far on this thread through [`CountingAlloc`] (0
/// when it is not the global allocator).
pub fn allocations() -> usize {
    ALLOCATIONS.try_with(std::cell::Cell::get).unwrap_or(0)
}

fn count_one() {
    // A thread being torn down has no count left to keep.
    let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
}

impl MockHelm {
    /// The allocations this mock made recording the postings and flags it holds: one
    /// per non-empty string it copied, and for a number what formatting it again costs.
    /// An allocation test takes this off what a call made; run it outside the measured
    /// span (it formats).
    pub fn recording_allocations(&self) -> usize {
        let mut n = self.flags.len();
        for (var, val, key) in &self.posts {
            n += usize::from(!var.is_empty()) + usize::from(!key.is_empty());
            // A number is recorded as `format!("{n}")` (more than one allocation when long).
            match val.parse::<f64>() {
                Ok(v) if format!("{v}") == *val => {
                    let before = allocations();
                    std::hint::black_box(format!("{}", std::hint::black_box(v)));
                    n += allocations() - before;
                }
                _ => n += usize::from(!val.is_empty()),
            }
        }
        n
    }
}

/// Everything an IvP function is made of, its numbers by their bits: two functions are
/// the same bit for bit when these are equal (a kept function against a fresh build).
#[allow(clippy::type_complexity)]
pub fn function_bits(
    f: &ivp::IvpFunction,
) -> (Vec<i32>, Vec<u64>, Vec<u32>, Vec<u64>, String, u64) {
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    (
        f.bounds().to_vec(),
        bits(f.weights()),
        f.gelbox().to_vec(),
        bits(f.grid_bounds()),
        f.domain().to_ipf_string(),
        f.pwt().to_bits(),
    )
}

/// [`function_bits`] of a function as it crosses the ABI: its domain text, pieces, pwt,
/// gel box and grid, numbers by their bits (a kept function handed out against a fresh
/// build's `function_data`).
#[allow(clippy::type_complexity)]
pub fn function_data_bits(
    f: &crate::FunctionData,
) -> (String, Vec<i32>, Vec<u64>, u64, Vec<u32>, Vec<u64>) {
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    (
        f.domain.to_string(),
        f.bounds.to_vec(),
        bits(&f.weights),
        f.pwt.to_bits(),
        f.gelbox.to_vec(),
        bits(&f.grid),
    )
}

/// Fold `text` (and a separator) into an FNV-1a `hash`: a fingerprint of a behavior's
/// postings, to compare them across versions.
pub fn fnv(hash: &mut u64, text: &str) {
    for b in text.bytes().chain([0xff]) {
        *hash ^= u64::from(b);
        *hash = hash.wrapping_mul(0x100_0000_01b3);
    }
}

// SAFETY: every call is passed on to the system allocator unchanged.
unsafe impl std::alloc::GlobalAlloc for CountingAlloc {
    unsafe fn alloc(&self, layout: std::alloc::Layout) -> *mut u8 {
        count_one();
        // SAFETY: the caller's contract, passed on.
        unsafe { std::alloc::System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: std::alloc::Layout) {
        // SAFETY: the caller's contract, passed on.
        unsafe { std::alloc::System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: std::alloc::Layout, new_size: usize) -> *mut u8 {
        count_one();
        // SAFETY: the caller's contract, passed on.
        unsafe { std::alloc::System.realloc(ptr, layout, new_size) }
    }
}
