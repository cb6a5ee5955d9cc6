use super::*;

const HEADER: &str = "%%%%%%%%\n%% LOG FILE:  x.alog\n%% LOGSTART           1795316330.37\n%%%%\n";

fn index(text: &[u8]) -> AlogIndex {
    AlogIndex::read(text, "ownship")
}

#[test]
fn vehicle_is_where_the_log_puts_it_at_each_time() {
    let mut s = String::from(HEADER);
    for i in 0..10 {
        let t = f64::from(i);
        s.push_str(&format!(
            "{t:.3} NODE_REPORT_LOCAL pNodeReporter NAME=abe,X={},Y={},HDG=90,SPD=2,MODE=M{}\n",
            i * 2,
            -i,
            i / 5
        ));
    }
    let ix = index(s.as_bytes());
    assert_eq!(ix.lines, 10);
    assert_eq!((ix.t0, ix.t1), (0.0, 9.0));
    let f = ix.frame(4.5);
    assert_eq!(f.vehicles.len(), 1);
    let v = &f.vehicles[0];
    assert_eq!((v.x, v.y, v.hdg, v.mode.as_str()), (8.0, -4.0, 90.0, "M0"));
    assert_eq!(f.trails["abe"].len(), 5);
    assert_eq!(ix.frame(9.0).vehicles[0].mode, "M1");
    assert!(ix.frame(-1.0).vehicles.is_empty());
    assert_eq!(ix.bounds, Some([0.0, -9.0, 18.0, 0.0]));
    // The header's clock and the log's own vehicle, for lining up a fleet's logs.
    assert_eq!(ix.logstart, Some(1795316330.37));
    assert_eq!(ix.local.iter().collect::<Vec<_>>(), ["abe"]);
}

#[test]
fn shapes_appear_and_disappear_across_checkpoints() {
    let mut s = String::from(HEADER);
    // Many events so the frame crosses stored checkpoints.
    for i in 0..2000 {
        s.push_str(&format!(
            "{}.0 VIEW_POINT b x={i},y=0,label=p{}\n",
            i,
            i % 7
        ));
    }
    s.push_str("3000.0 VIEW_POLYGON b pts={0,0:10,0:10,10},label=box\n");
    s.push_str("3010.0 VIEW_POLYGON b pts={0,0:9,0:0,9},active=false,label=box\n");
    let ix = index(s.as_bytes());
    let f = ix.frame(1000.5);
    assert_eq!(f.objects.len(), 7);
    let p3 = f.objects.iter().find(|o| o.key == "point:p3").expect("p3");
    // The last p3 at or before t=1000 was posted at t=997 (997 % 7 == 3).
    assert_eq!(p3.pts[0], [997.0, 0.0]);
    assert!(ix
        .frame(3005.0)
        .objects
        .iter()
        .any(|o| o.key == "polygon:box"));
    assert!(!ix
        .frame(3010.0)
        .objects
        .iter()
        .any(|o| o.key == "polygon:box"));
}

#[test]
fn bad_lines_are_skipped_and_counted_by_reason() {
    let mut b = HEADER.as_bytes().to_vec();
    b.extend_from_slice(b"1.0 NAV_X uSim 5\n");
    b.extend_from_slice(b"1.0 NAV_Y uSim 6\n");
    b.extend_from_slice(b"abc DEPLOY x true\n");
    b.extend_from_slice(b"2.0 DEPLOY\n");
    b.extend_from_slice(b"2.5 VIEW_POLYGON b pts={1,2:3\n");
    b.extend_from_slice(b"3.0 NAV_X \xff\xfe 7\n");
    b.extend_from_slice(&[0u8; 40]);
    b.push(b'\n');
    b.extend_from_slice(b"4.0 NAV_X uSim ");
    b.extend_from_slice(&vec![b'9'; MAX_LINE + 10]);
    b.push(b'\n');
    b.extend_from_slice(b"5.0 NAV_X uSim 8\n");
    b.extend_from_slice(b"6.0 VIEW_POI");
    let ix = index(&b);
    let k = |s: &str| ix.skipped.get(s).copied().unwrap_or(0);
    assert_eq!(k("time not a number"), 1, "{:?}", ix.skipped);
    // A run of NUL bytes (a power loss) is one column.
    assert_eq!(k("fewer than 3 columns"), 2, "{:?}", ix.skipped);
    assert_eq!(k("not UTF-8"), 1);
    assert_eq!(k("longer than 1 MiB"), 1);
    assert_eq!(k("last line cut short"), 1);
    assert_eq!(k("malformed VIEW_POLYGON (unreadable)"), 1);
    assert!(
        ix.skipped_summary().starts_with("7 skipped: "),
        "{}",
        ix.skipped_summary()
    );
    let f = ix.frame(10.0);
    assert_eq!(
        (f.vehicles[0].name.as_str(), f.vehicles[0].x),
        ("ownship", 8.0)
    );
}

#[test]
fn a_line_without_end_that_reads_is_kept() {
    let ix = index(b"1.0 NAV_X s 1\n1.0 NAV_Y s 2\n2.0 DESIRED_SPEED pHelmIvP 1.5");
    assert!(ix.skipped.is_empty(), "{:?}", ix.skipped);
    assert_eq!(ix.frame(2.0).vars["DESIRED_SPEED"], "1.5");
    assert!(!ix.frame(1.5).vars.contains_key("DESIRED_SPEED"));
}

#[test]
fn empty_and_header_only_logs_open() {
    let ix = index(b"");
    assert_eq!((ix.lines, ix.t0, ix.t1), (0, 0.0, 0.0));
    assert!(ix.frame(0.0).vehicles.is_empty());
    let ix = index(HEADER.as_bytes());
    assert_eq!(ix.lines, 0);
}

#[test]
fn a_shape_with_a_duration_is_gone_that_long_after_it_was_posted() {
    let mut s = String::from(HEADER);
    s.push_str("10.0 VIEW_POLYGON b pts={0,0:10,0:10,10},label=zone,duration=5\n");
    s.push_str("10.0 VIEW_POINT b x=1,y=1,label=stay\n");
    s.push_str("20.0 VIEW_POINT b x=2,y=2,label=late\n");
    let ix = index(s.as_bytes());
    let keys =
        |t: f64| -> Vec<String> { ix.frame(t).objects.iter().map(|o| o.key.clone()).collect() };
    assert!(keys(12.0).contains(&"polygon:zone".to_string()));
    assert!(keys(14.9).contains(&"polygon:zone".to_string()));
    assert!(!keys(15.0).contains(&"polygon:zone".to_string()));
    assert!(keys(30.0).contains(&"point:stay".to_string()));
}
