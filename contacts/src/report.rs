//! One `NODE_REPORT` string read into its fields (contacts-appcast.md §2.2).
//!
//! The form pNodeReporter writes is a comma list of `KEY=value` pairs (keys
//! case-insensitive, values trimmed); a report wrapped in `{...}` is read as JSON-ish
//! (`{"NAME":"alpha","X":"1"}`: quotes removed, `:` between key and value). Commas inside
//! braces do not split. Numeric fields count only when their text passes the helm's
//! number test (`mbutil::is_number`: no `nan`, no exponent), so `X=nan` is "no X".
//!
//! Reading never fails: acceptance (what is missing, the type rules) is the ledger's
//! business ([`crate::Ledger::ingest`]); this only finds the fields, borrowing from the
//! input.

/// The fields of one report, borrowed from the report text. A numeric field is `None`
/// when absent or not a number; a text field is `""` when absent.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NodeReport<'a> {
    pub name: &'a str,
    pub vtype: &'a str,
    pub group: &'a str,
    pub color: &'a str,
    pub vsource: &'a str,
    pub mode: &'a str,
    pub allstop: &'a str,
    pub time: Option<f64>,
    pub x: Option<f64>,
    pub y: Option<f64>,
    pub lat: Option<f64>,
    pub lon: Option<f64>,
    pub spd: Option<f64>,
    pub hdg: Option<f64>,
    pub dep: Option<f64>,
    pub length: Option<f64>,
    pub cog: Option<f64>,
    /// Fields of no known key (kept by the C++ as extra properties, unused by the helm;
    /// here only counted, so a hostile report cannot grow memory through them).
    pub unknown_fields: usize,
}

impl<'a> NodeReport<'a> {
    /// Read `text` (either form). Never fails; see the module doc.
    ///
    /// ```
    /// let r = contacts::NodeReport::parse("NAME=bob,X=5,Y=-2.5,SPD=1,HDG=90,TIME=1000,TYPE=kayak");
    /// assert_eq!((r.name, r.x, r.y, r.time), ("bob", Some(5.0), Some(-2.5), Some(1000.0)));
    /// ```
    pub fn parse(text: &'a str) -> Self {
        let t = text.trim();
        let json = t.len() >= 2 && t.starts_with('{') && t.ends_with('}');
        let body = if json { &t[1..t.len() - 1] } else { t };
        let mut r = NodeReport::default();
        for field in split_top_level(body, b',') {
            let (key, value) = if json {
                match field.find(':') {
                    Some(i) => (unquote(&field[..i]), unquote(&field[i + 1..])),
                    None => (unquote(field), ""),
                }
            } else {
                match field.find('=') {
                    Some(i) => (field[..i].trim(), field[i + 1..].trim()),
                    None => (field.trim(), ""),
                }
            };
            r.set(key, value);
        }
        r
    }

    fn set(&mut self, key: &str, value: &'a str) {
        let num = || mbutil::parse_number(value);
        let is = |k: &str| key.eq_ignore_ascii_case(k);
        if is("NAME") {
            self.name = value;
        } else if is("TYPE") {
            self.vtype = value;
        } else if is("GROUP") {
            self.group = value;
        } else if is("COLOR") {
            self.color = value;
        } else if is("VSOURCE") {
            self.vsource = value;
        } else if is("MODE") {
            self.mode = value;
        } else if is("ALLSTOP") {
            self.allstop = value;
        } else if is("TIME") || is("UTC_TIME") {
            // A non-numeric TIME leaves an earlier numeric one in place.
            if let Some(v) = num() {
                self.time = Some(v);
            }
        } else if is("X") {
            self.x = num().or(self.x);
        } else if is("Y") {
            self.y = num().or(self.y);
        } else if is("LAT") {
            self.lat = num().or(self.lat);
        } else if is("LON") {
            self.lon = num().or(self.lon);
        } else if is("SPD") || is("SPEED") {
            self.spd = num().or(self.spd);
        } else if is("HDG") || is("HEADING") {
            self.hdg = num().or(self.hdg);
        } else if is("DEP") || is("DEPTH") {
            self.dep = num().or(self.dep);
        } else if is("LENGTH") || is("LEN") {
            self.length = num().or(self.length);
        } else if is("COG") {
            self.cog = num().or(self.cog);
        } else {
            self.unknown_fields += 1;
        }
    }

    /// Both X and Y given as numbers.
    pub fn has_xy(&self) -> bool {
        self.x.is_some() && self.y.is_some()
    }

    /// "LAT/LON present", tested on LON alone as the reference does (a LON without LAT
    /// counts, with latitude 0).
    pub fn has_latlon(&self) -> bool {
        self.lon.is_some()
    }
}

/// Trim, then drop one pair of surrounding double quotes.
fn unquote(s: &str) -> &str {
    mbutil::strip_quotes(s.trim()).trim()
}

/// Split at `sep` where not inside `{...}` (any depth). An unbalanced `}` is ignored.
pub(crate) fn split_top_level(s: &str, sep: u8) -> impl Iterator<Item = &str> {
    let mut depth = 0usize;
    let mut start = 0usize;
    let bytes = s.as_bytes();
    let mut i = 0usize;
    let mut done = s.is_empty();
    std::iter::from_fn(move || {
        if done {
            return None;
        }
        while i < bytes.len() {
            let b = bytes[i];
            i += 1;
            match b {
                b'{' => depth += 1,
                b'}' => depth = depth.saturating_sub(1),
                _ if b == sep && depth == 0 => {
                    // `sep` is ASCII, so these are char boundaries.
                    let piece = &s[start..i - 1];
                    start = i;
                    return Some(piece);
                }
                _ => {}
            }
        }
        done = true;
        Some(&s[start..])
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_pnodereporter_form() {
        let s = "NAME=alpha,X=0,Y=0,SPD=0,HDG=0,DEP=0,LAT=43.8253,LON=-70.3304,TYPE=kayak,\
                 COLOR=yellow,MODE=PARK,ALLSTOP=ManualOverride,INDEX=19,YAW=1.5707963,\
                 TIME=3590845246.47,LENGTH=4";
        let r = NodeReport::parse(s);
        assert_eq!(r.name, "alpha");
        assert_eq!(r.vtype, "kayak");
        assert_eq!(r.color, "yellow");
        assert_eq!(r.mode, "PARK");
        assert_eq!(r.allstop, "ManualOverride");
        assert_eq!(r.time, Some(3590845246.47));
        assert_eq!(r.lat, Some(43.8253));
        assert_eq!(r.lon, Some(-70.3304));
        assert_eq!(r.length, Some(4.0));
        assert_eq!(r.unknown_fields, 2); // INDEX, YAW
        assert!(r.has_xy() && r.has_latlon());
    }

    #[test]
    fn keys_are_case_insensitive_values_trimmed_and_aliases_work() {
        let r =
            NodeReport::parse(" name = Bob , speed=2, heading = 45,depth=3, utc_time=7, len=9 ");
        assert_eq!(r.name, "Bob");
        assert_eq!((r.spd, r.hdg, r.dep), (Some(2.0), Some(45.0), Some(3.0)));
        assert_eq!((r.time, r.length), (Some(7.0), Some(9.0)));
    }

    #[test]
    fn numeric_fields_need_the_number_test() {
        let r = NodeReport::parse("NAME=a,X=nan,Y=1e3,TIME=12abc,SPD=inf,HDG=-,DEP=+4");
        assert_eq!(
            (r.x, r.y, r.time, r.spd, r.hdg),
            (None, None, None, None, None)
        );
        assert_eq!(r.dep, Some(4.0));
    }

    #[test]
    fn json_form_and_braces() {
        let r =
            NodeReport::parse(r#"{"NAME":"alpha","X":"12.5","Y":-3,"TIME":"5","GROUP":"{a,b}"}"#);
        assert_eq!(r.name, "alpha");
        assert_eq!((r.x, r.y, r.time), (Some(12.5), Some(-3.0), Some(5.0)));
        assert_eq!(r.group, "{a,b}");
        // Braces inside the plain form do not split either.
        let r = NodeReport::parse("NAME=a,GROUP={x,y},TIME=1");
        assert_eq!((r.group, r.time), ("{x,y}", Some(1.0)));
    }

    #[test]
    fn splitter_edges() {
        let v: Vec<&str> = split_top_level("", b',').collect();
        assert!(v.is_empty());
        let v: Vec<&str> = split_top_level("a,,b,", b',').collect();
        assert_eq!(v, ["a", "", "b", ""]);
        let v: Vec<&str> = split_top_level("}a,{b,c}}d,e", b',').collect();
        assert_eq!(v, ["}a", "{b,c}}d", "e"]);
    }
}
