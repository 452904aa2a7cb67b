//! Initial shapes (lots) for `shapegram derive`: from `--lot`, then from the OBJ and GeoJSON
//! files `shapegram_runtime::lots` reads, or the default 20 × 30 lot.

use std::path::Path;

use shapegram_eval::InitialShape;
use shapegram_runtime::ErrorKind;

pub use shapegram_runtime::default_lot;
pub use shapegram_runtime::lots::{Collected, Frame, Placing, from_text};

use crate::Failure;
use crate::primitive::parse_points;

/// The lots of `--lot` (in order) and then of each `--lots` file (in order), or the default lot
/// when there are none; with warnings about parts of the files that were skipped. `--lot`
/// takes local metres only.
pub fn collect(
    lot_args: &[String],
    files: &[impl AsRef<Path>],
    placing: Placing,
) -> Result<Collected, Failure> {
    if placing.crs.is_geographic() && !lot_args.is_empty() {
        return Err(Failure::usage(format!(
            "--lot takes local metres: with --crs {} give the lots as a GeoJSON file",
            placing.crs
        )));
    }
    let mut given = Vec::new();
    for text in lot_args {
        let points = parse_points(text, "--lot").map_err(Failure::new)?;
        given.push(InitialShape::from_xz(&points).ok_or_else(|| {
            Failure::new(format!(
                "invalid --lot '{}': the polygon has no area",
                text.escape_debug()
            ))
        })?);
    }
    shapegram_runtime::lots::collect(given, files, placing).map_err(|e| match e.kind {
        // An OBJ file with a geographic CRS: the options do not go together.
        ErrorKind::InvalidArgument => Failure::usage(e.message),
        _ => Failure::new(e.message),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use shapegram_export::tiles::Crs;
    use shapegram_geom::mesh::newell;

    const LOCAL: Placing = Placing {
        crs: Crs::Local,
        recentre: false,
    };

    fn xz(lot: &InitialShape) -> Vec<(f64, f64)> {
        lot.footprint.iter().map(|p| (p.x, p.z)).collect()
    }

    fn up(lot: &InitialShape) -> bool {
        newell(lot.footprint.iter().copied()).y > 0.0
    }

    #[test]
    fn the_default_lot_is_20_by_30_facing_up() {
        let lots = collect(&[], &[] as &[&Path], LOCAL).unwrap().lots;
        let [lot] = lots.as_slice() else {
            panic!("{} lots", lots.len())
        };
        assert!(up(lot));
        let mut corners = xz(lot);
        corners.sort_by(|a, b| a.partial_cmp(b).unwrap());
        assert_eq!(
            corners,
            [(0.0, 0.0), (0.0, 30.0), (20.0, 0.0), (20.0, 30.0)]
        );
        assert!(lot.footprint.iter().all(|p| p.y == 0.0));
    }

    #[test]
    fn lots_come_from_every_lot_option_in_order() {
        let Collected { lots, warnings, .. } = collect(
            &["0,0 1,0 1,1".to_owned(), "5,5 6,5 6,7 5,7".to_owned()],
            &[] as &[&Path],
            LOCAL,
        )
        .unwrap();
        assert!(warnings.is_empty());
        assert_eq!(lots.len(), 2);
        assert_eq!(lots[1].footprint.len(), 4);
        assert!(lots.iter().all(up));
    }

    #[test]
    fn bad_lot_options_are_one_line_errors() {
        let message = |text: &str| {
            collect(&[text.to_owned()], &[] as &[&Path], LOCAL)
                .unwrap_err()
                .message
                .unwrap()
        };
        assert_eq!(
            message("0,0 1,x 1,1"),
            "invalid --lot: '1,x' is not an x,z pair of numbers like 4,2.5"
        );
        assert!(message("0,0 1,0").starts_with("invalid --lot '0,0 1,0': expected at least three"));
        assert_eq!(
            message("0,0 1,0 2,0"),
            "invalid --lot '0,0 1,0 2,0': the polygon has no area"
        );
    }
}
