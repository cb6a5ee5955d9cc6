//! The `_into` context forms (0.1.2) give what the returning forms give, written into the
//! caller's string, whose storage they keep.

use behavior_api::testing::MockHelm;

#[test]
fn into_forms_match_the_returning_forms_and_keep_the_storage() {
    let mut helm = MockHelm::new("avd_abe");
    helm.contact("abe", 10.0, 20.0, 90.0, 1.0, "kayak");
    helm.strs.insert("MODE".into(), "SURVEYING".into());
    helm.with(|ctx| {
        let mut out = String::with_capacity(64);
        let storage = out.as_ptr();
        // The returning form's answer, then the `_into` form's over a stale text.
        let mut check = |what: &str, want: String, into: &dyn Fn(&mut String)| {
            out.push_str("left over");
            into(&mut out);
            assert_eq!(out, want, "{what}");
            assert_eq!(out.as_ptr(), storage, "{what}: storage kept");
        };
        check("name", ctx.name(), &|o| ctx.name_into(o));
        check("ownship", ctx.ownship(), &|o| ctx.ownship_into(o));
        check("type", ctx.contact_text("abe", "type"), &|o| {
            ctx.contact_text_into("abe", "type", o)
        });
        check("unknown contact", ctx.contact_text("zed", "type"), &|o| {
            ctx.contact_text_into("zed", "type", o)
        });
        let mut name = String::from("stale");
        assert!(ctx.contact_name_into(0, &mut name));
        assert_eq!(name, "abe");
        assert!(!ctx.contact_name_into(1, &mut name));
        assert_eq!(name, "");
    });
    helm.with(|ctx| {
        let mut out = String::from("stale");
        assert!(ctx.get_buffer_string_val_quiet_into("MODE", &mut out));
        assert_eq!(out, "SURVEYING");
        assert!(!ctx.get_buffer_string_val_quiet_into("NOPE", &mut out));
        assert_eq!(out, "");
        assert!(!ctx.get_buffer_string_val_into("NOPE", &mut out));
    });
}
