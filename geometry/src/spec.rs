//! Output spec formatting for VIEW_* postings (behaviors-std.md §1.5).

/// The compact number formatter (§1.5): printf `%.<d>f`, then trailing zeros and a
/// trailing `.` stripped; `-0` becomes `0`. One function with `bhv::number::compact`:
/// both are `mbutil::compact`.
pub use mbutil::compact as fmt_x;

/// True if `s` is a colour: the one colour parser shared by every behavior and every
/// VIEW_* attribute (`mbutil::color`).
pub fn is_color(s: &str) -> bool {
    mbutil::is_color(s)
}

/// Attributes of a visual object, printed in the fixed order of §1.5.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Attrs {
    pub active: Option<bool>,
    pub label: String,
    pub msg: String,
    pub source: String,
    pub vsource: String,
    pub id: String,
    pub label_color: String,
    pub edge_color: String,
    pub vertex_color: String,
    pub fill_color: String,
    pub time: Option<f64>,
    pub duration: Option<f64>,
    pub vertex_size: Option<f64>,
    pub edge_size: Option<f64>,
    pub fill_transparency: Option<f64>,
}

impl Attrs {
    /// Set one attribute from a `key=value` field of a spec string. Returns false if the
    /// key is not an attribute or the value is malformed. Unknown colors are ignored.
    pub fn set(&mut self, key: &str, value: &str) -> bool {
        let value = value.trim();
        let num = || value.parse::<f64>().ok().filter(|v| v.is_finite());
        match key.trim().to_ascii_lowercase().as_str() {
            "active" => match value.to_ascii_lowercase().as_str() {
                "true" => self.active = Some(true),
                "false" => self.active = Some(false),
                _ => return false,
            },
            "label" => self.label = value.to_string(),
            "msg" => self.msg = value.to_string(),
            "source" => self.source = value.to_string(),
            "vsource" => self.vsource = value.to_string(),
            "id" => self.id = value.to_string(),
            "label_color" => self.set_color_field(0, value),
            "edge_color" => self.set_color_field(1, value),
            "vertex_color" => self.set_color_field(2, value),
            "fill_color" => self.set_color_field(3, value),
            "time" => match num() {
                Some(v) => self.time = Some(v),
                None => return false,
            },
            "duration" => match num() {
                Some(v) => self.duration = Some(v),
                None => return false,
            },
            "vertex_size" => match num() {
                Some(v) => self.vertex_size = Some(v),
                None => return false,
            },
            "edge_size" => match num() {
                Some(v) => self.edge_size = Some(v),
                None => return false,
            },
            "fill_transparency" => match num() {
                Some(v) => self.fill_transparency = Some(v),
                None => return false,
            },
            _ => return false,
        }
        true
    }

    fn set_color_field(&mut self, which: u8, value: &str) {
        if !is_color(value) {
            return;
        }
        let v = value.to_string();
        match which {
            0 => self.label_color = v,
            1 => self.edge_color = v,
            2 => self.vertex_color = v,
            _ => self.fill_color = v,
        }
    }

    /// The attributes as `,key=value` fields (leading comma included for each).
    pub fn spec(&self) -> String {
        let mut s = String::with_capacity(96);
        self.push_spec(&mut s);
        s
    }

    /// [`Attrs::spec`] appended to `out` (behaviors post these every iteration: no
    /// string of their own, no formatter).
    pub fn push_spec(&self, out: &mut String) {
        if let Some(a) = self.active {
            out.push_str(if a { ",active=true" } else { ",active=false" });
        }
        let strs = [
            ("label", &self.label),
            ("msg", &self.msg),
            ("source", &self.source),
            ("vsource", &self.vsource),
            ("id", &self.id),
            ("label_color", &self.label_color),
            ("edge_color", &self.edge_color),
            ("vertex_color", &self.vertex_color),
            ("fill_color", &self.fill_color),
        ];
        for (k, v) in strs {
            if !v.is_empty() {
                push_field(out, k, v);
            }
        }
        let nums = [
            ("time", self.time, 2),
            ("duration", self.duration, 2),
            ("vertex_size", self.vertex_size, 1),
            ("edge_size", self.edge_size, 1),
            ("fill_transparency", self.fill_transparency, 2),
        ];
        for (k, v, decimals) in nums {
            if let Some(v) = v {
                out.push(',');
                out.push_str(k);
                out.push('=');
                mbutil::push_compact(out, v, decimals);
            }
        }
    }
}

/// `,key=value` appended.
fn push_field(out: &mut String, key: &str, value: &str) {
    out.push(',');
    out.push_str(key);
    out.push('=');
    out.push_str(value);
}

/// A vertex (x, y, optional z).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vertex {
    pub x: f64,
    pub y: f64,
    pub z: Option<f64>,
}

impl Vertex {
    pub fn new(x: f64, y: f64) -> Self {
        Vertex { x, y, z: None }
    }
}

/// `x=..,y=..[,z=..]` (2 decimals compact) then the attributes.
pub fn point_spec(x: f64, y: f64, z: Option<f64>, attrs: &Attrs) -> String {
    // Room for the usual spec at once (growing it step by step reallocates 4 times).
    let mut s = String::with_capacity(128);
    push_point_spec(&mut s, x, y, z, attrs);
    s
}

/// [`point_spec`] appended to `out`.
pub fn push_point_spec(out: &mut String, x: f64, y: f64, z: Option<f64>, attrs: &Attrs) {
    out.push_str("x=");
    mbutil::push_compact(out, x, 2);
    out.push_str(",y=");
    mbutil::push_compact(out, y, 2);
    if let Some(z) = z {
        out.push_str(",z=");
        mbutil::push_compact(out, z, 2);
    }
    attrs.push_spec(out);
}

/// Inactive point used to erase a drawn point: `x=0,y=0,active=false[,label=L]`.
pub fn point_erase_spec(label: &str) -> String {
    let mut s = String::with_capacity(32 + label.len());
    s.push_str("x=0,y=0,active=false");
    if !label.is_empty() {
        push_field(&mut s, "label", label);
    }
    s
}

/// `pts={x,y:x,y:...}` with `precision` decimals (compact); z only when not 0.
pub fn pts_spec(pts: &[Vertex], precision: usize) -> String {
    pts_props_spec(pts, &[], precision)
}

/// [`pts_spec`] with per-vertex properties (`props` empty, or one per vertex): a vertex
/// with a property prints `x,y,z,property` even when z is 0 (geometry-formats.md §3.6).
pub fn pts_props_spec(pts: &[Vertex], props: &[String], precision: usize) -> String {
    let mut s = String::new();
    push_pts_props_spec(&mut s, pts, props, precision);
    s
}

/// [`pts_props_spec`] appended to `out`.
pub fn push_pts_props_spec(out: &mut String, pts: &[Vertex], props: &[String], precision: usize) {
    out.push_str("pts={");
    for (i, p) in pts.iter().enumerate() {
        if i > 0 {
            out.push(':');
        }
        mbutil::push_compact(out, p.x, precision);
        out.push(',');
        mbutil::push_compact(out, p.y, precision);
        let prop = props.get(i).map_or("", String::as_str);
        let z = p.z.unwrap_or(0.0);
        if z != 0.0 || !prop.is_empty() {
            out.push(',');
            mbutil::push_compact(out, z, precision);
        }
        if !prop.is_empty() {
            out.push(',');
            out.push_str(prop);
        }
    }
    out.push('}');
}

/// An edge tag of a seglist: the edge from vertex `from` to vertex `to` is tagged `tag`
/// (the lawnmower tags each lane `lane`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EdgeTag {
    pub from: usize,
    pub to: usize,
    pub tag: String,
}

/// The full printed form of a seglist or polygon (geometry-formats.md §3.6): vertices
/// (only if any), edge tags (only if any), then the attributes; precision clipped to 6.
pub fn object_spec(
    pts: &[Vertex],
    props: &[String],
    tags: &[EdgeTag],
    attrs: &Attrs,
    precision: usize,
) -> String {
    let precision = precision.min(6);
    let mut s = String::new();
    if !pts.is_empty() {
        s.push_str(&pts_props_spec(pts, props, precision));
    }
    if !tags.is_empty() {
        let t: Vec<String> = tags
            .iter()
            .map(|t| format!("{}:{}:{}", t.from, t.to, t.tag))
            .collect();
        if !s.is_empty() {
            s.push(',');
        }
        s.push_str(&format!("tags={{{}}}", t.join("#")));
    }
    let a = attrs.spec();
    if s.is_empty() {
        s.push_str(a.strip_prefix(',').unwrap_or(&a));
    } else {
        s.push_str(&a);
    }
    s
}

/// Seglist or polygon spec: the vertices then the attributes.
/// Remembers the last seglist spec built, so a path that does not change (most
/// iterations) is not formatted again.
#[derive(Clone, Debug, Default)]
pub struct SeglistSpecCache {
    pts: Vec<Vertex>,
    tags: Vec<EdgeTag>,
    precision: usize,
    attrs: Attrs,
    spec: String,
}

/// `a == b`, the texts compared in place (`mbutil::short_str`): the derived compare
/// calls `memcmp` for each of the nine, empty ones too, at every view a behavior posts.
/// (`a` taken apart whole: a new field must be added here to compile.)
fn same_attrs(a: &Attrs, b: &Attrs) -> bool {
    use mbutil::short_str::same;
    let Attrs {
        active,
        label,
        msg,
        source,
        vsource,
        id,
        label_color,
        edge_color,
        vertex_color,
        fill_color,
        time,
        duration,
        vertex_size,
        edge_size,
        fill_transparency,
    } = a;
    *active == b.active
        && same(label, &b.label)
        && same(msg, &b.msg)
        && same(source, &b.source)
        && same(vsource, &b.vsource)
        && same(id, &b.id)
        && same(label_color, &b.label_color)
        && same(edge_color, &b.edge_color)
        && same(vertex_color, &b.vertex_color)
        && same(fill_color, &b.fill_color)
        && *time == b.time
        && *duration == b.duration
        && *vertex_size == b.vertex_size
        && *edge_size == b.edge_size
        && *fill_transparency == b.fill_transparency
}

impl SeglistSpecCache {
    /// [`seglist_spec`] of these inputs, built only when they differ from the last call.
    pub fn get(&mut self, pts: &[Vertex], precision: usize, attrs: &Attrs) -> &str {
        self.get_tagged(pts, &[], precision, attrs)
    }

    /// [`seglist_spec`] with the edge tags after the vertices (`tags={…}`, §3.6 of
    /// geometry-formats.md), built only when the inputs differ from the last call.
    pub fn get_tagged(
        &mut self,
        pts: &[Vertex],
        tags: &[EdgeTag],
        precision: usize,
        attrs: &Attrs,
    ) -> &str {
        if self.spec.is_empty()
            || self.pts != pts
            || self.tags != tags
            || self.precision != precision
            || !same_attrs(&self.attrs, attrs)
        {
            self.pts.clear();
            self.pts.extend_from_slice(pts);
            self.tags = tags.to_vec();
            self.precision = precision;
            self.attrs = attrs.clone();
            self.spec = if tags.is_empty() || pts.is_empty() {
                seglist_spec(pts, precision, attrs)
            } else {
                object_spec(pts, &[], tags, attrs, precision)
            };
        }
        &self.spec
    }
}

pub fn seglist_spec(pts: &[Vertex], precision: usize, attrs: &Attrs) -> String {
    let mut s = String::with_capacity(96 + 16 * pts.len());
    push_pts_props_spec(&mut s, pts, &[], precision);
    attrs.push_spec(&mut s);
    s
}

/// Inactive seglist/polygon used for erasing: `pts={0,0:9,0:0,9},active=false[,label=L]`.
pub fn seglist_erase_spec(label: &str) -> String {
    let mut s = String::with_capacity(48 + label.len());
    s.push_str("pts={0,0:9,0:0,9},active=false");
    if !label.is_empty() {
        push_field(&mut s, "label", label);
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compact() {
        assert_eq!(fmt_x(3.0, 2), "3");
        assert_eq!(fmt_x(2.50, 2), "2.5");
        assert_eq!(fmt_x(-0.0001, 2), "0");
        assert_eq!(fmt_x(-1.234, 1), "-1.2");
        assert_eq!(fmt_x(100.0, 0), "100");
        assert_eq!(fmt_x(63.43494882, 3), "63.435");
        // C printf: ties (exact binary halves) to even, otherwise the binary value decides.
        assert_eq!(fmt_x(0.25, 1), "0.2");
        assert_eq!(fmt_x(0.125, 2), "0.12");
        assert_eq!(fmt_x(0.35, 1), "0.3");
        assert_eq!(fmt_x(0.005, 2), "0.01");
        assert_eq!(fmt_x(-0.05, 1), "-0.1");
        assert_eq!(fmt_x(f64::NAN, 1), "nan");
        assert_eq!(fmt_x(-f64::NAN, 1), "-nan");
        assert_eq!(fmt_x(f64::NEG_INFINITY, 1), "-inf");
    }

    #[test]
    fn attribute_order() {
        let mut a = Attrs::default();
        assert!(a.set("vertex_size", "5"));
        assert!(a.set("vertex_color", "yellow"));
        assert!(a.set("label_color", "aqua"));
        assert!(a.set("label", "abe's nextpt"));
        a.active = Some(true);
        assert_eq!(
            point_spec(1.0, -2.5, None, &a),
            "x=1,y=-2.5,active=true,label=abe's nextpt,label_color=aqua,vertex_color=yellow,vertex_size=5"
        );
        assert!(a.set("edge_color", "not_a_color"));
        assert!(a.edge_color.is_empty());
        assert!(!a.set("vertex_size", "big"));
        assert!(!a.set("bogus", "1"));
        assert!(is_color("dodger_blue"));
        assert!(is_color("DodgerBlue"));
    }

    #[test]
    fn seglists() {
        let pts = [Vertex::new(0.0, -40.0), Vertex::new(60.123456, -40.0)];
        let a = Attrs {
            label: "abe_wpt".into(),
            edge_size: Some(1.0),
            ..Attrs::default()
        };
        assert_eq!(
            seglist_spec(&pts, 3, &a),
            "pts={0,-40:60.123,-40},label=abe_wpt,edge_size=1"
        );
        assert_eq!(
            seglist_erase_spec("L"),
            "pts={0,0:9,0:0,9},active=false,label=L"
        );
        assert_eq!(point_erase_spec(""), "x=0,y=0,active=false");
    }

    #[test]
    fn same_attrs_is_eq() {
        let base = Attrs {
            label: "abe_wpt".into(),
            edge_color: "gray_70".into(),
            edge_size: Some(1.0),
            ..Attrs::default()
        };
        let mut all = vec![base.clone(), Attrs::default()];
        let edits: [fn(&mut Attrs); 8] = [
            |a| a.label.push('x'),
            |a| a.msg = "m".into(),
            |a| a.fill_color = "red".into(),
            |a| a.active = Some(false),
            |a| a.edge_size = Some(-0.0),
            |a| a.time = Some(f64::NAN),
            |a| a.vertex_size = Some(0.0),
            |a| a.id = "a_much_longer_identifier_than_any_word".into(),
        ];
        for e in edits {
            let mut a = base.clone();
            e(&mut a);
            all.push(a);
        }
        for a in &all {
            for b in &all {
                assert_eq!(same_attrs(a, b), a == b, "{a:?} {b:?}");
            }
        }
    }
}
