//! The colour parser: one parser for every behavior parameter and every VIEW_* attribute
//! (behaviors-std.md, the correction at its top).
//!
//! A value is compared lower-cased, ends trimmed, every `_` removed (`Dark_Khaki` =
//! `darkkhaki`). It is a colour when it is
//! - one of the four words `black`, `empty`, `off`, `invisible` (always colours);
//! - a known name: the names the real parser knows (including its misspelt ones such as
//!   `tomatao`, and `gray05` ... `grey95`, `hillside`, `macbeige`, ...) and every CSS name
//!   (`tomato`, `grey`, `aliceblue`, ...): accepting a name the real helm refuses breaks
//!   no mission, refusing one it accepts does;
//! - `hex:` then three two-digit hex numbers separated by `,` (blanks allowed);
//! - a decimal triple when the value holds `,` `%` `$` `#` or `:` (the first of these, in
//!   that order, is the separator): exactly three numbers, each clipped into [0,1].
//!
//! A triple that comes out pure black (0,0,0) is not a colour: only the word `black`
//! (or `empty`/`off`/`invisible`) names black.

/// A parsed colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Color {
    /// A known name or one of the four words, as its canonical lower-case table entry
    /// without `_` (`"darkkhaki"`, `"off"`).
    Named(&'static str),
    /// Red, green and blue in [0,1] from a `hex:` or decimal triple.
    Rgb(f64, f64, f64),
}

/// The words that are colours whatever they parse to (they all mean black / not drawn).
const ALWAYS: &[&str] = &["black", "empty", "off", "invisible"];

/// Every known name, lower case without `_`, sorted (binary search). The union of the
/// real parser's 180 names (misspellings kept) and the CSS colour names.
const NAMES: &[&str] = &[
    "aliceblue",
    "antiquewhite",
    "aqua",
    "aquamarine",
    "azure",
    "beige",
    "bisque",
    "black",
    "blanchedalmond",
    "blue",
    "blueviolet",
    "brown",
    "burlywood",
    "cadetblue",
    "chartreuse",
    "chocolate",
    "coral",
    "cornflowerblue",
    "cornsilk",
    "crimson",
    "cyan",
    "darkblue",
    "darkcyan",
    "darkgoldenrod",
    "darkgray",
    "darkgreen",
    "darkgrey",
    "darkkhaki",
    "darkmagenta",
    "darkolivegreen",
    "darkorange",
    "darkorchid",
    "darkred",
    "darksalmon",
    "darkseagreen",
    "darkslateblue",
    "darkslategray",
    "darkslategrey",
    "darkturquoise",
    "darkviolet",
    "deeppink",
    "deepskyblue",
    "dimgray",
    "dimgrey",
    "dodgerblue",
    "firebrick",
    "floralwhite",
    "forestgreen",
    "fuchsia",
    "gainsboro",
    "ghostwhite",
    "gold",
    "goldenrod",
    "gray",
    "gray05",
    "gray10",
    "gray15",
    "gray20",
    "gray25",
    "gray30",
    "gray35",
    "gray40",
    "gray45",
    "gray50",
    "gray55",
    "gray60",
    "gray65",
    "gray70",
    "gray75",
    "gray80",
    "gray85",
    "gray90",
    "gray95",
    "green",
    "greenyellow",
    "grey",
    "grey05",
    "grey10",
    "grey15",
    "grey20",
    "grey25",
    "grey30",
    "grey35",
    "grey40",
    "grey45",
    "grey50",
    "grey55",
    "grey60",
    "grey65",
    "grey70",
    "grey75",
    "grey80",
    "grey85",
    "grey90",
    "grey95",
    "hillside",
    "honeydew",
    "hotpink",
    "indianred",
    "indigo",
    "ivory",
    "khaki",
    "lavender",
    "lavenderblush",
    "lawngreen",
    "lemonchiffon",
    "lightblue",
    "lightcoral",
    "lightcyan",
    "lightgoldenrod",
    "lightgoldenrodyellow",
    "lightgray",
    "lightgreen",
    "lightgrey",
    "lightpink",
    "lightsalmon",
    "lightseagreen",
    "lightskyblue",
    "lightslategray",
    "lightslategrey",
    "lightsteelblue",
    "lightyellow",
    "lime",
    "limegreen",
    "linen",
    "macbeige",
    "macpurple",
    "magenta",
    "maroon",
    "mediumaquamarine",
    "mediumblue",
    "mediumorchid",
    "mediumprchid",
    "mediumpurple",
    "mediumseagreen",
    "mediumslateblue",
    "mediumspringgreen",
    "mediumturquoise",
    "mediumvioletred",
    "midnightblue",
    "mintcream",
    "mistyrose",
    "moccasin",
    "navajowhite",
    "navy",
    "oldlace",
    "olive",
    "olivedrab",
    "orange",
    "orangered",
    "orchid",
    "oxfordindigo",
    "palegoldenrod",
    "palegreen",
    "paleturquoise",
    "palevioletred",
    "papayawhip",
    "peachpuff",
    "pelegoldenrod",
    "peru",
    "pink",
    "plum",
    "powderblue",
    "purple",
    "rebeccapurple",
    "red",
    "rosybrown",
    "royalblue",
    "saddlebrowm",
    "saddlebrown",
    "salmon",
    "sandybrown",
    "seagreen",
    "seashell",
    "sienna",
    "silver",
    "skyblue",
    "slateblue",
    "slategray",
    "slategrey",
    "snow",
    "springgreen",
    "steelblue",
    "tan",
    "teal",
    "thistle",
    "tomatao",
    "tomato",
    "turquoise",
    "violet",
    "vlightpink",
    "wheat",
    "white",
    "whitesmoke",
    "yellow",
    "yellowgreen",
];

/// Separators of a decimal triple, in the order they are looked for.
const TRIPLE_SEPARATORS: [char; 5] = [',', '%', '$', '#', ':'];

/// The colour `s` names, or `None` when it is not a colour.
///
/// ```
/// use mbutil::{parse_color, Color};
/// assert_eq!(parse_color("Dodger_Blue"), Some(Color::Named("dodgerblue")));
/// assert_eq!(parse_color("hex:ff,00,80"), Some(Color::Rgb(1.0, 0.0, 128.0 / 255.0)));
/// assert_eq!(parse_color("0.5:2:0"), Some(Color::Rgb(0.5, 1.0, 0.0)));
/// assert_eq!(parse_color("0,0,0"), None);
/// ```
pub fn parse_color(s: &str) -> Option<Color> {
    let folded: String = s
        .trim()
        .chars()
        .filter(|c| *c != '_')
        .map(|c| c.to_ascii_lowercase())
        .collect();
    if let Some(w) = ALWAYS.iter().find(|w| **w == folded) {
        return Some(Color::Named(w));
    }
    if let Ok(i) = NAMES.binary_search(&folded.as_str()) {
        return Some(Color::Named(NAMES[i]));
    }
    let (r, g, b) = if let Some(hex) = folded.strip_prefix("hex:") {
        hex_triple(hex)?
    } else {
        decimal_triple(&folded)?
    };
    // Pure black only by name: a triple that parses to black is a failed parse.
    if r == 0.0 && g == 0.0 && b == 0.0 {
        return None;
    }
    Some(Color::Rgb(r, g, b))
}

/// True when `s` is a colour ([`parse_color`]).
pub fn is_color(s: &str) -> bool {
    parse_color(s).is_some()
}

/// `bd,b7,6b` (blanks allowed around each): three two-digit hex numbers.
fn hex_triple(s: &str) -> Option<(f64, f64, f64)> {
    let mut out = [0.0; 3];
    let mut n = 0;
    for part in s.split(',') {
        let part = part.trim_matches(|c: char| c == ' ' || c == '\t');
        if n == 3 || part.len() != 2 || !part.bytes().all(|b| b.is_ascii_hexdigit()) {
            return None;
        }
        out[n] = f64::from(u8::from_str_radix(part, 16).ok()?) / 255.0;
        n += 1;
    }
    (n == 3).then_some((out[0], out[1], out[2]))
}

/// Three numbers separated by the first of [`TRIPLE_SEPARATORS`] the value holds, each
/// clipped into [0,1].
fn decimal_triple(s: &str) -> Option<(f64, f64, f64)> {
    let sep = TRIPLE_SEPARATORS.into_iter().find(|c| s.contains(*c))?;
    let mut out = [0.0; 3];
    let mut n = 0;
    for part in s.split(sep) {
        if n == 3 {
            return None;
        }
        out[n] = crate::number::parse_number(part)?.clamp(0.0, 1.0);
        n += 1;
    }
    (n == 3).then_some((out[0], out[1], out[2]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_is_sorted_lower_case_without_underscores() {
        assert!(NAMES.windows(2).all(|w| w[0] < w[1]));
        for n in NAMES {
            assert!(n
                .bytes()
                .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit()));
        }
        // The real parser's 180 names are all here (spot checks of each kind).
        for n in [
            "gray70",
            "grey05",
            "hillside",
            "macbeige",
            "macpurple",
            "oxfordindigo",
        ] {
            assert!(is_color(n), "{n}");
        }
        assert!(NAMES.len() >= 180);
    }

    #[test]
    fn names_fold_case_and_underscores_and_trim() {
        assert_eq!(parse_color("gray70"), Some(Color::Named("gray70")));
        assert_eq!(parse_color("Dark_Khaki"), Some(Color::Named("darkkhaki")));
        assert_eq!(
            parse_color("  DODGER_BLUE\t"),
            Some(Color::Named("dodgerblue"))
        );
        assert_eq!(parse_color("light_blue"), Some(Color::Named("lightblue")));
        assert_eq!(parse_color("_g_r_a_y_7_0_"), Some(Color::Named("gray70")));
        assert!(!is_color("dodger blue"));
        assert!(!is_color("gray71"));
        assert!(!is_color("not_a_color"));
        assert!(!is_color(""));
        assert!(!is_color("   "));
        assert!(!is_color("_"));
    }

    #[test]
    fn misspelt_real_names_and_correct_css_names() {
        for (wrong, right) in [
            ("mediumprchid", "mediumorchid"),
            ("pelegoldenrod", "palegoldenrod"),
            ("saddlebrowm", "saddlebrown"),
            ("tomatao", "tomato"),
        ] {
            assert_eq!(parse_color(wrong), Some(Color::Named(wrong)));
            assert_eq!(parse_color(right), Some(Color::Named(right)));
        }
        for css in ["grey", "aliceblue", "mediumaquamarine", "darkslategrey"] {
            assert!(is_color(css), "{css}");
        }
    }

    #[test]
    fn the_four_words_are_always_colours() {
        for w in [
            "black",
            "empty",
            "off",
            "invisible",
            "Black",
            "OFF",
            "In_Visible",
        ] {
            assert!(is_color(w), "{w}");
        }
        assert_eq!(parse_color("Empty"), Some(Color::Named("empty")));
        assert!(!is_color("inactive"));
        assert!(!is_color("none"));
    }

    #[test]
    fn hex_triples() {
        assert_eq!(
            parse_color("hex:bd,b7,6b"),
            Some(Color::Rgb(189.0 / 255.0, 183.0 / 255.0, 107.0 / 255.0))
        );
        assert_eq!(parse_color("HEX:FF,00,00"), Some(Color::Rgb(1.0, 0.0, 0.0)));
        assert_eq!(
            parse_color("hex: ff , 00,00 "),
            Some(Color::Rgb(1.0, 0.0, 0.0))
        );
        assert_eq!(
            parse_color("h_ex:ff,00,00"),
            Some(Color::Rgb(1.0, 0.0, 0.0))
        );
        for bad in [
            "hex:",
            "hex:ff",
            "hex:ff,00",
            "hex:ff,00,00,00",
            "hex:f,00,00",
            "hex:fff,00,00",
            "hex:gg,00,00",
            "hex:ff:00:00",
            "hex:ff0000",
            "hex:ff,,00",
            "0xff0000",
        ] {
            assert!(!is_color(bad), "{bad}");
        }
    }

    #[test]
    fn decimal_triples_with_each_separator() {
        for sep in [",", "%", "$", "#", ":"] {
            let v = format!("0.741{sep}0.718{sep}0.42");
            assert_eq!(parse_color(&v), Some(Color::Rgb(0.741, 0.718, 0.42)), "{v}");
        }
        // Blanks around the numbers; clipped into [0,1].
        assert_eq!(
            parse_color(" 1 , 0.5 , 0 "),
            Some(Color::Rgb(1.0, 0.5, 0.0))
        );
        assert_eq!(parse_color("2,-1,0.5"), Some(Color::Rgb(1.0, 0.0, 0.5)));
        assert_eq!(parse_color("255,0,0"), Some(Color::Rgb(1.0, 0.0, 0.0)));
        // The first separator in the order , % $ # : wins: the others stay in a field.
        assert!(!is_color("0.5,0.5:0.5"));
        assert!(!is_color("0.5:0.5%0.5"));
        // Exactly three numbers.
        for bad in [
            "0.5,0.5",
            "0.5,0.5,0.5,0.5",
            "0.5,,0.5",
            "a,b,c",
            "1e0,0,0",
            "0.5,0.5,",
        ] {
            assert!(!is_color(bad), "{bad}");
        }
    }

    #[test]
    fn pure_black_only_by_name() {
        for bad in ["0,0,0", "0:0:0", "-1,-2,0", "hex:00,00,00", "0.0%0%0"] {
            assert!(!is_color(bad), "{bad}");
        }
        assert!(is_color("black"));
        assert!(is_color("0,0,0.001"));
        assert!(is_color("hex:00,00,01"));
    }

    proptest::proptest! {
        #[test]
        fn never_panics(s in ".{0,24}") {
            let _ = parse_color(&s);
        }
    }
}
