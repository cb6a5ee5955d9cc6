//! Helpers shared by the standard behaviors: value parsing the way the reference does it,
//! the platform (ownship) update and macro substitution.

use behavior_api::sdk::Ctx;

/// The number test of bhv-format.md §8.6 followed by the value (`atof`): MOOS-IvP's one
/// number parser, shared with the `.bhv` reader and every plugin.
pub use behavior_api::parse_number;

/// A non-negative number.
pub fn parse_nonneg(s: &str) -> Option<f64> {
    parse_number(s).filter(|v| *v >= 0.0)
}

/// Boolean words: true/false, yes/no, on/off (any case).
pub fn parse_bool(s: &str) -> Option<bool> {
    match s.trim().to_ascii_lowercase().as_str() {
        "true" | "yes" | "on" => Some(true),
        "false" | "no" | "off" => Some(false),
        _ => None,
    }
}

/// A variable name: non-empty, no white space.
pub fn no_white(s: &str) -> Option<&str> {
    let t = s.trim();
    (!t.is_empty() && !t.chars().any(char::is_whitespace)).then_some(t)
}

/// Ownship as read by the platform update.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Platform {
    pub x: f64,
    pub y: f64,
    pub heading: f64,
    pub speed: f64,
}

/// `updatePlatformInfo`: NAV_X/NAV_Y/NAV_HEADING required (BHV_ERROR otherwise),
/// NAV_SPEED optional (warning only, 0). Records the values for `$[OSX]`...
pub fn platform_update(ctx: &mut Ctx<'_>) -> Option<Platform> {
    let x = ctx.get_buffer_double_val("NAV_X");
    let y = ctx.get_buffer_double_val("NAV_Y");
    let (Some(x), Some(y)) = (x, y) else {
        ctx.post_emessage("No ownship X/Y info in info_buffer.");
        return None;
    };
    let Some(h) = ctx.get_buffer_double_val("NAV_HEADING") else {
        ctx.post_emessage("No ownship heading info in info_buffer.");
        return None;
    };
    let heading = geometry::angle360(h);
    let speed = ctx.get_buffer_double_val("NAV_SPEED").unwrap_or(0.0);
    ctx.set_platform(x, y, heading, speed);
    Some(Platform {
        x,
        y,
        heading,
        speed,
    })
}

pub use behavior_api::flag::{has_macro_named, macro_at, subst};

/// Variables appearing as the left operand of a comparison in a logic condition.
pub fn condition_vars(cond: &str) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    let bytes: Vec<char> = cond.chars().collect();
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i];
        if c == '=' || c == '<' || c == '>' || c == '!' {
            // walk back over blanks, then collect the identifier
            let mut j = i;
            while j > 0 && bytes[j - 1] == ' ' {
                j -= 1;
            }
            let end = j;
            while j > 0 && (bytes[j - 1].is_alphanumeric() || bytes[j - 1] == '_') {
                j -= 1;
            }
            if j < end {
                let word: String = bytes[j..end].iter().collect();
                let lower = word.to_ascii_lowercase();
                if lower != "and"
                    && lower != "or"
                    && parse_number(&word).is_none()
                    && !out.contains(&word)
                {
                    out.push(word);
                }
            }
            while i < bytes.len() && matches!(bytes[i], '=' | '<' | '>' | '!') {
                i += 1;
            }
            continue;
        }
        i += 1;
    }
    out
}

/// [`fmt_f0`] appended to `out`. Below 2^52 the value is rounded here (to the nearest
/// integer, ties to even, as `{:.0}` rounds a binary value) and printed as an integer:
/// the status reports print two such numbers every iteration.
pub fn push_f0(out: &mut String, v: f64) {
    if v.is_nan() {
        out.push_str("nan");
    } else if v.is_infinite() {
        out.push_str(if v > 0.0 { "inf" } else { "-inf" });
    } else if v.abs() < 4_503_599_627_370_496.0 {
        if v.is_sign_negative() {
            out.push('-');
        }
        behavior_api::push_u64(out, v.abs().round_ties_even() as u64);
    } else {
        behavior_api::push_fixed(out, v, 0);
    }
}

/// printf `%.0f` of a ratio, with C's spelling of infinities and NaN.
pub fn fmt_f0(v: f64) -> String {
    if v.is_nan() {
        "nan".to_string()
    } else if v.is_infinite() {
        if v > 0.0 { "inf" } else { "-inf" }.to_string()
    } else {
        format!("{v:.0}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers() {
        assert_eq!(parse_number("3"), Some(3.0));
        assert_eq!(parse_number(" -2.5 "), Some(-2.5));
        assert_eq!(parse_number("+4"), Some(4.0));
        assert_eq!(parse_number(".5"), Some(0.5));
        assert_eq!(parse_number("1e3"), None);
        assert_eq!(parse_number("1.2.3"), None);
        assert_eq!(parse_number("abc"), None);
        assert_eq!(parse_number(""), None);
        assert_eq!(parse_number("-"), None);
        assert_eq!(parse_number("3-"), None);
        assert_eq!(parse_nonneg("-1"), None);
        assert_eq!(parse_bool("TRUE"), Some(true));
        assert_eq!(parse_bool("off"), Some(false));
        assert_eq!(parse_bool("maybe"), None);
        assert_eq!(no_white("A B"), None);
        assert_eq!(no_white(" AB "), Some("AB"));
    }

    #[test]
    fn macros_and_conditions() {
        let mut s = "a=$[NI] b=$(NI) c=$[NIX]".to_string();
        subst(&mut s, "NI", "3");
        assert_eq!(s, "a=3 b=3 c=$[NIX]");
        assert_eq!(
            condition_vars("(LEAD = true) and (SPEED_OK != false) or X<=3"),
            vec!["LEAD", "SPEED_OK", "X"]
        );
        assert_eq!(fmt_f0(f64::INFINITY), "inf");
        assert_eq!(fmt_f0(f64::NAN), "nan");
        assert_eq!(fmt_f0(2.5), "2");
        let halves = (-40..40).map(|k| f64::from(k) + 0.5);
        let near = [0.49999999999999994, 1.5000000000000002, 2.4999999999999996];
        let mut seed = 11u64;
        // 53 random bits scaled by 2^0 .. 2^-62: integers, halves and fractions of all sizes.
        let random = std::iter::repeat_with(move || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
            let sign = if seed & 1 == 0 { 1.0 } else { -1.0 };
            sign * (seed >> 11) as f64 * 2f64.powi(-(((seed >> 3) % 63) as i32))
        });
        let big = [
            4503599627370495.5,
            4503599627370496.0,
            9007199254740993.0,
            1e300,
        ];
        let special = [
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            2.5,
            -0.4,
            1e20,
            3.0,
        ];
        for v in special
            .into_iter()
            .chain(halves)
            .chain(near)
            .chain(big)
            .chain([0.0, -0.0, 5e-324, -5e-324])
            .chain(random.take(20000))
        {
            let mut s = String::from("d=");
            push_f0(&mut s, v);
            assert_eq!(s, format!("d={}", fmt_f0(v)), "{v:e}");
        }
    }

    /// The plain form `subst` replaced: a copy of the text per pattern.
    fn subst_plain(text: &mut String, key: &str, value: &str) {
        for pat in [format!("$[{key}]"), format!("$({key})")] {
            if text.contains(&pat) {
                *text = text.replace(&pat, value);
            }
        }
    }

    #[test]
    fn subst_in_place_matches_the_plain_replace_on_random_texts() {
        let atoms = [
            "$", "[", "]", "(", ")", "N", "I", "X", "é", "$[NI]", "$(NI)", "$[N",
        ];
        let values = ["", "3", "$(NI)", "12.5,-3", "ñé"];
        let mut seed = 7u64;
        let mut next = |n: usize| {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 33) as usize % n
        };
        for _ in 0..20000 {
            let len = next(12);
            let text: String = (0..len).map(|_| atoms[next(atoms.len())]).collect();
            let key = ["NI", "N", "X"][next(3)];
            let value = values[next(values.len())];
            let (mut a, mut b) = (text.clone(), text.clone());
            subst(&mut a, key, value);
            subst_plain(&mut b, key, value);
            assert_eq!(a, b, "text {text:?} key {key} value {value:?}");
            let plain = text.contains(&format!("$[{key}]")) || text.contains(&format!("$({key})"));
            assert_eq!(has_macro_named(&text, key), plain, "{text:?} {key}");
        }
    }
}
