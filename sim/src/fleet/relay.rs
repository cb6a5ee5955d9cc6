//! A node report on its way between vehicles, read once for all its readers.
//!
//! The comms model hands one vehicle's `NODE_REPORT_LOCAL` to up to every other
//! vehicle, where the helm's ledger and the contact manager each read it: 2 × (n − 1)
//! reads of one text. Here it is read once, by the first reader ([`Relayed::report`]),
//! and kept as where its text fields lie in the text, so every reader gets the same
//! [`NodeReport`] without reading again. Each receiving app keeps the reports posted to
//! it in a [`Pending`] queue, in posting order (the bus's order), and takes the one at
//! the front for a `NODE_REPORT` of the same text: a message of any other text (a value
//! sent on registration, a poke) is read by the app itself, so what it gets is always
//! `NodeReport::parse` of its own text.

use std::cell::{Cell, OnceCell};
use std::collections::VecDeque;
use std::rc::Rc;

use contacts::NodeReport;
use helm_engine::posting::Value;
use helm_engine::Mail;

/// One report text, with its reading once somebody asked for it.
#[derive(Debug)]
pub struct Relayed {
    /// Private: the spans of `read` index it unchecked, so it never changes.
    text: String,
    read: OnceCell<Option<Read>>,
}

/// `NodeReport::parse(text)`: its numbers, and its text fields as byte ranges of
/// `text` (name, type, group, color, vsource, mode, allstop).
#[derive(Debug)]
pub struct Read {
    /// The reading with every text field empty.
    pub numbers: NodeReport<'static>,
    pub spans: [(usize, usize); 7],
}

impl Relayed {
    pub fn new(text: String) -> Rc<Relayed> {
        Rc::new(Relayed {
            text,
            read: OnceCell::new(),
        })
    }

    /// A report whose reading is known: `read`, when given, must be what
    /// `NodeReport::parse(&text)` gives (its writer's, see `super::reporter`).
    pub fn read_as(text: String, read: Option<Read>) -> Rc<Relayed> {
        let r = Relayed::new(text);
        // Spans that are not pieces of the text are dropped (the reader then parses).
        let fits = |read: &Read| read.spans.iter().all(|&(a, b)| r.text.get(a..b).is_some());
        if let Some(read) = read.filter(fits) {
            let _ = r.read.set(Some(read));
        }
        r
    }

    /// The report's text.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// `NodeReport::parse(&self.text)`, read on the first call. `None` only if a field
    /// were not a piece of the text (parsing only borrows, so never): the reader parses.
    pub fn report(&self) -> Option<NodeReport<'_>> {
        let read = self.read.get_or_init(|| read(&self.text)).as_ref()?;
        // SAFETY: every span was checked against this same text when it was set
        // (`span_in` or `read_as`: `text.get(a..b)` is some, a piece at char
        // boundaries), and the text never changes (private, never written after `new`);
        // checking again on every reader's read cost more than the rest of the
        // hand-over (tested below against `parse`).
        let field = |(a, b): (usize, usize)| unsafe { self.text.get_unchecked(a..b) };
        let [name, vtype, group, color, vsource, mode, allstop] = read.spans.map(field);
        Some(NodeReport {
            name,
            vtype,
            group,
            color,
            vsource,
            mode,
            allstop,
            ..read.numbers.clone()
        })
    }
}

fn read(text: &str) -> Option<Read> {
    let r = NodeReport::parse(text);
    let fields = [
        r.name, r.vtype, r.group, r.color, r.vsource, r.mode, r.allstop,
    ];
    let mut spans = [(0, 0); 7];
    for (span, field) in spans.iter_mut().zip(fields) {
        *span = span_in(text, field)?;
    }
    Some(Read {
        numbers: NodeReport {
            name: "",
            vtype: "",
            group: "",
            color: "",
            vsource: "",
            mode: "",
            allstop: "",
            time: r.time,
            x: r.x,
            y: r.y,
            lat: r.lat,
            lon: r.lon,
            spd: r.spd,
            hdg: r.hdg,
            dep: r.dep,
            length: r.length,
            cog: r.cog,
            unknown_fields: r.unknown_fields,
        },
        spans,
    })
}

/// Where `field`, a piece of `text` (or empty), lies in it: found by address, checked.
fn span_in(text: &str, field: &str) -> Option<(usize, usize)> {
    if field.is_empty() {
        return Some((0, 0));
    }
    let start = (field.as_ptr() as usize).wrapping_sub(text.as_ptr() as usize);
    let end = start.checked_add(field.len())?;
    let piece = text.get(start..end)?;
    (piece.as_ptr() == field.as_ptr()).then_some((start, end))
}

/// The reports posted to one app, not yet fetched, in posting order.
#[derive(Debug, Default)]
pub struct Pending {
    queue: VecDeque<Rc<Relayed>>,
    /// The last batch's matches: (index of the message, its report).
    matched: Vec<(usize, Rc<Relayed>)>,
    /// Where the next read is likely found in `matched` (reads come in message order).
    next: Cell<usize>,
}

/// Reports kept per app at most. Between two fetches an app gets one per other vehicle
/// per report tick (tens); should the queue ever stop matching what the bus delivers
/// (an app that stopped fetching, a bus that dropped one), the oldest go: the app then
/// reads those texts itself, and memory stays bounded.
const MAX_PENDING: usize = 512;

impl Pending {
    pub fn push(&mut self, r: Rc<Relayed>) {
        if self.queue.len() >= MAX_PENDING {
            self.queue.pop_front();
        }
        self.queue.push_back(r);
    }

    /// Match a fetched batch: for each `NODE_REPORT` (or ownship's `NODE_REPORT_LOCAL`)
    /// whose text is the front report's, that report; then read them as
    /// `contacts::report::ReadReports`.
    pub fn take(&mut self, batch: &[Mail]) {
        self.matched.clear();
        self.next.set(0);
        if self.queue.is_empty() {
            return;
        }
        for (k, m) in batch.iter().enumerate() {
            let Value::Str(s) = &m.value else { continue };
            if !matches!(m.var.as_str(), "NODE_REPORT" | "NODE_REPORT_LOCAL") {
                continue;
            }
            if self.queue.front().is_some_and(|r| r.text == *s) {
                self.matched.extend(self.queue.pop_front().map(|r| (k, r)));
            }
        }
    }
}

/// The batch last taken: message `k`'s reading, if it is a matched report.
impl contacts::report::ReadReports for Pending {
    fn read(&self, k: usize) -> Option<NodeReport<'_>> {
        let at = self.next.get();
        let i = match self.matched.get(at) {
            Some((j, _)) if *j == k => at,
            _ => self.matched.binary_search_by_key(&k, |(i, _)| *i).ok()?,
        };
        self.next.set(i + 1);
        self.matched[i].1.report()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use contacts::report::ReadReports;

    fn mail(var: &str, text: &str) -> Mail {
        Mail {
            var: var.into(),
            value: Value::Str(text.into()),
            time: 0.0,
            source: String::new(),
            source_aux: String::new(),
        }
    }

    #[test]
    fn a_relayed_report_reads_as_its_text() {
        for text in [
            "NAME=bob,X=1.50,Y=-2,SPD=1,HDG=90,DEP=0,LAT=43.8,LON=-70.3,TYPE=kayak,\
             COLOR=red,MODE=DRIVE,INDEX=3,YAW=0.1,TIME=1000.25,LENGTH=4",
            " name = Bob , group=g1, vsource=ais, allstop=x, X=nan, Y=2 ",
            "{\"NAME\":\"dee\",\"X\":\"1\",\"TYPE\":\"{a,b}\"}",
            "",
            "X=1,Y=2",
        ] {
            let r = Relayed::new(text.to_string());
            assert_eq!(r.report(), Some(NodeReport::parse(text)), "{text}");
            assert_eq!(r.report(), Some(NodeReport::parse(text)), "again: {text}");
        }
        let t = String::from("abc");
        assert_eq!(span_in(&t, &t[1..2]), Some((1, 2)));
        assert_eq!(span_in(&t, "b"), None, "not a piece of the text");
    }

    #[test]
    fn pending_matches_by_text_in_order() {
        let (a, b) = (
            Relayed::new("NAME=a,X=1".into()),
            Relayed::new("NAME=b".into()),
        );
        let mut p = Pending::default();
        p.push(a.clone());
        p.push(b.clone());
        let c = Relayed::new("NAME=c".into());
        p.push(c);
        // A registration copy of an older text, then a, another variable, then b, then
        // ownship's c.
        let batch = [
            mail("NODE_REPORT", "NAME=z"),
            mail("NODE_REPORT", "NAME=a,X=1"),
            mail("NAV_X", "NAME=b"),
            mail("NODE_REPORT", "NAME=b"),
            mail("NODE_REPORT_LOCAL", "NAME=c"),
        ];
        p.take(&batch);
        let got: Vec<_> = (0..batch.len()).map(|k| p.read(k)).collect();
        assert_eq!(
            got,
            [
                None,
                Some(NodeReport::parse("NAME=a,X=1")),
                None,
                Some(NodeReport::parse("NAME=b")),
                Some(NodeReport::parse("NAME=c"))
            ]
        );
        drop(got);
        // Out of order (the cursor is only a guess), and again.
        for k in [4, 1, 3, 1, 0, 4] {
            assert_eq!(
                p.read(k),
                (k % 2 == 1 || k == 4).then(|| {
                    NodeReport::parse(match &batch[k].value {
                        Value::Str(s) => s,
                        Value::Num(_) => "",
                    })
                })
            );
        }
        p.take(&batch[2..3]);
        assert!(p.read(0).is_none(), "nothing matched: nothing handed over");
    }

    /// A queue that never matches (its app stopped fetching) stays bounded, and after
    /// losing its oldest entries it still matches what comes in order.
    #[test]
    fn pending_is_bounded() {
        let mut p = Pending::default();
        let lost = Relayed::new("NAME=lost".into());
        p.push(lost);
        for k in 0..3 * MAX_PENDING {
            p.push(Relayed::new(format!("NAME=v{k}")));
        }
        assert_eq!(p.queue.len(), MAX_PENDING);
        let next = format!("NAME=v{}", 2 * MAX_PENDING);
        p.take(&[mail("NODE_REPORT", &next)]);
        assert_eq!(p.read(0), Some(NodeReport::parse(&next)));
    }
}
