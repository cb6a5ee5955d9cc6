//! The drawing surface the pictures share: the SVG size, the margin, the world-to-screen
//! mapping with equal scales, and small text helpers.

use std::fmt::Write as _;

pub const W: f64 = 900.0;
pub const H: f64 = 700.0;
/// Margin around the drawing; the legend and the title live in it.
pub const MARGIN: f64 = 60.0;

/// World box → screen mapping (equal scales, y up).
pub struct View {
    x0: f64,
    y1: f64,
    pub scale: f64,
    ox: f64,
    oy: f64,
}

impl View {
    pub fn fit(pts: &[(f64, f64)]) -> View {
        let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for &(x, y) in pts {
            x0 = x0.min(x);
            x1 = x1.max(x);
            y0 = y0.min(y);
            y1 = y1.max(y);
        }
        if x0 > x1 {
            (x0, x1, y0, y1) = (-10.0, 10.0, -10.0, 10.0);
        }
        // At least 20 m across, and a 5% border.
        let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
        let half_w = ((x1 - x0) / 2.0).max(10.0) * 1.05;
        let half_h = ((y1 - y0) / 2.0).max(10.0) * 1.05;
        let (aw, ah) = (W - 2.0 * MARGIN - 170.0, H - 2.0 * MARGIN);
        let scale = (aw / (2.0 * half_w)).min(ah / (2.0 * half_h));
        let (x0, y1) = (cx - half_w, cy + half_h);
        // Centre the drawing in the area left of the legend.
        let ox = MARGIN + (aw - 2.0 * half_w * scale) / 2.0;
        let oy = MARGIN + (ah - 2.0 * half_h * scale) / 2.0;
        View {
            x0,
            y1,
            scale,
            ox,
            oy,
        }
    }

    /// The world point at screen point `(px, py)`.
    pub fn world(&self, px: f64, py: f64) -> (f64, f64) {
        (
            self.x0 + (px - self.ox) / self.scale,
            self.y1 - (py - self.oy) / self.scale,
        )
    }

    pub fn p(&self, x: f64, y: f64) -> (f64, f64) {
        (
            self.ox + (x - self.x0) * self.scale,
            self.oy + (self.y1 - y) * self.scale,
        )
    }
}

pub fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

pub fn poly_points(v: &View, pts: &[(f64, f64)]) -> String {
    let mut s = String::new();
    for &(x, y) in pts {
        let (px, py) = v.p(x, y);
        let _ = write!(s, "{px:.1},{py:.1} ");
    }
    s
}

/// A round scale-bar length near a fifth of the drawing width (m).
pub fn nice_length(width_m: f64) -> f64 {
    let target = (width_m / 5.0).max(1.0);
    let p = 10f64.powf(target.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * p)
        .rfind(|l| *l <= target)
        .unwrap_or(p)
}

/// The scale bar, bottom left: a round length ([`nice_length`]) of the drawing's width
/// at `v`'s scale, with its ticks and its length in metres.
pub fn scale_bar(s: &mut String, v: &View) {
    let width_m = (W - 2.0 * MARGIN - 170.0) / v.scale;
    let len = nice_length(width_m);
    let (bx, by) = (MARGIN, H - 25.0);
    let bw = len * v.scale;
    let _ = writeln!(
        s,
        r##"<path d="M{bx},{by} h{bw:.1} M{bx},{:.1} v10 M{:.1},{:.1} v10" stroke="#222" stroke-width="2"/><text x="{:.1}" y="{:.1}" font-size="12" fill="#222">{len} m</text>"##,
        by - 5.0,
        bx + bw,
        by - 5.0,
        bx + bw + 8.0,
        by + 4.0
    );
}

/// The halo (outline, SVG attributes) that keeps a label in `color` legible over
/// anything: 3 px of white, or a thin dark grey outline when the text itself is light
/// (white, yellow, a `light…` or `pale…` name, a hex colour of luminance above 0.8). A
/// white halo around white or yellow text would blot out the picture and leave the text
/// unreadable; a 3 px dark one makes small text a smudge.
pub fn halo(color: &str) -> &'static str {
    const LIGHT: &[&str] = &[
        "white",
        "yellow",
        "ivory",
        "snow",
        "azure",
        "beige",
        "linen",
        "seashell",
        "honeydew",
        "mintcream",
        "aliceblue",
        "cornsilk",
        "oldlace",
        "wheat",
        "khaki",
        "gold",
        "lime",
        "cyan",
        "aqua",
        "aquamarine",
        "chartreuse",
        "greenyellow",
        "lawngreen",
        "gainsboro",
        "lavenderblush",
        "lemonchiffon",
        "papayawhip",
        "blanchedalmond",
        "moccasin",
        "bisque",
        "mistyrose",
        "floralwhite",
        "ghostwhite",
        "whitesmoke",
    ];
    let c = color.trim().to_ascii_lowercase();
    let light = if let Some(hex) = c.strip_prefix('#').filter(|h| h.len() == 6) {
        let ch =
            |i: usize| u8::from_str_radix(&hex[i..i + 2], 16).map_or(0.0, |v| v as f64 / 255.0);
        0.2126 * ch(0) + 0.7152 * ch(2) + 0.0722 * ch(4) > 0.8
    } else {
        LIGHT.contains(&c.as_str()) || c.starts_with("light") || c.starts_with("pale")
    };
    if light {
        r##"stroke="#333" stroke-width="1.2" paint-order="stroke""##
    } else {
        r##"stroke="#fff" stroke-width="3" paint-order="stroke""##
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn scale_bar_lengths_are_round() {
        assert_eq!(super::nice_length(230.0), 20.0);
        assert_eq!(super::nice_length(1000.0), 200.0);
        assert_eq!(super::nice_length(3.0), 1.0);
    }

    #[test]
    fn light_text_gets_a_dark_halo() {
        for light in ["white", "yellow", "lightblue", "#ffff80", "#FFFFFF"] {
            assert!(super::halo(light).contains("#333"), "{light}");
        }
        for dark in ["dodgerblue", "#c0392b", "#b8b8b8", "orangered"] {
            assert!(super::halo(dark).contains("#fff"), "{dark}");
        }
    }
}
