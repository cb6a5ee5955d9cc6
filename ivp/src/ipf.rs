//! BHV_IPF serialization (spec §9).

use crate::domain::push_compact;
use crate::function::IvpFunction;
use std::fmt::Write;

/// The custom 4-decimal weight encoding of spec §9.1.
pub fn encode_weight(w: f64, out: &mut String) {
    let mut a = w;
    if a < 0.0 {
        out.push('-');
        a = -a;
    }
    if a == 0.0 {
        out.push('0');
        return;
    }
    if !a.is_finite() {
        let _ = write!(out, "{a}");
        return;
    }
    let x = a * 10000.0 + 0.5;
    // Integer arithmetic gives the same digits as the float form for every weight below
    // 1e15 / 10000 and avoids float formatting on the per-iteration path. Below 1e15
    // (< 2^53) `x as u64` is exactly `x.trunc()`, without a libm call per weight.
    if x < 1e15 {
        let n = x as u64;
        if n == 0 {
            out.push_str("0.0000");
            return;
        }
        // Integer part and up to four fractional digits on the stack, then one append.
        let mut ib = itoa::Buffer::new();
        out.push_str(ib.format(n / 10000));
        let frac = (n % 10000) as u32;
        let mut buf = [b'.', b'0', b'0', b'0', b'0'];
        let mut len = 1;
        if frac != 0 {
            buf[1] += (frac / 1000) as u8;
            buf[2] += (frac / 100 % 10) as u8;
            buf[3] += (frac / 10 % 10) as u8;
            buf[4] += (frac % 10) as u8;
            len = 5;
            while buf[len - 1] == b'0' {
                len -= 1;
            }
        }
        out.push_str(std::str::from_utf8(&buf[..len]).unwrap_or("."));
        return;
    }
    let n = x.trunc();
    let int = (n / 10000.0).trunc();
    let frac = (n - int * 10000.0) as u32;
    let _ = write!(out, "{int:.0}.");
    push_frac4(out, frac);
}

fn push_i32(out: &mut String, v: i32) {
    out.push_str(itoa::Buffer::new().format(v));
}

/// Four fractional digits with trailing zeros removed (nothing for 0).
fn push_frac4(out: &mut String, frac: u32) {
    if frac == 0 {
        return;
    }
    let digits = [frac / 1000, frac / 100 % 10, frac / 10 % 10, frac % 10];
    let mut last = 4;
    while last > 0 && digits[last - 1] == 0 {
        last -= 1;
    }
    for d in &digits[..last] {
        out.push((b'0' + *d as u8) as char);
    }
}

/// BHV_IPF whole-function string (spec §9.1).
pub fn encode(f: &IvpFunction) -> String {
    let dim = f.dim();
    // Generous: growing a string of thousands of pieces copies it each time.
    let mut s = String::with_capacity(
        96 + f.context().len() + f.piece_count() * (dim * 12 + (dim + 1) * 10),
    );
    let _ = write!(
        s,
        "H,{},{},{},{},1,",
        f.context().chars().count(),
        f.context(),
        dim,
        f.piece_count(),
    );
    push_compact(&mut s, f.pwt());
    s.push_str(",D,");
    f.domain().write_ipf(&mut s);
    s.push_str(",G");
    for &g in f.gelbox() {
        s.push(',');
        s.push_str(itoa::Buffer::new().format(g));
    }
    s.push_str(",F");
    for p in f.pieces() {
        for d in 0..dim {
            s.push(',');
            push_i32(&mut s, p.lo(d));
            s.push(',');
            push_i32(&mut s, p.hi(d));
        }
        for &w in p.weights() {
            s.push(',');
            encode_weight(w, &mut s);
        }
    }
    s
}

/// Smallest packet body. The spec's `2000 - header` goes to 0 and below for behavior
/// names of 1950+ characters (one packet per character, thousands per iteration); names
/// under 1450 characters never reach this floor, so real missions are split as specified.
const MIN_BODY: usize = 500;

/// Split a whole-function string into BHV_IPF packets (spec §9.2, packet size 2000).
pub fn ipf_packets(id: &str, whole: &str) -> Vec<String> {
    if whole.is_ascii() && id.is_ascii() {
        let header = id.len() + 50;
        let body = 2000usize.saturating_sub(header).max(MIN_BODY);
        let count = whole.len() / body + 1;
        return (1..=count)
            .map(|k| {
                let a = ((k - 1) * body).min(whole.len());
                let b = (k * body).min(whole.len());
                let mut p = String::with_capacity(id.len() + 24 + (b - a));
                let _ = write!(p, "P,{id},{count},{k},");
                p.push_str(&whole[a..b]);
                p
            })
            .collect();
    }
    let chars: Vec<char> = whole.chars().collect();
    let header = id.chars().count() + 50;
    let body = 2000usize.saturating_sub(header).max(MIN_BODY);
    let count = chars.len() / body + 1;
    (1..=count)
        .map(|k| {
            let a = ((k - 1) * body).min(chars.len());
            let b = (k * body).min(chars.len());
            let mut p = format!("P,{id},{count},{k},");
            p.extend(&chars[a..b]);
            p
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::domain::Domain;

    fn enc(w: f64) -> String {
        let mut s = String::new();
        encode_weight(w, &mut s);
        s
    }

    #[test]
    fn weights() {
        assert_eq!(enc(2.0), "2.");
        assert_eq!(enc(100.0), "100.");
        assert_eq!(enc(-0.00004), "-0.0000");
        assert_eq!(enc(0.25), "0.25");
        assert_eq!(enc(123.45678), "123.4568");
        assert_eq!(enc(-1000.0), "-1000.");
        assert_eq!(enc(0.289425), "0.2894");
        assert_eq!(enc(0.0), "0");
        assert_eq!(enc(0.05), "0.05");
        assert_eq!(enc(1.0001), "1.0001");
        assert_eq!(enc(12345678.9), "12345678.9");
        assert_eq!(enc(3e14), "300000000000000.");
    }

    #[test]
    fn spec_packet_example() {
        let d = Domain::parse("speed:0:2:21").unwrap();
        let mut f = IvpFunction::from_pieces(
            d,
            &[
                (vec![(0, 4)], vec![2.0, 100.0]),
                (vec![(5, 11)], vec![-0.00004, 0.25]),
                (vec![(12, 20)], vec![123.45678, -1000.0]),
            ],
        )
        .unwrap();
        f.set_pwt(37.5);
        f.set_context("12:abc");
        let p = ipf_packets("abc^12", &encode(&f));
        assert_eq!(p, vec!["P,abc^12,1,1,H,6,12:abc,1,3,1,37.5,D,speed;0;2;21,G,20,F,0,4,2.,100.,5,11,-0.0000,0.25,12,20,123.4568,-1000.".to_string()]);
    }

    #[test]
    fn chunking_exact_multiple() {
        let id = "x";
        let body = 2000 - 51;
        let whole: String = "a".repeat(body * 2);
        let p = ipf_packets(id, &whole);
        assert_eq!(p.len(), 3);
        assert_eq!(p[2], "P,x,3,3,");
    }

    #[test]
    fn chunking_keeps_the_spec_body_up_to_the_floor() {
        let whole: String = "a".repeat(5000);
        // A 1449-character id: body 2000 - 1499 = 501, as specified.
        let id = "n".repeat(1449);
        let p = ipf_packets(&id, &whole);
        assert_eq!(p.len(), 5000 / 501 + 1);
        // Past it the body stays at 500 (the spec's would reach 0 at 1950).
        let id = "n".repeat(3000);
        let p = ipf_packets(&id, &whole);
        assert_eq!(p.len(), 5000 / 500 + 1);
        assert!(p[0].ends_with(&"a".repeat(500)));
    }
}
