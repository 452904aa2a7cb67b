//! A goal grammar's library through the ABI: added as files, folders and texts, used by every
//! load of a goal grammar until cleared, refused for other grammars, and its errors.

use std::ffi::{CStr, CString, c_char};
use std::path::{Path, PathBuf};

use shapegram_ffi::*;

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

fn c(text: &str) -> CString {
    CString::new(text).unwrap()
}

fn c_path(path: &Path) -> CString {
    c(path.to_str().unwrap())
}

fn last_error(state: *mut sg_state) -> String {
    unsafe { CStr::from_ptr(sg_state_last_error(state)) }
        .to_str()
        .unwrap()
        .to_owned()
}

/// Derives the loaded grammar: the counts of vertices, indices and parts, and the parts'
/// colours as the grammar writes them.
fn derive(state: *mut sg_state) -> ([usize; 3], Vec<String>) {
    assert_eq!(
        sg_state_derive(state),
        sg_status::SG_OK,
        "{}",
        last_error(state)
    );
    let mut mesh = std::mem::MaybeUninit::<sg_mesh>::uninit();
    assert_eq!(sg_state_mesh(state, mesh.as_mut_ptr()), sg_status::SG_OK);
    let mesh = unsafe { mesh.assume_init() };
    let parts = unsafe { std::slice::from_raw_parts(mesh.parts, mesh.part_count) };
    let colors = parts
        .iter()
        .map(|p| {
            let [r, g, b] = [p.color[0], p.color[1], p.color[2]].map(|c| (c * 255.0).round() as u8);
            format!("#{r:02x}{g:02x}{b:02x}")
        })
        .collect();
    (
        [mesh.vertex_count, mesh.index_count, mesh.part_count],
        colors,
    )
}

fn load_chair(state: *mut sg_state) -> sg_status {
    sg_state_load_file(
        state,
        c_path(&example("chairs/chair.goal")).as_ptr(),
        SG_KIND_AUTO,
    )
}

/// The chair's counts with `examples/chairs/materials` as its library, as `shapegram derive
/// examples/chairs/chair.goal --library examples/chairs/materials` makes it (the runtime's
/// tests): 72 triangles in three parts, painted brown by `wood.goal`.
const CHAIR: [usize; 3] = [144, 216, 3];

#[test]
fn the_library_is_used_by_every_load_until_cleared() {
    let state = sg_state_new();
    let materials = c_path(&example("chairs/materials"));
    assert_eq!(
        sg_state_add_library_file(state, materials.as_ptr()),
        sg_status::SG_OK
    );
    assert_eq!(load_chair(state), sg_status::SG_OK, "{}", last_error(state));
    assert_eq!(derive(state), (CHAIR, vec!["#8b5a2b".to_owned(); 3]));
    // Loaded again, with the library still there.
    assert_eq!(load_chair(state), sg_status::SG_OK);
    assert_eq!(derive(state).1, ["#8b5a2b"; 3]);

    // Another kind of grammar is refused while there is a library, and the chair stays.
    let house = example("house.cga");
    let status = sg_state_load_file(state, c_path(&house).as_ptr(), SG_KIND_AUTO);
    assert_eq!(status, sg_status::SG_GRAMMAR_ERROR);
    assert_eq!(
        last_error(state),
        format!(
            "{} is not a goal grammar: a library gives goal grammars their rules",
            house.display()
        )
    );
    assert_eq!(derive(state).1, ["#8b5a2b"; 3]);

    // Without it, the chair's goal `wooden` stays open: the default grey.
    assert_eq!(sg_state_clear_library(state), sg_status::SG_OK);
    assert_eq!(load_chair(state), sg_status::SG_OK);
    assert_eq!(derive(state), (CHAIR, vec!["#cccccc".to_owned(); 3]));
    assert_eq!(
        sg_state_load_file(state, c_path(&house).as_ptr(), SG_KIND_AUTO),
        sg_status::SG_OK
    );
    assert_eq!(sg_state_free(state), sg_status::SG_OK);
}

#[test]
fn library_texts_and_folders_holding_the_grammar_load_with_it() {
    let state = sg_state_new();
    let wood = c("fulfills(wooden) --> color(\"#a0522d\")\n");
    assert_eq!(
        sg_state_add_library_text(state, c("sienna.goal").as_ptr(), wood.as_ptr()),
        sg_status::SG_OK
    );
    let chair = std::fs::read_to_string(example("chairs/chair.goal")).unwrap();
    let status = sg_state_load_text(
        state,
        c(&chair).as_ptr(),
        SG_KIND_GOAL,
        c("chair.goal").as_ptr(),
    );
    assert_eq!(status, sg_status::SG_OK, "{}", last_error(state));
    assert_eq!(derive(state), (CHAIR, vec!["#a0522d".to_owned(); 3]));
    // The chair's own folder: its file is left out, so its name `chair` is not taken twice.
    assert_eq!(sg_state_clear_library(state), sg_status::SG_OK);
    let folder = c_path(&example("chairs"));
    assert_eq!(
        sg_state_add_library_file(state, folder.as_ptr()),
        sg_status::SG_OK
    );
    assert_eq!(load_chair(state), sg_status::SG_OK, "{}", last_error(state));
    assert_eq!(derive(state).0, CHAIR);
    assert_eq!(sg_state_free(state), sg_status::SG_OK);
}

#[test]
fn an_error_in_a_library_grammar_is_a_grammar_error_in_its_file() {
    let state = sg_state_new();
    let paint = c("// paints boxes\nfulfills(box) --> color(\"#ff0000\"\n");
    assert_eq!(
        sg_state_add_library_text(state, c("lib/paint.goal").as_ptr(), paint.as_ptr()),
        sg_status::SG_OK
    );
    assert_eq!(load_chair(state), sg_status::SG_GRAMMAR_ERROR);
    let message = last_error(state);
    assert!(
        message.starts_with("error: unclosed `(`\n") && message.contains("--> lib/paint.goal:2:24"),
        "{message}"
    );
    // Two grammars of one name.
    assert_eq!(sg_state_clear_library(state), sg_status::SG_OK);
    let wood = c("fulfills(wooden) --> color(\"#8b5a2b\")\n");
    for name in ["a/wood.goal", "b/wood.goal"] {
        let status = sg_state_add_library_text(state, c(name).as_ptr(), wood.as_ptr());
        assert_eq!(status, sg_status::SG_OK);
    }
    assert_eq!(load_chair(state), sg_status::SG_GRAMMAR_ERROR);
    assert_eq!(
        last_error(state),
        "two library grammars are called `wood`: a/wood.goal and b/wood.goal \
         (grammars are named by their file names: rename one)"
    );
    assert_eq!(sg_state_free(state), sg_status::SG_OK);
}

#[test]
fn bad_library_arguments_are_statuses_with_messages() {
    let state = sg_state_new();
    let text = c("fulfills(wooden) --> color(\"#8b5a2b\")\n");
    let name = c("wood.goal");
    let null = std::ptr::null::<c_char>();
    let calls: [(&dyn Fn() -> sg_status, &str); 3] = [
        (
            &|| sg_state_add_library_text(state, null, text.as_ptr()),
            "the library grammar's name is NULL",
        ),
        (
            &|| sg_state_add_library_text(state, name.as_ptr(), null),
            "the library grammar's text is NULL",
        ),
        (
            &|| sg_state_add_library_file(state, null),
            "the library path is NULL",
        ),
    ];
    for (call, expected) in calls {
        assert_eq!(call(), sg_status::SG_NULL_ARGUMENT);
        assert_eq!(last_error(state), expected);
    }
    let latin1 = CString::new(b"caf\xe9.goal".to_vec()).unwrap();
    assert_eq!(
        sg_state_add_library_file(state, latin1.as_ptr()),
        sg_status::SG_INVALID_UTF8
    );
    assert_eq!(
        last_error(state),
        "the library path is not UTF-8 (invalid byte at offset 3)"
    );
    let missing = c("no/such/library");
    assert_eq!(
        sg_state_add_library_file(state, missing.as_ptr()),
        sg_status::SG_IO
    );
    assert_eq!(
        last_error(state),
        "the library no/such/library is neither a file nor a folder"
    );
    // Nothing was added: the chair loads on its own.
    assert_eq!(load_chair(state), sg_status::SG_OK);
    assert_eq!(derive(state).1, ["#cccccc"; 3]);
    assert_eq!(sg_state_free(state), sg_status::SG_OK);

    let handle = std::ptr::null_mut();
    assert_eq!(
        sg_state_add_library_text(handle, name.as_ptr(), text.as_ptr()),
        sg_status::SG_NULL_ARGUMENT
    );
    assert_eq!(
        sg_state_add_library_file(handle, missing.as_ptr()),
        sg_status::SG_NULL_ARGUMENT
    );
    assert_eq!(sg_state_clear_library(handle), sg_status::SG_NULL_ARGUMENT);
}

/// A library file that disappears after it was added fails the load that reads it, with
/// `SG_IO`, and the old grammar stays.
#[test]
fn a_library_file_gone_before_the_load_is_an_io_error() {
    let folder = std::env::temp_dir().join(format!("shapegram-ffi-library-{}", std::process::id()));
    std::fs::create_dir_all(&folder).unwrap();
    let wood = folder.join("wood.goal");
    std::fs::write(&wood, "fulfills(wooden) --> color(\"#8b5a2b\")\n").unwrap();
    let state = sg_state_new();
    assert_eq!(
        sg_state_add_library_file(state, c_path(&wood).as_ptr()),
        sg_status::SG_OK
    );
    assert_eq!(load_chair(state), sg_status::SG_OK);
    std::fs::remove_dir_all(&folder).unwrap();
    assert_eq!(load_chair(state), sg_status::SG_IO);
    assert_eq!(
        last_error(state),
        format!(
            "the library {} is neither a file nor a folder",
            wood.display()
        )
    );
    assert_eq!(derive(state).1, ["#8b5a2b"; 3]);
    assert_eq!(sg_state_free(state), sg_status::SG_OK);
}
