//! Coordinate systems of lot files and the local frame lots are derived in.
//!
//! Every georeferenced input goes through geodetic WGS84 coordinates to Earth-centred,
//! Earth-fixed (ECEF) ones and then to the east-north-up (ENU) tangent plane at one origin: the
//! local frame. Lots are derived there, in metres with small coordinates, so a city far from
//! any CRS's origin keeps its precision; the tileset's root transform (ENU → ECEF, in f64)
//! puts the frame back on the globe. Projections and datum shifts are proj4rs's, with the
//! EPSG registry's definitions; the frame is ours.

use std::cell::RefCell;
use std::fmt;

use proj4rs::Proj;
use shapegram_geom::DVec3;

/// WGS84's semi-major axis in metres.
const A: f64 = 6_378_137.0;
/// WGS84's flattening.
const F: f64 = 1.0 / 298.257_223_563;
/// The first eccentricity squared.
const E2: f64 = F * (2.0 - F);
/// Geodetic WGS84, the target of every projection's inverse (angles in radians).
const WGS84_LONGLAT: &str = "+proj=longlat +datum=WGS84 +no_defs";

/// The coordinate system of the positions in a lot file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Crs {
    /// Metres in the grammar's ground plane as they are (x east, y north), not on the globe.
    Local,
    /// Longitude and latitude in degrees on WGS84, as RFC 7946 GeoJSON has them (EPSG:4326).
    Wgs84,
    /// Any other coordinate system of the EPSG registry that proj4rs knows: a projection
    /// (UTM zones, national grids, Web Mercator) in its own units, or another datum's
    /// longitude and latitude in degrees.
    Epsg(u16),
}

impl Crs {
    /// Reads `local`, `wgs84` (or `EPSG:4326`, `CRS84`) and `EPSG:<code>` for the other codes
    /// of the EPSG registry, case-insensitive.
    pub fn parse(text: &str) -> Result<Crs, String> {
        let lower = text.trim().to_ascii_lowercase();
        match lower.as_str() {
            "local" => return Ok(Crs::Local),
            "wgs84" | "crs84" | "epsg:4326" => return Ok(Crs::Wgs84),
            _ => {}
        }
        let unknown = |why: &str| {
            format!(
                "unknown coordinate system '{}': {why}; expected local, wgs84 (EPSG:4326) or \
                 EPSG:<code> (for example a UTM zone, EPSG:32633)",
                text.escape_debug()
            )
        };
        let code = lower
            .strip_prefix("epsg:")
            .ok_or_else(|| unknown("not an EPSG code"))?;
        let code = code
            .parse::<u16>()
            .map_err(|_| unknown("not an EPSG code"))?;
        let proj = Proj::from_epsg_code(code).map_err(|e| unknown(&e.to_string()))?;
        if proj.is_geocent() {
            return Err(unknown("an Earth-centred system has no ground plane"));
        }
        Ok(Crs::Epsg(code))
    }

    /// Whether positions are on the globe (anything but [`Crs::Local`]).
    pub fn is_geographic(self) -> bool {
        self != Crs::Local
    }

    /// The geodetic position (longitude, latitude in degrees) of a position `(x, y)` of this
    /// system; an error saying what is out of range for it. [`Crs::Local`] has none.
    pub fn to_geodetic(self, x: f64, y: f64) -> Result<Geodetic, String> {
        match self {
            Crs::Local => Err("local coordinates are not on the globe".to_owned()),
            Crs::Wgs84 => Geodetic::checked(x, y).ok_or_else(|| {
                format!(
                    "[{x}, {y}] is no longitude in [-180, 180] and latitude in [-90, 90] \
                     (projected metres need --crs EPSG:… or local)"
                )
            }),
            Crs::Epsg(code) => {
                if let Some((zone, north)) = utm_zone(code) {
                    // Within a zone eastings stay within about 160 km to 840 km and northings
                    // within the hemisphere: beyond, the input is in another system.
                    if !(100_000.0..=900_000.0).contains(&x) || !(0.0..=10_000_000.0).contains(&y) {
                        return Err(format!(
                            "[{x}, {y}] is outside UTM zone {zone}{} (easting 100,000 to \
                             900,000 m, northing 0 to 10,000,000 m)",
                            if north { "N" } else { "S" }
                        ));
                    }
                }
                inverse(code, x, y)
            }
        }
    }
}

/// The zone and hemisphere of a WGS84 UTM code (EPSG:326zz north, EPSG:327zz south).
fn utm_zone(code: u16) -> Option<(u16, bool)> {
    let zone = code % 100;
    match (code / 100, zone) {
        (326, 1..=60) => Some((zone, true)),
        (327, 1..=60) => Some((zone, false)),
        _ => None,
    }
}

thread_local! {
    /// The last system converted from and geodetic WGS84: lots come file by file, so one entry
    /// spares parsing the definition for every position.
    static PROJECTIONS: RefCell<Option<(u16, Proj, Proj)>> = const { RefCell::new(None) };
}

/// `(x, y)` of EPSG:`code` as geodetic WGS84.
fn inverse(code: u16, x: f64, y: f64) -> Result<Geodetic, String> {
    PROJECTIONS.with_borrow_mut(|cached| {
        if cached.as_ref().is_none_or(|(c, _, _)| *c != code) {
            let from = Proj::from_epsg_code(code).map_err(|e| format!("EPSG:{code}: {e}"))?;
            let to = Proj::from_proj_string(WGS84_LONGLAT).map_err(|e| e.to_string())?;
            *cached = Some((code, from, to));
        }
        let (_, from, to) = cached.as_ref().expect("filled above");
        // proj4rs takes and gives angles in radians.
        let mut p = if from.is_latlong() {
            (x.to_radians(), y.to_radians(), 0.0)
        } else {
            (x, y, 0.0)
        };
        let input = p;
        let mut back = None;
        if proj4rs::transform::transform(from, to, &mut p).is_ok() {
            let mut q = p;
            back = proj4rs::transform::transform(to, from, &mut q)
                .is_ok()
                .then_some(q);
        }
        // Far outside a projection's area the inverse still gives a point (the pole, a wrapped
        // longitude) that does not project back: that is an error, not a lot somewhere else.
        let tolerance = if from.is_latlong() { 1e-9 } else { 1e-3 };
        back.filter(|q| (q.0 - input.0).abs() <= tolerance && (q.1 - input.1).abs() <= tolerance)
            .and_then(|_| Geodetic::checked(p.0.to_degrees(), p.1.to_degrees()))
            .ok_or_else(|| format!("[{x}, {y}] is outside the area of EPSG:{code}"))
    })
}

impl fmt::Display for Crs {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Crs::Local => f.write_str("local"),
            Crs::Wgs84 => f.write_str("EPSG:4326"),
            Crs::Epsg(code) => write!(f, "EPSG:{code}"),
        }
    }
}

/// A position on WGS84, in degrees, on the ellipsoid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Geodetic {
    /// East of Greenwich, −180 to 180.
    pub longitude: f64,
    /// North of the equator, −90 to 90.
    pub latitude: f64,
}

impl Geodetic {
    /// The position at `longitude`, `latitude` if both are finite and in range.
    fn checked(longitude: f64, latitude: f64) -> Option<Self> {
        ((-180.0..=180.0).contains(&longitude) && (-90.0..=90.0).contains(&latitude)).then_some(
            Self {
                longitude,
                latitude,
            },
        )
    }

    /// Its ECEF position in metres at `height` above the ellipsoid.
    pub fn to_ecef(self, height: f64) -> DVec3 {
        let (sin_lat, cos_lat) = self.latitude.to_radians().sin_cos();
        let (sin_lon, cos_lon) = self.longitude.to_radians().sin_cos();
        let n = A / (1.0 - E2 * sin_lat * sin_lat).sqrt();
        DVec3::new(
            (n + height) * cos_lat * cos_lon,
            (n + height) * cos_lat * sin_lon,
            (n * (1.0 - E2) + height) * sin_lat,
        )
    }
}

/// The east-north-up tangent frame at a point of the ellipsoid: lots are derived in it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnuFrame {
    /// Its origin, in ECEF metres.
    pub origin: DVec3,
    /// Its unit axes in ECEF: east, north, up.
    pub axes: [DVec3; 3],
}

impl EnuFrame {
    /// The frame at `at` on the ellipsoid.
    pub fn at(at: Geodetic) -> Self {
        let (sin_lat, cos_lat) = at.latitude.to_radians().sin_cos();
        let (sin_lon, cos_lon) = at.longitude.to_radians().sin_cos();
        Self {
            origin: at.to_ecef(0.0),
            axes: [
                DVec3::new(-sin_lon, cos_lon, 0.0),
                DVec3::new(-sin_lat * cos_lon, -sin_lat * sin_lon, cos_lat),
                DVec3::new(cos_lat * cos_lon, cos_lat * sin_lon, sin_lat),
            ],
        }
    }

    /// East and north of the frame's origin, in metres, of a point on the ellipsoid (its
    /// height above the tangent plane is dropped: lots lie flat in the plane).
    pub fn east_north(&self, at: Geodetic) -> (f64, f64) {
        let d = at.to_ecef(0.0) - self.origin;
        (d.dot(self.axes[0]), d.dot(self.axes[1]))
    }

    /// The 4 × 4 matrix from the frame (x east, y north, z up) to ECEF, column-major as 3D
    /// Tiles' `transform` has it.
    pub fn matrix(&self) -> [f64; 16] {
        let [e, n, u] = self.axes;
        let o = self.origin;
        [
            e.x, e.y, e.z, 0.0, n.x, n.y, n.z, 0.0, u.x, u.y, u.z, 0.0, o.x, o.y, o.z, 1.0,
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coordinate_systems_are_named_as_epsg_codes() {
        assert_eq!(Crs::parse("local"), Ok(Crs::Local));
        assert_eq!(Crs::parse("WGS84"), Ok(Crs::Wgs84));
        assert_eq!(Crs::parse("epsg:4326"), Ok(Crs::Wgs84));
        assert_eq!(Crs::parse("EPSG:32633"), Ok(Crs::Epsg(32633)));
        assert_eq!(Crs::parse(" EPSG:2056 "), Ok(Crs::Epsg(2056)));
        assert_eq!(Crs::parse("epsg:32733").unwrap().to_string(), "EPSG:32733");
        for (bad, why) in [
            ("EPSG:1", "projection not found"),
            ("EPSG:4978", "Earth-centred"),
            ("EPSG:4267", "NAD grid not available"),
            ("EPSG:99999", "not an EPSG code"),
            ("utm", "not an EPSG code"),
            ("", "not an EPSG code"),
        ] {
            let error = Crs::parse(bad).unwrap_err();
            assert!(error.starts_with("unknown coordinate system"), "{error}");
            assert!(
                error.to_lowercase().contains(&why.to_lowercase()),
                "{error}"
            );
        }
    }

    #[test]
    fn utm_on_the_central_meridian_gives_the_meridian_arc() {
        let utm = Crs::Epsg(32633);
        let equator = utm.to_geodetic(500_000.0, 0.0).unwrap();
        assert!(
            (equator.longitude - 15.0).abs() < 1e-12 && equator.latitude.abs() < 1e-12,
            "{equator:?}"
        );
        // The meridian arc from the equator to 45° on WGS84 is 4,984,944.378 m; UTM scales it
        // by 0.9996 on the central meridian.
        let p = utm.to_geodetic(500_000.0, 4_984_944.378 * 0.9996).unwrap();
        assert!((p.latitude - 45.0).abs() < 1e-8, "{p:?}");
        assert!((p.longitude - 15.0).abs() < 1e-12, "{p:?}");
    }

    #[test]
    fn projections_find_surveyed_points() {
        // (code, x, y, longitude, latitude, tolerance in degrees: 1e-5° is about a metre).
        let points = [
            // The CN Tower: 17T 630084 E 4833438 N is 43.642567° N, 79.387139° W.
            (32617, 630_084.0, 4_833_438.0, -79.387_139, 43.642_567, 2e-5),
            // The origin of the Swiss LV95 grid, the old observatory of Bern, 7°26′22.50″ E
            // 46°57′08.66″ N on the Bessel ellipsoid: the datum shift to WGS84 moves it by
            // about 100 m, to 7.438632° E 46.951083° N.
            (2056, 2_600_000.0, 1_200_000.0, 7.438_632, 46.951_083, 2e-5),
            // Web Mercator: y = R ln tan(π/4 + φ/2) on the sphere of radius 6,378,137 m.
            (3857, 1_113_194.907_9, 0.0, 10.0, 0.0, 1e-9),
        ];
        for (code, x, y, longitude, latitude, tolerance) in points {
            let p = Crs::Epsg(code).to_geodetic(x, y).unwrap();
            assert!(
                (p.longitude - longitude).abs() < tolerance
                    && (p.latitude - latitude).abs() < tolerance,
                "EPSG:{code}: {p:?}"
            );
        }
        // Another datum's degrees go through its datum shift too.
        let etrs89 = Crs::parse("EPSG:4258")
            .unwrap()
            .to_geodetic(9.0, 50.0)
            .unwrap();
        assert!((etrs89.longitude - 9.0).abs() < 1e-6 && (etrs89.latitude - 50.0).abs() < 1e-6);
    }

    #[test]
    fn out_of_range_positions_are_errors() {
        let error = Crs::Wgs84.to_geodetic(448_252.0, 5_411_935.0).unwrap_err();
        assert!(error.contains("no longitude in [-180, 180]"), "{error}");
        let error = Crs::Epsg(32631).to_geodetic(2.29, 48.86).unwrap_err();
        assert!(error.contains("outside UTM zone 31N"), "{error}");
        let error = Crs::Epsg(3857).to_geodetic(1e12, 1e12).unwrap_err();
        assert_eq!(
            error,
            "[1000000000000, 1000000000000] is outside the area of EPSG:3857"
        );
        let error = Crs::Epsg(2056).to_geodetic(f64::NAN, 0.0).unwrap_err();
        assert!(
            error.ends_with("is outside the area of EPSG:2056"),
            "{error}"
        );
    }

    #[test]
    fn the_enu_frame_is_orthonormal_and_round_trips() {
        let origin = Geodetic {
            longitude: 13.4,
            latitude: 52.5,
        };
        let frame = EnuFrame::at(origin);
        let [e, n, u] = frame.axes;
        assert!((e.cross(n) - u).length() < 1e-15);
        assert!(frame.origin.length() > 6.36e6 && frame.origin.length() < 6.38e6);
        assert_eq!(frame.east_north(origin), (0.0, 0.0));
        // 0.001° of latitude is about 111.3 m north; of longitude about 67.8 m east here.
        let (east, north) = frame.east_north(Geodetic {
            longitude: 13.401,
            latitude: 52.501,
        });
        assert!((north - 111.3).abs() < 0.2, "{north}");
        assert!((east - 67.8).abs() < 0.2, "{east}");
        let m = frame.matrix();
        assert_eq!(&m[12..15], &frame.origin.to_array());
        assert_eq!(m[15], 1.0);
    }
}
