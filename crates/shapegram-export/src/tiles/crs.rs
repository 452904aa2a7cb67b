//! Coordinate systems of lot files and the local frame lots are derived in.
//!
//! Every georeferenced input goes through geodetic WGS84 coordinates to Earth-centred,
//! Earth-fixed (ECEF) ones and then to the east-north-up (ENU) tangent plane at one origin: the
//! local frame. Lots are derived there, in metres with small coordinates, so a city far from
//! any CRS's origin keeps its precision; the tileset's root transform (ENU → ECEF, in f64)
//! puts the frame back on the globe.

use std::fmt;

use shapegram_geom::DVec3;

/// WGS84's semi-major axis in metres.
const A: f64 = 6_378_137.0;
/// WGS84's flattening.
const F: f64 = 1.0 / 298.257_223_563;
/// The first eccentricity squared.
const E2: f64 = F * (2.0 - F);
/// UTM's scale factor on the central meridian.
const UTM_K0: f64 = 0.9996;
/// UTM's false easting.
const UTM_EAST: f64 = 500_000.0;
/// UTM's false northing in the southern hemisphere.
const UTM_SOUTH: f64 = 10_000_000.0;

/// The coordinate system of the positions in a lot file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Crs {
    /// Metres in the grammar's ground plane as they are (x east, y north), not on the globe.
    Local,
    /// Longitude and latitude in degrees on WGS84, as RFC 7946 GeoJSON has them (EPSG:4326).
    Wgs84,
    /// A WGS84 UTM zone (EPSG:326zz north, EPSG:327zz south): easting and northing in metres.
    Utm {
        /// The zone, 1 to 60.
        zone: u8,
        /// Whether it is the northern hemisphere's zone (false northing 0).
        north: bool,
    },
}

impl Crs {
    /// Reads `local`, `wgs84` (or `EPSG:4326`, `CRS84`) and `EPSG:32601`…`EPSG:32660` (UTM
    /// north) or `EPSG:32701`…`EPSG:32760` (UTM south), case-insensitive.
    pub fn parse(text: &str) -> Result<Crs, String> {
        let lower = text.trim().to_ascii_lowercase();
        let code = lower.strip_prefix("epsg:");
        match (lower.as_str(), code) {
            ("local", _) => return Ok(Crs::Local),
            ("wgs84" | "crs84", _) | (_, Some("4326")) => return Ok(Crs::Wgs84),
            _ => {}
        }
        let utm = code.and_then(|c| c.parse::<u32>().ok()).and_then(|n| {
            let zone = u8::try_from(n % 100)
                .ok()
                .filter(|z| (1..=60).contains(z))?;
            match n / 100 {
                326 => Some(Crs::Utm { zone, north: true }),
                327 => Some(Crs::Utm { zone, north: false }),
                _ => None,
            }
        });
        utm.ok_or_else(|| {
            format!(
                "unknown coordinate system '{}': expected local, wgs84 (EPSG:4326) or a WGS84 UTM \
                 zone EPSG:32601…32660 (north) or EPSG:32701…32760 (south)",
                text.escape_debug()
            )
        })
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
            Crs::Wgs84 => {
                if !(-180.0..=180.0).contains(&x) || !(-90.0..=90.0).contains(&y) {
                    return Err(format!(
                        "[{x}, {y}] is no longitude in [-180, 180] and latitude in [-90, 90] \
                         (projected metres need --crs EPSG:… or local)"
                    ));
                }
                Ok(Geodetic {
                    longitude: x,
                    latitude: y,
                })
            }
            Crs::Utm { zone, north } => {
                // Within a zone eastings stay within about 160 km to 840 km and northings
                // within the hemisphere; beyond, the series below loses its accuracy.
                if !(100_000.0..=900_000.0).contains(&x) || !(0.0..=UTM_SOUTH).contains(&y) {
                    return Err(format!(
                        "[{x}, {y}] is outside UTM zone {zone}{} (easting 100,000 to 900,000 m, \
                         northing 0 to 10,000,000 m)",
                        if north { "N" } else { "S" }
                    ));
                }
                Ok(utm_inverse(zone, north, x, y))
            }
        }
    }
}

impl fmt::Display for Crs {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Crs::Local => f.write_str("local"),
            Crs::Wgs84 => f.write_str("EPSG:4326"),
            Crs::Utm { zone, north } => {
                write!(f, "EPSG:{}{zone:02}", if *north { 326 } else { 327 })
            }
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

/// UTM easting/northing to geodetic, by the series of Snyder, "Map Projections: A Working
/// Manual" (USGS 1987), equations 8-18 to 8-25 and 3-26; better than a millimetre within a zone.
fn utm_inverse(zone: u8, north: bool, easting: f64, northing: f64) -> Geodetic {
    let ep2 = E2 / (1.0 - E2);
    let m = (northing - if north { 0.0 } else { UTM_SOUTH }) / UTM_K0;
    let mu = m / (A * (1.0 - E2 / 4.0 - 3.0 * E2 * E2 / 64.0 - 5.0 * E2 * E2 * E2 / 256.0));
    let e1 = (1.0 - (1.0 - E2).sqrt()) / (1.0 + (1.0 - E2).sqrt());
    let phi1 = mu
        + (1.5 * e1 - 27.0 / 32.0 * e1.powi(3)) * (2.0 * mu).sin()
        + (21.0 / 16.0 * e1 * e1 - 55.0 / 32.0 * e1.powi(4)) * (4.0 * mu).sin()
        + 151.0 / 96.0 * e1.powi(3) * (6.0 * mu).sin()
        + 1097.0 / 512.0 * e1.powi(4) * (8.0 * mu).sin();
    let (sin1, cos1) = phi1.sin_cos();
    let tan1 = sin1 / cos1;
    let c1 = ep2 * cos1 * cos1;
    let t1 = tan1 * tan1;
    let w = 1.0 - E2 * sin1 * sin1;
    let n1 = A / w.sqrt();
    let r1 = A * (1.0 - E2) / w.powf(1.5);
    let d = (easting - UTM_EAST) / (n1 * UTM_K0);
    let latitude = phi1
        - n1 * tan1 / r1
            * (d * d / 2.0
                - (5.0 + 3.0 * t1 + 10.0 * c1 - 4.0 * c1 * c1 - 9.0 * ep2) * d.powi(4) / 24.0
                + (61.0 + 90.0 * t1 + 298.0 * c1 + 45.0 * t1 * t1 - 252.0 * ep2 - 3.0 * c1 * c1)
                    * d.powi(6)
                    / 720.0);
    let central = f64::from(zone) * 6.0 - 183.0;
    let longitude = central
        + ((d - (1.0 + 2.0 * t1 + c1) * d.powi(3) / 6.0
            + (5.0 - 2.0 * c1 + 28.0 * t1 - 3.0 * c1 * c1 + 8.0 * ep2 + 24.0 * t1 * t1)
                * d.powi(5)
                / 120.0)
            / cos1)
            .to_degrees();
    Geodetic {
        longitude,
        latitude: latitude.to_degrees(),
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
        assert_eq!(
            Crs::parse("EPSG:32633"),
            Ok(Crs::Utm {
                zone: 33,
                north: true
            })
        );
        assert_eq!(
            Crs::parse("EPSG:32760"),
            Ok(Crs::Utm {
                zone: 60,
                north: false
            })
        );
        for bad in ["EPSG:32661", "EPSG:32600", "EPSG:3857", "utm", ""] {
            let error = Crs::parse(bad).unwrap_err();
            assert!(error.starts_with("unknown coordinate system"), "{error}");
        }
        assert_eq!(Crs::parse("epsg:32733").unwrap().to_string(), "EPSG:32733");
    }

    #[test]
    fn utm_on_the_central_meridian_gives_the_meridian_arc() {
        let utm = Crs::Utm {
            zone: 33,
            north: true,
        };
        let equator = utm.to_geodetic(500_000.0, 0.0).unwrap();
        assert_eq!((equator.longitude, equator.latitude), (15.0, 0.0));
        // The meridian arc from the equator to 45° on WGS84 is 4,984,944.378 m.
        let p = utm.to_geodetic(500_000.0, 4_984_944.378 * UTM_K0).unwrap();
        assert!((p.latitude - 45.0).abs() < 1e-8, "{p:?}");
        assert_eq!(p.longitude, 15.0);
    }

    #[test]
    fn utm_inverse_finds_a_surveyed_point() {
        // The CN Tower: 17T 630084 E 4833438 N is 43.642567° N, 79.387139° W (metre rounding:
        // 1e-5° is about a metre).
        let utm = Crs::parse("EPSG:32617").unwrap();
        let p = utm.to_geodetic(630_084.0, 4_833_438.0).unwrap();
        assert!((p.latitude - 43.642_567).abs() < 2e-5, "{p:?}");
        assert!((p.longitude + 79.387_139).abs() < 2e-5, "{p:?}");
    }

    #[test]
    fn out_of_range_positions_are_errors() {
        let error = Crs::Wgs84.to_geodetic(448_252.0, 5_411_935.0).unwrap_err();
        assert!(error.contains("no longitude in [-180, 180]"), "{error}");
        let utm = Crs::parse("EPSG:32631").unwrap();
        let error = utm.to_geodetic(2.29, 48.86).unwrap_err();
        assert!(error.contains("outside UTM zone 31N"), "{error}");
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
