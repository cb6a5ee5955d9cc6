//! The mission's buttons, as pMarineViewer's `ProcessConfig = pMarineViewer` block
//! defines them: `button_one = DEPLOY # DEPLOY=true # MOOS_MANUAL_OVERRIDE=false`. The
//! first field, when it holds no `=`, is the label; the rest are `VAR=value` postings
//! (split at the first `=`, so `WPT_UPDATE=speed=1.5` posts `speed=1.5`). A second line
//! with the same name adds postings to the same button. These postings are all the page
//! can ever ask the viewer to make.

use serde::Serialize;

/// One posting of a button.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Posting {
    pub var: String,
    pub value: String,
    /// Posted as a double (the value is a number), else as a string.
    pub numeric: bool,
}

/// One button.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Button {
    /// `button_one`, ...
    pub name: String,
    pub label: String,
    pub postings: Vec<Posting>,
}

/// Buttons from `(name, value)` lines of the pMarineViewer block, in order of first
/// appearance; lines not named `button_*` are ignored, buttons without a posting dropped.
///
/// ```
/// let b = viewer::buttons::read_buttons([
///     ("button_one", "DEPLOY # DEPLOY=true"),
///     ("button_one", "MOOS_MANUAL_OVERRIDE=false # RETURN=false"),
///     ("scope", "NODE_REPORT"),
/// ]);
/// assert_eq!(b.len(), 1);
/// assert_eq!(b[0].label, "DEPLOY");
/// assert_eq!(b[0].postings.len(), 3);
/// ```
pub fn read_buttons<'a>(lines: impl IntoIterator<Item = (&'a str, &'a str)>) -> Vec<Button> {
    let mut out: Vec<Button> = Vec::new();
    for (name, value) in lines {
        let name = name.trim().to_ascii_lowercase();
        if !name.starts_with("button_") {
            continue;
        }
        let i = match out.iter().position(|b| b.name == name) {
            Some(i) => i,
            None => {
                out.push(Button {
                    label: name.clone(),
                    name: name.clone(),
                    postings: Vec::new(),
                });
                out.len() - 1
            }
        };
        let b = &mut out[i];
        for (k, field) in value.split('#').enumerate() {
            let field = field.trim();
            match field.split_once('=') {
                Some((var, val)) if !var.trim().is_empty() => {
                    let val = mbutil::strip_quotes(val.trim()).to_owned();
                    b.postings.push(Posting {
                        var: var.trim().to_owned(),
                        numeric: mbutil::is_number(&val),
                        value: val,
                    });
                }
                None if k == 0 && !field.is_empty() => b.label = field.to_owned(),
                _ => {}
            }
        }
    }
    out.retain(|b| !b.postings.is_empty());
    out
}

/// The buttons of a mission file's pMarineViewer block (none without one).
pub fn mission_buttons(m: &moos::MissionFile) -> Vec<Button> {
    let lines = m.process_config("pMarineViewer").unwrap_or_default();
    read_buttons(lines.iter().map(|l| (l.name.as_str(), l.value.as_str())))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_postings_and_numbers() {
        let b = read_buttons([
            ("BUTTON_TWO", "RETURN # RETURN=true"),
            ("button_three", "SLOWER # WPT_UPDATE=speed=1.5 # SPEED=1.5"),
            ("button_four", "   "),
            ("button_five", "HALT # "),
        ]);
        assert_eq!(b.len(), 2);
        assert_eq!(
            (b[0].name.as_str(), b[0].label.as_str()),
            ("button_two", "RETURN")
        );
        assert_eq!(
            b[1].postings,
            [
                Posting {
                    var: "WPT_UPDATE".into(),
                    value: "speed=1.5".into(),
                    numeric: false
                },
                Posting {
                    var: "SPEED".into(),
                    value: "1.5".into(),
                    numeric: true
                }
            ]
        );
    }
}
