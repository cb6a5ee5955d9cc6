//! `NODE_REPORT_LOCAL`: ownship's own report (from pNodeReporter). It never enters the
//! ledger; the helm only copies a few fields into its info buffer (contacts-appcast.md
//! §2.1).

use crate::report::NodeReport;

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
    let r = NodeReport::parse(report);
    if r.name.is_empty() {
        return Err(UnhandledLocal);
    }
    let up = r.name.to_uppercase();
    let mut out = Vec::with_capacity(4);
    for (suffix, s) in [("GROUP", r.group), ("TYPE", r.vtype), ("COLOR", r.color)] {
        if !s.is_empty() {
            out.push((format!("{up}_NAV_{suffix}"), NavValue::Text(s.to_string())));
        }
    }
    if let Some(l) = r.length.filter(|&l| l != 0.0) {
        out.push((format!("{up}_NAV_LENGTH"), NavValue::Num(l)));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

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
