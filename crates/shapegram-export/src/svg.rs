//! SVG for 2D drawings such as an L-system's turtle output: polylines with a width and colour
//! each, and filled polygons.
//!
//! The drawing's y axis points up (as the turtle's does) and is flipped for SVG, whose y points
//! down. The view box fits the drawing with a small margin and room for the widest line; the
//! picture is 800 pixels along its longer side. Numbers are rounded to a resolution of about a
//! millionth of the drawing's size and printed without trailing zeros, so the same drawing gives
//! the same bytes. Points that are not finite drop their polyline or polygon.

use std::fmt::Write;

use shapegram_geom::{Color, DVec2};

/// Pixels along the longer side of the picture.
const PICTURE_SIZE: f64 = 800.0;
/// Margin around the drawing, as a fraction of its larger extent.
const MARGIN: f64 = 0.02;

/// A line through points, drawn with round caps and joins.
#[derive(Clone, Debug, PartialEq)]
pub struct SvgPolyline {
    /// The points, y up.
    pub points: Vec<DVec2>,
    /// Line width in drawing units.
    pub width: f64,
    /// Line colour.
    pub color: Color,
}

/// A filled polygon.
#[derive(Clone, Debug, PartialEq)]
pub struct SvgPolygon {
    /// The corners, y up.
    pub points: Vec<DVec2>,
    /// Fill colour.
    pub color: Color,
}

/// A 2D drawing: polylines first, then polygons on top of them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SvgDrawing {
    /// Lines.
    pub polylines: Vec<SvgPolyline>,
    /// Filled polygons.
    pub polygons: Vec<SvgPolygon>,
}

/// The drawing as an SVG document.
pub fn write_svg(drawing: &SvgDrawing) -> String {
    let finite = |points: &[DVec2]| points.iter().all(|p| p.is_finite());
    let polylines: Vec<&SvgPolyline> = drawing
        .polylines
        .iter()
        .filter(|l| {
            l.points.len() >= 2 && finite(&l.points) && l.width.is_finite() && l.width > 0.0
        })
        .collect();
    let polygons: Vec<&SvgPolygon> = drawing
        .polygons
        .iter()
        .filter(|p| p.points.len() >= 3 && finite(&p.points))
        .collect();

    let mut min = DVec2::splat(f64::INFINITY);
    let mut max = DVec2::splat(f64::NEG_INFINITY);
    let mut widest: f64 = 0.0;
    for line in &polylines {
        widest = widest.max(line.width);
    }
    let points = polylines
        .iter()
        .flat_map(|l| &l.points)
        .chain(polygons.iter().flat_map(|p| &p.points));
    for p in points {
        // Flip y: SVG's y points down.
        let q = DVec2::new(p.x, -p.y);
        min = min.min(q);
        max = max.max(q);
    }
    if !min.is_finite() {
        min = DVec2::ZERO;
        max = DVec2::ONE;
    }
    let extent = (max - min).max_element();
    let pad = if extent > 0.0 {
        extent * MARGIN + widest / 2.0
    } else {
        widest.max(1.0)
    };
    let origin = min - DVec2::splat(pad);
    let size = (max - min) + DVec2::splat(2.0 * pad);
    let decimals = decimals_for(size.max_element());
    let number = |v: f64| format_number(v, decimals);
    let pixels = size * (PICTURE_SIZE / size.max_element());

    let mut svg = String::new();
    let _ = writeln!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{}" height="{}" viewBox="{} {} {} {}">"#,
        format_number(pixels.x, 1),
        format_number(pixels.y, 1),
        number(origin.x),
        number(origin.y),
        number(size.x),
        number(size.y)
    );
    let points_text = |points: &[DVec2]| {
        let mut text = String::new();
        for (k, p) in points.iter().enumerate() {
            if k > 0 {
                text.push(' ');
            }
            let _ = write!(text, "{},{}", number(p.x), number(-p.y));
        }
        text
    };
    if !polylines.is_empty() {
        svg.push_str("<g fill=\"none\" stroke-linecap=\"round\" stroke-linejoin=\"round\">\n");
        for line in &polylines {
            let _ = writeln!(
                svg,
                r#"<polyline points="{}" stroke="{}"{} stroke-width="{}"/>"#,
                points_text(&line.points),
                rgb(line.color),
                opacity("stroke-opacity", line.color),
                format_width(line.width, decimals)
            );
        }
        svg.push_str("</g>\n");
    }
    for polygon in &polygons {
        let _ = writeln!(
            svg,
            r#"<polygon points="{}" fill="{}"{}/>"#,
            points_text(&polygon.points),
            rgb(polygon.color),
            opacity("fill-opacity", polygon.color)
        );
    }
    svg.push_str("</svg>\n");
    svg
}

/// Decimals that resolve about a millionth of `size`.
fn decimals_for(size: f64) -> usize {
    if !(size.is_finite() && size > 0.0) {
        return 6;
    }
    (6.0 - size.log10().ceil()).clamp(0.0, 12.0) as usize
}

/// `v` with at most `decimals` decimals, without trailing zeros, never `-0`.
fn format_number(v: f64, decimals: usize) -> String {
    let mut text = format!("{v:.decimals$}");
    if text.contains('.') {
        let trimmed = text.trim_end_matches('0').trim_end_matches('.').len();
        text.truncate(trimmed);
    }
    if text == "-0" {
        text = "0".to_string();
    }
    text
}

/// A line width: like other numbers, but a width too thin for the resolution keeps one
/// significant digit instead of vanishing.
fn format_width(width: f64, decimals: usize) -> String {
    let text = format_number(width, decimals);
    if text != "0" {
        return text;
    }
    let digits = (-width.log10().floor()).clamp(0.0, 300.0) as usize;
    format_number(width, digits)
}

/// `#rrggbb`, without alpha.
fn rgb(color: Color) -> String {
    Color { a: 1.0, ..color }.to_hex()
}

/// An opacity attribute for colours that are not opaque.
fn opacity(attribute: &str, color: Color) -> String {
    if color.a >= 1.0 {
        String::new()
    } else {
        format!(
            r#" {attribute}="{}""#,
            format_number(f64::from(color.a.max(0.0)), 3)
        )
    }
}
