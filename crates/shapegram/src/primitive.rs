//! `shapegram primitive`: one primitive shape written to a file.

use shapegram_export::{ExportOptions, Format};
use shapegram_geom::{Color, DVec2, DVec3, Mesh, Model, primitives};

use crate::cli::{Kind, PrimitiveArgs};
use crate::{Failure, counted};

/// Default number of sides of cylinders and cones, and of segments of spheres.
const DEFAULT_SIDES: u32 = 32;
/// Default number of rings of spheres.
const DEFAULT_RINGS: u32 = 16;
/// Upper bound on any one subdivision count, so a typo cannot ask for billions of vertices.
const MAX_SUBDIVISIONS: u32 = 100_000;
/// Upper bound on segments × rings of a sphere (its vertex count, roughly).
const MAX_SPHERE_VERTICES: u64 = 1_000_000;

/// Builds the primitive, writes it and prints the summary line.
pub fn run(args: &PrimitiveArgs) -> Result<(), Failure> {
    // Check the extension before any work, so a typo in -o fails fast and first.
    Format::from_path(&args.output)?;
    let color = match &args.color {
        Some(text) => Color::from_hex(text).ok_or_else(|| {
            Failure::new(format!(
                "invalid --color '{}': expected a hex colour like '#3a6ea5'",
                text.escape_debug()
            ))
        })?,
        None => Color::default(),
    };
    let mesh = build(args)?;
    let summary = (!args.quiet).then(|| {
        format!(
            "{}, {}, {}",
            counted(mesh.vertex_count(), "vertex", "vertices"),
            counted(mesh.face_count(), "face", "faces"),
            counted(mesh.triangulate().len(), "triangle", "triangles")
        )
    });
    let model = Model::single(args.kind.name(), color, mesh);
    let options = ExportOptions {
        group_by_part: args.group,
        ..ExportOptions::default()
    };
    shapegram_export::save(&model, &args.output, &options)?;
    if let Some(summary) = summary {
        eprintln!("wrote {}: {summary}", args.output.display());
    }
    Ok(())
}

/// The mesh the arguments describe, after checking that every option given applies to the kind.
fn build(args: &PrimitiveArgs) -> Result<Mesh, Failure> {
    let kind = args.kind;
    let uses_sides = matches!(kind, Kind::Cylinder | Kind::Cone);
    let is_sphere = kind == Kind::Sphere;
    // An option that the kind ignores is almost always a mistake (a forgotten kind change, a
    // misplaced flag), so say so rather than silently write a different shape.
    let not_applying = [
        ("--size", args.size.is_some() && kind == Kind::Footprint),
        ("--sides", args.sides.is_some() && !uses_sides),
        ("--segments", args.segments.is_some() && !is_sphere),
        ("--rings", args.rings.is_some() && !is_sphere),
        ("--points", args.points.is_some() && kind != Kind::Footprint),
    ];
    if let Some((flag, _)) = not_applying.iter().find(|(_, bad)| *bad) {
        return Err(Failure::new(format!(
            "{flag} does not apply to {}",
            kind.name()
        )));
    }

    let flat = kind == Kind::Quad;
    let size = match &args.size {
        Some(text) => parse_size(text, flat).map_err(Failure::new)?,
        None => DVec3::ONE,
    };
    let count = |flag: &str, value: Option<u32>, default: u32, min: u32| match value {
        None => Ok(default),
        Some(n) if (min..=MAX_SUBDIVISIONS).contains(&n) => Ok(n),
        Some(n) => Err(Failure::new(format!(
            "invalid {flag} {n}: expected {min} to {MAX_SUBDIVISIONS} for a {}",
            kind.name()
        ))),
    };
    Ok(match kind {
        Kind::Cuboid => primitives::cuboid(size),
        Kind::Quad => primitives::quad(size.x, size.z),
        Kind::Footprint => {
            let text = args
                .points
                .as_deref()
                .ok_or_else(|| Failure::new("footprint needs --points \"x,z x,z x,z ...\""))?;
            let points = parse_points(text, "--points").map_err(Failure::new)?;
            primitives::footprint(&points).ok_or_else(|| {
                Failure::new(format!(
                    "invalid --points '{}': the polygon has no area",
                    text.escape_debug()
                ))
            })?
        }
        Kind::Cylinder => {
            primitives::cylinder(size, count("--sides", args.sides, DEFAULT_SIDES, 3)?)
        }
        Kind::Cone => primitives::cone(size, count("--sides", args.sides, DEFAULT_SIDES, 3)?),
        Kind::Sphere => {
            let segments = count("--segments", args.segments, DEFAULT_SIDES, 3)?;
            let rings = count("--rings", args.rings, DEFAULT_RINGS, 2)?;
            if u64::from(segments) * u64::from(rings) > MAX_SPHERE_VERTICES {
                return Err(Failure::new(format!(
                    "a sphere of {segments} segments × {rings} rings is too fine: segments × \
                     rings must be at most {MAX_SPHERE_VERTICES}"
                )));
            }
            primitives::sphere(size, segments, rings)
        }
        Kind::Pyramid => primitives::pyramid(size),
    })
}

/// Parses `--size X,Y,Z`: three positive numbers. When `flat` (a quad), Y is ignored and may be 0.
fn parse_size(text: &str, flat: bool) -> Result<DVec3, String> {
    let expected = if flat {
        "expected three numbers like 10,0,5 (X and Z positive; Y is ignored)"
    } else {
        "expected three positive numbers like 10,20,5"
    };
    let error = || format!("invalid --size '{}': {expected}", text.escape_debug());
    let values = parse_numbers(text, 3).ok_or_else(error)?;
    let size = DVec3::from_slice(&values);
    // Positive once stored as the file's f32, so a size like 1e-50 cannot collapse to zero.
    let positive = |v: f64| v as f32 > 0.0;
    if !(positive(size.x) && positive(size.z) && (positive(size.y) || flat && size.y == 0.0)) {
        return Err(error());
    }
    Ok(size)
}

/// Parses `--points "x,z x,z ..."` (or another `flag` of that form): at least three pairs
/// separated by whitespace.
pub fn parse_points(text: &str, flag: &str) -> Result<Vec<DVec2>, String> {
    let points = text
        .split_whitespace()
        .map(|pair| {
            parse_numbers(pair, 2)
                .map(|v| DVec2::new(v[0], v[1]))
                .ok_or_else(|| {
                    format!(
                        "invalid {flag}: '{}' is not an x,z pair of numbers like 4,2.5",
                        pair.escape_debug()
                    )
                })
        })
        .collect::<Result<Vec<_>, _>>()?;
    if points.len() < 3 {
        return Err(format!(
            "invalid {flag} '{}': expected at least three x,z pairs separated by spaces, like \
             \"0,0 4,0 4,3\"",
            text.escape_debug()
        ));
    }
    Ok(points)
}

/// Exactly `n` comma-separated numbers (spaces around them allowed), each finite and within the
/// range of the 32-bit floats the file formats store; `None` otherwise.
fn parse_numbers(text: &str, n: usize) -> Option<Vec<f64>> {
    let values = text
        .split(',')
        .map(|part| part.trim().parse::<f64>().ok())
        .collect::<Option<Vec<_>>>()?;
    let representable = |v: &f64| v.is_finite() && v.abs() <= f64::from(f32::MAX);
    (values.len() == n && values.iter().all(representable)).then_some(values)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_with_or_without_spaces() {
        assert_eq!(
            parse_size("10,20,5", false),
            Ok(DVec3::new(10.0, 20.0, 5.0))
        );
        assert_eq!(
            parse_size(" 0.5 , 1e3,2 ", false),
            Ok(DVec3::new(0.5, 1000.0, 2.0))
        );
    }

    #[test]
    fn bad_sizes_are_rejected_with_the_text_and_an_example() {
        for bad in [
            "1,x,3",
            "1,2",
            "1,2,3,4",
            "",
            "1,,3",
            "0,1,1",
            "1,-1,1",
            "NaN,1,1",
            "inf,1,1",
            "1e39,1,1",
            "1e-50,1,1",
            "1;2;3",
        ] {
            let message = parse_size(bad, false).unwrap_err();
            assert_eq!(
                message,
                format!("invalid --size '{bad}': expected three positive numbers like 10,20,5")
            );
        }
    }

    #[test]
    fn flat_sizes_ignore_a_zero_y_but_not_a_negative_one() {
        assert_eq!(parse_size("4,0,3", true), Ok(DVec3::new(4.0, 0.0, 3.0)));
        assert!(parse_size("4,-1,3", true).is_err());
        assert!(parse_size("0,1,3", true).is_err());
        assert!(parse_size("4,0,3", false).is_err());
    }

    #[test]
    fn points_parse_as_whitespace_separated_pairs() {
        assert_eq!(
            parse_points(" 0,0 4,0\t-1.5,3 ", "--points"),
            Ok(vec![
                DVec2::new(0.0, 0.0),
                DVec2::new(4.0, 0.0),
                DVec2::new(-1.5, 3.0)
            ])
        );
    }

    #[test]
    fn bad_points_name_the_bad_pair() {
        assert_eq!(
            parse_points("0,0 4,x 4,3", "--points"),
            Err("invalid --points: '4,x' is not an x,z pair of numbers like 4,2.5".into())
        );
        assert!(parse_points("0,0 4,0,1 4,3", "--points").is_err());
        assert!(parse_points("0,0 nan,0 4,3", "--points").is_err());
    }

    #[test]
    fn fewer_than_three_points_are_rejected() {
        assert!(
            parse_points("0,0 4,0", "--points")
                .unwrap_err()
                .starts_with("invalid --points '0,0 4,0'")
        );
        assert!(parse_points("0,0,4,0,4,3", "--points").is_err());
        assert!(parse_points("", "--points").is_err());
    }
}
