//! One behavior's part in one helm iteration (behavior-common.md §4 and §6).

use behavior_api::{CallResult, FunctionData as Function, HelmCtx};
use bhv::number::atof;

use super::context::with_ctx;
use super::flags::{post_flags, FlagKind};
use super::updates::process_updates;
use super::{fault, BehaviorCore, BehaviorInstance, HostEnv, RunState};
use crate::info_buffer::InfoBuffer;
use crate::posting::Value;

/// Call a behavior hook; a panic disables the behavior and posts BHV_ERROR. A completion
/// requested inside the hook posts the endflags where it was requested.
fn call<R: Default>(
    inst: &mut BehaviorInstance,
    env: &HostEnv,
    ib: &InfoBuffer,
    f: impl FnOnce(&mut behavior_api::BehaviorBox, HelmCtx<'_>) -> CallResult<R>,
) -> R {
    // A behavior that misbehaved is never called again.
    if inst.core.faulted {
        return R::default();
    }
    let (bhv, core) = (&mut inst.bhv, &mut inst.core);
    let result = with_ctx(core, env, ib, |ctx| f(bhv, ctx));
    let out = result.into_result().unwrap_or_else(|panic| {
        fault(&mut inst.core, &format!("behavior panicked: {panic}"));
        R::default()
    });
    // Checked here, the rare completion out of line: this follows every hook call.
    if let Some(pos) = inst.core.complete_requested.take() {
        finish_completion(inst, env, ib, pos);
    }
    out
}

#[cold]
fn finish_completion(inst: &mut BehaviorInstance, env: &HostEnv, ib: &InfoBuffer, pos: usize) {
    let pos = pos.min(inst.core.messages.len());
    let tail = inst.core.messages.split_off(pos);
    set_complete(inst, env, ib);
    inst.core.messages.extend(tail);
}

/// `setComplete`: endflags (repeatable); completed unless perpetual.
fn set_complete(inst: &mut BehaviorInstance, env: &HostEnv, ib: &InfoBuffer) {
    post_flags(inst, env, ib, FlagKind::End, true);
    if !inst.core.perpetual {
        inst.core.completed = true;
    }
}

fn post_duration_status(core: &mut BehaviorCore, remaining: f64) {
    if core.duration_status.is_empty() {
        return;
    }
    let v = if remaining <= 10.0 {
        remaining
    } else {
        (remaining + 0.5).trunc()
    };
    let var = std::mem::take(&mut core.duration_status); // lent, not copied
    core.post(&var, Value::Num(v), "");
    core.duration_status = var;
}

fn reset_duration(core: &mut BehaviorCore) {
    core.duration_started = false;
    core.duration_reset_pending = false;
    core.dur_idle_time = 0.0;
    core.dur_run_time = 0.0;
    if core.duration >= 0.0 {
        let d = core.duration;
        post_duration_status(core, d);
    }
}

/// `duration_reset = VAR=VAL`, checked before the runnable test.
fn check_duration_reset(core: &mut BehaviorCore, ib: &InfoBuffer) {
    let Some((var, val)) = &core.duration_reset else {
        return;
    };
    let Some(t) = ib.update_time(var) else {
        return;
    };
    let matches =
        val.is_empty() || ib.sval(var) == Some(val.as_str()) || ib.dval(var) == Some(atof(val));
    let fresh = core.last_reset_trigger_time.is_none_or(|last| t > last);
    if matches && fresh {
        core.last_reset_trigger_time = Some(t);
        reset_duration(core);
    }
}

/// The runnable test (§4 step 4), with its side effects.
fn runnable(inst: &mut BehaviorInstance, env: &HostEnv, ib: &InfoBuffer) -> RunState {
    let core = &mut inst.core;
    if core.completed {
        return RunState::Completed;
    }
    if core.faulted {
        return RunState::Disabled;
    }
    let failed = match core.conditions_checked {
        Some((iteration, failed)) if iteration == core.iteration => failed,
        _ => {
            let failed = core.conditions.iter_mut().position(|c| !c.update_eval(ib));
            core.conditions_checked = Some((core.iteration, failed));
            failed
        }
    };
    if let Some(c) = failed.and_then(|i| core.conditions.get(i)) {
        core.status_info.push_str(",pc=");
        core.status_info.push_str(c.raw());
        return RunState::Idle;
    }
    if core.duration_reset_pending {
        reset_duration(core);
    }
    if core.duration >= 0.0 {
        let now = ib.curr_time();
        if !core.duration_started {
            core.duration_started = true;
            core.duration_start_time = now;
            core.dur_idle_time = 0.0;
        }
        let mut elapsed = now - core.duration_start_time;
        if !core.duration_idle_decay {
            elapsed -= core.dur_idle_time;
        }
        post_duration_status(core, (core.duration - elapsed).max(0.0));
        if elapsed >= core.duration {
            core.status_info.push_str(",pc=completed-byduration");
            set_complete(inst, env, ib);
            if inst.core.perpetual {
                inst.core.duration_reset_pending = true;
            } else {
                return RunState::Completed;
            }
        }
    }
    let core = &mut inst.core;
    if core.empty_domain {
        core.post_error("Null IvPDomain given to Behavior");
        return RunState::Idle;
    }
    if let Some((vars, secs)) = &core.nostarve {
        for v in vars {
            let age = ib.time_val(v);
            if age < 0.0 || age > *secs {
                let pc = format!(",pc=VarStarve: {v}");
                core.status_info.push_str(&pc);
                return RunState::Idle;
            }
        }
    }
    RunState::Running
}

/// Common state-duration bookkeeping: the interval since the previous call goes to the
/// state of this call.
fn accumulate(core: &mut BehaviorCore, now: f64, running: bool) {
    if let Some(prev) = core.dur_last_call {
        if running {
            core.dur_run_time += now - prev;
        } else {
            core.dur_idle_time += now - prev;
        }
    }
    core.dur_last_call = Some(now);
}

/// Checks a function from a behavior, read where it lies, before the helm trusts it:
/// its weight and piece count, or `None` when it is to be dropped.
fn validate(core: &mut BehaviorCore, f: &Function) -> Option<(f64, usize)> {
    // Thousands of weights a function: the solver's SIMD scan.
    let nan = ivp_solver::any_nan(&f.weights);
    if nan || f.pwt.is_nan() {
        // Never trusted again: disabled, like a panic (the C++ helm only discards it).
        fault(core, "NaN detected in IvP Function");
        return None;
    }
    // `FunctionData::piece_count`, with the dimensions of the domain text placed last
    // (the same text every iteration) instead of counting its colons again.
    let same = mbutil::short_str::same(&core.placed_domain, f.domain.as_str());
    let dim = if same { core.placed_dim } else { f.dim() };
    let n = f.bounds.len().checked_div(2 * dim).unwrap_or(0);
    if n * 2 * dim != f.bounds.len() || f.weights.len() != n * (dim + 1) || dim == 0 {
        fault(core, MISMATCH);
        return None;
    }
    (f.pwt > 0.0).then_some((f.pwt, n))
}

const MISMATCH: &str = "IvP function rejected: its buffers do not match its domain";

/// Run one behavior for one iteration: its objective function, validated (no NaN, positive
/// weight, consistent buffers), in `f` (written once, not moved through every result).
pub fn step(inst: &mut BehaviorInstance, env: &HostEnv, ib: &InfoBuffer, f: &mut Option<Function>) {
    let old = inst.core.state;
    let now = ib.curr_time();
    inst.core.iteration += 1;
    inst.core.ok = true;
    inst.core.status_info.clear();
    inst.core.status_info.push_str("name=");
    let core = &mut inst.core;
    core.status_info.push_str(&core.name);

    if process_updates(inst, env, ib) {
        inst.core.config_posted = false;
        call(inst, env, ib, |b, c| b.on_params_complete(c));
    }
    check_duration_reset(&mut inst.core, ib);

    let mut new = runnable(inst, env, ib);
    call(inst, env, ib, |b, c| b.on_every_state(c));
    if new == RunState::Completed {
        call(inst, env, ib, |b, c| b.on_complete(c));
    }
    if !inst.core.config_posted {
        post_flags(inst, env, ib, FlagKind::Config, false);
        inst.core.config_posted = true;
    }
    *f = None;
    match new {
        RunState::Idle => {
            if old != RunState::Idle {
                post_flags(inst, env, ib, FlagKind::Idle, true);
                post_flags(inst, env, ib, FlagKind::Inactive, true);
            }
            if matches!(old, RunState::Running | RunState::Active) {
                call(inst, env, ib, |b, c| b.on_run_to_idle(c));
            }
            call(inst, env, ib, |b, c| b.on_idle_state(c));
            accumulate(&mut inst.core, now, false);
        }
        RunState::Running => {
            if inst.core.duration >= 0.0 && inst.core.duration_started {
                let core = &mut inst.core;
                let mut remaining = core.duration - (now - core.duration_start_time);
                if !core.duration_idle_decay {
                    remaining += core.dur_idle_time;
                }
                post_duration_status(core, remaining.max(0.0));
            }
            if old == RunState::Idle {
                call(inst, env, ib, |b, c| b.on_idle_to_run(c));
            }
            call(inst, env, ib, |b, c| b.on_run(c).map(|o| *f = o.into()));
            if matches!(old, RunState::Idle | RunState::Fresh) {
                post_flags(inst, env, ib, FlagKind::Run, true);
            }
            post_flags(inst, env, ib, FlagKind::Runx, true);
            let kept = f.as_ref().and_then(|f| validate(&mut inst.core, f));
            if let Some((pwt, pcs)) = kept {
                if old != RunState::Active {
                    post_flags(inst, env, ib, FlagKind::Active, true);
                }
                new = RunState::Active;
                let core = &mut inst.core;
                let (bits, count, text) = &mut core.pwt_pcs;
                if (*bits, *count) != (pwt.to_bits(), pcs) {
                    (*bits, *count) = (pwt.to_bits(), pcs);
                    text.clear();
                    text.push_str(",pwt=");
                    mbutil::push_fixed(text, pwt, 5);
                    text.push_str(",pcs=");
                    mbutil::push_u64(text, pcs as u64);
                }
                core.status_info.push_str(text);
            } else {
                *f = None;
                if old == RunState::Active {
                    post_flags(inst, env, ib, FlagKind::Inactive, true);
                }
                call(inst, env, ib, |b, c| b.on_inactive(c));
            }
            accumulate(&mut inst.core, now, true);
        }
        _ => {}
    }

    // Post-check: the runnable test once more, with all its side effects.
    if new != RunState::Completed && new != RunState::Disabled {
        let again = runnable(inst, env, ib);
        if again == RunState::Completed {
            new = RunState::Completed;
            call(inst, env, ib, |b, c| b.on_complete(c));
        }
    }
    if inst.core.faulted {
        new = RunState::Disabled;
        *f = None;
    }

    let core = &mut inst.core;
    // `<status info>,state=<state>,updates=<good>/<total> or n/a`: the status info itself
    // becomes the message (not copied), a spare string taking its place.
    // The tail is the same text while the state and the counts hold: copied, not
    // written again.
    let shown = (
        new,
        core.good_updates,
        core.bad_updates,
        core.updates_var.is_empty(),
    );
    if core.status_tail.0 != Some(shown) {
        let mut tail = std::mem::take(&mut core.status_tail.1);
        tail.clear();
        tail.push_str(",state=");
        tail.push_str(new.as_str());
        tail.push_str(",updates=");
        core.push_update_counts(&mut tail);
        core.status_tail = (Some(shown), tail);
    }
    let room = core.status_info.len() + 40;
    let mut status = std::mem::replace(&mut core.status_info, core.pool.take_for(room));
    status.push_str(&core.status_tail.1);
    core.post("BHV_STATUS", Value::Str(status), "");
    if new != old {
        core.state_entry_time = now;
    }
    core.state = new;
    if core.iteration == 1 {
        post_flags(inst, env, ib, FlagKind::Spawnx, true);
    }
}

/// A behavior just spawned from a template: its hooks, then its spawnflags.
pub fn spawned(inst: &mut BehaviorInstance, env: &HostEnv, ib: &InfoBuffer) {
    call(inst, env, ib, |b, c| b.on_params_complete(c));
    call(inst, env, ib, |b, c| b.on_spawn(c));
    post_flags(inst, env, ib, FlagKind::Spawn, true);
}
