//! The attribute setter shared by every format (geometry-formats.md §3.1).

use crate::spec::{is_color, Attrs};
use crate::text::atof;

impl Attrs {
    /// `setAttr(key, value)` of the real objects: `key` is compared as given (the caller
    /// decides on lower-casing). Returns whether the key was handled. Numbers are read
    /// with `atof` (no check); a colour the colour parser rejects is dropped (§3.2).
    pub fn set_attr(&mut self, key: &str, value: &str) -> bool {
        match key {
            "label" => self.label = value.to_string(),
            "msg" => self.msg = value.to_string(),
            "id" => self.id = value.to_string(),
            "source" => self.source = value.to_string(),
            "vsource" => self.vsource = value.to_string(),
            // Stored by the real objects but never printed: nothing observable to keep.
            "type" => {}
            "vertex_size" | "edge_size" => {
                let v = atof(value);
                if v >= 0.0 {
                    if key == "vertex_size" {
                        self.vertex_size = Some(v);
                    } else {
                        self.edge_size = Some(v);
                    }
                }
            }
            "vertex_color" | "edge_color" | "label_color" | "fill_color" => {
                if let Some(c) = color_value(value) {
                    match key {
                        "vertex_color" => self.vertex_color = c,
                        "edge_color" => self.edge_color = c,
                        "label_color" => self.label_color = c,
                        _ => self.fill_color = c,
                    }
                }
            }
            "time" => self.time = Some(atof(value)),
            "duration" | "dur" => {
                let d = atof(value);
                self.duration = Some(if d < 0.0 { -1.0 } else { d });
            }
            "fill_transparency" => self.fill_transparency = Some(atof(value).clamp(0.0, 1.0)),
            "active" => match value.to_ascii_lowercase().as_str() {
                // Active is the default and is not printed; only inactive is remembered.
                "true" => self.active = None,
                "false" => self.active = Some(false),
                _ => return false,
            },
            _ => return false,
        }
        true
    }
}

/// A colour as printed back: the three "invisible" spellings print `invisible` (their
/// capitalised forms too: undefined in C++, §3.2 allows this), other accepted colours
/// print as given, unrecognised ones are dropped.
fn color_value(value: &str) -> Option<String> {
    match value.to_ascii_lowercase().as_str() {
        "invisible" | "empty" | "off" => Some("invisible".to_string()),
        _ => is_color(value).then(|| value.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn set_attr_is_the_real_setter() {
        let mut a = Attrs::default();
        assert!(a.set_attr("edge_color", "Invisible"));
        assert!(a.set_attr("vertex_color", "off"));
        assert!(a.set_attr("label_color", "notacolor"));
        assert!(a.set_attr("fill_color", "DarkKhaki"));
        assert!(a.set_attr("vertex_size", "-2"));
        assert!(a.set_attr("edge_size", "abc"));
        assert!(a.set_attr("dur", "-5"));
        assert!(a.set_attr("fill_transparency", "3"));
        assert!(a.set_attr("type", "anything"));
        assert!(!a.set_attr("active", "yes"));
        assert!(!a.set_attr("LABEL", "x"), "keys are case-sensitive");
        assert!(!a.set_attr("snap", "1"));
        assert_eq!(
            a.spec(),
            ",edge_color=invisible,vertex_color=invisible,fill_color=DarkKhaki,duration=-1,edge_size=0,fill_transparency=1"
        );
        assert!(a.set_attr("active", "FALSE"));
        assert_eq!(a.active, Some(false));
        assert!(a.set_attr("active", "true"));
        assert_eq!(a.active, None, "active is the default and is not printed");
    }
}
