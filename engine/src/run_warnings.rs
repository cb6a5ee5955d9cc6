//! The helm's run warnings and events, as AppCasting shows them (appcast.md,
//! contacts-appcast.md §5): counted per text, retractable, the last events kept. The
//! engine reports into it; the MOOS app's AppCasting reads it.

use std::collections::{BTreeMap, VecDeque};

/// At most this many events are kept (the oldest is dropped).
pub const MAX_EVENTS: usize = 8;
/// At most this many distinct run-warning texts are listed.
pub const MAX_RUN_WARNINGS: usize = 10;

/// Run warnings (counted per text, retractable) and the last events.
#[derive(Clone, Debug, Default)]
pub struct Warnings {
    run: BTreeMap<String, u32>,
    run_total: u64,
    events: VecDeque<String>,
    events_total: u64,
    /// A run warning arrived since the last appcast.
    pub new_run_warning: bool,
}

impl Warnings {
    /// One report of a run warning.
    pub fn run_warning(&mut self, text: &str) {
        if text.is_empty() {
            return;
        }
        *self.run.entry(text.to_string()).or_insert(0) += 1;
        self.run_total += 1;
        self.new_run_warning = true;
    }

    /// Retract a run warning (the exact text): its entry and its count go.
    pub fn retract(&mut self, text: &str) {
        if let Some(n) = self.run.remove(text) {
            self.run_total = self.run_total.saturating_sub(u64::from(n));
        }
    }

    /// An event at `elapsed` seconds since the app started.
    pub fn event(&mut self, elapsed: f64, text: &str) {
        if self.events.len() == MAX_EVENTS {
            self.events.pop_front();
        }
        self.events.push_back(format!("[{elapsed:.2}]: {text}"));
        self.events_total += 1;
    }

    pub fn run_total(&self) -> u64 {
        self.run_total
    }

    /// Each run warning's text and count, in text order.
    pub fn run(&self) -> &BTreeMap<String, u32> {
        &self.run
    }

    /// The last events, oldest first (at most [`MAX_EVENTS`]).
    pub fn events(&self) -> &VecDeque<String> {
        &self.events
    }

    /// Every event ever reported.
    pub fn events_total(&self) -> u64 {
        self.events_total
    }

    /// `<count>:<text>` entries in text order (at most [`MAX_RUN_WARNINGS`]; the rest
    /// counted under `Other Run Warnings`).
    pub fn run_entries(&self) -> Vec<String> {
        let mut out: Vec<String> = self
            .run
            .iter()
            .take(MAX_RUN_WARNINGS)
            .map(|(t, n)| format!("{n}:{t}"))
            .collect();
        let others: u32 = self.run.values().skip(MAX_RUN_WARNINGS).sum();
        if others > 0 {
            out.push(format!("{others}:Other Run Warnings"));
        }
        out
    }
}
