//! Every kind of grammar through the ABI from its file, with imports and inserted files found
//! beside it as `shapegram derive` finds them.

use std::ffi::{CStr, CString};
use std::path::{Path, PathBuf};

use shapegram_ffi::*;

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

/// Loads and derives `path` with a new handle: the derive status, the last message and the
/// counts of vertices, indices and parts.
fn derive_file(path: &Path, kind: u32) -> (sg_status, String, [usize; 3]) {
    let state = sg_state_new();
    let path = CString::new(path.to_str().unwrap()).unwrap();
    let mut status = sg_state_load_file(state, path.as_ptr(), kind);
    if status == sg_status::SG_OK {
        status = sg_state_derive(state);
    }
    let message = unsafe { CStr::from_ptr(sg_state_last_error(state)) }
        .to_str()
        .unwrap()
        .to_owned();
    let mut mesh = std::mem::MaybeUninit::<sg_mesh>::uninit();
    assert_eq!(sg_state_mesh(state, mesh.as_mut_ptr()), sg_status::SG_OK);
    let mesh = unsafe { mesh.assume_init() };
    let counts = [mesh.vertex_count, mesh.index_count, mesh.part_count];
    assert_eq!(sg_state_free(state), sg_status::SG_OK);
    (status, message, counts)
}

#[test]
fn every_kind_of_grammar_derives_from_its_file() {
    for (file, kind) in [
        ("house.cga", SG_KIND_AUTO),
        ("rotating_tower.mul", SG_KIND_AUTO),
        ("sgl_medieval_house.sgl", SG_KIND_AUTO),
        ("chairs/chair.goal", SG_KIND_AUTO),
        ("bush-3d.lsys", SG_KIND_AUTO),
        ("tree-3d.lsys", SG_KIND_LSYSTEM),
        ("grotto.cave", SG_KIND_AUTO),
        ("topo_house.grammar", SG_KIND_AUTO),
        ("park.cga", SG_KIND_CGA),
    ] {
        let (status, message, [vertices, indices, parts]) = derive_file(&example(file), kind);
        assert_eq!(status, sg_status::SG_OK, "{file}: {message}");
        assert!(
            vertices > 0 && indices > 0 && parts > 0,
            "{file}: {vertices} vertices, {indices} indices, {parts} parts"
        );
    }
}

#[test]
fn a_file_inserted_by_the_grammar_is_found_beside_it_and_nowhere_else() {
    let park = example("park.cga");
    let (_, _, beside) = derive_file(&park, SG_KIND_AUTO);
    // The same text in a folder without the L-system files: the insert fails with its place.
    let folder = std::env::temp_dir().join(format!("shapegram-ffi-park-{}", std::process::id()));
    std::fs::create_dir_all(&folder).unwrap();
    let alone = folder.join("park.cga");
    std::fs::copy(&park, &alone).unwrap();
    let (status, message, counts) = derive_file(&alone, SG_KIND_AUTO);
    assert_eq!(status, sg_status::SG_DERIVE_ERROR);
    assert!(message.contains("tree-3d.lsys"), "{message}");
    assert!(message.contains("park.cga:21:"), "{message}");
    assert_eq!(counts, [0, 0, 0]);
    // With the tree beside it (and the shrub), it derives as in the examples folder.
    for plant in ["tree-3d.lsys", "shrub-3d.lsys"] {
        std::fs::copy(example(plant), folder.join(plant)).unwrap();
    }
    let (status, message, counts) = derive_file(&alone, SG_KIND_AUTO);
    std::fs::remove_dir_all(&folder).unwrap();
    assert_eq!(status, sg_status::SG_OK, "{message}");
    assert_eq!(counts, beside);
}

#[test]
fn imports_are_read_beside_the_grammar_and_their_errors_name_their_file() {
    let folder = std::env::temp_dir().join(format!("shapegram-ffi-import-{}", std::process::id()));
    std::fs::create_dir_all(&folder).unwrap();
    std::fs::write(folder.join("walls.cga"), "Base --> extrude(4) Mass.\n").unwrap();
    let main = folder.join("main.cga");
    std::fs::write(
        &main,
        "import w : \"walls.cga\"\n@StartRule\nLot --> w.Base\n",
    )
    .unwrap();
    let (status, message, counts) = derive_file(&main, SG_KIND_AUTO);
    assert_eq!(status, sg_status::SG_OK, "{message}");
    // A box: six quads of four corners.
    assert_eq!(counts, [24, 36, 1]);
    std::fs::write(folder.join("walls.cga"), "Base --> extrude(4 Mass.\n").unwrap();
    let (status, message, _) = derive_file(&main, SG_KIND_AUTO);
    std::fs::remove_dir_all(&folder).unwrap();
    assert_eq!(status, sg_status::SG_GRAMMAR_ERROR);
    assert!(message.contains("walls.cga:1:"), "{message}");
}

#[test]
fn a_topological_grammar_brings_its_uvs_and_images() {
    let state = sg_state_new();
    let path = CString::new(example("topo_brick_house.grammar").to_str().unwrap()).unwrap();
    assert_eq!(
        sg_state_load_file(state, path.as_ptr(), SG_KIND_AUTO),
        sg_status::SG_OK
    );
    assert_eq!(sg_state_derive(state), sg_status::SG_OK);
    let mut mesh = std::mem::MaybeUninit::<sg_mesh>::uninit();
    assert_eq!(sg_state_mesh(state, mesh.as_mut_ptr()), sg_status::SG_OK);
    let mesh = unsafe { mesh.assume_init() };
    assert!(!mesh.uvs.is_null());
    let parts = unsafe { std::slice::from_raw_parts(mesh.parts, mesh.part_count) };
    let name = |p: *const std::ffi::c_char| {
        (!p.is_null()).then(|| unsafe { CStr::from_ptr(p) }.to_str().unwrap())
    };
    let materials: Vec<_> = parts
        .iter()
        .map(|p| (name(p.material), p.texture))
        .collect();
    assert_eq!(
        materials,
        [
            (Some("Brick"), 0),
            (Some("RoofTiles"), 1),
            (Some("Stone"), -1),
            (Some("Stone"), -1),
            (None, -1),
            (Some("Brick"), 0),
            (Some("Glass"), -1),
        ]
    );
    assert_eq!(mesh.texture_count, 2);
    let mut texture = std::mem::MaybeUninit::<sg_texture>::uninit();
    assert_eq!(
        sg_state_texture(state, 1, texture.as_mut_ptr()),
        sg_status::SG_OK
    );
    let texture = unsafe { texture.assume_init() };
    assert_eq!(name(texture.path), Some("textures/tiles.png"));
    let image = unsafe { std::slice::from_raw_parts(texture.data, texture.size) };
    assert_eq!(image, std::fs::read(example("textures/tiles.png")).unwrap());
    // The gable's top corner (0, 7, 4) facing −x: (z / 1.2, 1 − y / 0.6) in brick tiles.
    let positions = unsafe { std::slice::from_raw_parts(mesh.positions, 3 * mesh.vertex_count) };
    let uvs = unsafe { std::slice::from_raw_parts(mesh.uvs, 2 * mesh.vertex_count) };
    let gable =
        parts[0].first_vertex as usize..(parts[0].first_vertex + parts[0].vertex_count) as usize;
    let top = gable
        .into_iter()
        .find(|&v| positions[3 * v..3 * v + 3] == [0.0, 7.0, 4.0])
        .unwrap();
    assert_eq!(
        uvs[2 * top..2 * top + 2],
        [(4.0 / 1.2) as f32, (1.0 - 7.0 / 0.6) as f32]
    );
    assert_eq!(sg_state_free(state), sg_status::SG_OK);
}
