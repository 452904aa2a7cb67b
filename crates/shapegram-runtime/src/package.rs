//! CityEngine rule packages (`.rpk`) as a host loads them: read whole into memory from a file
//! or from bytes, a rule file chosen as `shapegram derive package.rpk` chooses it (or named, as
//! `--rule-file` names it), its imports, assets and textures read from inside the package.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use shapegram_load::{Files, PackageError, RulePackage};
use shapegram_syntax::Dialect;

use crate::error::Error;
use crate::grammar::{Grammar, Origin};

/// A rule package read into memory, from which grammars load.
#[derive(Clone)]
pub struct Package(Arc<RulePackage>);

impl Package {
    /// Reads the package at `path`. A file that cannot be read is an error of kind
    /// [`crate::ErrorKind::Io`]; one that is not a 7-Zip archive, or a damaged one, of kind
    /// [`crate::ErrorKind::Package`].
    pub fn open(path: &Path) -> Result<Package, Error> {
        let name = path.display().to_string();
        let bytes = std::fs::read(path)
            .map_err(|e| Error::io(format!("cannot read the rule package {name}: {e}")))?;
        Self::from_bytes(&name, bytes)
    }

    /// Reads a package from its bytes; `name` (its file name or path) names it in messages.
    pub fn from_bytes(name: &str, bytes: Vec<u8>) -> Result<Package, Error> {
        RulePackage::from_bytes(name.to_owned(), bytes)
            .map(|package| Package(Arc::new(package)))
            .map_err(package_error)
    }

    /// The package's name as given.
    pub fn name(&self) -> &str {
        self.0.name()
    }

    /// The rule files a grammar can load from (`rules/**/*.cga`), sorted; an error of kind
    /// [`crate::ErrorKind::Package`] when it holds none, or only compiled rules (`.cgb`).
    pub fn rule_files(&self) -> Result<Vec<String>, Error> {
        self.0
            .runnable_sources()
            .map(|sources| sources.into_iter().map(str::to_owned).collect())
            .map_err(package_error)
    }

    /// The rule file `requested` names (its path in the package, `rules/a.cga` or `a.cga`, or
    /// its compiled file `bin/a.cgb`), else the one `shapegram derive` runs: the source of the
    /// package's one compiled rule file, as PRT runs it, or its one rule source. Which cannot be
    /// found or chosen is an error of kind [`crate::ErrorKind::Package`] listing the rule files.
    pub fn rule_file(&self, requested: Option<&str>) -> Result<String, Error> {
        self.0.rule_file(requested).map_err(package_error)
    }

    /// Loads rule file `requested` (see [`Package::rule_file`]) as CGA, with its imports and
    /// assets read from the package; its errors are named `package.rpk!/rules/a.cga:line:column`.
    pub fn load(&self, requested: Option<&str>) -> Result<Grammar, Error> {
        let entry = PathBuf::from(self.rule_file(requested)?);
        let files = Files::Package(Arc::clone(&self.0));
        let read = shapegram_load::read_in(&files, &entry).map_err(Error::io)?;
        let origin = Origin::Package(Arc::clone(&self.0), entry);
        Grammar::load_shape(read.source, Some(Dialect::Cga), Vec::new(), origin)
    }
}

impl Grammar {
    /// Loads a rule file of the rule package at `path`: [`Package::open`], then
    /// [`Package::load`].
    pub fn load_package(path: &Path, rule_file: Option<&str>) -> Result<Grammar, Error> {
        Package::open(path)?.load(rule_file)
    }

    /// [`Grammar::load_package`] for a package given by its bytes, named `name` in messages.
    pub fn load_package_bytes(
        name: &str,
        bytes: Vec<u8>,
        rule_file: Option<&str>,
    ) -> Result<Grammar, Error> {
        Package::from_bytes(name, bytes)?.load(rule_file)
    }
}

/// A package's error as the runtime's, its hint in the message. The hint the command line gives
/// names its option; hosts name the rule file their own way, as an argument of the load.
fn package_error(error: PackageError) -> Error {
    let message = match error.hint {
        Some(hint) => format!(
            "{} (hint: {})",
            error.message,
            hint.replace("with --rule-file", "by naming its rule file")
        ),
        None => error.message,
    };
    Error::package(message)
}
