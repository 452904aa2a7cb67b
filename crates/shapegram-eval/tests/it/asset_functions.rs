//! CGA's asset and image functions through the derivation's assets: sorting files by how they
//! fit the scope (`assetsSortSize`, `assetsSortRatio`, `imagesSortRatio`), the choosing
//! functions built on them, `imageInfo`, `assetNamingInfo(s)` and `assetMetadata`.

use crate::common;

use std::sync::Arc;

use shapegram_eval::{AssetLoader, AssetNaming, DeriveError, DeriveOptions, derive};
use shapegram_geom::{DVec3, Mesh, primitives};

/// A pool of box assets, images and one named tree; searches find all of one kind.
struct Pool;

impl AssetLoader for Pool {
    fn load(&self, path: &str) -> Result<Arc<Mesh>, String> {
        let size = match path {
            "cube_1.obj" => DVec3::splat(1.0),
            "cube_2.obj" => DVec3::splat(2.0),
            "cube_4.obj" => DVec3::splat(4.0),
            "slab.obj" => DVec3::new(4.0, 1.0, 2.0),
            "tree.obj" => DVec3::new(2.0, 6.0, 2.0),
            other => return Err(format!("no mesh `{other}`")),
        };
        Ok(Arc::new(primitives::cuboid(size)))
    }

    fn search(&self, query: &str) -> Result<Vec<Arc<str>>, String> {
        let found: &[&str] = match query {
            "boxes" => &[
                "cube_1.obj",
                "cube_2.obj",
                "cube_4.obj",
                "notes.txt",
                "slab.obj",
            ],
            "images" => &["square.png", "tall.jpg", "tree.obj", "wide.png"],
            "twins" => &["twin_a.png", "twin_b.png", "wide.png"],
            _ => &[],
        };
        Ok(found.iter().map(|&f| Arc::from(f)).collect())
    }

    fn image_size(&self, path: &str) -> Result<(u32, u32), String> {
        match path {
            "wide.png" => Ok((400, 100)),
            "square.png" => Ok((256, 256)),
            "tall.jpg" => Ok((100, 300)),
            "twin_a.png" => Ok((200, 100)),
            "twin_b.png" => Ok((400, 200)),
            other => Err(format!("no image `{other}`")),
        }
    }

    fn naming(&self, path: &str) -> Result<Arc<AssetNaming>, String> {
        match path {
            "tree.obj" => Ok(Arc::new(AssetNaming {
                groups: vec!["Trunk".into(), "Crown".into()],
                materials: vec!["Bark".into(), "Leaves".into()],
            })),
            other => Err(format!("no mesh `{other}`")),
        }
    }
}

/// What `grammar` prints, derived on a `w` × `d` lot with the [`Pool`].
fn prints(grammar: &str, w: f64, d: f64) -> Vec<String> {
    derive_with(grammar, w, d).unwrap().prints
}

fn derive_with(grammar: &str, w: f64, d: f64) -> Result<shapegram_eval::Derivation, DeriveError> {
    let options = DeriveOptions {
        assets: Some(Arc::new(Pool)),
        ..DeriveOptions::default()
    };
    derive(&common::compile(grammar), &[common::lot(w, d)], &options)
}

/// The error of deriving `grammar`, with the text its span covers.
fn error(grammar: &str) -> (String, String) {
    let e = derive_with(grammar, 3.0, 3.0).unwrap_err();
    let span = e.span.expect("the error has a place");
    (
        e.message,
        grammar[span.start as usize..span.end as usize].to_owned(),
    )
}

#[test]
fn assets_sort_by_how_much_they_would_be_scaled() {
    // A 3 × 3 lot: along x and z the 4 m cube scales by 0.75, the 2 m cube and the slab's
    // z by 1.5, the 1 m cube by 3; the text file is no mesh and takes no part.
    let p = prints(
        "const all = \"cube_1.obj;cube_2.obj;cube_4.obj;slab.obj;notes.txt;\"\n\
         Lot --> print(assetsSortSize(all, xz, 0)) print(assetsSortSize(all, \"xz\", 0.3)) \
         print(assetsSortSize([\"cube_1.obj\", \"slab.obj\", \"cube_2.obj\"], xz, 0.5)) \
         print(assetsSortSize(all, x, 0)) X.",
        3.0,
        3.0,
    );
    assert_eq!(
        p,
        [
            "cube_4.obj;cube_2.obj;slab.obj;cube_1.obj;",
            "cube_4.obj;",
            "[slab.obj,cube_2.obj]",
            "cube_4.obj;slab.obj;cube_2.obj;cube_1.obj;",
        ]
    );
}

#[test]
fn assets_sort_by_how_close_their_proportions_are() {
    // A 6 × 3 lot is twice as long as deep, as the 4 × 2 slab; the cubes are all square.
    let p = prints(
        "const all = \"cube_1.obj;cube_2.obj;slab.obj;notes.txt;\"\n\
         Lot --> print(assetsSortRatio(all, xz)) print(assetsSortRatio(all, xyz)) \
         print(assetBestRatio(\"boxes\", \"xz\")) print(assetApproxRatio(\"boxes\", \"xz\", 1)) X.",
        6.0,
        3.0,
    );
    assert_eq!(
        p,
        [
            "slab.obj;cube_1.obj;cube_2.obj;",
            // Against a flat scope no asset has its proportions along y: all equally far.
            "cube_1.obj;cube_2.obj;slab.obj;",
            "slab.obj",
            "slab.obj",
        ]
    );
}

#[test]
fn choosing_functions_take_the_best_or_draw_among_the_best() {
    // Ten 3 × 3 cells: by size the 4 m cube fits best, then the 2 m cube.
    let p = prints(
        "Lot --> split(x) { 3 : Cell }*\n\
         Cell --> print(assetBestSize(\"boxes\", \"xz\")) print(assetApproxSize(\"boxes\", \"xz\", 2)) \
         print(assetFitSize(\"boxes\", \"xz\", 0.6)) print(assetApproxSize(\"boxes\", \"xz\", 0)) \
         print(assetFitSize(\"boxes\", \"xz\", 0.1)) X.",
        30.0,
        3.0,
    );
    assert_eq!(p.len(), 50);
    let column = |k: usize| -> Vec<&str> { p.iter().skip(k).step_by(5).map(|s| &**s).collect() };
    assert!(column(0).iter().all(|&f| f == "cube_4.obj"), "{p:?}");
    let approx = column(1);
    assert!(
        approx
            .iter()
            .all(|f| ["cube_4.obj", "cube_2.obj"].contains(f)),
        "{approx:?}"
    );
    assert!(approx.contains(&"cube_4.obj") && approx.contains(&"cube_2.obj"));
    let fit = column(2);
    assert!(
        fit.iter()
            .all(|f| ["cube_4.obj", "cube_2.obj", "slab.obj"].contains(f)),
        "{fit:?}"
    );
    assert!(fit.contains(&"slab.obj"), "{fit:?}");
    // `n` below 1 leaves no asset, as does a scale error nothing meets.
    assert!(column(3).iter().all(|f| f.is_empty()));
    assert!(column(4).iter().all(|f| f.is_empty()));
}

#[test]
fn images_sort_by_width_to_height_against_two_scope_axes() {
    // An 8 × 2 lot: along x and z the 4:1 image fits, the square one less, the tall one
    // least; across (zx) the tall one fits best. The mesh found by the search is no image.
    let p = prints(
        "Lot --> print(imagesSortRatio(\"wide.png;square.png;tall.jpg;tree.obj;\", xz)) \
         print(imagesSortRatio([\"wide.png\", \"tall.jpg\"], zx)) \
         print(imageBestRatio(\"images\", \"xz\")) print(imageApproxRatio(\"images\", \"zx\", 1)) \
         print(imageInfo(\"wide.png\", sx)) print(imageInfo(\"tall.jpg\", \"sy\")) X.",
        8.0,
        2.0,
    );
    assert_eq!(
        p,
        [
            "wide.png;square.png;tall.jpg;",
            "[tall.jpg,wide.png]",
            "wide.png",
            "tall.jpg",
            "400",
            "300"
        ]
    );
}

#[test]
fn the_best_image_is_drawn_among_images_of_the_same_ratio() {
    // Two 2:1 images fit a 4 × 2 cell equally: each cell draws one of them.
    let p = prints(
        "Lot --> split(x) { 4 : Cell }*\nCell --> print(imageBestRatio(\"twins\", \"xz\")) \
         print(imageApproxRatio(\"twins\", \"xz\", 0)) print(imageApproxRatio(\"twins\", \"xz\", 0.5)) X.",
        40.0,
        2.0,
    );
    let best: Vec<&str> = p.iter().step_by(3).map(|s| &**s).collect();
    assert!(
        best.contains(&"twin_a.png") && best.contains(&"twin_b.png"),
        "{best:?}"
    );
    assert!(!best.contains(&"wide.png"));
    // With `n` of 0 or less the draw is among every image, between 0 and 1 among none.
    let any: Vec<&str> = p.iter().skip(1).step_by(3).map(|s| &**s).collect();
    assert!(any.contains(&"wide.png"), "{any:?}");
    assert!(p.iter().skip(2).step_by(3).all(|s| s.is_empty()), "{p:?}");
}

#[test]
fn naming_info_lists_group_and_material_names() {
    let p = prints(
        "Lot --> print(assetNamingInfo(\"tree.obj\", m)) print(assetNamingInfos(\"tree.obj\", g)) \
         print(assetNamingInfo(\"builtin:cube\", g)) print(size(assetNamingInfos(\"tree.obj\", \"m\"))) X.",
        3.0,
        3.0,
    );
    assert_eq!(p, ["Bark;Leaves;", "[Trunk,Crown]", "", "2"]);
}

#[test]
fn metadata_falls_back_to_the_default_for_every_key() {
    let p = prints(
        "Lot --> print(assetMetadata(\"tree.obj\", \"author\", \"nobody\")) \
         print(assetMetadata(\"builtin:cube\", \"height\", 2.5)) print(assetMetadata(\"tree.obj\", \"tags\", [true])) X.",
        3.0,
        3.0,
    );
    assert_eq!(p, ["nobody", "2.5", "[true]"]);
}

#[test]
fn bad_selectors_and_missing_files_are_errors_at_their_argument() {
    let cases = [
        (
            "Lot --> print(assetsSortSize(\"a.obj;\", xw, 0)) X.",
            "`xw`: expected the scope axes x, y, z, xy, xz, yz or xyz",
            "xw",
        ),
        (
            "Lot --> print(assetBestRatio(\"boxes\", \"x\")) X.",
            "`x`: expected the scope axes xy, xz, yz or xyz",
            "\"x\"",
        ),
        (
            "Lot --> print(imageApproxRatio(\"images\", \"xx\", 2)) X.",
            "`xx`: expected the scope axes xy, xz, yx, yz, zx or zy",
            "\"xx\"",
        ),
        (
            "Lot --> print(imageInfo(\"wide.png\", sz)) X.",
            "`sz`: expected sx (the width) or sy (the height)",
            "sz",
        ),
        (
            "Lot --> print(imageInfo(\"gone.png\", sx)) X.",
            "no image `gone.png`",
            "\"gone.png\"",
        ),
        (
            "Lot --> print(assetNamingInfo(\"tree.obj\", t)) X.",
            "`t`: expected g (group names) or m (material names)",
            "t",
        ),
        (
            "Lot --> print(assetNamingInfo(\"gone.obj\", g)) X.",
            "cannot read the asset `gone.obj`: no mesh `gone.obj`",
            "\"gone.obj\"",
        ),
        (
            "Lot --> print(assetMetadata(\"gone.obj\", \"k\", 1)) X.",
            "cannot read the asset `gone.obj`: no mesh `gone.obj`",
            "\"gone.obj\"",
        ),
        (
            "Lot --> print(assetsSortRatio(3, xz)) X.",
            "expected a list of files (a string list or a string array), found a number",
            "3",
        ),
        (
            "Lot --> print(assetApproxSize(\"boxes\", \"xz\", float(\"inf\"))) X.",
            "this evaluates to a number that is not finite (NaN or infinity)",
            "float(\"inf\")",
        ),
    ];
    for (grammar, message, at) in cases {
        assert_eq!(
            error(grammar),
            (message.to_owned(), at.to_owned()),
            "{grammar}"
        );
    }
}

#[test]
fn without_files_the_functions_say_so() {
    let e = common::try_run(
        "Lot --> print(imageInfo(\"a.png\", sx)) X.",
        common::lot(3.0, 3.0),
        &DeriveOptions::default(),
    )
    .unwrap_err();
    assert_eq!(
        e.message,
        "cannot read the image `a.png`: this derivation reads no files"
    );
}

#[test]
fn the_functions_compile_without_warnings() {
    let diagnostics = common::compile_errors(
        "Lot --> print(assetsSortSize(\"a;\", xz, 0)) print(assetsSortRatio(\"a;\", xyz)) \
         print(imagesSortRatio(\"a;\", yx)) print(assetFitSize(\"*\", \"x\", 0)) \
         print(imageInfo(\"a.png\", sx)) print(assetNamingInfo(\"a.obj\", m)) \
         print(assetMetadata(\"a.obj\", \"k\", 0)) X.",
    );
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    let wrong = common::compile_errors("Lot --> print(imageInfo(\"a.png\")) X.");
    assert!(
        wrong[0].contains("wrong number of arguments for `imageInfo`")
            && wrong[0].contains("imageInfo(filePath, sx | sy)"),
        "{wrong:?}"
    );
}
