//! pNodeReporter's `NODE_REPORT_LOCAL`, written as the app writes it and read as it is
//! written.
//!
//! A vehicle's report is read by its own helm and by up to every other vehicle's helm
//! and contact manager, each as `NodeReport::parse` reads it. Its writer knows where
//! each field lies, so it keeps the text fields' places and reads each number back
//! from the text it has just written (`parse_number` of that value, as the parse does)
//! instead of scanning the whole text: the report then travels read ([`Relayed`]). A
//! text field the parse would not give back as written (a comma or a brace in it,
//! blanks at its ends, anything but printable ASCII) leaves the reading to the readers.
//!
//! Why the two agree: the text starts with `NAME=` and ends with the length, so the
//! parse neither trims it nor takes it for the JSON form; with no brace in it, every
//! comma ends a field; each key is written once and is a known key but `INDEX` and
//! `YAW` (two unknown fields); a value is what follows its key's `=`, with no blanks
//! to trim. The tests hold the two against each other.

use std::rc::Rc;

use contacts::NodeReport;
use mbutil::{parse_number, push_fixed};

use super::relay::{Read, Relayed};

/// What pNodeReporter reports of ownship, before it is written.
pub struct Ownship<'a> {
    pub name: &'a str,
    pub x: f64,
    pub y: f64,
    pub spd: f64,
    pub hdg: f64,
    pub dep: f64,
    /// LAT, LON, when the mission has an origin.
    pub latlon: Option<(f64, f64)>,
    pub vtype: &'a str,
    pub color: &'a str,
    pub mode: &'a str,
    pub index: u64,
    pub yaw: f64,
    pub time: f64,
    /// `,LENGTH={length}`, written once (the length never changes).
    pub length_field: &'a str,
}

/// Numeric fields of the report, in the order they are written.
#[derive(Clone, Copy)]
enum Num {
    X,
    Y,
    Spd,
    Hdg,
    Dep,
    Lat,
    Lon,
    Time,
    Length,
    /// `YAW`: no field of the reading.
    Unread,
}

impl Ownship<'_> {
    /// The report into `out` (cleared first), as `format!("NAME={},X={:.2},...")` writes
    /// it (see `mbutil::push_fixed`), and its reading; `None` when a text field would
    /// not read back as written.
    pub fn write(&self, out: &mut String) -> Option<Read> {
        out.clear();
        let mut numbers = NodeReport::default();
        let mut spans = [(0, 0); 7];
        let mut text = |out: &mut String, key: &str, value: &str, span: Option<usize>| {
            out.push_str(key);
            let start = out.len();
            out.push_str(value);
            if let Some(k) = span {
                spans[k] = (start, out.len());
            }
        };
        let number = |out: &mut String, numbers: &mut NodeReport, key, which, x, decimals| {
            out.push_str(key);
            let start = out.len();
            push_fixed(out, x, decimals);
            read_number(numbers, which, &out[start..]);
        };
        // Span order: name, type, group, color, vsource, mode, allstop.
        text(out, "NAME=", self.name, Some(0));
        number(out, &mut numbers, ",X=", Num::X, self.x, 2);
        number(out, &mut numbers, ",Y=", Num::Y, self.y, 2);
        number(out, &mut numbers, ",SPD=", Num::Spd, self.spd, 2);
        number(out, &mut numbers, ",HDG=", Num::Hdg, self.hdg, 2);
        number(out, &mut numbers, ",DEP=", Num::Dep, self.dep, 2);
        if let Some((lat, lon)) = self.latlon {
            number(out, &mut numbers, ",LAT=", Num::Lat, lat, 8);
            number(out, &mut numbers, ",LON=", Num::Lon, lon, 8);
        }
        text(out, ",TYPE=", self.vtype, Some(1));
        text(out, ",COLOR=", self.color, Some(3));
        text(out, ",MODE=", self.mode, Some(5));
        out.push_str(",INDEX=");
        mbutil::push_u64(out, self.index);
        number(out, &mut numbers, ",YAW=", Num::Unread, self.yaw, 7);
        number(out, &mut numbers, ",TIME=", Num::Time, self.time, 2);
        out.push_str(self.length_field);
        let length = self.length_field.strip_prefix(",LENGTH=")?;
        read_number(&mut numbers, Num::Length, length);
        numbers.unknown_fields = 2;
        let plain = [self.name, self.vtype, self.color, self.mode]
            .iter()
            .all(|t| t.bytes().all(reads_back));
        plain.then_some(Read { numbers, spans })
    }

    /// [`Ownship::write`], the report made [`Relayed`] (read when its fields allow).
    pub fn relayed(&self, buf: &mut String) -> Rc<Relayed> {
        let read = self.write(buf);
        Relayed::read_as(buf.clone(), read)
    }
}

/// `NodeReport::set` of a numeric field written once: its number, if it is one.
fn read_number(r: &mut NodeReport, which: Num, value: &str) {
    let v = parse_number(value);
    let slot = match which {
        Num::X => &mut r.x,
        Num::Y => &mut r.y,
        Num::Spd => &mut r.spd,
        Num::Hdg => &mut r.hdg,
        Num::Dep => &mut r.dep,
        Num::Lat => &mut r.lat,
        Num::Lon => &mut r.lon,
        Num::Time => &mut r.time,
        Num::Length => &mut r.length,
        Num::Unread => return,
    };
    *slot = v;
}

/// A byte of a text field that the parse gives back as written: printable ASCII but a
/// field separator or a brace (a blank is not printable, so none can be at an end).
fn reads_back(b: u8) -> bool {
    b.is_ascii_graphic() && !matches!(b, b',' | b'{' | b'}')
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ownship<'a>(name: &'a str, vtype: &'a str, color: &'a str, x: f64) -> Ownship<'a> {
        Ownship {
            name,
            x,
            y: -x * 0.37,
            spd: x.abs() * 1e-3,
            hdg: (x * 7.3).rem_euclid(360.0),
            dep: 0.0,
            latlon: (x > 0.0).then_some((43.825_300_1 + x * 1e-6, -70.330_4 - x * 1e-6)),
            vtype,
            color,
            mode: "DRIVE",
            index: x.abs() as u64,
            yaw: (90.0 - x).to_radians(),
            time: 3_590_845_246.47 + x,
            length_field: ",LENGTH=4",
        }
    }

    /// The reading given with the report is `NodeReport::parse` of its text, over many
    /// numbers (negative, NaN, infinite, huge) and the text fields that read back.
    #[test]
    fn the_written_reading_is_the_parse() {
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let mut buf = String::new();
        let specials = [
            0.0,
            -0.0,
            f64::NAN,
            f64::INFINITY,
            -1e300,
            0.005,
            -0.004_999,
        ];
        for k in 0..4000 {
            let x = match k % 5 {
                0 => specials[k / 5 % specials.len()],
                1 => (next() % 2_000_000) as f64 / 7.0 - 140_000.0,
                2 => f64::from_bits(next() >> 2),
                _ => (next() % 100_000) as f64 / 100.0 - 500.0,
            };
            for (name, vtype, color) in [
                ("lia", "kayak", "dodger_blue"),
                ("", "", ""),
                ("a=b", "UUV", "0xff00ff"),
            ] {
                let o = ownship(name, vtype, color, x);
                let r = o.relayed(&mut buf);
                assert_eq!(r.text(), buf);
                let read = r.report().expect("read");
                assert_eq!(read, NodeReport::parse(&buf), "{buf}");
                assert_eq!(
                    format!("{read:?}"),
                    format!("{:?}", NodeReport::parse(&buf))
                );
            }
        }
        // What must not: the readers parse the text.
        for (name, vtype) in [("a,b", "kayak"), (" a", "kayak"), ("a", "{x"), ("é", "k")] {
            let o = ownship(name, vtype, "red", 1.0);
            assert!(o.write(&mut buf).is_none(), "{name} {vtype}");
            let r = o.relayed(&mut buf);
            assert_eq!(r.report(), Some(NodeReport::parse(&buf)));
        }
    }
}
