//! The SVG writer: exact documents for small drawings, y flipped, view box fitted, bad points
//! dropped, same bytes every time.

use shapegram_export::{SvgDrawing, SvgPolygon, SvgPolyline, write_svg};
use shapegram_geom::{Color, DVec2};

fn line(points: &[(f64, f64)], width: f64, color: &str) -> SvgPolyline {
    SvgPolyline {
        points: points.iter().map(|&(x, y)| DVec2::new(x, y)).collect(),
        width,
        color: Color::from_hex(color).unwrap(),
    }
}

#[test]
fn a_small_drawing_exactly() {
    let drawing = SvgDrawing {
        polylines: vec![line(
            &[(0.0, 0.0), (0.0, 10.0), (5.0, 10.0)],
            1.0,
            "#6b4a2b",
        )],
        polygons: vec![SvgPolygon {
            points: vec![
                DVec2::new(0.0, 0.0),
                DVec2::new(1.0, 0.0),
                DVec2::new(1.0, 1.0),
            ],
            color: Color {
                a: 0.5,
                ..Color::from_hex("#3f7d3a").unwrap()
            },
        }],
    };
    // Extent 10, margin 0.2 + half the width 0.5 on each side; y flipped.
    let expected = "\
<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"449.1\" height=\"800\" viewBox=\"-0.7 -10.7 6.4 11.4\">
<g fill=\"none\" stroke-linecap=\"round\" stroke-linejoin=\"round\">
<polyline points=\"0,0 0,-10 5,-10\" stroke=\"#6b4a2b\" stroke-width=\"1\"/>
</g>
<polygon points=\"0,0 1,0 1,-1\" fill=\"#3f7d3a\" fill-opacity=\"0.5\"/>
</svg>
";
    assert_eq!(write_svg(&drawing), expected);
}

#[test]
fn an_empty_drawing_is_a_valid_empty_picture() {
    let svg = write_svg(&SvgDrawing::default());
    assert!(svg.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\""));
    assert!(svg.ends_with("</svg>\n"));
    assert!(!svg.contains("<polyline"));
    assert!(!svg.contains("NaN"));
}

#[test]
fn non_finite_and_degenerate_items_are_dropped() {
    let drawing = SvgDrawing {
        polylines: vec![
            line(&[(0.0, 0.0), (f64::NAN, 1.0)], 1.0, "#000000"),
            line(&[(0.0, 0.0)], 1.0, "#000000"),
            line(&[(0.0, 0.0), (1.0, 1.0)], 0.0, "#000000"),
            line(&[(0.0, 0.0), (2.0, 0.0)], 0.1, "#ff0000"),
        ],
        polygons: vec![SvgPolygon {
            points: vec![DVec2::ZERO, DVec2::new(f64::INFINITY, 0.0), DVec2::ONE],
            color: Color::default(),
        }],
    };
    let svg = write_svg(&drawing);
    assert_eq!(svg.matches("<polyline").count(), 1);
    assert!(svg.contains("stroke=\"#ff0000\""));
    assert!(!svg.contains("<polygon"));
    assert!(!svg.contains("NaN") && !svg.contains("inf"));
}

#[test]
fn numbers_follow_the_size_of_the_drawing() {
    // A tiny drawing keeps its detail; thin lines keep a width.
    let tiny = write_svg(&SvgDrawing {
        polylines: vec![line(&[(0.0, 0.0), (0.001, 0.0005)], 1e-9, "#000000")],
        polygons: Vec::new(),
    });
    assert!(tiny.contains("points=\"0,0 0.001,-0.0005\""), "{tiny}");
    assert!(tiny.contains("stroke-width=\"0.000000001\""), "{tiny}");
    // A huge one drops decimals that nobody can see.
    let huge = write_svg(&SvgDrawing {
        polylines: vec![line(&[(0.0, 0.0), (1e7 + 0.123, 3.0)], 10.0, "#000000")],
        polygons: Vec::new(),
    });
    assert!(huge.contains("points=\"0,0 10000000,-3\""), "{huge}");
}

#[test]
fn the_same_drawing_gives_the_same_bytes() {
    let drawing = SvgDrawing {
        polylines: (0..50)
            .map(|i| {
                let t = f64::from(i) * 0.37;
                line(
                    &[(t.sin(), t.cos()), (t.cos() * 3.0, t.sin() / 7.0)],
                    0.05,
                    "#3a6ea5",
                )
            })
            .collect(),
        polygons: Vec::new(),
    };
    assert_eq!(write_svg(&drawing), write_svg(&drawing.clone()));
}
