use super::*;
use crate::number::Value;

fn parse(text: &str) -> SetSpec {
    parse_str(text, Path::new("t.bhv")).unwrap_or_else(|e| panic!("{e}"))
}

fn fail(text: &str) -> BhvError {
    match parse_str(text, Path::new("t.bhv")) {
        Ok(s) => panic!("expected an error for {text:?}, got {s:?}"),
        Err(e) => e,
    }
}

const BLOCK: &str = "Behavior = BHV_Waypoint\n{\n  name = a\n  speed = 2\n}\n";

#[test]
fn line_joining() {
    assert_eq!(join_lines("a \\\n b\nc"), ["a  b", "c"]);
    assert_eq!(join_lines("a\\  \nb\\\nc\nd"), ["abc", "d"]);
    assert_eq!(join_lines("x\\"), ["x"]);
    assert_eq!(join_lines("x\n"), ["x", ""]);
    let s = parse("Behavior = BHV_Waypoint\n{\n  points = 0,0 : \\\n    10,10\n  speed = 2\n}\n");
    let b = &s.behaviors[0];
    assert_eq!(b.lines[0].value, "0,0 :     10,10");
    // joined-line indexes: `speed` is on joined line 4 (physical line 5)
    assert_eq!(b.lines[1].line, 4);
}

#[test]
fn brace_splitting() {
    assert_eq!(
        brace_split("Behavior = BHV_Waypoint {"),
        ["Behavior = BHV_Waypoint", "{"]
    );
    assert_eq!(brace_split("{"), ["{"]);
    assert_eq!(brace_split("} INACTIVE"), ["}", "INACTIVE"]);
    assert_eq!(brace_split("{ name = foo"), ["{", "name = foo"]);
    assert_eq!(brace_split("speed = 2 }"), ["speed = 2 }"]);
    assert_eq!(brace_split("{}"), ["{", "}"]);
    assert_eq!(brace_split("} set M = X {"), ["}", "set M = X", "{"]);
    assert_eq!(brace_split("// x {"), ["// x {"]);
    assert_eq!(brace_split("# x {"), ["# x {"]);
    assert_eq!(
        brace_split("Behavior = BHV_X { // c"),
        ["Behavior = BHV_X { // c"]
    );
}

#[test]
fn trailing_close_brace_not_split() {
    let e = fail("Behavior = BHV_Waypoint {\n  speed = 2 }\n");
    assert!(matches!(e.kind, BhvErrorKind::UnclosedBlock(_)), "{e}");
    assert_eq!(e.line, 1);
}

#[test]
fn comment_after_open_brace_defeats_split() {
    let e = fail("Behavior = BHV_X { // c\n{\n}\n");
    assert!(matches!(e.kind, BhvErrorKind::BadBehavior(_)), "{e}");
    assert_eq!(e.line, 1);
}

#[test]
fn same_line_braces_work() {
    let s = parse(
        "Behavior = BHV_Waypoint {\n  speed = 2\n}\nBehavior = BHV_Loiter\n{ name = foo\n}\n",
    );
    assert_eq!(s.behaviors.len(), 2);
    assert_eq!(s.behaviors[1].lines[0].param, "name");
    assert_eq!(s.behaviors[1].line, 4);
}

#[test]
fn comments() {
    let s = parse(
        "// header\n  // indented\ninitialize A = 1 // one\nBehavior = BHV_W // type\n{ // open\n  \
         speed = 2 // fast\n  url = http://x\n} // close\n",
    );
    assert_eq!(s.inits[0].value, Value::Num(1.0));
    let b = &s.behaviors[0];
    assert_eq!(b.type_name, "BHV_W");
    assert_eq!(b.lines[0].value, "2");
    assert_eq!(b.lines[0].raw, "speed = 2 // fast");
    assert_eq!(b.lines[1].value, "http:", "comments cut even inside values");
}

#[test]
fn hash_lines_are_not_comments() {
    let e = fail("#include foo.bhv\n");
    assert_eq!(e.kind, BhvErrorKind::Preprocessor("#include".into()));
    assert_eq!((e.line, e.text.as_str()), (1, "#include foo.bhv"));
    assert!(e.to_string().contains("nsplug"), "{e}");
    assert!(matches!(
        fail("# note\n").kind,
        BhvErrorKind::UnexpectedLine
    ));
    // inside a block: passed on as a (bad) configuration line
    let s = parse("Behavior = BHV_W\n{\n#define X\n}\n");
    assert_eq!(s.behaviors[0].lines[0].param, "#define x");
    assert_eq!(s.behaviors[0].lines[0].value, "");
    assert_eq!(s.behaviors[0].lines[0].raw, "#define X");
    // macros are kept literally
    let s = parse("Behavior = BHV_W\n{\n speed = $(SPEED)\n}\n");
    assert_eq!(s.behaviors[0].lines[0].value, "$(SPEED)");
}

#[test]
fn state_machine_errors() {
    let cases: [(&str, usize, &str); 13] = [
        ("free text\n", 1, "free text"),
        ("Behavior = BHV_W\nspeed = 2\n{\n}\n", 2, "speed = 2"),
        ("{\n}\ntext\n", 3, "text"),
        ("}\n", 1, "}"),
        ("{\n{\n", 2, "{"),
        ("Behavior = BHV_W\n{\n{\n", 3, "{"),
        ("Behavior = BHV_W\n}\n", 2, "}"),
        ("set\n", 1, "set"),
        ("initialize\n", 1, "initialize"),
        ("set M = X\nA = 1\n", 2, "A = 1"),
        (
            "Behavior = BHV_W\nBehavior = BHV_X\n",
            2,
            "Behavior = BHV_X",
        ),
        ("\n\n  nonsense // c\n", 3, "nonsense // c"),
        ("set M = X {\n}\n{\n", 3, "{"),
    ];
    for (text, line, shown) in cases {
        let e = fail(text);
        assert_eq!((e.line, e.text.as_str()), (line, shown), "{text:?}: {e}");
        let msg = e.to_string();
        assert!(msg.starts_with(&format!("t.bhv:{line}: ")), "{msg}");
        assert!(msg.ends_with(&format!(" (line: {shown})")), "{msg}");
        assert!(!msg.contains('\n'), "one line: {msg}");
    }
    assert!(matches!(
        fail("}\n").kind,
        BhvErrorKind::UnexpectedCloseBrace
    ));
    assert!(matches!(
        fail("{\n{\n").kind,
        BhvErrorKind::UnexpectedOpenBrace
    ));
}

#[test]
fn helm_warning_texts() {
    let e = fail("initialize A = 1\n}\n");
    assert_eq!(
        e.helm_warnings(),
        [
            "File:t.bhv Line:1Unexpected close brace '}'",
            "Problem with line 2 in the BehaviorSet file: t.bhv Line: [}]"
        ]
    );
    let e = fail("\nhello // x\n");
    assert_eq!(
        e.helm_warnings(),
        ["Problem with line 2 in the BehaviorSet file: t.bhv Line: [hello // x]"]
    );
}

#[test]
fn anonymous_blocks() {
    let s = parse("{\n anything at all\n Behavior = X\n}\n\ninitialize A = 1\n");
    assert!(s.behaviors.is_empty());
    assert_eq!(s.inits.len(), 1);
    // keyword right after the `}` of an anonymous block
    let s = parse("{\n}\ninitialize A = 1\n");
    assert_eq!(s.inits.len(), 1);
}

#[test]
fn initialize_typing_and_deferral() {
    let s = parse(
        "initialize A = 1, B = hello, C = \"3\", D = \"x, y\", E = {a,b}\n\
         initialize_ F = -2.5\n\
         Initialize_ G = 1\n\
         INITIALIZE H = Mixed Case\n\
         initialize I = \"\"\n",
    );
    let got: Vec<(&str, &Value, bool)> = s
        .inits
        .iter()
        .map(|i| (i.var.as_str(), &i.value, i.deferred))
        .collect();
    let str_ = |v: &str| Value::Str(v.to_string());
    assert_eq!(
        got,
        [
            ("A", &Value::Num(1.0), false),
            ("B", &str_("hello"), false),
            ("C", &str_("3"), false),
            ("D", &str_("x, y"), false),
            ("E", &str_("{a,b}"), false),
            ("F", &Value::Num(-2.5), true),
            ("G", &Value::Num(1.0), false),
            ("H", &str_("Mixed Case"), false),
            ("I", &Value::Num(0.0), false),
        ]
    );
    assert_eq!(s.inits[5].line, 2);
    assert_eq!(s.inits[0].file, PathBuf::from("t.bhv"));
}

#[test]
fn initialize_errors() {
    for t in [
        "initialize A\n",
        "initialize = 1\n",
        "initialize A B = 1\n",
        "initialize A =\n",
        "initialize A = 1,\n",
        "initialize A = 1, , B = 2\n",
        "initialize\tA = 1\n",
    ] {
        let e = fail(t);
        assert_eq!(e.line, 1, "{t:?}");
    }
    assert!(matches!(
        fail("initialize A\n").kind,
        BhvErrorKind::BadInitialize(_)
    ));
}

#[test]
fn behavior_blocks() {
    let s = parse(
        "Behavior = BHV_Waypoint\n{\n  Name = first\n  templating = clone\n  max_spawnings = 5\n  \
         updates = WPT_UPDATE\n  Speed = Fast\n}\n\nBEHAVIOR = BHV_Loiter\n{\n  speed = 1\n  \
         updates = TWO WORDS\n}\nbehavior=BHV_Timer\n{\n  name = t\n  templating = Spawn\n}\n",
    );
    let b = &s.behaviors;
    assert_eq!(b.len(), 3);
    assert_eq!((b[0].type_name.as_str(), b[0].line), ("BHV_Waypoint", 1));
    assert_eq!(b[0].templating, Templating::Clone);
    assert_eq!(b[0].max_spawnings, 5);
    assert_eq!(b[0].updates_var.as_deref(), Some("WPT_UPDATE"));
    assert_eq!(b[0].name_prefix, "first");
    let params: Vec<&str> = b[0].lines.iter().map(|l| l.param.as_str()).collect();
    assert_eq!(
        params,
        ["name", "updates", "speed"],
        "templating/max_spawnings consumed"
    );
    assert_eq!(b[0].lines[2].value, "Fast");
    assert_eq!(b[0].lines[2].raw, "Speed = Fast");
    assert_eq!(b[0].lines[2].line, 7);
    // second block: no name → inherits the prefix; updates with blanks not taken
    assert_eq!(b[1].name_prefix, "first");
    assert_eq!(b[1].updates_var, None);
    assert_eq!(b[1].lines.len(), 2, "updates line still passed on");
    assert_eq!(b[1].templating, Templating::Disallow);
    assert_eq!(b[1].max_spawnings, 0);
    assert_eq!(b[2].type_name, "BHV_Timer");
    assert_eq!(b[2].templating, Templating::Spawn);
    assert_eq!(b[2].name_prefix, "t");
}

#[test]
fn behavior_block_errors() {
    for (t, line) in [
        ("Behavior\n{\n}\n", 1),
        ("Behavior =\n{\n}\n", 1),
        ("Behavior = A B\n{\n}\n", 1),
        ("Behavior = X\n{\n templating = sometimes\n}\n", 3),
        ("Behavior = X\n{\n max_spawnings = -1\n}\n", 3),
        ("Behavior = X\n{\n max_spawnings = many\n}\n", 3),
    ] {
        assert_eq!(fail(t).line, line, "{t:?}");
    }
}

#[test]
fn set_blocks() {
    let s = parse(
        "set MODE = ACTIVE {\n  DEPLOY = true\n} INACTIVE\n\n\
         set MODE = RETURNING {\n  MODE = ACTIVE\n  RETURN = true\n}\nSURVEYING\n\
         set MODE = IDLE\n{\n  MODE = INACTIVE\n}\n\n\
         set LVL = HIGH {\n  X > 1\n}\nBehavior = BHV_W\n{\n}\n",
    );
    let e = s.modes.entries();
    assert_eq!(e.len(), 4);
    assert_eq!(
        (e[0].var(), e[0].value(), e[0].else_value(), e[0].prefix()),
        ("MODE", "ACTIVE", Some("INACTIVE"), None)
    );
    assert_eq!(
        (e[1].value(), e[1].else_value(), e[1].prefix()),
        ("RETURNING", Some("SURVEYING"), Some("ACTIVE"))
    );
    assert_eq!(e[1].conditions().len(), 2);
    assert_eq!((e[2].else_value(), e[2].prefix()), (None, Some("INACTIVE")));
    assert_eq!((e[3].var(), e[3].else_value()), ("LVL", None));
    assert_eq!(s.behaviors.len(), 1);
    assert_eq!(
        s.modes.modeset_string(),
        "MODE#---,ACTIVE#---,INACTIVE#ACTIVE,RETURNING#ACTIVE,SURVEYING#INACTIVE,IDLE#LVL#---,HIGH"
    );
}

#[test]
fn set_block_example_evaluates() {
    let mut s = parse(
        "initialize DEPLOY = false\ninitialize RETURN = false\nset MODE = ACTIVE {\n  \
         DEPLOY = true\n} INACTIVE\nset MODE = RETURNING {\n  MODE = ACTIVE\n  RETURN = true\n} SURVEYING\n",
    );
    assert_eq!(
        s.modes.modeset_string(),
        "MODE#---,ACTIVE#---,INACTIVE#ACTIVE,RETURNING#ACTIVE,SURVEYING"
    );
    let mut info = std::collections::HashMap::new();
    info.insert("DEPLOY".to_string(), Value::Str("true".into()));
    info.insert("RETURN".to_string(), Value::Str("false".into()));
    let out = s.modes.evaluate(&info).to_vec();
    assert_eq!(out, [("MODE".to_string(), "ACTIVE:SURVEYING".to_string())]);
    assert_eq!(s.modes.vars(), ["DEPLOY", "MODE", "RETURN"]);
}

#[test]
fn set_block_errors() {
    for (t, line, shown) in [
        ("set = X\n{\n}\n", 1, "set = X"),
        ("set M =\n{\n}\n", 1, "set M ="),
        ("set M X\n{\n}\n", 1, "set M X"),
        ("set M = X\n{\n  A == 1\n}\n", 3, "A == 1"),
        (
            "set M = X\n{\n  (A=1) and (B=2) and (C=3)\n}\n",
            3,
            "(A=1) and (B=2) and (C=3)",
        ),
        ("set M = X\n{\n  A\n}\n", 3, "A"),
        ("set M = X\n{\n  A = 1\n} TWO WORDS\n", 4, "TWO WORDS"),
        ("set M = X\n{\n  A = 1\n}\nTWO WORDS\n", 5, "TWO WORDS"),
        // a blank line ends the entry: the word after it is free text
        ("set M = X\n{\n  A = 1\n}\n\nELSE\n", 6, "ELSE"),
    ] {
        let e = fail(t);
        assert_eq!((e.line, e.text.as_str()), (line, shown), "{t:?}: {e}");
    }
    assert!(matches!(
        fail("set M = X\n{\n  A == 1\n}\n").kind,
        BhvErrorKind::BadCondition(_)
    ));
}

#[test]
fn set_entry_pending_until_finished() {
    // no newline after `}`: the entry stays pending and is never stored
    let s = parse("set M = X {\n A = 1\n}");
    assert!(s.modes.is_empty());
    let s = parse("set M = X {\n A = 1\n}\n");
    assert_eq!(s.modes.entries().len(), 1);
    // a blank-containing variable is silently not stored (§6.1 quirk)
    let s = parse("set M N = X {\n A = 1\n}\n");
    assert!(s.modes.is_empty());
}

#[test]
fn unclosed_blocks_are_errors() {
    for (t, line) in [
        ("\nBehavior = BHV_W\n{\n speed = 1\n", 2),
        ("Behavior = BHV_W\n", 1),
        ("set M = X\n{\n", 1),
        ("{\n", 1),
    ] {
        let e = fail(t);
        assert!(matches!(e.kind, BhvErrorKind::UnclosedBlock(_)), "{t:?}");
        assert_eq!(e.line, line, "{t:?}");
    }
}

fn tmp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("bhv-reader-{}-{tag}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap_or_else(|e| panic!("{e}"));
    d
}

#[test]
fn read_files_sorted_dedup_state_carried() {
    let d = tmp_dir("multi");
    let (a, b) = (d.join("a.bhv"), d.join("b.bhv"));
    // b is named first, but a is read first; the set entry of a (no final
    // newline) is finished by b's first blank line.
    std::fs::write(&b, "\ninitialize B = 2\n").unwrap_or_else(|e| panic!("{e}"));
    std::fs::write(&a, "initialize A = 1\nset M = X {\n A = 1\n}")
        .unwrap_or_else(|e| panic!("{e}"));
    let s = read_files(&[b.clone(), a.clone(), b.clone()]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.files, [a.clone(), b.clone()]);
    let vars: Vec<&str> = s.inits.iter().map(|i| i.var.as_str()).collect();
    assert_eq!(vars, ["A", "B"]);
    assert_eq!(s.inits[1].file, b);
    assert_eq!(s.modes.entries().len(), 1);
    // a block may even continue across files
    let (c, e) = (d.join("c.bhv"), d.join("e.bhv"));
    std::fs::write(&c, "Behavior = BHV_W\n{\n").unwrap_or_else(|e| panic!("{e}"));
    std::fs::write(&e, "speed = 1\n}\n").unwrap_or_else(|e| panic!("{e}"));
    let s = read_files(&[e.clone(), c.clone()]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.behaviors[0].lines[0].line, 1);
    assert_eq!(s.behaviors[0].file, c);
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn read_files_bytewise_order() {
    let d = tmp_dir("order");
    let (p1, p2) = (d.join("Z.bhv"), d.join("a.bhv"));
    std::fs::write(&p1, "initialize Z = 1\n").unwrap_or_else(|e| panic!("{e}"));
    std::fs::write(&p2, "initialize A = 1\n").unwrap_or_else(|e| panic!("{e}"));
    let s = read_files(&[p2.clone(), p1.clone()]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.inits[0].var, "Z", "upper case sorts first byte-wise");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn missing_file() {
    let d = tmp_dir("missing");
    let good = d.join("good.bhv");
    std::fs::write(&good, BLOCK).unwrap_or_else(|e| panic!("{e}"));
    let missing = d.join("nope.bhv");
    let e = read_files(&[missing.clone(), good]).unwrap_err();
    assert!(matches!(e.kind, BhvErrorKind::FileNotFound(_)));
    assert_eq!(e.file, missing);
    assert!(e
        .to_string()
        .starts_with(&format!("Could not find File: {}", missing.display())));
    assert_eq!(
        e.helm_warnings(),
        [format!("Could not find File: {}", missing.display())]
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn syntax_error_names_its_file() {
    let d = tmp_dir("errfile");
    let (a, b) = (d.join("a.bhv"), d.join("b.bhv"));
    std::fs::write(&a, BLOCK).unwrap_or_else(|e| panic!("{e}"));
    std::fs::write(&b, "\n\noops\n").unwrap_or_else(|e| panic!("{e}"));
    let e = read_files(&[a, b.clone()]).unwrap_err();
    assert_eq!((e.file, e.line), (b, 3));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn crlf_lines() {
    let s = parse("initialize A = x\r\nBehavior = BHV_W\r\n{\r\n speed = 2\r\n}\r\n");
    assert_eq!(s.inits[0].value, Value::Str("x".into()));
    assert_eq!(s.behaviors[0].lines[0].value, "2");
}

#[test]
fn parses_real_example() {
    let s = parse(
        "initialize   DEPLOY = false\ninitialize   RETURN = false\n\nset MODE = ACTIVE {\n  \
         DEPLOY = true\n} INACTIVE\n\nset MODE = SURVEYING {\n  MODE = ACTIVE\n  RETURN != true\n} \
         RETURNING\n\nBehavior = BHV_Waypoint\n{\n  name      = waypt_survey\n  condition = MODE == \
         SURVEYING\n}\n",
    );
    assert_eq!(s.modes.entries().len(), 2);
    assert_eq!(s.behaviors[0].lines[1].value, "MODE == SURVEYING");
}

proptest::proptest! {
    #[test]
    fn reader_never_panics(t in "[a-zA-Z_ =\\{\\}/#\\\\\n\"(),:!<>0-9]{0,80}") {
        let _ = parse_str(&t, Path::new("p.bhv"));
    }

    #[test]
    fn keyword_case_insensitive(kw in "[iI][nN][iI][tT][iI][aA][lL][iI][zZ][eE]") {
        let s = parse_str(&format!("{kw} A = 1\n"), Path::new("p.bhv"));
        proptest::prop_assert!(s.is_ok());
        if let Ok(s) = s {
            proptest::prop_assert!(!s.inits[0].deferred);
        }
    }
}

proptest::proptest! {
    #[test]
    fn arbitrary_text_never_panics(t in "(.|\n|[{}=()#\\\\/ ]){0,60}") {
        let _ = parse_str(&t, Path::new("p.bhv"));
        let _ = crate::logic::LogicCondition::parse(&t);
        let _ = crate::flag::parse_flag(&t);
    }
}

#[test]
fn invalid_utf8_names_the_joined_line() {
    let dir = std::env::temp_dir().join(format!("bhv-utf8-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("bad.bhv");
    let mut bytes = b"initialize A = 1\nBehavior = BHV_W\n{\n  points = 0,0 : \\\n  1,1\n  name = x\xff\xfey\n}\n".to_vec();
    std::fs::write(&f, &bytes).unwrap();
    let e = read_files(std::slice::from_ref(&f)).unwrap_err();
    assert!(matches!(e.kind, BhvErrorKind::InvalidUtf8(_)), "{e}");
    // Physical line 6, joined line 5 (lines 4 and 5 are one).
    assert_eq!(e.line, 5, "{e}");
    assert_eq!(e.text, "name = x\u{fffd}\u{fffd}y");
    let msg = e.to_string();
    assert!(
        msg.starts_with(&format!("{}:5: invalid UTF-8", f.display())),
        "{msg}"
    );
    assert!(!msg.contains('\n'));
    // Too large: refused without reading it all.
    bytes.resize(MAX_FILE_BYTES as usize + 10, b'\n');
    std::fs::write(&f, &bytes).unwrap();
    let e = read_files(std::slice::from_ref(&f)).unwrap_err();
    assert!(matches!(e.kind, BhvErrorKind::TooLarge { .. }), "{e}");
    assert!(e.to_string().contains("larger than"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}
