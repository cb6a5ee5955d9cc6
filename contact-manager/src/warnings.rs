//! Run warnings, configuration warnings and events, as an appcast reports them
//! (contacts-appcast.md §5.3): run warnings counted per distinct text (at most
//! [`MAX_RUN_WARNINGS`] texts, the rest under `Other Run Warnings`), the last
//! [`MAX_EVENTS`] events.

use std::collections::{BTreeMap, VecDeque};

pub const MAX_RUN_WARNINGS: usize = 10;
pub const MAX_EVENTS: usize = 8;
/// Longest warning text kept (a hostile report is quoted in its warning).
pub const MAX_TEXT: usize = 400;

#[derive(Clone, Debug, Default)]
pub struct Warnings {
    run: BTreeMap<String, u64>,
    run_total: u64,
    new_run: bool,
    config: Vec<String>,
    new_config: bool,
    events: VecDeque<String>,
}

fn clip(s: &str) -> String {
    if s.len() <= MAX_TEXT {
        return s.to_string();
    }
    let mut end = MAX_TEXT;
    while !s.is_char_boundary(end) {
        end -= 1;
    }
    format!("{}...", &s[..end])
}

impl Warnings {
    pub fn run_warning(&mut self, text: &str) {
        tracing::debug!(warning = text, "run warning");
        let text = clip(text);
        let key = if self.run.contains_key(&text) || self.run.len() < MAX_RUN_WARNINGS {
            text
        } else {
            "Other Run Warnings".to_string()
        };
        *self.run.entry(key).or_insert(0) += 1;
        self.run_total += 1;
        self.new_run = true;
    }

    pub fn config_warning(&mut self, text: &str) {
        self.config.push(clip(text));
        self.new_config = true;
    }

    /// An event stamped with the seconds since the app started.
    pub fn event(&mut self, since_start: f64, text: &str) {
        self.events
            .push_back(format!("[{since_start:.2}]: {}", clip(text)));
        while self.events.len() > MAX_EVENTS {
            self.events.pop_front();
        }
    }

    /// Distinct run warnings with their counts, in text order.
    pub fn run_warnings(&self) -> impl Iterator<Item = (&str, u64)> {
        self.run.iter().map(|(k, v)| (k.as_str(), *v))
    }

    pub fn run_total(&self) -> u64 {
        self.run_total
    }

    pub fn config_warnings(&self) -> &[String] {
        &self.config
    }

    pub fn events(&self) -> impl Iterator<Item = &str> {
        self.events.iter().map(String::as_str)
    }

    /// New run or configuration warnings since the last [`Warnings::clear_new`].
    pub fn new_run(&self) -> bool {
        self.new_run
    }

    pub fn new_config(&self) -> bool {
        self.new_config
    }

    pub fn clear_new(&mut self) {
        self.new_run = false;
        self.new_config = false;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counted_capped_and_clipped() {
        let mut w = Warnings::default();
        w.run_warning("b");
        w.run_warning("a");
        w.run_warning("b");
        let v: Vec<(&str, u64)> = w.run_warnings().collect();
        assert_eq!(v, [("a", 1), ("b", 2)]);
        for i in 0..20 {
            w.run_warning(&format!("w{i}"));
        }
        assert_eq!(w.run_warnings().count(), MAX_RUN_WARNINGS + 1);
        assert_eq!(w.run_total(), 23);
        w.run_warning(&"x".repeat(10_000));
        assert!(w.run_warnings().all(|(t, _)| t.len() <= MAX_TEXT + 3));
        for i in 0..20 {
            w.event(i as f64, "e");
        }
        assert_eq!(w.events().count(), MAX_EVENTS);
        assert!(w.new_run());
        w.clear_new();
        assert!(!w.new_run());
    }
}
