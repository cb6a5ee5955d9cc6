//! The `.alog` index behind a replay: one pass over the log (pLogger's or `helm sim`'s,
//! moos-wire.md / `moos::alog`) keeps only what the page draws, in time order, so the
//! picture at any time is a binary search away.
//!
//! A log cut by a power loss, garbled or enormous still opens: every line that cannot be
//! read is skipped and counted by reason (not UTF-8, longer than [`MAX_LINE`], too few
//! columns, time not a number, last line cut short), as is every posting the page cannot
//! draw (a malformed VIEW_*, a node report without a name). Lines are read with a bound,
//! so a file without newlines cannot exhaust memory.

use std::collections::{BTreeMap, BTreeSet};
use std::fs::File;
use std::io::{self, BufRead, BufReader, Read};
use std::path::Path;
use std::sync::Arc;

use thiserror::Error;

use crate::feed::{Appcast, Feed, Update, Value};
use crate::frame::{Frame, VarTimeline};
use crate::node::VehicleState;
use crate::view::{Shape, ViewChange};

/// A line longer than this is skipped (a real posting is far shorter).
pub const MAX_LINE: usize = 1 << 20;
/// At most this many trail points per vehicle go to the page in one frame.
pub const MAX_TRAIL: usize = 1500;
/// Shape events between two stored snapshots of the picture.
const CHECKPOINT_EVERY: usize = 512;

#[derive(Debug, Error)]
pub enum AlogIndexError {
    #[error("cannot open {path}: {source}")]
    Open {
        path: String,
        #[source]
        source: io::Error,
    },
}

/// One position of a vehicle.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Sample {
    t: f64,
    x: f64,
    y: f64,
    hdg: f64,
    spd: f64,
}

/// A vehicle's track and its description (the latest report's).
#[derive(Clone, Debug)]
struct Track {
    latest: VehicleState,
    samples: Vec<Sample>,
    /// (time, MODE) at each change.
    modes: Vec<(f64, String)>,
}

/// A replayable log.
#[derive(Clone, Debug, Default)]
pub struct AlogIndex {
    /// Data lines read (not counting the header).
    pub lines: u64,
    /// First and last data time (s since LOGSTART).
    pub t0: f64,
    pub t1: f64,
    /// Lines and postings skipped, by reason.
    pub skipped: BTreeMap<String, u64>,
    /// min x, min y, max x, max y over every position and shape vertex.
    pub bounds: Option<[f64; 4]>,
    /// The header's `%% LOGSTART` (UNIX time of time 0), to line up logs of one run.
    pub logstart: Option<f64>,
    /// Vehicles reported in `NODE_REPORT_LOCAL`: the log's own (the rest are contacts).
    pub local: BTreeSet<String>,
    tracks: BTreeMap<String, Track>,
    events: Vec<(f64, ViewChange)>,
    /// (number of events applied, key → index of the event that drew it).
    checkpoints: Vec<(usize, BTreeMap<String, usize>)>,
    vars: VarTimeline,
    appcasts: BTreeMap<String, Vec<(f64, Arc<Appcast>)>>,
}

/// How a line was read.
enum Line<'a> {
    Text(&'a str),
    Skip(&'static str),
    End,
}

/// Reads lines of at most [`MAX_LINE`] bytes; longer ones are consumed and reported.
struct Lines<R> {
    r: R,
    buf: Vec<u8>,
}

impl<R: BufRead> Lines<R> {
    fn next(&mut self) -> io::Result<Line<'_>> {
        self.buf.clear();
        let mut too_long = false;
        loop {
            let avail = self.r.fill_buf()?;
            if avail.is_empty() {
                if self.buf.is_empty() && !too_long {
                    return Ok(Line::End);
                }
                if too_long {
                    return Ok(Line::Skip("longer than 1 MiB"));
                }
                // The file ends inside this line (a log cut by a power loss): keep it
                // if it still reads.
                return Ok(match std::str::from_utf8(&self.buf) {
                    Ok(s) if line_reads(s) => Line::Text(s),
                    _ => Line::Skip("last line cut short"),
                });
            }
            let (chunk, done) = match avail.iter().position(|&b| b == b'\n') {
                Some(i) => (&avail[..i], i + 1),
                None => (avail, avail.len()),
            };
            let found = done > chunk.len();
            if !too_long {
                if self.buf.len() + chunk.len() > MAX_LINE {
                    too_long = true;
                    self.buf.clear();
                } else {
                    self.buf.extend_from_slice(chunk);
                }
            }
            self.r.consume(done);
            if found {
                if too_long {
                    return Ok(Line::Skip("longer than 1 MiB"));
                }
                return Ok(match std::str::from_utf8(&self.buf) {
                    Ok(s) => Line::Text(s),
                    Err(_) => Line::Skip("not UTF-8"),
                });
            }
        }
    }
}

/// A data line has a number, a variable and a source.
fn line_reads(s: &str) -> bool {
    let s = s.trim();
    if s.starts_with('%') || s.is_empty() {
        return true;
    }
    let mut it = s.split_whitespace();
    matches!(
        (it.next().map(str::parse::<f64>), it.next(), it.next()),
        (Some(Ok(_)), Some(_), Some(_))
    )
}

/// Split `time var source value` (the value is the rest of the line, trimmed).
fn columns(l: &str) -> Option<(&str, &str, &str)> {
    let mut rest = l;
    let mut next = || {
        let s = rest.trim_start();
        let end = s.find(char::is_whitespace).unwrap_or(s.len());
        rest = &s[end..];
        (end > 0).then_some(&s[..end])
    };
    let t = next()?;
    let var = next()?;
    next()?;
    Some((t, var, rest.trim()))
}

impl AlogIndex {
    /// Open and index a file. Only a file that cannot be opened is an error.
    pub fn open(path: &Path, ownship: &str) -> Result<AlogIndex, AlogIndexError> {
        let f = File::open(path).map_err(|source| AlogIndexError::Open {
            path: path.display().to_string(),
            source,
        })?;
        Ok(AlogIndex::read(f, ownship))
    }

    /// Index a log from any reader; never fails (a read error ends the log there and is
    /// counted). `ownship` names the vehicle built from `NAV_*` when the log has no
    /// node reports.
    pub fn read<R: Read>(r: R, ownship: &str) -> AlogIndex {
        let mut ix = AlogIndex {
            t0: f64::INFINITY,
            t1: f64::NEG_INFINITY,
            ..AlogIndex::default()
        };
        let mut feed = Feed::new(ownship, std::iter::empty());
        let mut lines = Lines {
            r: BufReader::with_capacity(1 << 18, r),
            buf: Vec::with_capacity(256),
        };
        let mut skipped: BTreeMap<String, u64> = BTreeMap::new();
        let mut skip = |why: &str| *skipped.entry(why.to_owned()).or_insert(0) += 1;
        loop {
            let l = match lines.next() {
                Ok(Line::End) => break,
                Ok(Line::Skip(why)) => {
                    skip(why);
                    continue;
                }
                Ok(Line::Text(l)) => l,
                Err(_) => {
                    skip("read error (the log ends there)");
                    break;
                }
            };
            let l = l.trim();
            if l.starts_with('%') {
                if ix.logstart.is_none() {
                    ix.logstart = logstart(l);
                }
                continue;
            }
            if l.is_empty() {
                continue;
            }
            let Some((t, var, value)) = columns(l) else {
                skip("fewer than 3 columns");
                continue;
            };
            let Some(t) = t.parse::<f64>().ok().filter(|t| t.is_finite()) else {
                skip("time not a number");
                continue;
            };
            ix.lines += 1;
            ix.t0 = ix.t0.min(t);
            ix.t1 = ix.t1.max(t);
            if !feed.wants(var) {
                continue;
            }
            let num = value.parse::<f64>();
            let v = match num {
                Ok(x) if !value.is_empty() => Value::Num(x),
                _ => Value::Str(value),
            };
            if let Some(u) = feed.apply(var, v, t) {
                if let (Update::Vehicle(v), "NODE_REPORT_LOCAL") = (&u, var) {
                    if !ix.local.contains(&v.name) {
                        ix.local.insert(v.name.clone());
                    }
                }
                ix.push(t, u);
            }
        }
        for (k, n) in feed.skipped {
            *skipped.entry(k).or_insert(0) += n;
        }
        ix.skipped = skipped;
        if ix.lines == 0 {
            (ix.t0, ix.t1) = (0.0, 0.0);
        }
        ix.finish();
        ix
    }

    fn grow(&mut self, x: f64, y: f64) {
        let b = self.bounds.get_or_insert([x, y, x, y]);
        b[0] = b[0].min(x);
        b[1] = b[1].min(y);
        b[2] = b[2].max(x);
        b[3] = b[3].max(y);
    }

    fn push(&mut self, t: f64, u: Update) {
        match u {
            Update::Vehicle(v) => {
                self.grow(v.x, v.y);
                let s = Sample {
                    t,
                    x: v.x,
                    y: v.y,
                    hdg: v.hdg,
                    spd: v.spd,
                };
                // Looked up before inserting: no name allocated per sample.
                if !self.tracks.contains_key(&v.name) {
                    let tr = Track {
                        latest: v.clone(),
                        samples: Vec::new(),
                        modes: Vec::new(),
                    };
                    self.tracks.insert(v.name.clone(), tr);
                }
                let Some(tr) = self.tracks.get_mut(&v.name) else {
                    return;
                };
                if tr.modes.last().map(|m| &m.1) != Some(&v.mode) {
                    tr.modes.push((t, v.mode.clone()));
                }
                tr.samples.push(s);
                tr.latest = v;
            }
            Update::View(c) => {
                if let ViewChange::Draw(s) = &c {
                    for p in &s.pts {
                        self.grow(p[0], p[1]);
                    }
                }
                self.events.push((t, c));
            }
            Update::Var(k, v) => self.vars.push(k, t, v),
            Update::Appcast(a) => self
                .appcasts
                .entry(a.key.clone())
                .or_default()
                .push((t, Arc::new(a))),
        }
    }

    /// Sort what came out of order (clocks of different apps) and build the checkpoints.
    fn finish(&mut self) {
        let by_t = |a: f64, b: f64| a.total_cmp(&b);
        for tr in self.tracks.values_mut() {
            tr.samples.sort_by(|a, b| by_t(a.t, b.t));
            tr.modes.sort_by(|a, b| by_t(a.0, b.0));
        }
        self.events.sort_by(|a, b| by_t(a.0, b.0));
        self.vars.sort();
        for v in self.appcasts.values_mut() {
            v.sort_by(|a, b| by_t(a.0, b.0));
        }
        let mut state: BTreeMap<String, usize> = BTreeMap::new();
        self.checkpoints.push((0, state.clone()));
        for (i, (_, c)) in self.events.iter().enumerate() {
            apply_event(&mut state, c, i);
            if (i + 1) % CHECKPOINT_EVERY == 0 {
                self.checkpoints.push((i + 1, state.clone()));
            }
        }
    }

    /// The vehicles' names.
    pub fn vehicle_names(&self) -> Vec<String> {
        self.tracks.keys().cloned().collect()
    }

    /// Every vehicle's whole track thinned to at most `n` points.
    pub fn tracks(&self, n: usize) -> BTreeMap<String, Vec<[f64; 2]>> {
        self.tracks
            .iter()
            .map(|(k, tr)| (k.clone(), thin(&tr.samples, tr.samples.len(), n)))
            .collect()
    }

    /// The picture at time `t` (s since LOGSTART): vehicles where they were, their
    /// tracks so far, the shapes standing, the helm's variables and appcasts.
    pub fn frame(&self, t: f64) -> Frame {
        let mut f = Frame::full(t);
        for (name, tr) in &self.tracks {
            let n = tr.samples.partition_point(|s| s.t <= t);
            if n == 0 {
                continue;
            }
            let s = tr.samples[n - 1];
            let m = tr.modes.partition_point(|m| m.0 <= t);
            let mode = m.checked_sub(1).map(|i| tr.modes[i].1.clone());
            f.vehicles.push(VehicleState {
                t: s.t,
                x: s.x,
                y: s.y,
                hdg: s.hdg,
                spd: s.spd,
                mode: mode.unwrap_or_default(),
                ..tr.latest.clone()
            });
            f.trails
                .insert(name.clone(), thin(&tr.samples, n, MAX_TRAIL));
        }
        let n = self.events.partition_point(|e| e.0 <= t);
        let c = self.checkpoints.partition_point(|c| c.0 <= n) - 1;
        let (from, base) = &self.checkpoints[c];
        let mut state = base.clone();
        for (i, (_, e)) in self.events.iter().enumerate().take(n).skip(*from) {
            apply_event(&mut state, e, i);
        }
        f.objects = state
            .values()
            .filter_map(|&i| match &self.events[i] {
                (posted, ViewChange::Draw(s)) if s.alive(*posted, t) => Some((**s).clone()),
                _ => None,
            })
            .collect::<Vec<Shape>>();
        f.vars = self.vars.at(t);
        f.appcasts = self
            .appcasts
            .values()
            .filter_map(|v| {
                let i = v.partition_point(|a| a.0 <= t);
                i.checked_sub(1).map(|i| (*v[i].1).clone())
            })
            .collect();
        f
    }

    /// A one-line account of what was skipped (empty when nothing was).
    pub fn skipped_summary(&self) -> String {
        summary(&self.skipped)
    }
}

/// The time of a `%% LOGSTART 1700000000.00` header line.
fn logstart(l: &str) -> Option<f64> {
    let mut it = l.trim_start_matches('%').split_whitespace();
    (it.next()? == "LOGSTART").then_some(())?;
    it.next()?.parse().ok().filter(|t: &f64| t.is_finite())
}

/// `N lines skipped: 3 not UTF-8, 1 last line cut short` (empty when none).
pub fn summary(skipped: &BTreeMap<String, u64>) -> String {
    let total: u64 = skipped.values().sum();
    if total == 0 {
        return String::new();
    }
    let parts: Vec<String> = skipped.iter().map(|(k, n)| format!("{n} {k}")).collect();
    format!("{total} skipped: {}", parts.join(", "))
}

fn apply_event(state: &mut BTreeMap<String, usize>, c: &ViewChange, i: usize) {
    match c {
        ViewChange::Draw(s) => {
            state.insert(s.key.clone(), i);
        }
        ViewChange::Erase(k) => {
            state.remove(k);
        }
    }
}

/// The first `n` samples thinned to at most `max` points, the last one always kept.
fn thin(samples: &[Sample], n: usize, max: usize) -> Vec<[f64; 2]> {
    let stride = n.div_ceil(max.max(1)).max(1);
    let mut v: Vec<[f64; 2]> = samples[..n]
        .iter()
        .step_by(stride)
        .map(|s| [s.x, s.y])
        .collect();
    if let Some(l) = n.checked_sub(1).map(|i| samples[i]) {
        if v.last() != Some(&[l.x, l.y]) {
            v.push([l.x, l.y]);
        }
    }
    v
}

#[cfg(test)]
mod tests;
