//! The manager: mail in, an iteration, postings out (the helm engine's shape).

use std::collections::{BTreeMap, HashMap};

use contact_manager::{MailValue, Posting, Warnings};
use geometry::Polygon;

use crate::able::{relay, AbleLists, Action};
use crate::alert::{update_string, AlertRequest};
use crate::config::{Config, DistPolicy};
use crate::flags::Flag;
use crate::hull;
use crate::obstacle::{Given, GivenError, Obstacle, Source, TrackedPoint};

/// Counters shown in the appcast.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    pub points_valid: u64,
    pub points_invalid: u64,
    pub points_ignored: u64,
    /// `$[OBS_EVER]`: every accepted point and given obstacle (the reference's quirk).
    pub obstacles_ever: u64,
    pub resolved: u64,
    pub alert_requests: u64,
    /// Obstacles whose changed mark was cleared by the alert step.
    pub updates: u64,
    pub hull_failures: u64,
}

/// pObstacleMgr as a library. Per iteration: [`ObstacleManager::handle_mail`] with the
/// batch, then [`ObstacleManager::iterate`], then post what it returns.
#[derive(Debug)]
pub struct ObstacleManager {
    cfg: Config,
    nav: (f64, f64),
    /// Sorted by key: the reference's "key order".
    table: BTreeMap<String, Obstacle>,
    request: Option<AlertRequest>,
    alert_range: f64,
    min_dist_ever: Option<f64>,
    over: (bool, bool, bool),
    able: AbleLists,
    mail_counts: HashMap<String, u64>,
    mail_total: u64,
    pending_flags: Vec<Posting>,
    postings: Vec<Posting>,
    handed_out: bool,
    warnings: Warnings,
    counts: Counts,
    iterations: u64,
    start: f64,
    removed: Vec<String>,
    xy: Vec<(f64, f64)>,
    text: String,
}

impl ObstacleManager {
    /// A manager started at time `now`: the `given_obstacle` lines are taken (no
    /// duration check) and `OBM_CONNECT = true` is queued with their flags.
    ///
    /// ```
    /// use obstacle_manager::{Config, ObstacleManager};
    /// let mut cfg = Config::default();
    /// cfg.set("given_obstacle", "pts={60,-12:60,6:80,6:80,-12},label=oba").unwrap();
    /// let mut m = ObstacleManager::new(cfg, 0.0);
    /// let p = m.iterate(0.0);
    /// assert!(p.iter().any(|p| p.var == "OBM_CONNECT"));
    /// assert_eq!(m.obstacles().count(), 1);
    /// ```
    pub fn new(cfg: Config, now: f64) -> ObstacleManager {
        let mut m = ObstacleManager {
            alert_range: cfg.alert_range,
            cfg,
            nav: (0.0, 0.0),
            table: BTreeMap::new(),
            request: None,
            min_dist_ever: None,
            over: (false, false, false),
            able: AbleLists::default(),
            mail_counts: HashMap::new(),
            mail_total: 0,
            pending_flags: Vec::new(),
            postings: Vec::new(),
            handed_out: false,
            warnings: Warnings::default(),
            counts: Counts::default(),
            iterations: 0,
            start: now,
            removed: Vec::new(),
            xy: Vec::new(),
            text: String::new(),
        };
        for note in m.cfg.notes.clone() {
            m.warnings.config_warning(&note);
        }
        for g in m.cfg.given.clone() {
            if let Err(e) = m.given(now, &g, false) {
                m.warnings
                    .config_warning(&format!("given_obstacle: {e}: {g}"));
            }
        }
        m.postings.push(Posting::str("OBM_CONNECT", "true"));
        m
    }

    pub fn config(&self) -> &Config {
        &self.cfg
    }
    /// Ownship's last NAV_X/NAV_Y.
    pub fn nav(&self) -> (f64, f64) {
        self.nav
    }
    /// The obstacles in key order.
    pub fn obstacles(&self) -> impl Iterator<Item = (&str, &Obstacle)> {
        self.table.iter().map(|(k, o)| (k.as_str(), o))
    }
    pub fn request(&self) -> Option<&AlertRequest> {
        self.request.as_ref()
    }
    /// The current alert range (the configured one until a request replaces it).
    pub fn alert_range(&self) -> f64 {
        self.alert_range
    }
    pub fn counts(&self) -> Counts {
        self.counts
    }
    pub fn able_lists(&self) -> &AbleLists {
        &self.able
    }
    pub fn warnings(&self) -> &Warnings {
        &self.warnings
    }
    pub fn warnings_mut(&mut self) -> &mut Warnings {
        &mut self.warnings
    }
    pub fn iterations(&self) -> u64 {
        self.iterations
    }

    /// The variables the manager reads (point variable, mail-flag keys, relays).
    pub fn subscriptions(&self) -> Vec<String> {
        let mut v: Vec<String> = ["NAV_X", "NAV_Y", "GIVEN_OBSTACLE", "OBM_ALERT_REQUEST"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        let c = &self.cfg;
        let extra = [&c.point_var, &c.disable_var, &c.enable_var, &c.expunge_var];
        for s in extra.into_iter().chain(c.mail_flags.iter().map(|f| &f.key)) {
            if !s.is_empty() && !v.contains(s) {
                v.push(s.clone());
            }
        }
        v
    }

    fn fresh_postings(&mut self) {
        if self.handed_out {
            self.postings.clear();
            self.handed_out = false;
        }
    }

    /// Take one batch of mail received by time `now`.
    pub fn handle_mail(&mut self, now: f64, mail: &[(&str, MailValue<'_>)]) {
        self.fresh_postings();
        for (var, val) in mail {
            let mut handled = self.mail_flag(var, now);
            if *var == self.cfg.point_var {
                handled |= self.point(now, &val.text());
            }
            handled |= self.one_mail(now, var, val);
            if !handled {
                self.warnings.run_warning(&format!("Unhandled Mail: {var}"));
            }
        }
        self.postings.append(&mut self.pending_flags);
    }

    fn one_mail(&mut self, now: f64, var: &str, val: &MailValue<'_>) -> bool {
        match var {
            "NAV_X" | "NAV_Y" => {
                let Some(v) = val.num().filter(|v| v.is_finite()) else {
                    return false;
                };
                if var == "NAV_X" {
                    self.nav.0 = v;
                } else {
                    self.nav.1 = v;
                }
                true
            }
            "GIVEN_OBSTACLE" => {
                let text = val.text();
                match self.given(now, &text, true) {
                    Ok(()) => true,
                    Err(e @ (GivenError::MissingDuration | GivenError::DurationTooLong)) => {
                        self.warnings.run_warning(&e.to_string());
                        self.warnings.run_warning(&text);
                        false
                    }
                    Err(e) => {
                        if e == GivenError::KnownAsData {
                            self.warnings.run_warning(&e.to_string());
                        }
                        false
                    }
                }
            }
            "OBM_ALERT_REQUEST" => {
                self.counts.alert_requests += 1;
                match AlertRequest::parse(&val.text()) {
                    Ok(r) => {
                        self.alert_range = r.range;
                        self.request = Some(r);
                        for o in self.table.values_mut() {
                            o.changed = true;
                        }
                        true
                    }
                    Err(e) => {
                        tracing::warn!(request = %val.text(), error = %e, "alert request refused");
                        false
                    }
                }
            }
            _ => self.able_mail(var, &val.text()),
        }
    }

    /// Mail-flag handling: whether `var` has flags (then it counts as handled).
    fn mail_flag(&mut self, var: &str, now: f64) -> bool {
        let exact = self.cfg.mail_flags.iter().any(|f| f.key == var);
        let key = if exact { var } else { "ANY" };
        if !self.cfg.mail_flags.iter().any(|f| f.key == key) {
            return false;
        }
        let cnt = {
            let c = self.mail_counts.entry(var.to_string()).or_insert(0);
            *c += 1;
            *c
        };
        self.mail_total += 1;
        let (cnt, mcnt, utc) = (
            cnt.to_string(),
            self.mail_total.to_string(),
            format!("{now:.2}"),
        );
        let macros = [("$[CNT]", &*cnt), ("$[MCNT]", &*mcnt), ("$[UTC]", &*utc)];
        for f in self.cfg.mail_flags.iter().filter(|f| f.key == key) {
            self.pending_flags.extend(f.flag.posting(&macros));
        }
        true
    }

    fn point(&mut self, now: f64, text: &str) -> bool {
        let p = match TrackedPoint::parse(text) {
            Ok(p) => p,
            Err(e) => {
                self.counts.points_invalid += 1;
                tracing::debug!(point = text, error = %e, "invalid point");
                self.warnings.run_warning(&format!("Invalid point:{text}"));
                return false;
            }
        };
        let ir = self.cfg.ignore_range;
        if ir > 0.0 && (p.x - self.nav.0).hypot(p.y - self.nav.1) > ir {
            self.counts.points_ignored += 1;
            return true;
        }
        self.counts.points_valid += 1;
        self.counts.obstacles_ever += 1;
        let o = match self.table.get_mut(p.key) {
            Some(o) => o,
            None => self
                .table
                .entry(p.key.to_string())
                .or_insert_with(|| Obstacle::new(Source::Points)),
        };
        o.source = Source::Points;
        o.points.push_front((p.x, p.y, now));
        if o.max_points.is_some_and(|max| o.points.len() > max) {
            o.points.pop_back();
        }
        o.max_points = Some(self.cfg.max_pts_per_cluster);
        o.changed = true;
        o.duration = 0.0;
        if o.vsource != p.vsource {
            o.vsource = p.vsource.to_string();
        }
        true
    }

    /// A given obstacle (§2.4); `mail` applies the duration limit.
    fn given(&mut self, now: f64, text: &str, mail: bool) -> Result<(), GivenError> {
        let g = Given::parse(text)?;
        let max = self.cfg.given_max_duration;
        if mail && max > 0.0 {
            match g.duration {
                None => return Err(GivenError::MissingDuration),
                Some(d) if d > max => return Err(GivenError::DurationTooLong),
                Some(_) => {}
            }
        }
        let key = g.poly.attrs.label.clone();
        if self
            .table
            .get(&key)
            .is_some_and(|o| o.source == Source::Points)
        {
            return Err(GivenError::KnownAsData);
        }
        let o = self
            .table
            .entry(key)
            .or_insert_with(|| Obstacle::new(Source::Given));
        o.vsource.clone_from(&g.poly.attrs.vsource);
        o.set_poly(g.poly);
        o.duration = g.duration.unwrap_or(-1.0);
        o.timestamp = now;
        o.changed = true;
        self.counts.obstacles_ever += 1;
        let flags = std::mem::take(&mut self.cfg.new_obs_flags);
        self.post_flags(&flags);
        self.cfg.new_obs_flags = flags;
        Ok(())
    }

    /// Post `flags` with the §2.9 macros expanded.
    fn post_flags(&mut self, flags: &[Flag]) {
        if flags.is_empty() {
            return;
        }
        let all: Vec<&str> = self.able.disabled.iter().map(String::as_str).collect();
        let (now_s, ever_s, total_s, all_s) = (
            self.table.len().to_string(),
            self.counts.obstacles_ever.to_string(),
            self.able.disabled.len().to_string(),
            all.join(","),
        );
        let front = |l: &std::collections::VecDeque<String>| l.front().cloned().unwrap_or_default();
        let (rd, re) = (front(&self.able.disabled), front(&self.able.enabled));
        let macros = [
            ("$[RECENT_DISABLED]", rd.as_str()),
            ("$[RECENT_ENABLED]", re.as_str()),
            ("$[TOTAL_DISABLED]", total_s.as_str()),
            ("$[ALL_DISABLED]", all_s.as_str()),
            ("$[OBS_NOW]", now_s.as_str()),
            ("$[OBS_EVER]", ever_s.as_str()),
        ];
        for f in flags {
            self.postings.extend(f.posting(&macros));
        }
    }

    fn able_mail(&mut self, var: &str, text: &str) -> bool {
        let c = &self.cfg;
        let action = if var == c.disable_var {
            Action::Disable
        } else if var == c.enable_var {
            Action::Enable
        } else if var == c.expunge_var {
            Action::Expunge
        } else {
            return false;
        };
        match relay(action, text) {
            Ok(r) => {
                self.postings
                    .push(Posting::str("BHV_ABLE_FILTER", r.filter));
                if let Some(id) = r.listed_id {
                    self.able.note(action, &id);
                    if action == Action::Expunge {
                        self.table.remove(&id);
                    }
                }
                true
            }
            Err(e) => {
                tracing::debug!(var, value = text, error = %e, "relay refused");
                false
            }
        }
    }

    /// One iteration at time `now` (§2.5): prune, hulls, ranges, alerts. Returns
    /// everything to post since the last call (mail postings too).
    pub fn iterate(&mut self, now: f64) -> &[Posting] {
        self.fresh_postings();
        self.iterations += 1;
        self.prune(now);
        self.hulls(now);
        self.ranges();
        if self.request.is_some() {
            self.alerts();
        }
        self.handed_out = true;
        &self.postings
    }

    fn prune(&mut self, now: f64) {
        let max_age = self.cfg.max_age_per_point;
        self.removed.clear();
        for (key, o) in self.table.iter_mut() {
            let gone = match o.source {
                Source::Points => {
                    let before = o.points.len();
                    o.points.retain(|p| now - p.2 <= max_age);
                    if o.points.len() != before {
                        o.changed = true;
                    }
                    o.points.is_empty()
                }
                Source::Given => o.duration >= 0.0 && now - o.timestamp > o.duration,
            };
            if gone || o.poly.attrs.active == Some(false) {
                self.removed.push(key.clone());
            }
        }
        for key in std::mem::take(&mut self.removed) {
            let Some(o) = self.table.remove(&key) else {
                continue;
            };
            if self.cfg.post_view_polys {
                self.postings.push(Posting::str(
                    "VIEW_POLYGON",
                    geometry::seglist_erase_spec(&o.poly.attrs.label),
                ));
            }
            self.postings.push(Posting::str("OBM_RESOLVED", key));
            self.counts.resolved += 1;
        }
    }

    fn hulls(&mut self, now: f64) {
        let n = self.table.len();
        let c = &self.cfg;
        let over = (
            n > c.poly_label_thresh,
            n > c.poly_shade_thresh,
            n > c.poly_vertex_thresh,
        );
        let crossed = over != self.over;
        self.over = over;
        let mut xy = std::mem::take(&mut self.xy);
        for (key, o) in self.table.iter_mut() {
            if !(o.changed || crossed) || o.points.is_empty() {
                continue;
            }
            o.xy(&mut xy);
            let mut poly = if c.lasso {
                self.warnings.event(now - self.start, "gen_lasso");
                hull::lasso(&xy, c.lasso_radius, c.lasso_points).unwrap_or_default()
            } else {
                hull::convex_hull(&xy)
            };
            if !poly.is_convex() {
                self.counts.hull_failures += 1;
                self.warnings.run_warning(&format!(
                    "hull failure - Placeholder needed {}",
                    poly.size()
                ));
                match hull::placeholder(&xy) {
                    Some(p) => poly = p,
                    None => continue,
                }
            }
            poly.attrs.label = format!("obmgr_{key}");
            o.set_poly(poly);
            if c.post_view_polys {
                let v = styled(&o.poly, c, over);
                self.postings.push(Posting::str("VIEW_POLYGON", v.spec(5)));
            }
        }
        self.xy = xy;
    }

    fn ranges(&mut self) {
        let (x, y) = self.nav;
        for o in self.table.values_mut() {
            if o.poly.is_empty() {
                continue;
            }
            let r = o.poly.dist_to_poly(x, y);
            if self.min_dist_ever.is_none_or(|m| r < m) {
                self.min_dist_ever = Some(r);
                self.postings.push(Posting::num("OBM_MIN_DIST_EVER", r));
            }
            if o.range > self.alert_range && r <= self.alert_range {
                o.changed = true;
            }
            o.range = r;
        }
    }

    fn alerts(&mut self) {
        let Some(req) = &self.request else { return };
        let (x, y) = self.nav;
        for (key, o) in self.table.iter_mut() {
            if !o.poly.is_convex() {
                continue;
            }
            let d = o.poly.dist_to_poly(x, y);
            let close = d <= self.alert_range;
            let post_dist = match self.cfg.post_dist_to_polys {
                DistPolicy::All => true,
                DistPolicy::Close => close,
                DistPolicy::Off => false,
            };
            if post_dist {
                self.postings.push(Posting::str(
                    "OBM_DIST_TO_OBJ",
                    format!("{},{d:.1}", key.to_ascii_uppercase()),
                ));
            }
            if !o.changed {
                continue;
            }
            o.changed = false;
            self.counts.updates += 1;
            if close {
                update_string(&mut self.text, &req.name, key, &o.poly, &o.vsource);
                self.postings
                    .push(Posting::str(&req.update_var, self.text.clone()));
            }
            if let Some(g) = &self.cfg.general_alert {
                if d <= g.range {
                    update_string(&mut self.text, &g.name, key, &o.poly, &o.vsource);
                    self.postings
                        .push(Posting::str(&g.update_var, self.text.clone()));
                }
            }
        }
    }
}

/// The hull drawing of §2.5 step 2, simplified above the thresholds.
fn styled(
    p: &Polygon,
    c: &Config,
    (label_over, shade_over, vertex_over): (bool, bool, bool),
) -> Polygon {
    let mut v = p.clone();
    let color = c.obstacles_color.clone();
    if label_over {
        v.attrs.label_color = "invisible".into();
    }
    if shade_over {
        v.attrs.fill_color = "invisible".into();
    } else {
        v.attrs.fill_color.clone_from(&color);
        v.attrs.fill_transparency = Some(0.15);
    }
    if vertex_over {
        v.attrs.vertex_color = "invisible".into();
        v.attrs.vertex_size = Some(0.0);
    } else {
        v.attrs.vertex_color.clone_from(&color);
        v.attrs.vertex_size = Some(3.0);
    }
    v.attrs.edge_color = color;
    v.attrs.edge_size = Some(1.0);
    v
}

#[cfg(test)]
#[path = "manager_tests.rs"]
mod tests;
