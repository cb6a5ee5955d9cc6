//! Number formatting into a caller's string: the compact formatter of MOOS-IvP
//! ([`mbutil::compact`]) without a string of its own, for text a helm or a behavior
//! writes every iteration into kept buffers.

/// `mbutil::compact(v, decimals)` appended to `out`, with no string of its own
/// (the helm's summary and a behavior's status postings format numbers every
/// iteration).
pub fn push_compact(out: &mut String, v: f64, decimals: usize) {
    use std::fmt::Write as _;
    if v.is_nan() {
        out.push_str(if v.is_sign_negative() { "-nan" } else { "nan" });
    } else if v.fract() == 0.0 && v.abs() < 1e15 {
        let _ = write!(out, "{}", v as i64);
    } else {
        let start = out.len();
        let _ = write!(out, "{v:.decimals$}");
        if out[start..].contains('.') {
            let kept = out.trim_end_matches('0').trim_end_matches('.').len();
            out.truncate(kept.max(start));
        }
        if &out[start..] == "-0" {
            out.truncate(start);
            out.push('0');
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn push_compact_is_compact() {
        let mut seed = 11u64;
        let mut out = String::from("x=");
        for k in 0..20_000 {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let scale = [1e-6, 1e-3, 1.0, 1e3, 1e9, 1e17][k % 6];
            let mut v = ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * scale;
            if k % 7 == 0 {
                v = v.round();
            }
            for v in [
                v,
                -0.0,
                f64::NAN,
                -f64::NAN,
                f64::INFINITY,
                f64::NEG_INFINITY,
            ] {
                for dec in [0, 2, 3, 5, 6] {
                    out.truncate(2);
                    push_compact(&mut out, v, dec);
                    assert_eq!(&out[2..], mbutil::compact(v, dec), "{v} {dec}");
                }
            }
        }
    }
}
