//! The words of a `.bhv` behavior block a host needs to explain a refused line: the
//! helm's common parameters and what each expects, the parameter names of the project's
//! behaviors (for did-you-mean), typical values, and a nearest-word search.

/// The common parameters the helm handles for every behavior, and what each expects
/// (behavior-common.md §1-§2).
pub const COMMON: &[(&str, &str)] = &[
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
pub const KNOWN_TYPE_PARAMS: &[&str] = &[
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
pub const PROBE_VALUES: &[&str] = &[
    "1",
    "0",
    "true",
    // A flag only one way accepted (`use_refinery`, which the helm does not build) and
    // the grade words: without them a refused value read as an unknown parameter.
    "false",
    "linear",
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
pub fn expected_by_name(param: &str) -> &'static str {
    let p = param.to_ascii_lowercase();
    if p == "use_refinery" {
        // AvoidCollision refuses `true`: its refinery is not described, so it is not
        // guessed (plugins/README.md); the COLREGS behaviors take a boolean.
        "false for BHV_AvoidCollision (this helm does not build its refinery), a boolean elsewhere"
    } else if p.contains("color") || p.contains("colour") {
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
pub fn edit_distance(a: &str, b: &str) -> usize {
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
pub fn near<'a>(word: &str, candidates: impl Iterator<Item = &'a str>) -> Vec<&'a str> {
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
