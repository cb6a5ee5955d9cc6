//! Why a `.bhv` line was refused, in words a new user can act on: an unknown parameter
//! (with a did-you-mean) or a bad value (with what was expected). The behavior ABI
//! answers only "accepted or not", so the host tells the two apart by asking a spare
//! instance of the same type about the name with a few typical values.

use crate::factory::BehaviorFactory;
use crate::info_buffer::InfoBuffer;
use crate::runtime::{apply_config_line, BehaviorCore, BehaviorInstance, HostEnv};

/// The common parameters the helm handles for every behavior, and what each expects
/// (behavior-common.md §1-§2).
const COMMON: &[(&str, &str)] = &[
    ("name", "a name of letters, digits and _-[]()#@+"),
    ("descriptor", "a name of letters, digits and _-[]()#@+"),
    ("pwt", "a number >= 0"),
    ("priwt", "a number >= 0"),
    ("priority", "a number >= 0"),
    ("condition", "a logic condition, e.g. `DEPLOY = true`"),
    ("duration", "a number >= 0 or no-time-limit"),
    ("duration_status", "a variable name without spaces"),
    ("duration_reset", "VAR=value"),
    ("duration_idle_decay", "true or false"),
    ("perpetual", "true or false"),
    ("updates", "a variable name without spaces"),
    ("nostarve", "VAR[,VAR...],seconds"),
    ("post_mapping", "FROM,TO"),
    ("comms_policy", "open, lean or dire"),
    ("build_info", "text"),
    ("precision", "text"),
    ("runflag", "VAR = value"),
    ("runxflag", "VAR = value"),
    ("activeflag", "VAR = value"),
    ("inactiveflag", "VAR = value"),
    ("idleflag", "VAR = value"),
    ("endflag", "VAR = value"),
    ("spawnflag", "VAR = value"),
    ("spawnxflag", "VAR = value"),
    ("configflag", "VAR = value"),
];

/// Parameter names of the project's behaviors (built in and shipped plugins), used only
/// to suggest a name; a suggestion is offered only if the behavior accepts it.
const KNOWN_TYPE_PARAMS: &[&str] = &[
    "speed",
    "heading",
    "depth",
    "course",
    "points",
    "point",
    "polygon",
    "radius",
    "nm_radius",
    "capture_radius",
    "slip_radius",
    "lead",
    "lead_damper",
    "lead_to_start",
    "order",
    "repeat",
    "capture_line",
    "visual_hints",
    "station_pt",
    "center_activate",
    "inner_radius",
    "outer_radius",
    "outer_speed",
    "transit_speed",
    "swing_time",
    "hibernation_radius",
    "clockwise",
    "basewidth",
    "peakwidth",
    "summitdelta",
    "summit_delta",
    "tolerance",
    "max_speed",
    "max_depth",
    "cycle_flag",
    "wpt_status_var",
    "wpt_index_var",
    "post_suffix",
    "acquire_dist",
    "spiral_factor",
    "patience",
];

/// Values tried on a spare instance to learn whether a name is known at all.
const PROBE_VALUES: &[&str] = &[
    "1",
    "0",
    "true",
    "red",
    "0,0",
    "x=0,y=0",
    "pts={0,0:10,0:10,10:0,10}",
    "0,0:10,0:10,10:0,10",
    "FOO=1",
    "FOO",
    "name:0:10:11",
];

/// What a value of `param` usually is, from its name (for a type's own parameters).
fn expected_by_name(param: &str) -> &'static str {
    let p = param.to_ascii_lowercase();
    if p.contains("color") || p.contains("colour") {
        "a colour name (e.g. red, dodger_blue, off) or hex"
    } else if p.contains("polygon") || p == "points" || p == "pts" {
        "a convex polygon or point list, e.g. `pts={0,0:10,0:10,10}`"
    } else if p.ends_with("_pt") || p == "point" {
        "a point, e.g. `60,60` or `x=60,y=60`"
    } else if p.contains("domain") {
        "`name:low:high:points`"
    } else if p.contains("speed")
        || p.contains("radius")
        || p.contains("depth")
        || p.contains("dist")
        || p.contains("time")
        || p.contains("width")
    {
        "a number >= 0"
    } else if p.contains("heading") || p.contains("course") {
        "a number (degrees)"
    } else {
        "a value this behavior accepts (see its documentation)"
    }
}

/// The edit distance of two short words.
pub(crate) fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let cur = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != *cb)).min(row[j] + 1).min(cur + 1);
            prev = cur;
        }
    }
    row[b.len()]
}

/// Candidates within a third of `word`'s length (at least 2, at most 3 edits), nearest
/// first.
pub(crate) fn near<'a>(word: &str, candidates: impl Iterator<Item = &'a str>) -> Vec<&'a str> {
    let w = word.to_ascii_lowercase();
    let limit = (w.chars().count() / 3).clamp(2, 3);
    let mut found: Vec<(usize, &str)> = candidates
        .map(|c| (edit_distance(&w, &c.to_ascii_lowercase()), c))
        .filter(|(d, _)| *d <= limit)
        .collect();
    found.sort();
    found.dedup_by(|a, b| a.1 == b.1);
    found.into_iter().map(|(_, c)| c).collect()
}

/// The message for a refused `param = value` line of a behavior of `type_name`.
pub(crate) fn refused_line(
    factory: &BehaviorFactory,
    env: &HostEnv,
    ib: &InfoBuffer,
    type_name: &str,
    param: &str,
    value: &str,
) -> String {
    let value = value.trim();
    let lower = param.to_ascii_lowercase();
    let common = lower.strip_prefix('_').unwrap_or(&lower);
    let common = common
        .strip_suffix("_flag")
        .map_or(common.to_string(), |s| format!("{s}flag"));
    if let Some((_, expected)) = COMMON.iter().find(|(n, _)| *n == common) {
        return format!("bad value for `{param}`: `{value}` (expected {expected})");
    }
    let accepts = |name: &str, values: &[&str]| -> bool {
        let Some(Ok(bhv)) = factory.create(type_name, &env.helm_domain) else {
            return false;
        };
        let mut probe = BehaviorInstance {
            core: BehaviorCore::new(type_name, "probe", "probe"),
            bhv,
        };
        values
            .iter()
            .any(|v| matches!(apply_config_line(&mut probe, env, ib, name, v), Ok(true)))
    };
    if accepts(param, PROBE_VALUES) {
        return format!(
            "bad value for `{param}`: `{value}` (expected {})",
            expected_by_name(param)
        );
    }
    let mut tries: Vec<&str> = vec![value];
    tries.extend(PROBE_VALUES);
    let suggestion = near(
        param,
        COMMON
            .iter()
            .map(|(n, _)| *n)
            .chain(KNOWN_TYPE_PARAMS.iter().copied()),
    )
    .into_iter()
    .find(|c| COMMON.iter().any(|(n, _)| n == c) || accepts(c, &tries));
    let hint = suggestion
        .map(|s| format!(" (did you mean `{s}`?)"))
        .unwrap_or_default();
    format!(
        "unknown parameter `{param}` for {type_name}{hint}; the helm's common parameters \
         are {}; the type's own are in its documentation",
        COMMON
            .iter()
            .filter(|(n, _)| !matches!(*n, "descriptor" | "priwt" | "priority"))
            .map(|(n, _)| *n)
            .collect::<Vec<_>>()
            .join(", ")
    )
}

/// The known behavior type nearest `type_name`, for an unknown one.
pub(crate) fn nearest_type(factory: &BehaviorFactory, type_name: &str) -> Option<String> {
    let mut names: Vec<String> = behaviors_std::builtin_types()
        .iter()
        .map(|(n, _)| n.to_string())
        .collect();
    for l in factory.libraries() {
        names.extend(l.types.iter().cloned());
    }
    names.extend(
        crate::factory::SHIPPED_LIBRARY_TYPES
            .iter()
            .map(|s| s.to_string()),
    );
    let strip = |s: &str| s.strip_prefix("BHV_").unwrap_or(s).to_ascii_lowercase();
    let want = strip(type_name);
    let limit = (want.chars().count() / 3).clamp(1, 4);
    names
        .into_iter()
        .map(|n| (edit_distance(&want, &strip(&n)), n))
        .filter(|(d, _)| *d <= limit)
        .min()
        .map(|(_, n)| n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn near_finds_the_close_ones_first() {
        assert_eq!(
            near("spede", ["speed", "spread", "pwt"].into_iter()),
            vec!["speed"]
        );
        assert!(near("zzz", ["speed"].into_iter()).is_empty());
    }

    #[test]
    fn names_hint_the_expected_value() {
        assert!(expected_by_name("edge_color").contains("colour"));
        assert!(expected_by_name("polygon").contains("convex polygon"));
        assert!(expected_by_name("speed").contains(">= 0"));
    }
}
