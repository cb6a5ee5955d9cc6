//! Small text conventions shared by client and DB: `*`/`?` wildcards, the `key=value`
//! lookup of spec §5.7, and C++ `ostream << double` formatting (`%g`, 6 digits).

/// Wildcard match: `*` matches any run (including none), `?` exactly one byte.
pub fn wildcard_match(pattern: &str, text: &str) -> bool {
    let (p, t) = (pattern.as_bytes(), text.as_bytes());
    let (mut pi, mut ti) = (0usize, 0usize);
    let mut star: Option<(usize, usize)> = None;
    while ti < t.len() {
        if pi < p.len() && (p[pi] == b'?' || p[pi] == t[ti]) {
            pi += 1;
            ti += 1;
        } else if pi < p.len() && p[pi] == b'*' {
            star = Some((pi, ti));
            pi += 1;
        } else if let Some((sp, st)) = star {
            pi = sp + 1;
            ti = st + 1;
            star = Some((sp, st + 1));
        } else {
            return false;
        }
    }
    while pi < p.len() && p[pi] == b'*' {
        pi += 1;
    }
    pi == p.len()
}

/// Look up `token` in a `k=v,k=v` string (spec §5.7). Case-sensitive unless `nocase`.
pub fn find_value(s: &str, token: &str, nocase: bool) -> Option<String> {
    for part in s.split(',') {
        let part = part.trim_start_matches([' ', '\t']);
        let Some(eq) = part.find('=') else { continue };
        let (name, rest) = (part[..eq].trim_end(), &part[eq + 1..]);
        let hit = if nocase {
            name.eq_ignore_ascii_case(token)
        } else {
            name == token
        };
        if hit {
            return Some(rest.trim().to_owned());
        }
    }
    None
}

/// C `atof`: the longest numeric prefix after leading white space, else 0.
pub fn atof(s: &str) -> f64 {
    let s = s.trim_start();
    let b = s.as_bytes();
    let mut end = 0;
    let mut best = 0.0;
    // Try every prefix that could be a number; keep the longest that parses.
    while end < b.len() && (b[end].is_ascii_digit() || b"+-.eE".contains(&b[end])) {
        end += 1;
        if let Ok(v) = s[..end].parse::<f64>() {
            best = v;
        }
    }
    best
}

/// Format like C++ `ostream << double` with default precision (`%g`, 6 significant).
pub fn format_g(v: f64) -> String {
    format_g_prec(v, 6)
}

/// `%.<prec>g`.
pub fn format_g_prec(v: f64, prec: usize) -> String {
    if v.is_nan() {
        return "nan".into();
    }
    if v.is_infinite() {
        return if v > 0.0 { "inf".into() } else { "-inf".into() };
    }
    if v == 0.0 {
        return if v.is_sign_negative() {
            "-0".into()
        } else {
            "0".into()
        };
    }
    let p = prec.max(1);
    let e = format!("{:.*e}", p - 1, v);
    let (mant, exp) = e.split_once('e').unwrap_or((&e, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    if exp < -4 || exp >= p as i32 {
        let mant = strip_zeros(mant);
        let sign = if exp < 0 { '-' } else { '+' };
        format!("{mant}e{sign}{:02}", exp.abs())
    } else {
        let decimals = (p as i32 - 1 - exp).max(0) as usize;
        strip_zeros(&format!("{:.*}", decimals, v)).to_owned()
    }
}

fn strip_zeros(s: &str) -> &str {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn g_format() {
        assert_eq!(format_g(0.0), "0");
        assert_eq!(format_g(0.5), "0.5");
        assert_eq!(format_g(2.0), "2");
        assert_eq!(format_g(1e-5), "1e-05");
        assert_eq!(format_g(1234567.0), "1.23457e+06");
        assert_eq!(format_g(0.104904), "0.104904");
        assert_eq!(format_g(1e9), "1e+09");
    }

    #[test]
    fn wildcards() {
        assert!(wildcard_match("W_*", "W_A"));
        assert!(wildcard_match("*", ""));
        assert!(wildcard_match("", ""));
        assert!(!wildcard_match("", "X"));
        assert!(wildcard_match("N?V_*X", "NAV_X"));
        assert!(!wildcard_match("pub*", "other"));
        assert!(wildcard_match("*_X*", "NAV_X"));
    }

    #[test]
    fn kv() {
        let s = "AppPattern=*,VarPattern=W_*,Interval=0.5";
        assert_eq!(find_value(s, "VarPattern", false).as_deref(), Some("W_*"));
        assert_eq!(find_value(s, "Interval", false).as_deref(), Some("0.5"));
        assert_eq!(find_value(s, "interval", false), None);
        assert_eq!(
            find_value("hostname=vm", "hostname", false).as_deref(),
            Some("vm")
        );
        assert_eq!(atof("0.5xyz"), 0.5);
        assert_eq!(atof("abc"), 0.0);
    }
}
