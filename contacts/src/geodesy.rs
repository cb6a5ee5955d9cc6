//! Local x/y (metres east/north of the mission's `LatOrigin`/`LongOrigin`) from
//! latitude/longitude, as the reference helm converts them (contacts-appcast.md §2.3):
//! the UTM forward projection of the USGS series (Snyder, *Map Projections — A Working
//! Manual*, USGS Professional Paper 1395, eqs. 8-9/8-10) on WGS-84 with the rounded
//! eccentricity e² = 0.00669438, each point in its **own** zone, minus the origin's
//! easting/northing.
//!
//! Written here rather than taken from a crate: the spec's numbers (the rounded e², the
//! per-point zone with the Norway/Svalbard exceptions, the unnormalised difference of
//! eastings across a zone edge) are what the helm must reproduce, and a general geodesy
//! crate (`utm`, `proj`) projects with its own constants and zone choice. Checked against
//! every `NODE_REPORT` of the conformance cases (LAT/LON printed by pNodeReporter vs its
//! X/Y): `tests/cases.rs`.

const A: f64 = 6_378_137.0;
const E2: f64 = 0.006_694_38;
const K0: f64 = 0.9996;
const FALSE_EASTING: f64 = 500_000.0;
const FALSE_NORTHING_SOUTH: f64 = 10_000_000.0;

/// Longitude wrapped into [-180, 180).
fn wrap_lon(lon: f64) -> f64 {
    if !lon.is_finite() {
        return lon;
    }
    let l = (lon + 180.0).rem_euclid(360.0) - 180.0;
    if l >= 180.0 {
        l - 360.0
    } else {
        l
    }
}

/// The UTM zone of a point, with the Norway and Svalbard exceptions.
pub fn utm_zone(lat: f64, lon: f64) -> i32 {
    let lon = wrap_lon(lon);
    // Clamped so a non-finite longitude (hostile input) still names a zone.
    let mut zone = ((lon + 180.0) / 6.0).floor().clamp(0.0, 59.0) as i32 + 1;
    if (56.0..64.0).contains(&lat) && (3.0..12.0).contains(&lon) {
        zone = 32;
    }
    if (72.0..84.0).contains(&lat) {
        zone = if (0.0..9.0).contains(&lon) {
            31
        } else if (9.0..21.0).contains(&lon) {
            33
        } else if (21.0..33.0).contains(&lon) {
            35
        } else if (33.0..42.0).contains(&lon) {
            37
        } else {
            zone
        };
    }
    zone
}

/// UTM (easting, northing) in metres of a point, in its own zone.
pub fn utm_forward(lat: f64, lon: f64) -> (f64, f64) {
    let lon = wrap_lon(lon);
    let zone = utm_zone(lat, lon);
    let lon0 = f64::from((zone - 1) * 6 - 180 + 3);
    let ep2 = E2 / (1.0 - E2);
    let phi = lat.to_radians();
    let (s, c) = phi.sin_cos();
    let n = A / (1.0 - E2 * s * s).sqrt();
    // tan(φ) once (it is used twice; the same call gives the same bits).
    let tan_phi = phi.tan();
    let t = tan_phi.powi(2);
    let cc = ep2 * c * c;
    let a = c * (lon - lon0).to_radians();
    let e4 = E2 * E2;
    let e6 = e4 * E2;
    let m = A
        * ((1.0 - E2 / 4.0 - 3.0 * e4 / 64.0 - 5.0 * e6 / 256.0) * phi
            - (3.0 * E2 / 8.0 + 3.0 * e4 / 32.0 + 45.0 * e6 / 1024.0) * (2.0 * phi).sin()
            + (15.0 * e4 / 256.0 + 45.0 * e6 / 1024.0) * (4.0 * phi).sin()
            - (35.0 * e6 / 3072.0) * (6.0 * phi).sin());
    let easting = K0
        * n
        * (a + (1.0 - t + cc) * a.powi(3) / 6.0
            + (5.0 - 18.0 * t + t * t + 72.0 * cc - 58.0 * ep2) * a.powi(5) / 120.0)
        + FALSE_EASTING;
    let mut northing = K0
        * (m + n
            * tan_phi
            * (a * a / 2.0
                + (5.0 - t + 9.0 * cc + 4.0 * cc * cc) * a.powi(4) / 24.0
                + (61.0 - 58.0 * t + t * t + 600.0 * cc - 330.0 * ep2) * a.powi(6) / 720.0));
    if lat < 0.0 {
        northing += FALSE_NORTHING_SOUTH;
    }
    (easting, northing)
}

/// The mission's local grid: origin and its UTM coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Geodesy {
    lat0: f64,
    lon0: f64,
    e0: f64,
    n0: f64,
    /// `cos` of the origin's latitude (floored at 1e-9), the first guess's scale of
    /// longitude, computed once.
    cos0: f64,
}

/// Most corrections the x/y → lat/lon iteration makes (it converges in two or three).
const INVERSE_STEPS: usize = 30;
/// The inverse stops when the forward image is this close to the target (m).
const INVERSE_TOL: f64 = 1e-4;

impl Geodesy {
    /// From the mission's `LatOrigin` / `LongOrigin`.
    pub fn new(lat_origin: f64, lon_origin: f64) -> Self {
        let (e0, n0) = utm_forward(lat_origin, lon_origin);
        Geodesy {
            lat0: lat_origin,
            lon0: lon_origin,
            e0,
            n0,
            cos0: lat_origin.to_radians().cos().max(1e-9),
        }
    }

    pub fn origin(&self) -> (f64, f64) {
        (self.lat0, self.lon0)
    }

    /// Local (x, y) of a latitude/longitude.
    ///
    /// ```
    /// let g = contacts::Geodesy::new(43.8253, -70.3304);
    /// let (x, y) = g.to_local(43.8263968, -70.32899417); // bob's first report in avd_spawn_crossing
    /// assert!((x - 115.0).abs() < 0.03 && (y - 120.0).abs() < 0.03);
    /// ```
    pub fn to_local(&self, lat: f64, lon: f64) -> (f64, f64) {
        let (e, n) = utm_forward(lat, lon);
        (e - self.e0, n - self.n0)
    }

    /// Latitude/longitude of a local (x, y): a spherical first guess corrected by the
    /// forward projection's error until it is within 0.1 mm (the reference stops at
    /// 1 m; nothing the helm decides reads these, contacts-appcast.md §6).
    pub fn to_latlon(&self, x: f64, y: f64) -> (f64, f64) {
        let deg_per_m = 180.0 / (std::f64::consts::PI * A);
        let mut lat = self.lat0 + y * deg_per_m;
        let mut lon = self.lon0 + x * deg_per_m / self.cos0;
        for _ in 0..INVERSE_STEPS {
            let (fx, fy) = self.to_local(lat, lon);
            let (ex, ey) = (x - fx, y - fy);
            if !(ex.is_finite() && ey.is_finite()) || ex.hypot(ey) <= INVERSE_TOL {
                break;
            }
            let cos = lat.to_radians().cos().abs().max(1e-9);
            lat += ey * deg_per_m / K0;
            lon += ex * deg_per_m / (K0 * cos);
        }
        (lat, lon)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zones() {
        assert_eq!(utm_zone(43.8, -70.33), 19);
        assert_eq!(utm_zone(0.0, -180.0), 1);
        assert_eq!(utm_zone(0.0, 180.0), 1); // wrapped to -180
        assert_eq!(utm_zone(0.0, 179.9), 60);
        assert_eq!(utm_zone(60.0, 5.0), 32); // Norway
        assert_eq!(utm_zone(55.9, 5.0), 31);
        assert_eq!(utm_zone(78.0, 10.0), 33); // Svalbard
        assert_eq!(utm_zone(78.0, 8.9), 31);
        assert_eq!(utm_zone(78.0, 40.0), 37);
    }

    #[test]
    fn central_meridian_and_equator() {
        // On the equator at a central meridian: easting 500000, northing 0.
        let (e, n) = utm_forward(0.0, -69.0);
        assert!((e - 500_000.0).abs() < 1e-9 && n.abs() < 1e-9);
        // Along the central meridian the northing is k0 times the meridian arc; one
        // degree of it around 44°N is 111132.954 - 559.822·cos(88°) + 1.175·cos(176°)
        // = 111112.2 m (the textbook series for WGS-84).
        let (_, n1) = utm_forward(43.5, -69.0);
        let (_, n2) = utm_forward(44.5, -69.0);
        let arc = (n2 - n1) / K0;
        assert!((arc - 111_112.2).abs() < 1.0, "{arc}");
        // South of the equator the false northing is added.
        let (_, ns) = utm_forward(-0.0001, -69.0);
        assert!((ns - (10_000_000.0 - 11.06)).abs() < 0.1, "{ns}");
    }

    #[test]
    fn local_grid_round_trip() {
        let g = Geodesy::new(43.8253, -70.3304);
        assert_eq!(g.to_local(43.8253, -70.3304), (0.0, 0.0));
        for &(x, y) in &[
            (0.0, 0.0),
            (115.0, 120.0),
            (-2500.0, 730.5),
            (10_000.0, -8000.0),
        ] {
            let (lat, lon) = g.to_latlon(x, y);
            let (bx, by) = g.to_local(lat, lon);
            assert!(
                (bx - x).abs() < 1e-3 && (by - y).abs() < 1e-3,
                "{x},{y} -> {bx},{by}"
            );
        }
        // Hostile input ends (bounded loop) without panicking.
        let (lat, _) = g.to_latlon(f64::INFINITY, 1e300);
        let _ = lat;
    }
}
