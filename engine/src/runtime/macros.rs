//! Common flag macros (behavior-common.md §3.4).

use super::BehaviorCore;
use crate::info_buffer::InfoBuffer;

/// `%.3f` with trailing zeros and a trailing point removed.
pub fn fmt3(v: f64) -> String {
    bhv::number::compact(v, 3)
}

fn replace_both(text: &mut String, name: &str, value: &str) {
    for (open, close) in [("$[", "]"), ("$(", ")")] {
        let pat = format!("{open}{name}{close}");
        if text.contains(&pat) {
            *text = text.replace(&pat, value);
        }
    }
}

/// Expand the macros every behavior shares. Unknown macros are left as they are.
pub fn expand_common(core: &mut BehaviorCore, ib: &InfoBuffer, text: &str) -> String {
    let mut s = text.to_string();
    if !s.contains("$[") && !s.contains("$(") {
        return s;
    }
    replace_both(&mut s, "OWNSHIP", &core.ownship.clone());
    replace_both(&mut s, "BHVNAME", &core.name.clone());
    replace_both(&mut s, "BHVTYPE", &core.type_name.clone());
    replace_both(&mut s, "PWT", &fmt3(core.pwt));
    replace_both(&mut s, "CONTACT", "");
    replace_both(&mut s, "UTC", &fmt3(ib.curr_time()));
    let [x, y, h, v] = core.platform;
    replace_both(&mut s, "OSX", &fmt3(x));
    replace_both(&mut s, "OSY", &fmt3(y));
    replace_both(&mut s, "OSH", &fmt3(h));
    replace_both(&mut s, "OSV", &fmt3(v));
    replace_both(&mut s, "DUR_RUN_TIME", &fmt3(core.dur_run_time));
    replace_both(&mut s, "DUR_IDLE_TIME", &fmt3(core.dur_idle_time));
    if s.contains("$[NOW]") {
        let origin = *core.now_origin.get_or_insert(ib.curr_time());
        replace_both(&mut s, "NOW", &fmt3(ib.curr_time() - origin));
    }
    for (i, name) in ["CTR", "CTR1", "CTR2", "CTR3", "CTR4", "CTR5"]
        .iter()
        .enumerate()
    {
        if s.contains(&format!("$[{name}]")) {
            core.counters[i] += 1;
            replace_both(&mut s, name, &core.counters[i].to_string());
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compact_numbers() {
        assert_eq!(fmt3(2.0), "2");
        assert_eq!(fmt3(2.5), "2.5");
        assert_eq!(fmt3(-0.0001), "0");
        assert_eq!(fmt3(1.23456), "1.235");
    }

    #[test]
    fn expands_both_spellings() {
        let mut core = BehaviorCore::new("BHV_Timer", "t1", "alpha");
        let ib = InfoBuffer::new(10.0);
        assert_eq!(
            expand_common(&mut core, &ib, "$[OWNSHIP]-$(BHVNAME)-$[BHVTYPE]-$[X]"),
            "alpha-t1-BHV_Timer-$[X]"
        );
    }
}
