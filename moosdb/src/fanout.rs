//! Fan-out (spec §5.4.1): a notification encoded once into every subscriber's held mail
//! (`notify`, `hold`), then each asynchronous client's held mail sent as one packet
//! (`push_all`); an `impl State` apart from connection bookkeeping in `state.rs`.

use super::*;

impl State {
    /// Send every asynchronous client's held mail as one packet each (added by the
    /// publisher behind `gate`).
    /// A stalled client whose queue reached its cap is cut off here, the largest first
    /// (its `DB_EVENT`s go out in a second round).
    pub(super) fn push_all(&mut self, gate: &Arc<Gate>, marks: Marks, now: f64) {
        let mut cut: Vec<(Arc<str>, u64, usize)> = Vec::new();
        for round in 0..2 {
            let dirty = std::mem::take(&mut self.dirty);
            for &slot in &dirty {
                let Some(c) = self.slots.get_mut(slot).and_then(Option::as_mut) else {
                    continue;
                };
                if !c.is_async || c.held_count == 0 {
                    continue;
                }
                let count = c.held_count;
                finish_header(&mut c.held, count);
                let pushed = c.out.push_packet(&mut c.held, false, Some(gate), marks);
                self.delivered += count as u64;
                c.held.clear();
                c.held_count = 0;
                if pushed.was_empty {
                    self.flush.push(c.out.clone());
                }
                if pushed.over_cap {
                    cut.push((c.name.clone(), c.conn_id, pushed.queued));
                }
            }
            self.dirty = dirty;
            self.dirty.clear();
            if cut.is_empty() || round == 1 {
                break;
            }
            // The largest queue goes first: that may be room enough for the others.
            cut.sort_by_key(|c| std::cmp::Reverse(c.2));
            cut.truncate(1);
            for (name, conn_id, queued) in cut.drain(..) {
                let why = format!(
                    "accepted no bytes while its queue reached {} KiB",
                    queued >> 10
                );
                self.cut_off(&name, conn_id, &why, now);
            }
        }
    }

    /// Add one encoded message to the held mail of the client in `slot`.
    pub(super) fn hold(&mut self, slot: usize, encoded: &[u8]) {
        let Some(c) = self.slots.get_mut(slot).and_then(Option::as_mut) else {
            return;
        };
        if c.held_count == 0 {
            self.dirty.push(slot);
            c.held.clear();
            c.held.extend_from_slice(&[0u8; HDR]);
        }
        c.held.extend_from_slice(encoded);
        c.held_count += 1;
        if !c.is_async && !c.touched {
            c.touched = true;
            self.touched.push(slot);
        }
    }

    /// `N` (spec §5.4.1). `from` is the publishing client's slot and connection id (None
    /// for the DB's own variables). The forwarded copy is `m` with type `N` and the DB's
    /// community when `m` has none.
    pub(super) fn notify(&mut self, m: &MsgView<'_>, from: Option<(usize, u64)>, now: f64) {
        let mut var = self.vars.get_mut(m.key);
        // The publisher's PUBLISHED list (kept even if the write is refused below).
        let known_pub = matches!((from, &var), (Some((_, id)), Some(v)) if v.last_pub == id);
        if let (Some((slot, _)), false) = (from, known_pub) {
            if let Some(c) = self.slots.get_mut(slot).and_then(Option::as_mut) {
                if !c.published.contains(m.key) {
                    c.published.insert(m.key.to_owned());
                }
            }
        }
        if var.as_ref().is_none_or(|v| v.write_count == 0) {
            if !self.vars.contains_key(m.key) {
                self.vars.insert(m.key.to_owned(), Var::new(m.data_type));
                self.values_grew(m.key.len() as isize);
            }
            let mut matches = Vec::new();
            for c in self.slots.iter().flatten() {
                for f in &c.filters {
                    if wildcard_match(&f.app, m.source) && wildcard_match(&f.var, m.key) {
                        matches.push((c.name.clone(), f.interval));
                    }
                }
            }
            var = self.vars.get_mut(m.key);
            if let Some(v) = var.as_mut() {
                v.data_type = m.data_type;
                for (cname, interval) in matches {
                    add_sub(v, &cname, interval);
                }
            }
        }
        let Some(v) = var else {
            return;
        };
        if let Some((_, id)) = from {
            v.last_pub = id;
        }
        if v.data_type != m.data_type {
            tracing::warn!(var = %m.key, have = %(v.data_type.0 as char), got = %(m.data_type.0 as char), source = %m.source, "type mismatch: notification dropped");
            return;
        }
        let mut grew = 0;
        if m.data_type == DataType::DOUBLE {
            v.dval = m.dval;
        } else {
            grew = m.sval.len() as isize - v.sval.len() as isize;
            v.sval.clear();
            v.sval.extend_from_slice(m.sval);
        }
        if v.written_db > 0.0 && now > v.written_db {
            v.freq = 0.9 * v.freq + 0.1 / (now - v.written_db);
        }
        v.time = m.time;
        let same_source = same(&v.source, m.source);
        // After any write, `writers` holds the latest source (DB_CLEAR resets both).
        let known_writer = same_source && v.write_count > 0;
        if !same_source {
            v.source.clear();
            v.source.push_str(m.source);
        }
        if !same(&v.source_aux, m.source_aux) {
            v.source_aux.clear();
            v.source_aux.push_str(m.source_aux);
        }
        v.written_db = now;
        if !known_writer && !v.writers.contains(m.source) {
            v.writers.insert(m.source.to_owned());
        }
        v.write_count += 1;
        let community = if m.community.is_empty() {
            self.community.as_str()
        } else {
            m.community
        };
        if !same(&v.community, community) {
            v.community.clear();
            v.community.push_str(community);
        }
        let mut targets = std::mem::take(&mut self.targets);
        targets.clear();
        for s in v.subs.iter_mut() {
            if s.interval == 0.0 || now - s.last_sent >= s.interval {
                s.last_sent = now;
                if s.slot_gen != self.client_gen {
                    s.slot = self.clients.get(&*s.client).copied();
                    s.slot_gen = self.client_gen;
                }
                if let Some(i) = s.slot {
                    targets.push(i);
                }
            }
        }
        if !targets.is_empty() {
            let fwd = MsgView {
                msg_type: MsgType::NOTIFY,
                community,
                ..*m
            };
            let mut enc = std::mem::take(&mut self.encoded);
            enc.clear();
            let _ = fwd.encode_into(&mut enc);
            for &t in &targets {
                self.hold(t, &enc);
            }
            self.encoded = enc;
        }
        self.targets = targets;
        self.values_grew(grew);
    }
}
