//! `Format`, `save` and `load`: extensions, files on disk and error messages that name them.

use crate::common;

use std::path::Path;

use common::*;
use shapegram_export::{Error, ExportOptions, Format, load, save};
use shapegram_geom::Color;

#[test]
fn formats_by_extension() {
    assert_eq!(
        Format::from_path(Path::new("a/b.glb")).unwrap(),
        Format::Glb
    );
    assert_eq!(Format::from_path(Path::new("B.GLB")).unwrap(), Format::Glb);
    assert_eq!(Format::from_path(Path::new("x.Obj")).unwrap(), Format::Obj);
    assert_eq!(Format::from_path(Path::new("x.stl")).unwrap(), Format::Stl);
    for format in [Format::Glb, Format::Obj, Format::Stl] {
        let path = format!("model.{}", format.extension());
        assert_eq!(Format::from_path(Path::new(&path)).unwrap(), format);
    }
    let error = Format::from_path(Path::new("x.fbx")).unwrap_err();
    assert!(matches!(&error, Error::UnknownFormat(p) if p == Path::new("x.fbx")));
    assert_eq!(
        error.to_string(),
        "unknown file format 'x.fbx': use .glb, .obj or .stl"
    );
    assert!(Format::from_path(Path::new("glb")).is_err());
    assert!(Format::from_path(Path::new("model.glb.gz")).is_err());
}

#[test]
fn save_and_load_every_format() {
    let dir = scratch_dir("save-load");
    let model = sample_model();
    let options = ExportOptions {
        group_by_part: true,
        ..ExportOptions::default()
    };

    let glb = dir.join("model.glb");
    save(&model, &glb, &options).unwrap();
    let back = load(&glb).unwrap();
    assert_eq!(back.parts.len(), 6);
    assert_eq!(back.parts[4].color.to_hex(), GLASS.to_hex());

    let obj = dir.join("Model.OBJ");
    save(&model, &obj, &options).unwrap();
    let mtl = dir.join("Model.mtl");
    let obj_text = std::fs::read_to_string(&obj).unwrap();
    assert!(obj_text.contains("\nmtllib Model.mtl\n"));
    assert!(
        std::fs::read_to_string(&mtl)
            .unwrap()
            .contains("newmtl color_ff0000")
    );
    // With the MTL beside it, colours come back from Kd and d.
    let back = load(&obj).unwrap();
    let colours: Vec<Color> = back.parts.iter().map(|p| p.color).collect();
    assert_eq!(colours, [RED, BLUE, RED, GREEN, GLASS, GREY]);
    assert_eq!(back.parts[0].name, "front_wall");
    // Without it, the geometry still loads, in the default colour.
    std::fs::remove_file(&mtl).unwrap();
    let back = load(&obj).unwrap();
    assert_eq!(back.parts.len(), 6);
    assert!(back.parts.iter().all(|p| p.color == Color::default()));

    let stl = dir.join("model.stl");
    save(&model, &stl, &options).unwrap();
    let back = load(&stl).unwrap();
    let triangles: usize = model.parts.iter().map(|p| p.mesh.triangulate().len()).sum();
    assert_eq!(back.parts[0].mesh.face_count(), triangles);

    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn file_errors_name_the_path() {
    let dir = scratch_dir("errors");
    let model = sample_model();
    let options = ExportOptions::default();

    let missing = dir.join("no/such/dir/out.glb");
    let error = save(&model, &missing, &options).unwrap_err();
    assert_eq!(
        error.to_string(),
        format!(
            "cannot write {}: No such file or directory",
            missing.display()
        )
    );
    assert!(std::error::Error::source(&error).is_some());

    let error = load(&dir.join("absent.stl")).unwrap_err();
    assert_eq!(
        error.to_string(),
        format!(
            "cannot read {}: No such file or directory",
            dir.join("absent.stl").display()
        )
    );

    let unknown = save(&model, &dir.join("out.fbx"), &options).unwrap_err();
    assert!(unknown.to_string().starts_with("unknown file format '"));

    let bad = dir.join("bad.glb");
    std::fs::write(&bad, garbage(64, 1)).unwrap();
    assert_eq!(
        load(&bad).unwrap_err().to_string(),
        format!(
            "broken GLB file {}: not a GLB file (it does not start with 'glTF')",
            bad.display()
        )
    );

    let binary_obj = dir.join("bad.obj");
    std::fs::write(&binary_obj, [0xff, 0xfe, 0x00]).unwrap();
    let message = load(&binary_obj).unwrap_err().to_string();
    assert!(
        message.starts_with(&format!(
            "broken OBJ file {}: not UTF-8 text",
            binary_obj.display()
        )),
        "{message}"
    );

    std::fs::remove_dir_all(&dir).unwrap();
}
