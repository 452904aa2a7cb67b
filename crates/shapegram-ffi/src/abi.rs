//! The `extern "C"` functions and the types they share with C.
//!
//! The functions take raw pointers without being `unsafe fn`: they are made for C, whose
//! callers see no `unsafe`; the header states what each pointer must be, and the functions
//! check all they can (NULL, UTF-8, lengths). Rust callers use the `shapegram-runtime` crate
//! instead.
#![allow(clippy::not_unsafe_ptr_arg_deref)]

use std::cell::UnsafeCell;
use std::ffi::{CStr, CString, c_char};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use shapegram_eval::{DeriveControl, Value};
use shapegram_export::Buffers;
use shapegram_geom::DVec3;

use crate::status::{Error, sg_status};
use shapegram_runtime::{Grammar, Kind, Settings};

/// Detect the kind from the file name's extension, else read the text as CGA (or the
/// notation it is written in: `.mul`, `.sgl`, goal grammars).
pub const SG_KIND_AUTO: u32 = 0;
/// CGA (`.cga`).
pub const SG_KIND_CGA: u32 = 1;
/// The notation of Müller et al. 2006 (`.mul`).
pub const SG_KIND_MUL: u32 = 2;
/// SGL (`.sgl`).
pub const SG_KIND_SGL: u32 = 3;
/// A goal grammar, in its native or Michelangelo notation (`.goal`).
pub const SG_KIND_GOAL: u32 = 4;
/// An L-system (`.lsys`).
pub const SG_KIND_LSYSTEM: u32 = 5;
/// An implicit cave grammar (`.cave`).
pub const SG_KIND_CAVE: u32 = 6;
/// A compiled topological grammar (`.grammar`, JSON).
pub const SG_KIND_TOPO: u32 = 7;

/// One part of the derived model: its colour and where its vertices and indices are in the
/// buffers of [`sg_mesh`].
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct sg_part {
    /// The part's name (UTF-8, NUL-terminated): the rule or symbol that made it, or the
    /// colour's name for merged parts. Owned by the handle, valid as long as the buffers.
    pub name: *const c_char,
    /// sRGB colour with straight alpha, each channel in 0..1, in RGBA order.
    pub color: [f32; 4],
    /// The part's first vertex (in vertices, not floats).
    pub first_vertex: u32,
    /// How many vertices the part has.
    pub vertex_count: u32,
    /// The part's first index.
    pub first_index: u32,
    /// How many indices the part has (three per triangle).
    pub index_count: u32,
    /// The part's colour map, as an index for `sg_state_texture`; -1 when it has none.
    pub texture: i32,
    /// The material's name the grammar set (`set(material.name, …)`; UTF-8, NUL-terminated,
    /// owned by the handle like `name`); NULL when it set none.
    pub material: *const c_char,
}

/// The mesh buffers of the last derivation. The pointers point into memory the handle owns:
/// they stay valid and unchanged until the next call on the handle that loads, derives or frees
/// it; the caller never frees them. With no triangles they may be NULL (with their counts 0).
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct sg_mesh {
    /// `3 * vertex_count` floats: x, y, z of each vertex (y is up, metres).
    pub positions: *const f32,
    /// `3 * vertex_count` floats: the unit normal of each vertex.
    pub normals: *const f32,
    /// Number of vertices.
    pub vertex_count: usize,
    /// `index_count` indices, three per triangle, counter-clockwise seen from the front,
    /// counted from the first vertex of `positions` (so one draw call can draw every part).
    pub indices: *const u32,
    /// Number of indices.
    pub index_count: usize,
    /// `part_count` parts, in model order.
    pub parts: *const sg_part,
    /// Number of parts.
    pub part_count: usize,
    /// `2 * vertex_count` floats: u, v of each vertex as glTF has them (v down: the image's
    /// top row at v = 0), when some part is textured (0, 0 for the others' vertices); NULL when
    /// none is.
    pub uvs: *const f32,
    /// Number of textures (`sg_state_texture` reads them).
    pub texture_count: usize,
    /// `joint_count` joints of the model's skeletons, skeleton after skeleton, parents before
    /// their children; NULL when the model has no skeleton.
    pub joints: *const sg_joint,
    /// Number of joints.
    pub joint_count: usize,
    /// `vertex_count` joint indices, when some part hangs from a joint: the joint in `joints`
    /// that moves each vertex rigidly, `SG_NO_JOINT` for a vertex that hangs from none; NULL
    /// when no part hangs from a joint.
    pub vertex_joints: *const u32,
}

/// In `sg_mesh.vertex_joints`: the vertex hangs from no joint.
pub const SG_NO_JOINT: u32 = u32::MAX;

/// A joint of a skeleton: its transformation relative to its parent, in the derived pose and at
/// rest, its pose and its limits (the GLB's joint extras, `docs/kinematics.md`). The vertices
/// are in the derived pose: a host that poses joint `j` anew moves the vertices hanging from it
/// by `world_new(j) * inverse(world(j))`, where `world` multiplies the `translation`/`rotation`
/// frames from the root down.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct sg_joint {
    /// The section's name (UTF-8, NUL-terminated), the same when the grammar is derived again:
    /// its rule and a hash (`Boom_5d7b45`). Owned by the handle, valid as long as the buffers.
    pub name: *const c_char,
    /// The skeleton it belongs to (one per lot that has one).
    pub skeleton: u32,
    /// Its parent's index in `sg_mesh.joints`; -1 for a skeleton's root.
    pub parent: i32,
    /// Translation relative to the parent in the derived pose, metres.
    pub translation: [f32; 3],
    /// Rotation relative to the parent in the derived pose: a unit quaternion, x, y, z, w.
    pub rotation: [f32; 4],
    /// Translation relative to the parent at rest, metres.
    pub rest_translation: [f32; 3],
    /// Rotation relative to the parent at rest, x, y, z, w.
    pub rest_rotation: [f32; 4],
    /// The pose: degrees about the joint's x, then y, then z axis (fixed axes); the derived
    /// transformation is rest, then the pose's translation, then this rotation.
    pub pose_rotation_deg: [f32; 3],
    /// The pose's translation along the joint's axes, metres.
    pub pose_translation_m: [f32; 3],
    /// Per axis x, y, z: least and greatest rotation, degrees.
    pub rotation_limits_deg: [[f32; 2]; 3],
    /// Per axis x, y, z: least and greatest translation, metres.
    pub translation_limits_m: [[f32; 2]; 3],
}

/// An image a textured part is drawn with: its path as the grammar named it and the file's
/// bytes (PNG or JPEG, undecoded). Owned by the handle, valid as long as the buffers.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct sg_texture {
    /// The path (UTF-8, NUL-terminated).
    pub path: *const c_char,
    /// `size` bytes of the image file.
    pub data: *const u8,
    /// Number of bytes.
    pub size: usize,
}

/// A grammar, the settings of its derivation and the buffers of its last derivation
/// (the thesis's GrammarState). Opaque: made by `sg_state_new`, freed by `sg_state_free`.
#[allow(non_camel_case_types)]
pub struct sg_state {
    /// Set while a call other than `sg_state_cancel`/`sg_state_progress` runs on the handle.
    busy: AtomicBool,
    /// Shared with the running derivation.
    control: Arc<DeriveControl>,
    /// Only touched by the call holding `busy`.
    inner: UnsafeCell<Inner>,
}

// SAFETY: `inner` is only reached by the one call that holds `busy` (see `with_state`); the
// other fields are atomics, safe to share.
unsafe impl Sync for sg_state {}

/// What a handle holds.
struct Inner {
    grammar: Option<Grammar>,
    settings: Settings,
    buffers: Buffers,
    parts: Vec<sg_part>,
    /// The parts' names, which `parts` point into.
    names: Vec<CString>,
    /// The parts' material names, which `parts` point into.
    materials: Vec<Option<CString>>,
    /// The textures' paths, which `sg_state_texture` points into.
    texture_paths: Vec<CString>,
    joints: Vec<sg_joint>,
    /// The joints' names, which `joints` point into.
    joint_names: Vec<CString>,
    /// The files and folders of the library goal grammars load with, read at each load.
    library_paths: Vec<PathBuf>,
    /// The grammars of the library given as text: name and text.
    library_texts: Vec<(String, String)>,
    last_error: CString,
}

/// What `sg_state_last_error` says of a handle another thread is using.
const BUSY_MESSAGE: &CStr = c"the handle is busy: another call on it is running";
/// What `sg_state_last_error` says of NULL.
const NULL_MESSAGE: &CStr = c"the handle is NULL";

/// Runs `call` on the handle's contents, as the only call on it, with panics caught; records
/// the error message and returns the status.
fn with_state(
    state: *const sg_state,
    call: impl FnOnce(&mut Inner) -> Result<(), Error>,
) -> sg_status {
    // SAFETY: a non-NULL handle comes from `sg_state_new` and is not freed yet (the header's
    // contract).
    let Some(state) = (unsafe { state.as_ref() }) else {
        return sg_status::SG_NULL_ARGUMENT;
    };
    if state
        .busy
        .compare_exchange(false, true, Ordering::Acquire, Ordering::Relaxed)
        .is_err()
    {
        return sg_status::SG_BUSY;
    }
    // SAFETY: holding `busy`, this call is the only one that reaches `inner`.
    let inner = unsafe { &mut *state.inner.get() };
    let outcome = catch_unwind(AssertUnwindSafe(|| call(&mut *inner)));
    let error = match outcome {
        Ok(Ok(())) => None,
        Ok(Err(error)) => Some(error),
        Err(panic) => {
            // A derivation cut short leaves no half-made buffers behind.
            inner.clear_results();
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| (*s).to_owned())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a panic".to_owned());
            Some(Error::new(
                sg_status::SG_INTERNAL,
                format!("internal error (please report it): {what}"),
            ))
        }
    };
    let status = match error {
        None => {
            inner.last_error = CString::default();
            sg_status::SG_OK
        }
        Some(error) => {
            inner.last_error = CString::new(error.message.replace('\0', "\\0")).unwrap_or_default();
            error.status
        }
    };
    state.busy.store(false, Ordering::Release);
    status
}

/// A string argument: NULL and bytes that are not UTF-8 are errors naming `what`.
fn text<'a>(pointer: *const c_char, what: &str) -> Result<&'a str, Error> {
    if pointer.is_null() {
        return Err(Error::new(
            sg_status::SG_NULL_ARGUMENT,
            format!("{what} is NULL"),
        ));
    }
    // SAFETY: the caller passes a NUL-terminated string (the header's contract).
    let bytes = unsafe { CStr::from_ptr(pointer) };
    bytes.to_str().map_err(|e| {
        Error::new(
            sg_status::SG_INVALID_UTF8,
            format!(
                "{what} is not UTF-8 (invalid byte at offset {})",
                e.valid_up_to()
            ),
        )
    })
}

/// A string argument that may be NULL (`None`).
fn optional_text<'a>(pointer: *const c_char, what: &str) -> Result<Option<&'a str>, Error> {
    if pointer.is_null() {
        Ok(None)
    } else {
        text(pointer, what).map(Some)
    }
}

/// The kind of `SG_KIND_…`; `None` for `SG_KIND_AUTO`.
fn kind(kind: u32) -> Result<Option<Kind>, Error> {
    use shapegram_syntax::Dialect;
    Ok(Some(match kind {
        SG_KIND_AUTO => return Ok(None),
        SG_KIND_CGA => Kind::Shape(Some(Dialect::Cga)),
        SG_KIND_MUL => Kind::Shape(Some(Dialect::Muller2006)),
        SG_KIND_SGL => Kind::Shape(Some(Dialect::Sgl)),
        SG_KIND_GOAL => Kind::Shape(None),
        SG_KIND_LSYSTEM => Kind::LSystem,
        SG_KIND_CAVE => Kind::Cave,
        SG_KIND_TOPO => Kind::Topo,
        other => return Err(Error::invalid(format!("unknown grammar kind {other}"))),
    }))
}

impl Inner {
    /// Loads `text`, named `name`, as `kind` with the handle's library, and takes it.
    fn load_text(&mut self, name: &str, text: &str, kind: Option<Kind>) -> Result<(), Error> {
        let library = self.library(name)?;
        let grammar = Grammar::load_with_library(name, text, kind, &library)?;
        self.load(grammar);
        Ok(())
    }

    /// The library of the grammar named `main`: the goal grammars of the files and folders
    /// added, read now as `--library` reads them (`main` left out), then the texts added, in
    /// the order they were.
    fn library(&self, main: &str) -> Result<Vec<(String, String)>, Error> {
        let mut library = shapegram_runtime::read_library(&self.library_paths, Path::new(main))?;
        library.extend(self.library_texts.iter().cloned());
        Ok(library)
    }

    /// Takes a newly loaded grammar: the attributes set for the old one go, and so do the old
    /// results.
    fn load(&mut self, grammar: Grammar) {
        self.grammar = Some(grammar);
        self.settings.attrs.clear();
        self.clear_results();
    }

    /// Forgets the last derivation's buffers, keeping their memory.
    fn clear_results(&mut self) {
        self.buffers.clear();
        self.parts.clear();
        self.joints.clear();
    }

    fn set_attr(&mut self, name: *const c_char, value: Value) -> Result<(), Error> {
        let name = text(name, "the attribute name")?;
        let grammar = self.grammar.as_ref().ok_or_else(no_grammar)?;
        grammar.check_attr(name, &value)?;
        self.settings.attrs.retain(|(n, _)| n != name);
        self.settings.attrs.push((name.to_owned(), value));
        Ok(())
    }
}

fn no_grammar() -> Error {
    Error::new(sg_status::SG_NO_GRAMMAR, "no grammar is loaded")
}

/// Makes a handle with no grammar, seed 0, no attributes, no lots (the default 20 × 30 lot) and
/// the grammar's own generations. Free it with `sg_state_free`. Returns NULL only if the
/// library fails internally.
#[unsafe(no_mangle)]
pub extern "C" fn sg_state_new() -> *mut sg_state {
    catch_unwind(|| {
        let control = Arc::new(DeriveControl::new());
        Box::into_raw(Box::new(sg_state {
            busy: AtomicBool::new(false),
            control: Arc::clone(&control),
            inner: UnsafeCell::new(Inner {
                grammar: None,
                settings: Settings {
                    seed: 0,
                    attrs: Vec::new(),
                    lots: Vec::new(),
                    generations: None,
                    control,
                },
                buffers: Buffers::default(),
                parts: Vec::new(),
                names: Vec::new(),
                materials: Vec::new(),
                texture_paths: Vec::new(),
                joints: Vec::new(),
                joint_names: Vec::new(),
                library_paths: Vec::new(),
                library_texts: Vec::new(),
                last_error: CString::default(),
            }),
        }))
    })
    .unwrap_or(std::ptr::null_mut())
}

/// Frees a handle and everything it owns (its buffers and messages: pointers read from it
/// become invalid). NULL is accepted and does nothing. Returns `SG_BUSY`, freeing nothing, while
/// another thread runs a call on the handle; freeing a handle twice, or while another thread
/// may still call `sg_state_cancel` or `sg_state_progress` on it, is undefined behaviour.
#[unsafe(no_mangle)]
pub extern "C" fn sg_state_free(state: *mut sg_state) -> sg_status {
    if state.is_null() {
        return sg_status::SG_OK;
    }
    // SAFETY: a handle from `sg_state_new`, not freed yet (the header's contract).
    let busy = unsafe { &(*state).busy };
    if busy
        .compare_exchange(false, true, Ordering::Acquire, Ordering::Relaxed)
        .is_err()
    {
        return sg_status::SG_BUSY;
    }
    // SAFETY: as above; holding `busy`, no other call uses it.
    let dropped = catch_unwind(AssertUnwindSafe(|| drop(unsafe { Box::from_raw(state) })));
    match dropped {
        Ok(()) => sg_status::SG_OK,
        Err(_) => sg_status::SG_INTERNAL,
    }
}

/// Loads a grammar from `text` (NUL-terminated UTF-8). `name` (NUL-terminated UTF-8, or NULL
/// for "grammar") names it in messages and, with `kind` = `SG_KIND_AUTO`, tells its kind by its
/// extension. Replaces the loaded grammar (and drops the attributes set for it and the last
/// buffers); seed, lots and generations stay. Grammar errors return `SG_GRAMMAR_ERROR` with
/// every error (`name:line:column`) in `sg_state_last_error`, and keep the old grammar.
/// `name` is also where the grammar is: its imports and the files it inserts (`i("…")`) are
/// found beside it (relative to the current folder), in its CityEngine project and workspace,
/// as `shapegram derive` finds them. A goal grammar loads with the handle's library
/// (`sg_state_add_library_text`, `sg_state_add_library_file`); any other grammar loads only
/// while the library is empty (`SG_GRAMMAR_ERROR` otherwise).
#[unsafe(no_mangle)]
pub extern "C" fn sg_state_load_text(
    state: *mut sg_state,
    text_: *const c_char,
    kind_: u32,
    name: *const c_char,
) -> sg_status {
    with_state(state, |inner| {
        let source = text(text_, "the grammar text")?;
        let name = if name.is_null() {
            "grammar"
        } else {
            text(name, "the grammar name")?
        };
        inner.load_text(name, source, kind(kind_)?)
    })
}

/// Loads a grammar from the file at `path` (NUL-terminated UTF-8), as `sg_state_load_text`
/// does with the path as its name (a byte-order mark is skipped). Reading errors return
/// `SG_IO`; a file that is not UTF-8, `SG_INVALID_UTF8`. Imports and inserted files are found
/// beside it (each read once per loaded grammar, and kept for later derivations). A goal
/// grammar loads with the handle's library, which leaves the file itself out of a folder that
/// holds it. With `SG_KIND_AUTO`, a rule package (`.rpk`) loads as `sg_state_load_package_file`
/// loads it with no rule file named.
#[unsafe(no_mangle)]
pub extern "C" fn sg_state_load_file(
    state: *mut sg_state,
    path: *const c_char,
    kind_: u32,
) -> sg_status {
    with_state(state, |inner| {
        let path = text(path, "the path")?;
        if kind_ == SG_KIND_AUTO && shapegram_runtime::is_package(Path::new(path)) {
            let grammar = Grammar::load_package(Path::new(path), None)?;
            inner.load(grammar);
            return Ok(());
        }
        let bytes = std::fs::read(path)
            .map_err(|e| Error::new(sg_status::SG_IO, format!("cannot read {path}: {e}")))?;
        let source = String::from_utf8(bytes).map_err(|e| {
            Error::new(
                sg_status::SG_INVALID_UTF8,
                format!(
                    "{path} is not UTF-8 (invalid byte at offset {})",
                    e.utf8_error().valid_up_to()
                ),
            )
        })?;
        let source = source.strip_prefix('\u{feff}').unwrap_or(&source);
        inner.load_text(path, source, kind(kind_)?)
    })
}

/// Loads a rule file of the CityEngine rule package (`.rpk`, a 7-Zip archive) at `path`
/// (NUL-terminated UTF-8), as `shapegram derive package.rpk` does: the package is read into
/// memory, and the rule file's imports, inserted assets, textures and tables are read from it.
/// `rule_file` (NUL-terminated UTF-8, or NULL) names the rule file as `--rule-file` does: its
/// path in the package (`rules/a.cga`, `a.cga`, or its compiled `bin/a.cgb`) or its file name;
/// NULL runs the one PRT runs (the source of the package's one compiled rule file, or its one
/// rule source). Replaces the loaded grammar as `sg_state_load_text` does; messages name the
/// rule file `package.rpk!/rules/a.cga`. A package that cannot be read returns `SG_IO`; one
/// that is not a 7-Zip archive or is damaged, holds only compiled rules (`.cgb`), or lacks the
/// rule file named (or holds several, none named), `SG_PACKAGE_ERROR`, the message listing its
/// rule files; grammar errors, `SG_GRAMMAR_ERROR`. The handle's library is not used: packages
/// hold CGA, not goal grammars.
#[unsafe(no_mangle)]
pub extern "C" fn sg_state_load_package_file(
    state: *mut sg_state,
    path: *const c_char,
    rule_file: *const c_char,
) -> sg_status {
    with_state(state, |inner| {
        let path = text(path, "the path")?;
        let rule_file = optional_text(rule_file, "the rule file")?;
        let grammar = Grammar::load_package(Path::new(path), rule_file)?;
        inner.load(grammar);
        Ok(())
    })
}

/// Loads a rule file of a rule package given as the `size` bytes at `data` (copied), as
/// `sg_state_load_package_file` does; `name` (NUL-terminated UTF-8, or NULL for
/// "package.rpk") names the package in messages (`name!/rules/a.cga:3:7`). `data` may be NULL
/// only when `size` is 0.
#[unsafe(no_mangle)]
pub extern "C" fn sg_state_load_package_bytes(
    state: *mut sg_state,
    data: *const u8,
    size: usize,
    name: *const c_char,
    rule_file: *const c_char,
) -> sg_status {
    with_state(state, |inner| {
        let bytes = if size == 0 {
            Vec::new()
        } else if data.is_null() {
            return Err(Error::new(
                sg_status::SG_NULL_ARGUMENT,
                "the package's bytes are NULL",
            ));
        } else {
            // SAFETY: the caller passes `size` readable bytes (the header's contract).
            unsafe { std::slice::from_raw_parts(data, size) }.to_vec()
        };
        let name = optional_text(name, "the package name")?.unwrap_or("package.rpk");
        let rule_file = optional_text(rule_file, "the rule file")?;
        let grammar = Grammar::load_package_bytes(name, bytes, rule_file)?;
        inner.load(grammar);
        Ok(())
    })
}

/// Adds a goal grammar to the library that the goal grammars loaded next derive with (their
/// goals are fulfilled by its rules, as `shapegram derive --library` gives them): `text`
/// (NUL-terminated UTF-8, copied) named `name` (NUL-terminated UTF-8: a file name or path,
/// whose stem names the grammar; messages name it). The library stays for every later load
/// until `sg_state_clear_library`; it is compiled at each load, where its errors come out
/// (`SG_GRAMMAR_ERROR`, with `name:line:column`), as do two library grammars of one stem.
#[unsafe(no_mangle)]
pub extern "C" fn sg_state_add_library_text(
    state: *mut sg_state,
    name: *const c_char,
    text_: *const c_char,
) -> sg_status {
    with_state(state, |inner| {
        let name = text(name, "the library grammar's name")?;
        let source = text(text_, "the library grammar's text")?;
        inner
            .library_texts
            .push((name.to_owned(), source.to_owned()));
        Ok(())
    })
}

/// Adds a file, or a folder of goal grammars, to the library (`path`: NUL-terminated UTF-8),
/// as `shapegram derive --library` takes it: a folder gives every `*.goal` file in it and its
/// subfolders. The files are read at each load, so that a load sees them as they are: those of
/// every file and folder added, sorted by path, each once, without the grammar being loaded,
/// then the texts of `sg_state_add_library_text`. A path that is neither a file nor a folder is
/// `SG_IO` and is not added; a file that cannot be read when a grammar loads, `SG_IO` there.
#[unsafe(no_mangle)]
pub extern "C" fn sg_state_add_library_file(
    state: *mut sg_state,
    path: *const c_char,
) -> sg_status {
    with_state(state, |inner| {
        let path = PathBuf::from(text(path, "the library path")?);
        shapegram_runtime::check_library_path(&path)?;
        inner.library_paths.push(path);
        Ok(())
    })
}

/// Empties the library: goal grammars loaded next derive on their own, and other kinds load
/// again. The loaded grammar keeps the library it was loaded with.
#[unsafe(no_mangle)]
pub extern "C" fn sg_state_clear_library(state: *mut sg_state) -> sg_status {
    with_state(state, |inner| {
        inner.library_paths.clear();
        inner.library_texts.clear();
        Ok(())
    })
}

/// Sets the seed of every random choice (topological grammars use its low 48 bits).
#[unsafe(no_mangle)]
pub extern "C" fn sg_state_set_seed(state: *mut sg_state, seed: u64) -> sg_status {
    with_state(state, |inner| {
        inner.settings.seed = seed;
        Ok(())
    })
}

/// Sets the number of generations: of an L-system (its iterations), of a topological grammar
/// (8 when not set) or of a CGA-style derivation in generations (shapes left become leaves).
/// A negative number goes back to the grammar's own.
#[unsafe(no_mangle)]
pub extern "C" fn sg_state_set_generations(state: *mut sg_state, generations: i32) -> sg_status {
    with_state(state, |inner| {
        inner.settings.generations = u32::try_from(generations).ok();
        Ok(())
    })
}

/// Sets the attribute `name` (NUL-terminated UTF-8) of the loaded grammar to a number.
/// `SG_UNKNOWN_ATTRIBUTE` when the grammar has no such attribute, `SG_ATTRIBUTE_TYPE` when its
/// default is a literal of another type. Loading a grammar clears the attributes set.
#[unsafe(no_mangle)]
pub extern "C" fn sg_state_set_number(
    state: *mut sg_state,
    name: *const c_char,
    value: f64,
) -> sg_status {
    with_state(state, |inner| inner.set_attr(name, Value::Number(value)))
}

/// Sets the attribute `name` to a string (`value`: NUL-terminated UTF-8, copied), as
/// `sg_state_set_number` does.
#[unsafe(no_mangle)]
pub extern "C" fn sg_state_set_string(
    state: *mut sg_state,
    name: *const c_char,
    value: *const c_char,
) -> sg_status {
    with_state(state, |inner| {
        let value = text(value, "the attribute value")?;
        inner.set_attr(name, Value::string(value))
    })
}

/// Sets the attribute `name` to a boolean, as `sg_state_set_number` does.
#[unsafe(no_mangle)]
pub extern "C" fn sg_state_set_bool(
    state: *mut sg_state,
    name: *const c_char,
    value: bool,
) -> sg_status {
    with_state(state, |inner| inner.set_attr(name, Value::Bool(value)))
}

/// Adds a lot: a planar polygon of `corner_count` corners, `3 * corner_count` floats (x, y, z
/// each, y up) read from `xyz` and copied, counter-clockwise seen from above. Without lots,
/// CGA-style grammars derive on a 20 × 30 lot at the origin and goal grammars from their
/// axioms; L-systems, caves and topological grammars ignore lots.
#[unsafe(no_mangle)]
pub extern "C" fn sg_state_add_lot(
    state: *mut sg_state,
    xyz: *const f32,
    corner_count: usize,
) -> sg_status {
    with_state(state, |inner| {
        if xyz.is_null() {
            return Err(Error::new(
                sg_status::SG_NULL_ARGUMENT,
                "the lot's corners are NULL",
            ));
        }
        let floats = corner_count
            .checked_mul(3)
            .ok_or_else(|| Error::invalid("too many corners"))?;
        // SAFETY: the caller passes `3 * corner_count` floats (the header's contract).
        let floats = unsafe { std::slice::from_raw_parts(xyz, floats) };
        let footprint: Vec<DVec3> = floats
            .chunks_exact(3)
            .map(|c| DVec3::new(f64::from(c[0]), f64::from(c[1]), f64::from(c[2])))
            .collect();
        inner.settings.lots.push(shapegram_runtime::lot(footprint)?);
        Ok(())
    })
}

/// Removes every lot added (back to the default lot).
#[unsafe(no_mangle)]
pub extern "C" fn sg_state_clear_lots(state: *mut sg_state) -> sg_status {
    with_state(state, |inner| {
        inner.settings.lots.clear();
        Ok(())
    })
}

/// Derives the loaded grammar with the handle's settings and keeps the result's mesh buffers
/// (read them with `sg_state_mesh`). Blocks until done, cancelled (`SG_CANCELLED`) or failed
/// (`SG_DERIVE_ERROR`); on failure the buffers are empty. Runs on the calling thread (a
/// CGA-style derivation of several lots may use more threads of its own).
#[unsafe(no_mangle)]
pub extern "C" fn sg_state_derive(state: *mut sg_state) -> sg_status {
    with_state(state, |inner| {
        // Cleared, not replaced: a warm handle fills the same memory again.
        inner.clear_results();
        let grammar = inner.grammar.as_ref().ok_or_else(no_grammar)?;
        inner.settings.control.reset();
        let derived = grammar.derive(&inner.settings)?;
        derived.fill(&mut inner.buffers);
        inner.names = inner
            .buffers
            .parts
            .iter()
            .map(|p| CString::new(derived.part_name(p.part).replace('\0', "")).unwrap_or_default())
            .collect();
        inner.materials = inner
            .buffers
            .parts
            .iter()
            .map(|p| {
                let name = derived.part_material(p.part)?;
                Some(CString::new(name.replace('\0', "")).unwrap_or_default())
            })
            .collect();
        inner.parts = inner
            .buffers
            .parts
            .iter()
            .zip(inner.names.iter().zip(&inner.materials))
            .map(|(p, (name, material))| sg_part {
                name: name.as_ptr(),
                color: p.color,
                first_vertex: p.first_vertex,
                vertex_count: p.vertex_count,
                first_index: p.first_index,
                index_count: p.index_count,
                texture: p.texture.map_or(-1, |t| t as i32),
                material: material.as_ref().map_or(std::ptr::null(), |m| m.as_ptr()),
            })
            .collect();
        inner.texture_paths = inner
            .buffers
            .textures
            .iter()
            .map(|t| CString::new(t.path.replace('\0', "")).unwrap_or_default())
            .collect();
        inner.joint_names = inner
            .buffers
            .joints
            .iter()
            .map(|j| CString::new(j.name.replace('\0', "")).unwrap_or_default())
            .collect();
        inner.joints = inner
            .buffers
            .joints
            .iter()
            .zip(&inner.joint_names)
            .map(|(j, name)| sg_joint {
                name: name.as_ptr(),
                skeleton: j.skeleton,
                parent: j.parent.map_or(-1, |p| p as i32),
                translation: j.translation,
                rotation: j.rotation,
                rest_translation: j.rest_translation,
                rest_rotation: j.rest_rotation,
                pose_rotation_deg: j.pose_rotation_deg,
                pose_translation_m: j.pose_translation_m,
                rotation_limits_deg: j.rotation_limits_deg,
                translation_limits_m: j.translation_limits_m,
            })
            .collect();
        Ok(())
    })
}

/// Asks the derivation running on the handle (on another thread) to stop: it returns
/// `SG_CANCELLED` at its next check (CGA-style and goal grammars every 1,024 rule
/// applications, L-systems before each step, caves before each meshing block, topological
/// grammars before each generation). A cancel while no derivation runs has no effect. May be
/// called from any thread at any time before `sg_state_free`.
#[unsafe(no_mangle)]
pub extern "C" fn sg_state_cancel(state: *const sg_state) -> sg_status {
    // SAFETY: a handle from `sg_state_new`, not freed yet (the header's contract).
    match unsafe { state.as_ref() } {
        Some(state) => {
            state.control.cancel();
            sg_status::SG_OK
        }
        None => sg_status::SG_NULL_ARGUMENT,
    }
}

/// Writes to `applications` how many rules the running (or last) derivation has applied, in
/// steps of 1,024 (CGA-style and goal grammars only; others count 0). May be called from any
/// thread at any time before `sg_state_free`, to show progress.
#[unsafe(no_mangle)]
pub extern "C" fn sg_state_progress(state: *const sg_state, applications: *mut u64) -> sg_status {
    // SAFETY: a handle from `sg_state_new`, not freed yet, and a pointer to a u64 or NULL
    // (the header's contract).
    match unsafe { (state.as_ref(), applications.as_mut()) } {
        (Some(state), Some(out)) => {
            *out = state.control.applications();
            sg_status::SG_OK
        }
        _ => sg_status::SG_NULL_ARGUMENT,
    }
}

/// Writes the buffers of the last successful derivation to `*mesh` (all counts 0 before the
/// first, or after a failed one). The pointers are owned by the handle and stay valid until the
/// next `sg_state_load_text`, `sg_state_load_file`, `sg_state_load_package_file`,
/// `sg_state_load_package_bytes`, `sg_state_derive` or `sg_state_free` on it.
#[unsafe(no_mangle)]
pub extern "C" fn sg_state_mesh(state: *mut sg_state, mesh: *mut sg_mesh) -> sg_status {
    with_state(state, |inner| {
        if mesh.is_null() {
            return Err(Error::new(sg_status::SG_NULL_ARGUMENT, "the mesh is NULL"));
        }
        let buffers = &inner.buffers;
        let out = sg_mesh {
            positions: buffers.positions.as_flattened().as_ptr(),
            normals: buffers.normals.as_flattened().as_ptr(),
            vertex_count: buffers.positions.len(),
            indices: buffers.indices.as_ptr(),
            index_count: buffers.indices.len(),
            parts: inner.parts.as_ptr(),
            part_count: inner.parts.len(),
            uvs: if buffers.uvs.is_empty() {
                std::ptr::null()
            } else {
                buffers.uvs.as_flattened().as_ptr()
            },
            texture_count: buffers.textures.len(),
            joints: if inner.joints.is_empty() {
                std::ptr::null()
            } else {
                inner.joints.as_ptr()
            },
            joint_count: inner.joints.len(),
            vertex_joints: if buffers.vertex_joints.is_empty() {
                std::ptr::null()
            } else {
                buffers.vertex_joints.as_ptr()
            },
        };
        // SAFETY: checked non-NULL; the caller passes a writable `sg_mesh`.
        unsafe { mesh.write(out) };
        Ok(())
    })
}

/// Writes texture `index` of the last derivation's buffers (`sg_part.texture`) to `*texture`:
/// its path and image bytes, owned by the handle and valid as long as the buffers. An index at
/// or past `sg_mesh.texture_count` is `SG_INVALID_ARGUMENT`.
#[unsafe(no_mangle)]
pub extern "C" fn sg_state_texture(
    state: *mut sg_state,
    index: usize,
    texture: *mut sg_texture,
) -> sg_status {
    with_state(state, |inner| {
        if texture.is_null() {
            return Err(Error::new(
                sg_status::SG_NULL_ARGUMENT,
                "the texture is NULL",
            ));
        }
        let count = inner.buffers.textures.len();
        let (Some(found), Some(path)) = (
            inner.buffers.textures.get(index),
            inner.texture_paths.get(index),
        ) else {
            return Err(Error::invalid(format!(
                "texture {index}: the buffers have {count}"
            )));
        };
        let image = found.image.as_deref().unwrap_or_default();
        let out = sg_texture {
            path: path.as_ptr(),
            data: image.as_ptr(),
            size: image.len(),
        };
        // SAFETY: checked non-NULL; the caller passes a writable `sg_texture`.
        unsafe { texture.write(out) };
        Ok(())
    })
}

/// The message of the last call on the handle that failed (UTF-8, NUL-terminated; empty after a
/// call that succeeded). Grammar errors name the file, line and column (`house.cga:3:7`). The
/// string is owned by the handle and valid until the next call on it; never NULL (a NULL handle
/// gets a static message, as does a handle another thread is using).
#[unsafe(no_mangle)]
pub extern "C" fn sg_state_last_error(state: *const sg_state) -> *const c_char {
    // SAFETY: a handle from `sg_state_new`, not freed yet (the header's contract).
    let Some(state) = (unsafe { state.as_ref() }) else {
        return NULL_MESSAGE.as_ptr();
    };
    if state
        .busy
        .compare_exchange(false, true, Ordering::Acquire, Ordering::Relaxed)
        .is_err()
    {
        return BUSY_MESSAGE.as_ptr();
    }
    // SAFETY: holding `busy`; the string is only replaced by a later call.
    let message = unsafe { (*state.inner.get()).last_error.as_ptr() };
    state.busy.store(false, Ordering::Release);
    message
}
