//! CGA's asset and image functions: their names and signatures, the axis selectors they take,
//! and how they rank files against the scope. The evaluator (`expr/assets.rs`) reads the files;
//! everything here is arithmetic on sizes.
//!
//! CityEngine's library writes the choosing functions on top of three sorting ones, and so does
//! Shapegram: `assetBestSize(q, axes)` is the first of `assetsSortSize(fileSearch(q), axes, 0)`,
//! `assetApproxSize(q, axes, n)` draws one of its first `n`, `assetFitSize(q, axes, e)` one of
//! those within the scale error `e`; the ratio and image functions likewise.

use std::cmp::Ordering;

use shapegram_geom::DVec3;

/// An asset or image function.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum AssetFn {
    /// `assetInfo(path, sx | … | tz)`: the asset's bounding box.
    Info,
    /// `assetNamingInfo(path, g | m)`: group or material names as a string list.
    NamingInfo,
    /// `assetNamingInfos(path, g | m)`: the same as an array.
    NamingInfos,
    /// `assetMetadata(path, key, default)`.
    Metadata,
    /// `assetsSortSize(files, axes, maxScaleError)`.
    SortSize,
    /// `assetsSortRatio(files, axes)`.
    SortRatio,
    /// `assetBestSize(query, axes)`.
    BestSize,
    /// `assetApproxSize(query, axes, n)`.
    ApproxSize,
    /// `assetFitSize(query, axes, maxScaleError)`.
    FitSize,
    /// `assetBestRatio(query, axes)`.
    BestRatio,
    /// `assetApproxRatio(query, axes, n)`.
    ApproxRatio,
    /// `imageInfo(path, sx | sy)`: the image's pixel size.
    ImageInfo,
    /// `imagesSortRatio(files, axes)`.
    ImagesSortRatio,
    /// `imageBestRatio(query, axes)`.
    ImageBestRatio,
    /// `imageApproxRatio(query, axes, n)`.
    ImageApproxRatio,
}

impl AssetFn {
    const ALL: [(&'static str, AssetFn, usize, &'static str); 15] = [
        (
            "assetInfo",
            Self::Info,
            2,
            "assetInfo(filePath, sx | sy | sz | tx | ty | tz)",
        ),
        (
            "assetNamingInfo",
            Self::NamingInfo,
            2,
            "assetNamingInfo(filePath, g | m)",
        ),
        (
            "assetNamingInfos",
            Self::NamingInfos,
            2,
            "assetNamingInfos(filePath, g | m)",
        ),
        (
            "assetMetadata",
            Self::Metadata,
            3,
            "assetMetadata(filePath, key, defaultValue)",
        ),
        (
            "assetsSortSize",
            Self::SortSize,
            3,
            "assetsSortSize(filePathList | filePaths, x | y | z | xy | xz | yz | xyz, maxScaleError)",
        ),
        (
            "assetsSortRatio",
            Self::SortRatio,
            2,
            "assetsSortRatio(filePathList | filePaths, xy | xz | yz | xyz)",
        ),
        (
            "assetBestSize",
            Self::BestSize,
            2,
            "assetBestSize(searchQuery, \"x\" | \"xz\" | … | \"xyz\")",
        ),
        (
            "assetApproxSize",
            Self::ApproxSize,
            3,
            "assetApproxSize(searchQuery, \"x\" | \"xz\" | … | \"xyz\", n)",
        ),
        (
            "assetFitSize",
            Self::FitSize,
            3,
            "assetFitSize(searchQuery, \"x\" | \"xz\" | … | \"xyz\", maxScaleError)",
        ),
        (
            "assetBestRatio",
            Self::BestRatio,
            2,
            "assetBestRatio(searchQuery, \"xy\" | \"xz\" | \"yz\" | \"xyz\")",
        ),
        (
            "assetApproxRatio",
            Self::ApproxRatio,
            3,
            "assetApproxRatio(searchQuery, \"xy\" | \"xz\" | \"yz\" | \"xyz\", n)",
        ),
        (
            "imageInfo",
            Self::ImageInfo,
            2,
            "imageInfo(filePath, sx | sy)",
        ),
        (
            "imagesSortRatio",
            Self::ImagesSortRatio,
            2,
            "imagesSortRatio(filePathList | filePaths, xy | xz | yx | yz | zx | zy)",
        ),
        (
            "imageBestRatio",
            Self::ImageBestRatio,
            2,
            "imageBestRatio(searchQuery, \"xy\" | \"xz\" | \"yx\" | \"yz\" | \"zx\" | \"zy\")",
        ),
        (
            "imageApproxRatio",
            Self::ImageApproxRatio,
            3,
            "imageApproxRatio(searchQuery, \"xy\" | \"xz\" | \"yx\" | \"yz\" | \"zx\" | \"zy\", n)",
        ),
    ];

    /// Every asset function's name.
    pub fn names() -> impl Iterator<Item = &'static str> {
        Self::ALL.iter().map(|e| e.0)
    }

    /// The function of this name.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().find(|e| e.0 == name).map(|e| e.1)
    }

    fn entry(self) -> &'static (&'static str, AssetFn, usize, &'static str) {
        Self::ALL
            .iter()
            .find(|e| e.1 == self)
            .expect("every asset function is listed")
    }

    /// The number of arguments (each function has one form).
    pub fn arity(self) -> usize {
        self.entry().2
    }

    /// The signature shown in hints.
    pub fn signature(self) -> &'static str {
        self.entry().3
    }
}

/// The scope axes a size selector (`x`, `xz`, `xyz`, …) names, or `None` for another word.
pub(crate) fn size_axes(word: &str) -> Option<&'static [usize]> {
    Some(match word {
        "x" => &[0],
        "y" => &[1],
        "z" => &[2],
        "xy" => &[0, 1],
        "xz" => &[0, 2],
        "yz" => &[1, 2],
        "xyz" => &[0, 1, 2],
        _ => return None,
    })
}

/// The pairs of scope axes whose ratios an asset ratio selector (`xy`, `xz`, `yz`, `xyz`)
/// compares, or `None` for another word.
pub(crate) fn ratio_pairs(word: &str) -> Option<&'static [(usize, usize)]> {
    Some(match word {
        "xy" => &[(0, 1)],
        "xz" => &[(0, 2)],
        "yz" => &[(1, 2)],
        "xyz" => &[(0, 1), (0, 2), (1, 2)],
        _ => return None,
    })
}

/// The scope axes an image's width and height stand for under an image ratio selector
/// (`xz`: the width along x, the height along z), or `None` for another word.
pub(crate) fn image_axes(word: &str) -> Option<(usize, usize)> {
    let mut axes = word.chars().map(|c| match c {
        'x' => Some(0),
        'y' => Some(1),
        'z' => Some(2),
        _ => None,
    });
    match (axes.next()??, axes.next()??, axes.next()) {
        (a, b, None) if a != b => Some((a, b)),
        _ => None,
    }
}

/// How far an asset of size `asset` is from fitting the scope of size `scope` along `axes`:
/// the largest, over the axes, of how much `i()` would scale it (`|scope / asset − 1|`, 0.1
/// for ten percent either way), so that a `maxScaleError` of `e` keeps the assets whose
/// misfit is at most `e`. An axis the asset is flat along fits only a flat scope.
pub(crate) fn size_misfit(asset: DVec3, scope: DVec3, axes: &[usize]) -> f64 {
    axes.iter()
        .map(|&a| match (asset[a], scope[a]) {
            (s, t) if s == t => 0.0,
            (0.0, _) => f64::INFINITY,
            (s, t) => (t / s - 1.0).abs(),
        })
        .fold(0.0, f64::max)
}

/// How far the proportions `size` are from the scope's `scope` over the axis `pairs`: the sum
/// of `|ln(size ratio / scope ratio)|`, so a shape twice too long and one twice too short are
/// equally far. Proportions with a zero side fit only the same zero side.
pub(crate) fn ratio_misfit(size: DVec3, scope: DVec3, pairs: &[(usize, usize)]) -> f64 {
    pairs
        .iter()
        .map(|&(a, b)| {
            let (own, wanted) = (size[a] * scope[b], size[b] * scope[a]);
            if own == wanted {
                0.0
            } else if own == 0.0 || wanted == 0.0 {
                f64::INFINITY
            } else {
                (own / wanted).ln().abs()
            }
        })
        .sum()
}

/// The files in order of their misfit, best first; files of equal misfit keep their order
/// (the search's, alphabetical).
pub(crate) fn ranked<T>(mut scored: Vec<(f64, T)>) -> Vec<(f64, T)> {
    scored.sort_by(|a, b| a.0.partial_cmp(&b.0).unwrap_or(Ordering::Equal));
    scored
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn selectors_name_the_axes_of_the_reference_and_nothing_else() {
        assert_eq!(size_axes("xz"), Some(&[0, 2][..]));
        assert_eq!(size_axes("zx"), None);
        assert_eq!(ratio_pairs("xyz").map(<[_]>::len), Some(3));
        assert_eq!(ratio_pairs("x"), None);
        assert_eq!(image_axes("zy"), Some((2, 1)));
        assert_eq!(image_axes("xx"), None);
        assert_eq!(image_axes("xyz"), None);
        assert_eq!(image_axes("x"), None);
        assert_eq!(AssetFn::from_name("imageInfo"), Some(AssetFn::ImageInfo));
        assert_eq!(AssetFn::ApproxSize.arity(), 3);
    }

    #[test]
    fn size_misfit_is_the_largest_scaling_over_the_axes() {
        let asset = DVec3::new(2.0, 4.0, 5.0);
        let scope = DVec3::new(2.2, 3.0, 5.0);
        assert!((size_misfit(asset, scope, &[0]) - 0.1).abs() < 1e-12);
        assert_eq!(size_misfit(asset, scope, &[0, 1, 2]), 0.25);
        assert_eq!(size_misfit(asset, scope, &[2]), 0.0);
        let flat = DVec3::new(2.0, 0.0, 5.0);
        assert_eq!(
            size_misfit(flat, DVec3::new(2.0, 0.0, 5.0), &[0, 1, 2]),
            0.0
        );
        assert_eq!(size_misfit(flat, scope, &[1]), f64::INFINITY);
    }

    #[test]
    fn ratio_misfit_is_symmetric_in_too_long_and_too_short() {
        let scope = DVec3::new(4.0, 0.0, 2.0);
        let long = ratio_misfit(DVec3::new(8.0, 1.0, 2.0), scope, &[(0, 2)]);
        let short = ratio_misfit(DVec3::new(2.0, 1.0, 2.0), scope, &[(0, 2)]);
        assert!((long - 2f64.ln()).abs() < 1e-12, "{long}");
        assert!((short - long).abs() < 1e-12);
        assert_eq!(
            ratio_misfit(DVec3::new(6.0, 9.0, 3.0), scope, &[(0, 2)]),
            0.0
        );
        assert_eq!(ratio_misfit(DVec3::ONE, scope, &[(0, 1)]), f64::INFINITY);
        assert_eq!(
            ratio_misfit(DVec3::ONE, DVec3::ONE, &[(0, 1), (0, 2), (1, 2)]),
            0.0
        );
    }

    #[test]
    fn ranking_is_stable_among_equals() {
        let order: Vec<&str> = ranked(vec![
            (1.0, "b"),
            (0.5, "c"),
            (1.0, "a"),
            (f64::INFINITY, "d"),
        ])
        .into_iter()
        .map(|(_, f)| f)
        .collect();
        assert_eq!(order, ["c", "b", "a", "d"]);
    }
}
