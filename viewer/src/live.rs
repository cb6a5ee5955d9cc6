//! Live: the picture kept up to date from a MOOSDB, and the hub that sends it to every
//! viewer. Postings are applied as they arrive; a flusher sends what changed at most
//! every [`MIN_GAP`] (so a 10 Hz, 20-vehicle fleet makes about 30 small messages a
//! second, not 200), serialized once for all viewers. A viewer too slow to keep up is
//! dropped from the fan-out and sent the whole picture again when it catches up.

use std::collections::{BTreeMap, BTreeSet};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, Receiver, SyncSender};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use crate::feed::{Appcast, Feed, Update, Value};
use crate::frame::Frame;
use crate::node::VehicleState;
use crate::view::{Shape, ViewChange};

/// The shortest time between two updates sent to the viewers.
pub const MIN_GAP: Duration = Duration::from_millis(25);
/// Messages queued per viewer before it counts as too slow.
const VIEWER_QUEUE: usize = 256;
/// Trail points kept per vehicle (halved when reached).
const MAX_TRAIL: usize = 4000;
/// A new trail point only when the vehicle moved at least this far (m).
const TRAIL_STEP: f64 = 0.2;

/// The whole live picture.
#[derive(Default)]
struct Scene {
    t: f64,
    vehicles: BTreeMap<String, VehicleState>,
    trails: BTreeMap<String, Vec<[f64; 2]>>,
    objects: BTreeMap<String, Shape>,
    /// When each shape with a `duration=` was posted.
    posted: BTreeMap<String, f64>,
    vars: BTreeMap<String, String>,
    appcasts: BTreeMap<String, Appcast>,
    skipped: String,
}

/// What changed since the last flush.
#[derive(Default)]
struct Pending {
    vehicles: BTreeMap<String, VehicleState>,
    trails: BTreeMap<String, Vec<[f64; 2]>>,
    objects: BTreeMap<String, Shape>,
    removed: BTreeSet<String>,
    vars: BTreeMap<String, String>,
    appcasts: BTreeMap<String, Appcast>,
    skipped: Option<String>,
}

impl Pending {
    fn is_empty(&self) -> bool {
        self.vehicles.is_empty()
            && self.trails.is_empty()
            && self.objects.is_empty()
            && self.removed.is_empty()
            && self.vars.is_empty()
            && self.appcasts.is_empty()
            && self.skipped.is_none()
    }
}

struct State {
    scene: Scene,
    pending: Pending,
    viewers: Vec<SyncSender<Arc<str>>>,
    /// Postings applied, flushes sent (for tests and the status line).
    applied: u64,
    flushes: u64,
}

/// The live picture and its viewers.
pub struct Hub {
    st: Mutex<State>,
    cv: Condvar,
    stop: AtomicBool,
}

impl Default for Hub {
    fn default() -> Self {
        Hub {
            st: Mutex::new(State {
                scene: Scene::default(),
                pending: Pending::default(),
                viewers: Vec::new(),
                applied: 0,
                flushes: 0,
            }),
            cv: Condvar::new(),
            stop: AtomicBool::new(false),
        }
    }
}

impl Hub {
    fn lock(&self) -> MutexGuard<'_, State> {
        self.st.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Apply one update made at time `t`.
    pub fn apply(&self, t: f64, u: Update) {
        let mut st = self.lock();
        let State { scene, pending, .. } = &mut *st;
        scene.t = scene.t.max(t);
        match u {
            Update::Vehicle(v) => {
                let trail = scene.trails.entry(v.name.clone()).or_default();
                let moved = trail
                    .last()
                    .is_none_or(|l| (l[0] - v.x).hypot(l[1] - v.y) >= TRAIL_STEP);
                if moved {
                    trail.push([v.x, v.y]);
                    if trail.len() >= MAX_TRAIL {
                        let kept: Vec<[f64; 2]> = trail.iter().step_by(2).copied().collect();
                        *trail = kept;
                    }
                    pending
                        .trails
                        .entry(v.name.clone())
                        .or_default()
                        .push([v.x, v.y]);
                }
                scene.vehicles.insert(v.name.clone(), v.clone());
                pending.vehicles.insert(v.name.clone(), v);
            }
            Update::View(ViewChange::Draw(s)) => {
                pending.removed.remove(&s.key);
                if s.duration.is_some() {
                    scene.posted.insert(s.key.clone(), t);
                } else {
                    scene.posted.remove(&s.key);
                }
                scene.objects.insert(s.key.clone(), (*s).clone());
                pending.objects.insert(s.key.clone(), *s);
            }
            Update::View(ViewChange::Erase(k)) => {
                pending.objects.remove(&k);
                scene.posted.remove(&k);
                if scene.objects.remove(&k).is_some() {
                    pending.removed.insert(k);
                }
            }
            Update::Var(k, v) => {
                scene.vars.insert(k.clone(), v.clone());
                pending.vars.insert(k, v);
            }
            Update::Appcast(a) => {
                scene.appcasts.insert(a.key.clone(), a.clone());
                pending.appcasts.insert(a.key.clone(), a);
            }
        }
        // Shapes whose `duration=` ran out by now go, as if erased.
        if !scene.posted.is_empty() {
            let now = scene.t;
            let objects = &scene.objects;
            let expired: Vec<String> = scene
                .posted
                .iter()
                .filter(|(k, &p)| objects.get(*k).is_some_and(|s| !s.alive(p, now)))
                .map(|(k, _)| k.clone())
                .collect();
            for k in expired {
                scene.posted.remove(&k);
                scene.objects.remove(&k);
                pending.objects.remove(&k);
                pending.removed.insert(k);
            }
        }
        st.applied += 1;
        self.cv.notify_all();
    }

    /// Record what the viewer skipped so far (`alog_index::summary` form).
    pub fn set_skipped(&self, summary: String) {
        let mut st = self.lock();
        st.scene.skipped.clone_from(&summary);
        st.pending.skipped = Some(summary);
        self.cv.notify_all();
    }

    /// The whole picture, and a queue of the changes that follow it (none lost between).
    pub fn subscribe(&self) -> (String, Receiver<Arc<str>>) {
        let mut st = self.lock();
        let s = &st.scene;
        let f = Frame {
            full: true,
            t: s.t,
            vehicles: s.vehicles.values().cloned().collect(),
            trails: s.trails.clone(),
            objects: s.objects.values().cloned().collect(),
            removed: Vec::new(),
            vars: s.vars.clone(),
            appcasts: s.appcasts.values().cloned().collect(),
            skipped: Some(s.skipped.clone()),
        };
        let json = serde_json::to_string(&f).unwrap_or_default();
        let (tx, rx) = mpsc::sync_channel(VIEWER_QUEUE);
        st.viewers.push(tx);
        (json, rx)
    }

    /// Connected viewers (for the status line and tests).
    pub fn viewer_count(&self) -> usize {
        self.lock().viewers.len()
    }

    /// Postings applied so far.
    pub fn applied(&self) -> u64 {
        self.lock().applied
    }

    /// End [`Hub::run_flusher`].
    pub fn stop(&self) {
        self.stop.store(true, Ordering::SeqCst);
        self.cv.notify_all();
    }

    /// Send the changes to the viewers, at most every `gap`, until [`Hub::stop`].
    pub fn run_flusher(&self, gap: Duration) {
        let mut last = Instant::now() - gap;
        loop {
            let mut st = self.lock();
            while st.pending.is_empty() && !self.stop.load(Ordering::SeqCst) {
                st = self
                    .cv
                    .wait_timeout(st, Duration::from_millis(500))
                    .map_or_else(|p| p.into_inner().0, |r| r.0);
            }
            if self.stop.load(Ordering::SeqCst) {
                return;
            }
            let wait = gap.saturating_sub(last.elapsed());
            if !wait.is_zero() {
                drop(st);
                std::thread::sleep(wait);
                st = self.lock();
            }
            last = Instant::now();
            let p = std::mem::take(&mut st.pending);
            let f = Frame {
                full: false,
                t: st.scene.t,
                vehicles: p.vehicles.into_values().collect(),
                trails: p.trails,
                objects: p.objects.into_values().collect(),
                removed: p.removed.into_iter().collect(),
                vars: p.vars,
                appcasts: p.appcasts.into_values().collect(),
                skipped: p.skipped,
            };
            let json: Arc<str> = serde_json::to_string(&f).unwrap_or_default().into();
            // A full queue drops the viewer from the fan-out: it drains what it has,
            // sees the channel closed and subscribes again (a whole picture).
            st.viewers.retain(|v| v.try_send(json.clone()).is_ok());
            st.flushes += 1;
        }
    }
}

/// How the viewer asks for appcasts at time warp `warp`: the `APPCAST_REQ` value and
/// how often to send it. An app counts a request's `duration` in MOOS seconds
/// (duration ÷ warp real seconds) and posts at most every 0.5 real s. pMarineViewer's
/// `duration=3.0` every 2 s lives 0.3 real s at warp 10: a request landing within
/// 0.5 s of the app's last appcast was dropped, and the panel kept the helm's first
/// appcast (`Helm Iteration: 0`) until a later request happened to land. Here a request
/// lives 3 real s (at most 30 MOOS s, the apps' cap) and the next one goes out well
/// before it ends, so the app posts its latest report every report interval.
pub fn appcast_request(key: &str, warp: f64) -> (String, Duration) {
    let warp = if warp.is_finite() && warp > 0.0 {
        warp
    } else {
        1.0
    };
    let duration = (3.0 * warp).clamp(3.0, 30.0);
    let lives = duration / warp;
    let every = Duration::from_secs_f64((lives / 2.0).min(2.0));
    (
        format!("node=all,app=all,duration={duration:.1},key={key},thresh=any"),
        every,
    )
}

/// Feed MOOS mail into the hub until `stop`: registers for what the page shows, keeps
/// every app asked for its appcast ([`appcast_request`]), applies each posting.
pub fn pump(
    client: &moos::Client,
    hub: &Hub,
    feed: Feed,
    extra_vars: &[String],
    stop: &AtomicBool,
) {
    pump_warped(client, hub, feed, extra_vars, stop, 1.0);
}

/// [`pump`] against a DB whose apps run at time warp `warp` (the appcast requests
/// follow it: [`appcast_request`]).
pub fn pump_warped(
    client: &moos::Client,
    hub: &Hub,
    mut feed: Feed,
    extra_vars: &[String],
    stop: &AtomicBool,
    warp: f64,
) {
    for v in crate::feed::subscriptions() {
        let _ = client.register(v, 0.0);
    }
    for v in extra_vars {
        let _ = client.register(v, 0.0);
    }
    let _ = client.register_wildcard("DESIRED_*", "*", 0.0);
    let mut mail = Vec::new();
    let mut last_req: Option<Instant> = None;
    let mut skipped = 0;
    let (req, every) = appcast_request(client.name(), warp);
    while !stop.load(Ordering::SeqCst) {
        if last_req.is_none_or(|l| l.elapsed() >= every) && client.is_connected() {
            let _ = client.notify_string("APPCAST_REQ", &req, None);
            let _ = client.notify_string("APPCAST_REQ_ALL", &req, None);
            last_req = Some(Instant::now());
        }
        client.wait_for_mail(Duration::from_millis(200));
        mail.clear();
        client.fetch(&mut mail);
        for m in &mail {
            if !feed.wants(&m.key) {
                continue;
            }
            let s;
            let v = if m.is_double() {
                Value::Num(m.dval)
            } else {
                s = m.string();
                Value::Str(&s)
            };
            if let Some(u) = feed.apply(&m.key, v, m.time) {
                hub.apply(m.time, u);
            }
        }
        let total: u64 = feed.skipped.values().sum();
        if total != skipped {
            skipped = total;
            hub.set_skipped(crate::alog_index::summary(&feed.skipped));
        }
    }
}

#[cfg(test)]
mod appcast_request_tests {
    use super::*;

    /// At every warp a request is alive all the time: the next one is sent before the
    /// last one ends (in real seconds), so the app posts every report interval.
    #[test]
    fn a_request_lives_until_the_next_one_at_any_warp() {
        for warp in [0.5, 1.0, 2.0, 4.0, 10.0, 20.0, 50.0, 100.0] {
            let (req, every) = appcast_request("uHelmView", warp);
            let duration: f64 = req
                .split(',')
                .find_map(|f| f.strip_prefix("duration="))
                .and_then(|d| d.parse().ok())
                .expect("a duration");
            assert!(duration <= 30.0, "the apps clip at 30: {req}");
            let lives = duration / warp;
            assert!(
                every.as_secs_f64() < lives,
                "warp {warp}: a request every {every:?} lives {lives} s: {req}"
            );
            assert!(
                req.starts_with("node=all,app=all,") && req.ends_with(",key=uHelmView,thresh=any")
            );
        }
    }
}

#[cfg(test)]
mod duration_tests {
    use super::*;
    use crate::view::read_view;

    #[test]
    fn a_live_shape_with_a_duration_expires_as_time_moves_on() {
        let hub = Hub::default();
        let draw = |v: &str, s: &str| Update::View(read_view(v, s).expect("readable"));
        hub.apply(
            10.0,
            draw("VIEW_POLYGON", "pts={0,0:10,0:10,10},label=zone,duration=5"),
        );
        hub.apply(10.0, draw("VIEW_POINT", "x=1,y=1,label=stay"));
        hub.apply(12.0, Update::Var("DEPLOY".into(), "true".into()));
        assert!(hub.subscribe().0.contains("polygon:zone"));
        hub.apply(15.5, Update::Var("DEPLOY".into(), "false".into()));
        let (full, _) = hub.subscribe();
        assert!(!full.contains("polygon:zone"), "{full}");
        assert!(full.contains("point:stay"), "{full}");
    }
}
