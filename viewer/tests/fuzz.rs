//! Fuzz harnesses of what `helm view` reads from outside, with the other parsers'
//! (bounded budget: `FUZZ_CASES`, `FUZZ_SECS`; see `fuzzkit`): the `.alog` index (a log
//! cut short, garbled, with binary junk) and the VIEW_*, NODE_REPORT and APPCAST readers.
//! Seeds: the repo's mission files' geometry values and a log of every posting kind the
//! viewer draws.
//!
//! Invariants: no panic, no hang, bounded memory (fuzzkit); what reaches the page is
//! finite (every coordinate of a vehicle or a shape, at any time asked), shape keys are
//! unique in a frame, the frame serializes, every colour is CSS without markup
//! characters, and lines read plus lines skipped never exceed the lines of the input.

use std::path::{Path, PathBuf};

use viewer::alog_index::AlogIndex;
use viewer::feed::read_appcast;
use viewer::node::read_node_report;
use viewer::view::{read_view, ViewChange, MAX_VERTICES, VIEW_VARS};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

const VIEW_SEEDS: &[&str] = &[
    "x=3,y=-4,label=home,vertex_color=yellow,vertex_size=4",
    "x=0,y=0,active=false,label=home",
    "pts={0,0:10,0:10,10},label=box,edge_color=Dark_Khaki,fill_color=pink,fill_transparency=0.3",
    "pts={0,0:9,0:0,9},active=false,label=box",
    "format=radial, x=5, y=5, radius=10, pts=8, label=ring",
    "format=lawnmower, x=0, y=0, height=60, width=100, lane_width=20, rows=ns",
    "x=1,y=2,radius=30,label=c1,edge_color=off",
    "x=1,y=2,type=diamond,scale=2,color=red,label=m",
    "x=1,y=2,label=<script>alert(1)</script>,label_color=0.5:0.2:1",
    "NAME=alpha,X=0,Y=-20,SPD=1.5,HDG=180,TYPE=kayak,COLOR=yellow,MODE=PARK,LENGTH=4",
    "{\"NAME\":\"bob\",\"X\":3,\"Y\":4,\"TYPE\":\"ship\"}",
    "proc=pHelmIvP!@#iter=1!@#node=alpha!@#messages=  a!@  b!@!@#!@#events_total=0!@#run_warning_total=1!@#run_warnings=1:x",
];

fn view_seeds() -> Vec<Vec<u8>> {
    let mut v: Vec<Vec<u8>> = VIEW_SEEDS.iter().map(|s| s.as_bytes().to_vec()).collect();
    for file in fuzzkit::seed_files(&repo().join("missions"), "bhv") {
        for line in String::from_utf8_lossy(&file).lines() {
            if let Some((k, val)) = line.split_once('=') {
                let k = k.trim().to_ascii_lowercase();
                if k.contains("point") || k.contains("polygon") {
                    v.push(val.trim().as_bytes().to_vec());
                }
            }
        }
    }
    v.sort();
    v.dedup();
    v
}

/// A CSS colour the server may send: `none`, `rgb(r,g,b)` or a lower-case name.
fn css_ok(c: &Option<String>) -> bool {
    c.as_ref().is_none_or(|c| {
        c.chars()
            .all(|ch| ch.is_ascii_lowercase() || ch.is_ascii_digit() || "(),.".contains(ch))
    })
}

fn check_view(data: &[u8]) {
    let s = String::from_utf8_lossy(data);
    for var in VIEW_VARS {
        match read_view(var, &s) {
            Ok(ViewChange::Draw(sh)) => {
                assert!(!sh.pts.is_empty() && sh.pts.len() <= MAX_VERTICES);
                assert!(sh.pts.iter().flatten().all(|v| v.is_finite()), "{sh:?}");
                assert!(sh.radius.is_none_or(f64::is_finite));
                assert!(sh.key.starts_with(sh.kind) && sh.key.ends_with(&sh.label));
                for c in [
                    &sh.edge_color,
                    &sh.fill_color,
                    &sh.vertex_color,
                    &sh.label_color,
                ] {
                    assert!(css_ok(c), "colour {c:?}");
                }
            }
            Ok(ViewChange::Erase(k)) => assert!(k.contains(':')),
            Err(_) => {}
        }
    }
    if let Ok(v) = read_node_report(&s, 1.0) {
        assert!(v.x.is_finite() && v.y.is_finite() && !v.name.is_empty());
        assert!(v.length > 0.0 && v.length.is_finite());
        assert!(css_ok(&Some(v.color)));
    }
    if let Some(a) = read_appcast(&s) {
        assert!(!a.proc_name.is_empty() && a.key.starts_with(&a.proc_name));
    }
}

#[test]
fn fuzz_view_readers() {
    fuzzkit::fuzz(
        "viewer_view",
        10000,
        &view_seeds(),
        &[
            b",",
            b"=",
            b":",
            b"{",
            b"}",
            b"!@#",
            b"!@",
            b"active=false",
            b"nan",
            b"1e999",
            b"<",
        ],
        check_view,
    );
}

fn alog_seeds() -> Vec<Vec<u8>> {
    let mut s = String::from("%%%%\n%% LOGSTART 1700000000.00\n%%%%\n");
    for i in 0..30 {
        let t = f64::from(i) * 0.25;
        s.push_str(&format!(
            "{t:.3} NODE_REPORT_LOCAL pNodeReporter NAME=abe,X={i},Y={},HDG=90,SPD=1\n\
             {t:.3} NAV_X uSimMarine {i}\n{t:.3} NAV_Y uSimMarine -{i}\n\
             {t:.3} DESIRED_SPEED pHelmIvP 1.5\n",
            i * 2
        ));
    }
    for (i, v) in VIEW_SEEDS.iter().enumerate() {
        let var = VIEW_VARS[i % VIEW_VARS.len()];
        s.push_str(&format!("{}.5 {var} pHelmIvP {v}\n", i));
    }
    s.push_str("9.0 APPCAST pHelmIvP ");
    s.push_str(VIEW_SEEDS[VIEW_SEEDS.len() - 1]);
    s.push('\n');
    let whole = s.into_bytes();
    let mut v = vec![whole.clone()];
    for c in whole.split(|&b| b == b'\n').collect::<Vec<_>>().chunks(15) {
        v.push(c.join(&b'\n'));
    }
    v
}

fn check_alog(data: &[u8]) {
    let ix = AlogIndex::read(data, "ownship");
    let lines = data.split(|&b| b == b'\n').count() as u64;
    let skipped: u64 = ix.skipped.values().sum();
    assert!(ix.lines <= lines, "{} lines read of {lines}", ix.lines);
    // A line is skipped at most once, except that a readable line may also carry a
    // posting the page cannot draw (counted too).
    assert!(skipped <= 2 * lines, "{skipped} skips of {lines} lines");
    for t in [
        ix.t0,
        (ix.t0 + ix.t1) / 2.0,
        ix.t1,
        f64::NAN,
        f64::INFINITY,
        -1e300,
    ] {
        let f = ix.frame(t);
        for v in &f.vehicles {
            assert!(v.x.is_finite() && v.y.is_finite(), "{v:?}");
        }
        for trail in f.trails.values() {
            assert!(trail.iter().flatten().all(|c| c.is_finite()));
        }
        let mut keys: Vec<&str> = f.objects.iter().map(|o| o.key.as_str()).collect();
        keys.sort_unstable();
        let n = keys.len();
        keys.dedup();
        assert_eq!(keys.len(), n, "duplicate shape keys");
        serde_json::to_string(&f).expect("a frame serializes");
    }
}

#[test]
fn fuzz_alog_index() {
    fuzzkit::fuzz(
        "viewer_alog_index",
        5000,
        &alog_seeds(),
        &[
            b"\n",
            b" ",
            b"%%",
            b"NODE_REPORT ",
            b"VIEW_POLYGON ",
            b"\xff",
            b"\0",
            b"nan",
            b"1e400",
        ],
        check_alog,
    );
}
