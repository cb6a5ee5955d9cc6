//! uFldObstacleSim's obstacle file (obstacles.md §3.2): `region`, `min_range`,
//! `min_size`, `max_size` and `poly` lines. Where the reference ignores the rest of the
//! file after a bad line, we refuse the file and name every bad line as `file:line`.

use std::path::Path;

use geometry::{parse_polygon, Polygon};

/// A polygon line's polygon, convex, or `None`.
fn convex(text: &str) -> Option<Polygon> {
    parse_polygon(text).filter(Polygon::is_convex)
}

/// What is wrong with one line.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum LineError {
    #[error("Poorly specified region: {0}")]
    Region(String),
    #[error("Poorly specified obstacle: {0}")]
    Obstacle(String),
    #[error("Poorly specified min_range: {0}")]
    MinRange(String),
    #[error("Poorly specified {0}: {1}")]
    Size(&'static str, String),
}

/// A file that cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum ObstacleFileError {
    #[error("Error reading: {path}: {source}")]
    Read {
        path: String,
        source: std::io::Error,
    },
    #[error("Error reading: {path}: empty or larger than 16 MB")]
    Empty { path: String },
    #[error("{}", lines.iter().map(|(l, e)| format!("{path}:{l}: {e}")).collect::<Vec<_>>().join("\n"))]
    Lines {
        path: String,
        /// (line number from 1, problem), in file order.
        lines: Vec<(usize, LineError)>,
    },
}

/// The contents of an obstacle file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ObstacleFile {
    /// The file name as given (posted in `PLOGGER_CMD`).
    pub path: String,
    pub region: Option<Polygon>,
    pub min_range: Option<f64>,
    pub min_size: f64,
    pub max_size: f64,
    /// The `poly` lines' polygons, in file order.
    pub obstacles: Vec<Polygon>,
    /// The reference's configuration warnings (`file:line` for ignored lines).
    pub warnings: Vec<String>,
}

fn size(v: &str) -> Option<f64> {
    mbutil::parse_number(v).filter(|n| n.is_finite() && *n >= 0.0)
}

impl ObstacleFile {
    /// Read `text` (named `path` in messages).
    ///
    /// ```
    /// use obstacle_manager::ObstacleFile;
    /// let f = ObstacleFile::parse("// comment\nmin_range = 20\npoly = pts={60,-12:60,6:80,6:80,-12},label=ob_0\n", "o.txt").unwrap();
    /// assert_eq!((f.obstacles.len(), f.min_range), (1, Some(20.0)));
    /// let e = ObstacleFile::parse("poly = pts={0,0:10,0:5,1:10,10:0,10}\nmin_range = far\n", "o.txt").unwrap_err();
    /// assert_eq!(e.to_string(), "o.txt:1: Poorly specified obstacle: pts={0,0:10,0:5,1:10,10:0,10}\n\
    ///                            o.txt:2: Poorly specified min_range: far");
    /// ```
    pub fn parse(text: &str, path: &str) -> Result<ObstacleFile, ObstacleFileError> {
        let mut f = ObstacleFile {
            path: path.to_string(),
            ..ObstacleFile::default()
        };
        let mut bad = Vec::new();
        for (i, raw) in text.lines().enumerate() {
            let n = i + 1;
            let line = raw.trim();
            if line.is_empty() || line.starts_with("//") {
                continue;
            }
            let Some((left, right)) = line.split_once('=') else {
                if !line.starts_with('#') {
                    f.warnings.push(format!("{path}:{n}: line ignored: {line}"));
                }
                continue;
            };
            let (left, right) = (left.trim().to_ascii_lowercase(), right.trim());
            match left.as_str() {
                "region" => match convex(right) {
                    Some(mut p) => {
                        p.attrs.label = "obs_region".into();
                        f.region = Some(p);
                    }
                    None => bad.push((n, LineError::Region(right.into()))),
                },
                "poly" => match convex(right) {
                    Some(mut p) => {
                        // The simulator keeps durations itself.
                        p.attrs.duration = None;
                        f.obstacles.push(p);
                    }
                    None => bad.push((n, LineError::Obstacle(right.into()))),
                },
                "min_range" => match size(right) {
                    Some(v) => f.min_range = Some(v),
                    None => bad.push((n, LineError::MinRange(right.into()))),
                },
                "min_size" => match size(right) {
                    Some(v) => f.min_size = v,
                    None => bad.push((n, LineError::Size("min_size", right.into()))),
                },
                "max_size" => match size(right) {
                    Some(v) => f.max_size = v,
                    None => bad.push((n, LineError::Size("max_size", right.into()))),
                },
                _ if left.starts_with('#') => {}
                _ => f.warnings.push(format!("{path}:{n}: line ignored: {line}")),
            }
        }
        if !bad.is_empty() {
            return Err(ObstacleFileError::Lines {
                path: path.to_string(),
                lines: bad,
            });
        }
        if f.min_size == 0.0 {
            f.warnings
                .push("Unset or non-positive min_poly_size".into());
        }
        if f.max_size == 0.0 {
            f.warnings.push("Unset max_poly_size".into());
        }
        if f.min_range.unwrap_or(0.0) == 0.0 {
            f.warnings.push("Unset or non-positive min_range".into());
        }
        if f.min_size > f.max_size {
            f.warnings
                .push("min_poly_size greater than max_poly_size".into());
            f.min_size = f.max_size;
        }
        Ok(f)
    }
}

/// Read and parse the file at `path`.
pub(super) fn read(path: &Path) -> Result<ObstacleFile, ObstacleFileError> {
    let name = path.display().to_string();
    let bytes =
        mbutil::file::read_capped(path, 16 << 20).map_err(|source| ObstacleFileError::Read {
            path: name.clone(),
            source,
        })?;
    let Some(bytes) = bytes.filter(|b| !b.is_empty()) else {
        return Err(ObstacleFileError::Empty { path: name });
    };
    ObstacleFile::parse(&String::from_utf8_lossy(&bytes), &name)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shape of m34_bo_alpha's obstacles.txt (obstacles.md §5).
    const M34: &str = "# obstacle field\n\
        region = pts={30,-20:30,-140:120,-140:120,-20}\n\
        min_range = 20\nmin_size = 6\nmax_size = 10\n\n\
        poly = pts={45.5,-40:48.3,-36.7:52,-35.5:55.7,-36.7:58.5,-40:58.5,-44:55.7,-47.3:52,-48.5}, label=ob_0\n\
        poly = pts={90,-100:95,-95:100,-100:95,-105}, label=ob_1\n";

    #[test]
    fn a_distribution_file() {
        let f = ObstacleFile::parse(M34, "obstacles.txt").unwrap();
        assert_eq!(f.obstacles.len(), 2);
        assert_eq!(f.obstacles[1].attrs.label, "ob_1");
        assert_eq!(f.region.as_ref().unwrap().attrs.label, "obs_region");
        assert_eq!(
            (f.min_size, f.max_size, f.min_range),
            (6.0, 10.0, Some(20.0))
        );
        assert!(f.warnings.is_empty(), "{:?}", f.warnings);
    }

    #[test]
    fn every_bad_line_named() {
        let text = "region = pts={0,0:10,0:5,1:10,10:0,10}\nmin_size = -1\nmax_size = x\n\
                    poly = nonsense\ncolour = red\nmin_range = 2\n";
        let Err(ObstacleFileError::Lines { lines, .. }) = ObstacleFile::parse(text, "f") else {
            panic!("accepted");
        };
        let at: Vec<usize> = lines.iter().map(|(l, _)| *l).collect();
        assert_eq!(at, [1, 2, 3, 4]);
        // Sizes unset or reversed are warnings, as in the reference.
        let f = ObstacleFile::parse("min_size = 9\nmax_size = 3\ncolour = red\n", "f").unwrap();
        assert_eq!(f.min_size, 3.0);
        assert!(f
            .warnings
            .iter()
            .any(|w| w == "f:3: line ignored: colour = red"));
        assert!(f
            .warnings
            .iter()
            .any(|w| w == "Unset or non-positive min_range"));
    }

    #[test]
    fn files_on_disk() {
        let dir = std::env::temp_dir().join(format!("obsfile-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("obstacles.txt");
        std::fs::write(&p, M34).unwrap();
        assert_eq!(read(&p).unwrap().obstacles.len(), 2);
        std::fs::write(&p, "").unwrap();
        assert!(matches!(read(&p), Err(ObstacleFileError::Empty { .. })));
        assert!(matches!(
            read(&dir.join("missing.txt")),
            Err(ObstacleFileError::Read { .. })
        ));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
