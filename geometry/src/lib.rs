//! Marine geometry shared by the helm and its behaviors (behaviors-std.md §1): compass
//! angles, points and segments, convex polygons, every point/seglist/polygon string
//! format a mission may write (specs/geometry-formats.md: `parse_polygon`,
//! `parse_seglist`, `parse_point`, one module per format in `formats/`), the VIEW_*
//! spec formatting, and the geometry of polygon obstacles ([`obstacle`]: buffer polygon,
//! tangent bearings, ray-to-polygon CPA).

pub mod angles;
mod formats;
mod objects;
pub mod obstacle;
pub mod parse;
pub mod points;
pub mod polygon;
pub mod spec;
pub mod text;

pub use angles::{
    angle180, angle360, angle_diff, angle_from_three_points, deg_to_radians, rel_ang, segment_angle,
};
pub use parse::{parse_point, parse_polygon, parse_seglist, Point, Seglist};
pub use points::{dist, dist_point_to_seg, perp_seg_int_pt, project_point, segments_cross};
pub use polygon::Polygon;
pub use spec::{
    fmt_x, is_color, object_spec, point_erase_spec, point_spec, pts_props_spec, pts_spec,
    push_point_spec, push_pts_props_spec, seglist_erase_spec, seglist_spec, Attrs, EdgeTag,
    SeglistSpecCache, Vertex,
};
