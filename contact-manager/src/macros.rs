//! Flag macros (contacts-appcast.md §4.3): a flag's value is expanded with the
//! contact's record when the flag is posted; `$[UTC]` also in the variable name.
//! `$[SPD]` is never expanded (the reference looks for a misspelled macro).

use crate::table::Contact;
use crate::value::{Posting, Value};
use crate::Flag;

fn num(v: f64) -> String {
    mbutil::compact(v, 2)
}

/// `s` with the contact's macros expanded.
///
/// ```
/// use contact_manager::{expand, Contact};
/// let c = Contact { name: "Bob".into(), vtype: "KAYAK".into(), x: 1.5, ..Contact::default() };
/// assert_eq!(expand("name=$[VNAME] # t=%[VTYPE] x=$[X] s=$[SPD]", &c), "name=Bob # t=kayak x=1.5 s=$[SPD]");
/// ```
pub fn expand(s: &str, c: &Contact) -> String {
    if !s.contains('[') {
        return s.to_string();
    }
    let mut out = s.to_string();
    let text: [(&str, &str); 5] = [
        ("$[VNAME]", &c.name),
        ("%[VNAME]", &c.name),
        ("$[VTYPE]", &c.vtype),
        ("$[GROUP]", &c.group),
        ("$[UTIME]", ""),
    ];
    for (m, v) in text {
        if m == "$[UTIME]" {
            if out.contains(m) {
                out = out.replace(m, &num(c.utc));
            }
        } else if out.contains(m) {
            out = out.replace(m, v);
        }
    }
    for (m, v) in [("%[VTYPE]", &c.vtype), ("%[GROUP]", &c.group)] {
        if out.contains(m) {
            out = out.replace(m, &v.to_ascii_lowercase());
        }
    }
    for (m, v, d) in [
        ("$[X]", c.x, 2),
        ("$[Y]", c.y, 2),
        ("$[LAT]", c.lat, 8),
        ("$[LON]", c.lon, 8),
        ("$[HDG]", c.hdg, 2),
        ("$[DEP]", c.dep, 2),
    ] {
        if out.contains(m) {
            out = out.replace(m, &mbutil::compact(v, d));
        }
    }
    out
}

/// The posting of one flag for a contact at time `now` (a numeric-looking value is
/// posted as a number).
pub fn flag_posting(f: &Flag, c: &Contact, now: f64) -> Posting {
    let var = if f.var.contains("$[UTC]") {
        f.var.replace("$[UTC]", &num(now))
    } else {
        f.var.clone()
    };
    Posting {
        var,
        val: Value::flag(&expand(&f.val, c)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_macro() {
        let c = Contact {
            name: "Bob".into(),
            vtype: "Kayak".into(),
            group: "Blue".into(),
            x: -3.25,
            y: 7.0,
            hdg: 270.0,
            dep: 0.5,
            lat: 43.825312345,
            lon: -70.33,
            utc: 1000.5,
            ..Contact::default()
        };
        assert_eq!(
            expand(
                "$[VNAME],%[VNAME],$[VTYPE],%[VTYPE],$[GROUP],%[GROUP],$[X],$[Y],$[HDG],$[DEP],$[LAT],$[LON],$[UTIME],$[SPD}",
                &c
            ),
            "Bob,Bob,Kayak,kayak,Blue,blue,-3.25,7,270,0.5,43.82531235,-70.33,1000.5,$[SPD}"
        );
        let p = flag_posting(
            &Flag {
                var: "HIT_$[UTC]".into(),
                val: "$[X]".into(),
            },
            &c,
            12.0,
        );
        assert_eq!(p, Posting::num("HIT_12", -3.25));
    }
}
