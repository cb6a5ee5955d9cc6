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
    let mut out = Vec::with_capacity(4);
    for_each_local_nav(report, |name, suffix, value| {
        let mut var = name.to_uppercase();
        var.push_str("_NAV_");
        var.push_str(suffix);
        out.push((
            var,
            match value {
                LocalValue::Text(s) => NavValue::Text(s.to_string()),
                LocalValue::Num(n) => NavValue::Num(n),
            },
        ));
    })?;
    Ok(out)
}

/// A value of [`for_each_local_nav`], borrowed from the report.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LocalValue<'a> {
    Text(&'a str),
    Num(f64),
}

/// [`local_nav_vars`] without allocating (ownship reports arrive every iteration):
/// `post(name, suffix, value)` for each posting, in the same order, where the variable
/// is `name` upper-cased, then `_NAV_`, then `suffix` (`GROUP`, `TYPE`, `COLOR`,
/// `LENGTH`).
pub fn for_each_local_nav<'a>(
    report: &'a str,
    mut post: impl FnMut(&'a str, &'static str, LocalValue<'a>),
) -> Result<(), UnhandledLocal> {
    let r = local_fields(report);
    if r.name.is_empty() {
        return Err(UnhandledLocal);
    }
    for (suffix, s) in [("GROUP", r.group), ("TYPE", r.vtype), ("COLOR", r.color)] {
        if !s.is_empty() {
            post(r.name, suffix, LocalValue::Text(s));
        }
    }
    if let Some(l) = r.length.filter(|&l| l != 0.0) {
        post(r.name, "LENGTH", LocalValue::Num(l));
    }
    Ok(())
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
