//! Contact flags (`cnflag = <tag> VAR=VALUE`, contacts-appcast.md §3.7): the tag says
//! when the flag is posted; range tags are decided here from the previous and current
//! range, event tags by the behavior from its contact-state history.

/// When a contact flag fires.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CnTag {
    /// `@<R`: the iteration the range goes from > R to ≤ R.
    EnterRange(f64),
    /// `@>R`: the iteration the range goes from ≤ R to > R.
    LeaveRange(f64),
    /// `<R`: every iteration while the range is below R.
    Below(f64),
    /// `>R`: every iteration while the range is above R.
    Above(f64),
    /// `@cpa`: the closest point of approach is reached.
    Cpa,
    OsPassedCn,
    OsPassedCnPort,
    OsPassedCnStar,
    CnPassedOs,
    CnPassedOsPort,
    CnPassedOsStar,
    /// `@os_crossed_cn*` / `@cn_crossed_os*`: accepted, never posted by the reference.
    Crossed,
}

/// One configured contact flag.
#[derive(Clone, Debug, PartialEq)]
pub struct CnFlag {
    pub tag: CnTag,
    pub var: String,
    pub value: String,
}

/// A `cnflag` value that cannot be read.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("bad cnflag: {0}")]
pub struct CnFlagError(pub String);

impl CnTag {
    pub fn parse(tag: &str) -> Option<CnTag> {
        let num = |s: &str| mbutil::parse_number(s).filter(|v| *v >= 0.0);
        let t = tag.trim().to_ascii_lowercase();
        Some(match t.as_str() {
            "@cpa" => CnTag::Cpa,
            "@os_passed_cn" => CnTag::OsPassedCn,
            "@os_passed_cn_port" => CnTag::OsPassedCnPort,
            "@os_passed_cn_star" => CnTag::OsPassedCnStar,
            "@cn_passed_os" => CnTag::CnPassedOs,
            "@cn_passed_os_port" => CnTag::CnPassedOsPort,
            "@cn_passed_os_star" => CnTag::CnPassedOsStar,
            _ if t.starts_with("@os_crossed_cn") || t.starts_with("@cn_crossed_os") => {
                CnTag::Crossed
            }
            _ => {
                if let Some(r) = t.strip_prefix("@<") {
                    CnTag::EnterRange(num(r)?)
                } else if let Some(r) = t.strip_prefix("@>") {
                    CnTag::LeaveRange(num(r)?)
                } else if let Some(r) = t.strip_prefix('<') {
                    CnTag::Below(num(r)?)
                } else if let Some(r) = t.strip_prefix('>') {
                    CnTag::Above(num(r)?)
                } else {
                    return None;
                }
            }
        })
    }

    /// Whether a range tag fires going from `prev` to `range` (`prev` is `None` before
    /// the first contact read: no edge yet). Event tags answer false here.
    pub fn fires_on_range(&self, prev: Option<f64>, range: f64) -> bool {
        match *self {
            CnTag::EnterRange(r) => prev.is_some_and(|p| p > r) && range <= r,
            CnTag::LeaveRange(r) => prev.is_some_and(|p| p <= r) && range > r,
            CnTag::Below(r) => range < r,
            CnTag::Above(r) => range > r,
            _ => false,
        }
    }
}

impl CnFlag {
    /// ```
    /// let f = contacts::CnFlag::parse("@<20 CLOSE=$[CN_NAME]").unwrap();
    /// assert_eq!(f.tag, contacts::CnTag::EnterRange(20.0));
    /// assert_eq!((f.var.as_str(), f.value.as_str()), ("CLOSE", "$[CN_NAME]"));
    /// assert!(f.tag.fires_on_range(Some(20.5), 19.9));
    /// ```
    pub fn parse(s: &str) -> Result<CnFlag, CnFlagError> {
        let err = || CnFlagError(s.to_string());
        let s2 = s.trim();
        let (tag, rest) = s2.split_once(char::is_whitespace).ok_or_else(err)?;
        let tag = CnTag::parse(tag).ok_or_else(err)?;
        let (var, value) = rest.split_once('=').ok_or_else(err)?;
        let var = var.trim();
        if var.is_empty() || var.contains(char::is_whitespace) {
            return Err(err());
        }
        Ok(CnFlag {
            tag,
            var: var.to_string(),
            value: value.trim().to_string(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tags_and_edges() {
        assert_eq!(CnTag::parse("@>50"), Some(CnTag::LeaveRange(50.0)));
        assert_eq!(CnTag::parse("<7.5"), Some(CnTag::Below(7.5)));
        assert_eq!(CnTag::parse(">7"), Some(CnTag::Above(7.0)));
        assert_eq!(CnTag::parse("@CPA"), Some(CnTag::Cpa));
        assert_eq!(CnTag::parse("@cn_crossed_os_port"), Some(CnTag::Crossed));
        assert_eq!(CnTag::parse("@<x"), None);
        assert_eq!(CnTag::parse("@<-3"), None);
        assert_eq!(CnTag::parse("soon"), None);
        let t = CnTag::EnterRange(20.0);
        assert!(!t.fires_on_range(None, 10.0));
        assert!(t.fires_on_range(Some(21.0), 20.0));
        assert!(!t.fires_on_range(Some(19.0), 18.0));
        let t = CnTag::LeaveRange(20.0);
        assert!(t.fires_on_range(Some(20.0), 20.1));
        assert!(!t.fires_on_range(Some(25.0), 30.0));
        assert!(CnTag::Below(5.0).fires_on_range(None, 4.9));
        assert!(!CnTag::Above(5.0).fires_on_range(Some(9.0), 5.0));
        assert!(!CnTag::Cpa.fires_on_range(Some(9.0), 1.0));
    }

    #[test]
    fn flags() {
        let f = CnFlag::parse("  @cpa  CPA_REACHED = $[CPA] ").unwrap();
        assert_eq!(f.tag, CnTag::Cpa);
        assert_eq!(
            (f.var.as_str(), f.value.as_str()),
            ("CPA_REACHED", "$[CPA]")
        );
        assert!(CnFlag::parse("@cpa").is_err());
        assert!(CnFlag::parse("@cpa NOVALUE").is_err());
        assert!(CnFlag::parse("@nope A=1").is_err());
        assert!(CnFlag::parse("@cpa =1").is_err());
    }
}
