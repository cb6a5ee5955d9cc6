//! `NODE_REPORT_LOCAL`: ownship's own report (from pNodeReporter). It never enters the
//! ledger; the helm only copies a few fields into its info buffer (contacts-appcast.md
//! §2.1).

use crate::report::{for_each_field, Key, NodeReport};

/// A value for the info buffer.
#[derive(Clone, Debug, PartialEq)]
pub enum NavValue {
    Text(String),
    Num(f64),
}

/// Ownship's report gave no NAME: the helm's run warning is `Unhandled NODE_REPORT_LOCAL`.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("Unhandled NODE_REPORT_LOCAL")]
pub struct UnhandledLocal;

/// The info-buffer postings for one `NODE_REPORT_LOCAL`: `<NAME>_NAV_GROUP` (if the
/// group is non-empty), `_NAV_TYPE` (type as reported, if non-empty), `_NAV_COLOR` (if
/// non-empty), `_NAV_LENGTH` (if given and ≠ 0), NAME upper-cased.
///
/// ```
/// let v = contacts::local_nav_vars("NAME=alpha,TYPE=kayak,COLOR=yellow,LENGTH=4").unwrap();
/// assert_eq!(v[0].0, "ALPHA_NAV_TYPE");
/// assert_eq!(v.len(), 3);
/// ```
pub fn local_nav_vars(report: &str) -> Result<Vec<(String, NavValue)>, UnhandledLocal> {
    let r = local_fields(report);
    if r.name.is_empty() {
        return Err(UnhandledLocal);
    }
    let mut prefix = r.name.to_uppercase();
    prefix.push_str("_NAV_");
    let var = |suffix: &str| {
        let mut v = String::with_capacity(prefix.len() + suffix.len());
        v.push_str(&prefix);
        v.push_str(suffix);
        v
    };
    let mut out = Vec::with_capacity(4);
    for (suffix, s) in [("GROUP", r.group), ("TYPE", r.vtype), ("COLOR", r.color)] {
        if !s.is_empty() {
            out.push((var(suffix), NavValue::Text(s.to_string())));
        }
    }
    if let Some(l) = r.length.filter(|&l| l != 0.0) {
        out.push((var("LENGTH"), NavValue::Num(l)));
    }
    Ok(out)
}

/// The fields of `report` that ownship's postings use (name, group, type, colour,
/// length), read as [`NodeReport::parse`] reads them, without parsing the other numbers
/// (a report has seven or more).
fn local_fields(report: &str) -> NodeReport<'_> {
    let mut r = NodeReport::default();
    for_each_field(report, |key, value| match key {
        Key::Name => r.name = value,
        Key::Group => r.group = value,
        Key::Type => r.vtype = value,
        Key::Color => r.color = value,
        Key::Length => r.length = mbutil::parse_number(value).or(r.length),
        _ => {}
    });
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn local_fields_are_the_full_readings_fields() {
        let reports = [
            "NAME=alpha,X=1,Y=2,TYPE=kayak,COLOR=yellow,LENGTH=4,TIME=5",
            " name = Bob , group=red, len=2.5, LENGTH=nan, type= UUV ,color=",
            r#"{"NAME":"a","GROUP":"{x,y}","LENGTH":"3","LEN":"x"}"#,
            "NAME=a,NAME=b,TYPE=t1,TYPE=,LENGTH=1,LENGTH=1e3,GROUP={g,h}",
            "",
            "X=1,Y=2",
        ];
        for text in reports {
            let (full, light) = (NodeReport::parse(text), local_fields(text));
            assert_eq!(
                (full.name, full.group, full.vtype, full.color, full.length),
                (
                    light.name,
                    light.group,
                    light.vtype,
                    light.color,
                    light.length
                ),
                "{text:?}"
            );
        }
    }

    #[test]
    fn local_report_postings() {
        let v = local_nav_vars("NAME=Alpha,GROUP=red,TYPE=KAYAK,LENGTH=0").unwrap();
        assert_eq!(
            v,
            vec![
                ("ALPHA_NAV_GROUP".to_string(), NavValue::Text("red".into())),
                ("ALPHA_NAV_TYPE".to_string(), NavValue::Text("KAYAK".into())),
            ]
        );
        let v = local_nav_vars("NAME=a,LENGTH=2.5").unwrap();
        assert_eq!(v, vec![("A_NAV_LENGTH".to_string(), NavValue::Num(2.5))]);
        assert_eq!(local_nav_vars("X=1,Y=2"), Err(UnhandledLocal));
        assert_eq!(UnhandledLocal.to_string(), "Unhandled NODE_REPORT_LOCAL");
    }
}
