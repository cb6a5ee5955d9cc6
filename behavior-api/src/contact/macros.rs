//! The contact behaviors' flag macros (contacts-appcast.md §3.7) and the life-event
//! post-mortem.

use super::ContactBase;
use crate::compact;
use crate::flag::{expand_macros, has_macro};
use crate::geometry::rel_ang;

/// The macro the helm expands on a behavior's death for the life event's
/// `post_mortem=` field (empty: none).
pub const POST_MORTEM_MACRO: &str = "$[BHV_POST_MORTEM]";

fn tf(b: bool) -> String {
    if b { "true" } else { "false" }.to_string()
}

impl ContactBase {
    /// The completion post-mortem: `rng=<range>#bng=<bearing ownship→contact>`, one
    /// decimal, trailing zeros removed (contacts-appcast.md §3.7).
    pub fn post_mortem(&self) -> String {
        let bng = rel_ang(self.os.x, self.os.y, self.cn.x, self.cn.y);
        format!("rng={}#bng={}", compact(self.range(), 1), compact(bng, 1))
    }

    /// Expand `$[CONTACT]`, the `CN_*` / `OS_*` macros and the post-mortem in `text`;
    /// `None` when nothing changed.
    pub fn expand_macros(&self, text: &str) -> Option<String> {
        if !has_macro(text) {
            return None;
        }
        if text == POST_MORTEM_MACRO {
            return Some(self.post_mortem());
        }
        let n1 = |v: f64| compact(v, 1);
        let mut subs: Vec<(&str, String)> = vec![
            ("CONTACT", self.contact.clone()),
            ("CNX", n1(self.cn.x)),
            ("CNY", n1(self.cn.y)),
            ("CNH", n1(self.cn.hdg)),
            ("CNV", n1(self.cn.spd)),
            ("CN_NAME", self.contact.clone()),
            ("CN_VTYPE", self.cn_type.clone()),
            ("CN_GROUP", self.cn_group.clone()),
        ];
        if let Some(r) = self.relation() {
            subs.extend([
                ("CN_RANGE", n1(r.range)),
                ("RANGE", n1(r.range)),
                ("ROC", n1(r.rate_of_closure)),
                ("OS_CN_REL_BNG", n1(r.os_cn_rel_bng)),
                ("CN_OS_REL_BNG", n1(r.cn_os_rel_bng)),
                ("BNG_RATE", n1(r.bearing_rate)),
                ("CN_SPD_IN_OS_POS", n1(r.cn_spd_in_os_pos)),
                ("OS_FORE_OF_CN", tf(r.os_fore_of_cn)),
                ("OS_AFT_OF_CN", tf(r.os_aft_of_cn)),
                ("OS_PORT_OF_CN", tf(r.os_port_of_cn)),
                ("OS_STAR_OF_CN", tf(r.os_star_of_cn)),
                ("CN_FORE_OF_OS", tf(r.cn_fore_of_os)),
                ("CN_AFT_OF_OS", tf(r.cn_aft_of_os)),
                ("CN_PORT_OF_OS", tf(r.cn_port_of_os)),
                ("CN_STAR_OF_OS", tf(r.cn_star_of_os)),
            ]);
        }
        let out = expand_macros(text, &subs);
        (out != text).then_some(out)
    }

    /// `$[CONTACT]` in a condition: upper-cased name; `$[contact]` lower-cased;
    /// `$[Contact]` as is (contacts-appcast.md §3.7).
    pub fn condition_text(&self, cond: &str) -> String {
        cond.replace("$[CONTACT]", &self.contact.to_ascii_uppercase())
            .replace("$[contact]", &self.contact.to_ascii_lowercase())
            .replace("$[Contact]", &self.contact)
    }
}
