//! Bad input: every reader returns a one-line `Err`, never panics.

use crate::common;

use common::*;
use serde_json::json;
use shapegram_export::{
    ExportOptions, read_glb, read_obj, read_stl, write_glb, write_obj, write_stl,
};
use shapegram_geom::primitives::cuboid;
use shapegram_geom::{DVec3, Model};

fn small_glb() -> Vec<u8> {
    write_glb(
        &Model::single("box", RED, cuboid(DVec3::ONE)),
        &ExportOptions::default(),
    )
}

fn glb_error(bytes: &[u8]) -> String {
    let message = read_glb(bytes).unwrap_err().to_string();
    assert!(message.starts_with("broken GLB file: "), "{message}");
    assert!(!message.contains('\n'), "{message}");
    message
}

#[test]
fn glb_garbage_and_short_input() {
    assert_eq!(
        glb_error(b""),
        "broken GLB file: 0 bytes is too short for a GLB header"
    );
    assert_eq!(
        glb_error(&garbage(1000, 7)),
        "broken GLB file: not a GLB file (it does not start with 'glTF')"
    );
    assert!(glb_error(b"{\"asset\":{\"version\":\"2.0\"}}").contains("does not start with 'glTF'"));
    // A header whose length field is below the header size.
    let mut tiny = b"glTF".to_vec();
    tiny.extend_from_slice(&2u32.to_le_bytes());
    tiny.extend_from_slice(&5u32.to_le_bytes());
    assert_eq!(
        glb_error(&tiny),
        "broken GLB file: the first chunk is not JSON"
    );
    let mut v1 = small_glb();
    v1[4] = 1;
    assert_eq!(
        glb_error(&v1),
        "broken GLB file: GLB version 1 is not supported (only 2)"
    );
}

#[test]
fn glb_truncated_at_every_length() {
    let bytes = small_glb();
    for len in 0..bytes.len() {
        let message = glb_error(&bytes[..len]);
        if len >= 12 {
            assert!(message.contains("truncated"), "{len}: {message}");
        }
    }
    assert!(read_glb(&bytes).is_ok());
}

#[test]
fn glb_chunk_lengths_are_checked() {
    let mut bytes = small_glb();
    // JSON chunk claims more than the file holds.
    bytes[12..16].copy_from_slice(&u32::MAX.to_le_bytes());
    assert!(glb_error(&bytes).contains("runs past the end"));
}

#[test]
fn glb_with_bad_json_or_references() {
    let (json, bin) = split_glb(&small_glb());
    let patched = |edit: &dyn Fn(&mut serde_json::Value)| {
        let mut j = json.clone();
        edit(&mut j);
        glb_error(&frame_glb(&j, &bin))
    };
    let mut not_json = small_glb();
    not_json[20] = b'#';
    assert!(glb_error(&not_json).contains("invalid JSON chunk"));
    assert!(
        patched(&|j| j["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(99))
            .contains("refers to missing accessor 99")
    );
    assert!(patched(&|j| j["nodes"][1]["mesh"] = json!(7)).contains("invalid glTF"));
    assert!(
        patched(&|j| j["accessors"][0]["count"] = json!(1_000_000_000_000u64))
            .contains("POSITION: 1000000000000 elements do not fit")
    );
    assert!(
        patched(&|j| j["accessors"][0]["count"] = json!(0))
            .contains("POSITION: the accessor has no elements")
    );
    assert!(
        patched(&|j| j["accessors"][1]["componentType"] = json!(5126))
            .contains("indices: unexpected type F32 Scalar")
    );
    assert!(
        patched(&|j| j["accessors"][0]["type"] = json!("VEC2"))
            .contains("POSITION: unexpected type")
    );
    assert!(
        patched(&|j| j["bufferViews"][0]["byteStride"] = json!(4))
            .contains("byte stride 4 is less than the element size 12")
    );
    assert!(
        patched(&|j| j["bufferViews"][0]["byteLength"] = json!(100_000))
            .contains("runs past the BIN chunk")
    );
    assert!(
        patched(&|j| j["buffers"][0]["uri"] = json!("data.bin"))
            .contains("external buffers are not supported")
    );
    assert!(
        patched(&|j| j["nodes"][1]["children"] = json!([0]))
            .contains("appears twice in the hierarchy")
    );
    assert!(
        patched(&|j| j["accessors"][1]["count"] = json!(35))
            .contains("35 corners is not a whole number of triangles")
    );
}

#[test]
fn glb_indices_out_of_range() {
    let (json, mut bin) = split_glb(&small_glb());
    // POSITION and indices: a flat box has no NORMAL.
    let view = &json["bufferViews"][1];
    assert_eq!(json["accessors"][1]["componentType"], 5123);
    let at = view["byteOffset"].as_u64().unwrap() as usize;
    bin[at..at + 2].copy_from_slice(&500u16.to_le_bytes());
    assert_eq!(
        glb_error(&frame_glb(&json, &bin)),
        "broken GLB file: mesh 0 primitive 0: index 500 is out of range (8 vertices)"
    );
}

#[test]
fn glb_byte_mutations_never_panic() {
    let bytes = small_glb();
    for (i, value) in garbage(bytes.len(), 3).into_iter().enumerate() {
        for flip in [value, 0xff, 0x00, b'9'] {
            let mut mutated = bytes.clone();
            mutated[i] = flip;
            // Either result is fine; a panic fails the test.
            let _ = read_glb(&mutated);
        }
    }
}

#[test]
fn obj_bad_input() {
    let error = |text: &str| {
        let message = read_obj(text).unwrap_err().to_string();
        assert!(message.starts_with("broken OBJ file: "), "{message}");
        message
    };
    error("v 0 0 0\nv 1 0 0\nf 1 2 3\n");
    error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n");
    error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -9\n");
    error("v 0 zero 0\n");
    error("v 0 0 0\nf 1 2 x\n");
    // Text without geometry is an empty model, not an error.
    assert!(read_obj("hello\nworld\n").unwrap().parts.is_empty());
}

/// Indices past the end (relative ones above all) used to overflow inside the OBJ parser (six
/// inputs found by the `obj` fuzz target): they are errors naming the line.
#[test]
fn obj_indices_out_of_range_are_errors_with_their_line() {
    let triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\n";
    for (face, expected) in [
        (
            "f 1//1 2//1 3//6148914691236517206",
            "line 6: normal index 6148914691236517206 is out of range (1 declared in the file)",
        ),
        (
            "f 1/1 2/1 3/9223372036854775807",
            "line 6: texture coordinate index 9223372036854775807 is out of range (1 declared in the file)",
        ),
        (
            "f 1//-4 2//1 3//1",
            "line 6: normal index -4 is out of range (1 declared before it)",
        ),
        (
            "f 1 2 -4",
            "line 6: vertex index -4 is out of range (3 declared before it)",
        ),
        (
            "l 1 0",
            "line 6: vertex index 0 is out of range (3 declared in the file)",
        ),
    ] {
        let message = read_obj(&format!("{triangle}{face}\n"))
            .unwrap_err()
            .to_string();
        assert_eq!(message, format!("broken OBJ file: {expected}"));
    }
    // Indices within range, relative ones included, read as before.
    let model = read_obj(&format!("{triangle}f -3//1 -2//1 -1//1\n")).unwrap();
    assert_eq!(model.parts[0].mesh.face_count(), 1);
}

#[test]
fn obj_truncations_and_mutations_never_panic() {
    let (obj, _) = write_obj(&sample_model(), &ExportOptions::default(), "m.mtl");
    let bytes = obj.as_bytes();
    for len in (0..bytes.len()).step_by(7) {
        if let Ok(text) = std::str::from_utf8(&bytes[..len]) {
            let _ = read_obj(text);
        }
    }
    for (i, value) in garbage(2000, 11).into_iter().enumerate() {
        let mut mutated = bytes[..2000].to_vec();
        mutated[i] = b" -/0123456789fvo\n"[usize::from(value) % 17];
        let _ = read_obj(std::str::from_utf8(&mutated).unwrap());
    }
}

#[test]
fn stl_bad_input() {
    let error = |bytes: &[u8]| {
        let message = read_stl(bytes).unwrap_err().to_string();
        assert!(message.starts_with("broken STL file: "), "{message}");
        message
    };
    let stl = write_stl(&Model::single("box", RED, cuboid(DVec3::ONE)));
    assert_eq!(
        error(&stl[..stl.len() - 10]),
        "broken STL file: the file ends early"
    );
    assert_eq!(error(&stl[..50]), "broken STL file: the file ends early");
    assert_eq!(error(b""), "broken STL file: the file ends early");
    error(&garbage(1000, 5));
    error(b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0\nendloop\nendfacet\nendsolid x\n");
    for len in 0..stl.len() {
        let _ = read_stl(&stl[..len]);
    }
}
