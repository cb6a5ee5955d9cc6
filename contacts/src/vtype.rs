//! Vehicle types as the ledger stores them (contacts-appcast.md §2.2 steps 4–5).

/// The types the ledger knows (compared case-insensitively); any other becomes `ship`.
pub const KNOWN_TYPES: &[&str] = &[
    "auv",
    "kayak",
    "uuv",
    "usv",
    "glider",
    "asv",
    "ship",
    "mokai",
    "longship",
    "buoy",
    "heron",
    "swimmer",
    "cray",
    "bcray",
    "crayx",
    "wamv",
    "bcrayx",
    "smr",
    "smrx",
    "skyw",
    "skywalker",
    "quad",
    "quadcopter",
];

/// Step 4: `uuv` (exactly, lower case) becomes `auv`; a known type keeps its spelling
/// (`KAYAK` stays `KAYAK`); anything else, the empty type included, becomes `ship`.
///
/// ```
/// assert_eq!(contacts::fix_type("uuv"), "auv");
/// assert_eq!(contacts::fix_type("UUV"), "UUV");
/// assert_eq!(contacts::fix_type("dinghy"), "ship");
/// ```
pub fn fix_type(t: &str) -> &str {
    if t == "uuv" {
        "auv"
    } else if KNOWN_TYPES.iter().any(|k| k.eq_ignore_ascii_case(t)) {
        t
    } else {
        "ship"
    }
}

/// A (fixed) type that must come with a depth: exactly `auv` or `glider`.
pub fn needs_depth(fixed_type: &str) -> bool {
    fixed_type == "auv" || fixed_type == "glider"
}

/// Step 5: the length a report gets when it gives none (or one ≤ 0), by exact
/// lower-case type; `None` leaves it as it was.
pub fn default_length(fixed_type: &str) -> Option<f64> {
    match fixed_type {
        "auv" | "kayak" | "heron" => Some(3.0),
        "glider" => Some(2.0),
        "cray" | "bcray" | "crayx" | "bcrayx" => Some(1.5),
        "ship" => Some(12.0),
        "longship" => Some(15.0),
        "wamv" | "smr" => Some(6.0),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn type_fixing() {
        assert_eq!(fix_type("kayak"), "kayak");
        assert_eq!(fix_type("KAYAK"), "KAYAK");
        assert_eq!(fix_type("Glider"), "Glider");
        assert_eq!(fix_type(""), "ship");
        assert_eq!(fix_type("uuv"), "auv");
        assert_eq!(fix_type("Uuv"), "Uuv");
        assert!(needs_depth("auv") && needs_depth("glider"));
        assert!(!needs_depth("AUV") && !needs_depth("Glider"));
    }

    #[test]
    fn default_lengths() {
        assert_eq!(default_length("kayak"), Some(3.0));
        assert_eq!(default_length("KAYAK"), None);
        assert_eq!(default_length("bcrayx"), Some(1.5));
        assert_eq!(default_length("longship"), Some(15.0));
        assert_eq!(default_length("smr"), Some(6.0));
        assert_eq!(default_length("usv"), None);
    }
}
