//! `shapegram.Grammar`: a loaded grammar, its attributes, and its derivation.

use std::mem::take;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyString};
use shapegram_eval::{DeriveControl, InitialShape, Value};
use shapegram_export::Buffers;
use shapegram_geom::DVec3;
use shapegram_runtime::{AttrType, Grammar as Engine, Kind, Settings, read_library};

use crate::errors::{guard, to_py};
use crate::mesh::Mesh;

/// A grammar of any kind the engine runs, loaded and compiled. Immutable: derive it as often as
/// needed, from any thread (each derivation runs without the GIL).
#[pyclass(module = "shapegram", frozen)]
pub struct Grammar {
    engine: Engine,
    name: String,
    /// The buffers of the last derivation, emptied and filled again by the next: reusing their
    /// memory saves a third of a topological house's call. A derivation on another thread at
    /// the same time finds it taken and fills buffers of its own.
    scratch: Mutex<Buffers>,
}

/// One attribute a grammar declares (`attr name = value`), for forms that set it.
#[pyclass(module = "shapegram", frozen, get_all)]
pub struct Attr {
    /// The attribute's name.
    name: String,
    /// `"number"`, `"string"`, `"bool"`, or `None` when its default is an expression.
    r#type: Option<&'static str>,
    /// Its default (a float, str or bool) when it is a literal, else `None`.
    default: Option<Py<PyAny>>,
    /// Where it is declared: `file:line:column`.
    location: String,
}

#[pymethods]
impl Attr {
    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let default = match &self.default {
            Some(value) => value.bind(py).repr()?.to_string(),
            None => "None".to_owned(),
        };
        Ok(format!(
            "Attr(name={:?}, type={}, default={default}, location={:?})",
            self.name,
            self.r#type
                .map_or_else(|| "None".to_owned(), |t| format!("{t:?}")),
            self.location
        ))
    }
}

/// A literal attribute value as a Python object.
fn py_value(py: Python<'_>, value: &Value) -> PyResult<Option<Py<PyAny>>> {
    Ok(Some(match value {
        Value::Number(n) => PyFloat::new(py, *n).into_any().unbind(),
        Value::Str(s) => PyString::new(py, s).into_any().unbind(),
        Value::Bool(b) => PyBool::new(py, *b).to_owned().into_any().unbind(),
        Value::Array(_) => return Ok(None),
    }))
}

/// The kind of grammar a name (`"cga"`, `"lsys"`, …, the extension of its files) says.
fn kind_of(name: Option<&str>) -> PyResult<Option<Kind>> {
    name.map(|name| {
        Kind::of_name(&format!("grammar.{name}")).ok_or_else(|| {
            PyValueError::new_err(format!(
                "unknown grammar kind {name:?} (one of \"cga\", \"mul\", \"sgl\", \"goal\", \
                 \"lsys\", \"cave\", \"grammar\")"
            ))
        })
    })
    .transpose()
}

/// A Python value as an attribute value of `name`: a number, a string or a boolean.
pub fn attr_value(name: &str, value: &Bound<'_, PyAny>) -> PyResult<Value> {
    if value.is_instance_of::<PyBool>() {
        Ok(Value::Bool(value.extract()?))
    } else if value.is_instance_of::<PyInt>() || value.is_instance_of::<PyFloat>() {
        Ok(Value::Number(value.extract()?))
    } else if let Ok(text) = value.cast::<PyString>() {
        Ok(Value::string(text.to_str()?))
    } else {
        Err(PyTypeError::new_err(format!(
            "the attribute `{name}` takes a number, a string or a boolean, not {}",
            value.get_type().name()?
        )))
    }
}

/// Lot `index` of a derivation, from its corners.
fn lot(index: usize, corners: &[[f64; 3]]) -> PyResult<InitialShape> {
    let footprint = corners.iter().map(|&c| DVec3::from_array(c)).collect();
    shapegram_runtime::lot(footprint)
        .map_err(|e| PyValueError::new_err(format!("lot {index}: {}", e.message)))
}

impl Grammar {
    fn new(engine: Engine, name: String) -> Self {
        Self {
            engine,
            name,
            scratch: Mutex::default(),
        }
    }

    /// The loaded engine grammar.
    pub fn engine(&self) -> &Engine {
        &self.engine
    }
}

#[pymethods]
impl Grammar {
    /// Loads the grammar in the file at `path` (its kind from the extension unless `kind` says
    /// it); its imports and inserted files are found beside it. A goal grammar takes a
    /// `library`, as `from_text` does (its own file is left out of a folder that holds it). A
    /// CityEngine rule package (`.rpk`) loads its rule file `rule_file` (`"rules/a.cga"`,
    /// `"a.cga"`), or without it the one PRT runs, as `from_package` does.
    #[staticmethod]
    #[pyo3(signature = (path, kind=None, library=None, rule_file=None))]
    pub fn load(
        py: Python<'_>,
        path: PathBuf,
        kind: Option<&str>,
        library: Option<Vec<PathBuf>>,
        rule_file: Option<&str>,
    ) -> PyResult<Self> {
        if kind.is_none() && shapegram_runtime::is_package(&path) {
            if library.is_some() {
                return Err(PyValueError::new_err(
                    "a rule package holds CGA rule files, which take no library",
                ));
            }
            let engine =
                py.detach(|| guard(|| Engine::load_package(&path, rule_file).map_err(to_py)))?;
            return Ok(Self::new(engine, path.to_string_lossy().into_owned()));
        }
        if rule_file.is_some() {
            return Err(PyValueError::new_err(format!(
                "rule_file picks a rule file of a rule package (.rpk); {} is a grammar file",
                path.display()
            )));
        }
        let text = std::fs::read(&path).map_err(|e| {
            pyo3::exceptions::PyOSError::new_err(format!("cannot read {}: {e}", path.display()))
        })?;
        let name = path.to_string_lossy().into_owned();
        let text = String::from_utf8(text).map_err(|e| {
            PyValueError::new_err(format!(
                "{name} is not UTF-8 (invalid byte at offset {})",
                e.utf8_error().valid_up_to()
            ))
        })?;
        let text = text.strip_prefix('\u{feff}').unwrap_or(&text).to_owned();
        Self::from_text(py, &text, &name, kind, library)
    }

    /// Loads a grammar from `text`, named `name` in messages; `name` also places it (its
    /// imports are found beside it) and, without `kind`, tells its kind by its extension.
    /// `library` (paths of goal grammar files, and of folders searched with their subfolders
    /// for `*.goal` files) gives a goal grammar the rules that fulfil its goals, as `shapegram
    /// derive --library` does; other grammars take none.
    #[staticmethod]
    #[pyo3(signature = (text, name="grammar", kind=None, library=None))]
    fn from_text(
        py: Python<'_>,
        text: &str,
        name: &str,
        kind: Option<&str>,
        library: Option<Vec<PathBuf>>,
    ) -> PyResult<Self> {
        let kind = kind_of(kind)?;
        let paths = library.unwrap_or_default();
        let engine = py.detach(|| {
            guard(|| {
                let library = read_library(&paths, Path::new(name)).map_err(to_py)?;
                Engine::load_with_library(name, text, kind, &library).map_err(to_py)
            })
        })?;
        Ok(Self::new(engine, name.to_owned()))
    }

    /// Loads a rule file of the CityEngine rule package (`.rpk`, a 7-Zip archive) whose bytes
    /// are `data`, named `name` in messages (`town.rpk!/rules/town.cga:3:7`): `rule_file` (its
    /// path in the package or its file name), or without it the one PRT runs (the source of the
    /// package's one compiled rule file, or its one rule source). Imports, assets and textures
    /// are read from the package. A package that cannot be used raises `PackageError`.
    #[staticmethod]
    #[pyo3(signature = (data, name="package.rpk", rule_file=None))]
    fn from_package(
        py: Python<'_>,
        data: &[u8],
        name: &str,
        rule_file: Option<&str>,
    ) -> PyResult<Self> {
        let data = data.to_vec();
        let engine = py.detach(|| {
            guard(|| Engine::load_package_bytes(name, data, rule_file).map_err(to_py))
        })?;
        Ok(Self::new(engine, name.to_owned()))
    }

    /// The name the grammar was loaded under (its path, for a file).
    #[getter]
    fn name(&self) -> &str {
        &self.name
    }

    /// The attributes the grammar declares, in order (none for L-systems, caves and
    /// topological grammars).
    #[getter]
    fn attrs(&self, py: Python<'_>) -> PyResult<Vec<Attr>> {
        self.engine
            .attrs()
            .iter()
            .map(|declared| {
                Ok(Attr {
                    name: declared.name.clone(),
                    r#type: declared.ty().map(|t| match t {
                        AttrType::Number => "number",
                        AttrType::String => "string",
                        AttrType::Bool => "bool",
                    }),
                    default: match &declared.default {
                        Some(value) => py_value(py, value)?,
                        None => None,
                    },
                    location: declared.location.clone(),
                })
            })
            .collect()
    }

    /// Derives the grammar: `seed` for every random choice, `attrs` overriding the grammar's
    /// (a dict of numbers, strings and booleans), `lots` as polygons of `(x, y, z)` corners
    /// (y up, counter-clockwise seen from above; the default 20 × 30 lot when `None`) and
    /// `generations` (the grammar's own when `None`). Releases the GIL while it derives.
    #[pyo3(signature = (*, seed=0, attrs=None, lots=None, generations=None))]
    fn derive(
        &self,
        py: Python<'_>,
        seed: u64,
        attrs: Option<&Bound<'_, PyDict>>,
        lots: Option<Vec<Vec<[f64; 3]>>>,
        generations: Option<u32>,
    ) -> PyResult<Mesh> {
        let mut values = Vec::new();
        for (name, value) in attrs.into_iter().flat_map(|d| d.iter()) {
            let name: String = name.extract().map_err(|_| {
                PyTypeError::new_err(format!(
                    "attribute names are strings, not {}",
                    name.get_type()
                        .name()
                        .map_or_else(|_| "?".into(), |n| n.to_string())
                ))
            })?;
            let value = attr_value(&name, &value)?;
            self.engine.check_attr(&name, &value).map_err(to_py)?;
            values.push((name, value));
        }
        let lots = lots
            .unwrap_or_default()
            .iter()
            .enumerate()
            .map(|(i, corners)| lot(i, corners))
            .collect::<PyResult<Vec<_>>>()?;
        let settings = Settings {
            seed,
            attrs: values,
            lots,
            generations,
            control: Arc::new(DeriveControl::new()),
        };
        let (buffers, names) = py.detach(|| {
            guard(|| {
                let derived = self.engine.derive(&settings).map_err(to_py)?;
                let mut buffers = self
                    .scratch
                    .lock()
                    .map(|mut b| take(&mut *b))
                    .unwrap_or_default();
                derived.fill(&mut buffers);
                let names: Vec<(String, Option<String>)> = buffers
                    .parts
                    .iter()
                    .map(|p| {
                        let material = derived.part_material(p.part).map(str::to_owned);
                        (derived.part_name(p.part).to_owned(), material)
                    })
                    .collect();
                Ok((buffers, names))
            })
        })?;
        let mesh = Mesh::new(py, &buffers, names);
        if let Ok(mut scratch) = self.scratch.lock() {
            *scratch = buffers;
        }
        mesh
    }

    fn __repr__(&self) -> String {
        format!("Grammar({:?})", self.name)
    }
}
