//! Where `shapegram repo login` keeps its tokens: `credentials.json` in the configuration
//! folder (`$SHAPEGRAM_CONFIG_DIR`, else `$XDG_CONFIG_HOME/shapegram`, else
//! `~/.config/shapegram`), one entry per repository URL, readable by its owner alone (0600) and
//! replaced atomically (written beside it, then renamed), so that a crash never leaves half a
//! file.

use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

/// A repository's stored login.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Login {
    /// The account's name.
    pub name: String,
    /// The token's id on the server (to revoke it at logout).
    pub id: i64,
    /// The secret.
    pub token: String,
}

/// The credentials file's contents.
#[derive(Debug, Default, Serialize, Deserialize)]
pub struct Credentials {
    /// Logins by repository URL.
    pub repositories: BTreeMap<String, Login>,
}

/// The configuration folder, from the environment; `None` when there is no home either.
pub fn config_dir() -> Option<PathBuf> {
    let var = |name| std::env::var_os(name).filter(|v| !v.is_empty());
    if let Some(dir) = var("SHAPEGRAM_CONFIG_DIR") {
        return Some(PathBuf::from(dir));
    }
    if let Some(dir) = var("XDG_CONFIG_HOME") {
        return Some(PathBuf::from(dir).join("shapegram"));
    }
    var("HOME").map(|home| PathBuf::from(home).join(".config").join("shapegram"))
}

/// The credentials file in `dir`.
pub fn file_in(dir: &Path) -> PathBuf {
    dir.join("credentials.json")
}

impl Credentials {
    /// Reads the file; a missing file holds no logins.
    pub fn load(path: &Path) -> Result<Credentials, String> {
        match std::fs::read_to_string(path) {
            Ok(text) => serde_json::from_str(&text)
                .map_err(|e| format!("{} is not a credentials file: {e}", path.display())),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(Credentials::default()),
            Err(e) => Err(format!("cannot read {}: {e}", path.display())),
        }
    }

    /// Writes the file with mode 0600 (its folder 0700 when created): a temporary file beside
    /// it, flushed to disk, renamed over it.
    pub fn save(&self, path: &Path) -> Result<(), String> {
        let fail = |e: std::io::Error| format!("cannot write {}: {e}", path.display());
        let dir = path.parent().unwrap_or(Path::new("."));
        create_private_dir(dir).map_err(fail)?;
        let temporary = dir.join(format!(".credentials.json.{}.tmp", std::process::id()));
        let text = serde_json::to_string_pretty(self).map_err(|e| e.to_string())? + "\n";
        let written = (|| {
            let mut file = private_file(&temporary)?;
            file.write_all(text.as_bytes())?;
            file.sync_all()?;
            std::fs::rename(&temporary, path)
        })();
        if written.is_err() {
            let _ = std::fs::remove_file(&temporary);
        }
        written.map_err(fail)
    }
}

#[cfg(unix)]
fn create_private_dir(dir: &Path) -> std::io::Result<()> {
    use std::os::unix::fs::DirBuilderExt;
    std::fs::DirBuilder::new()
        .recursive(true)
        .mode(0o700)
        .create(dir)
}

#[cfg(not(unix))]
fn create_private_dir(dir: &Path) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)
}

#[cfg(unix)]
fn private_file(path: &Path) -> std::io::Result<std::fs::File> {
    use std::os::unix::fs::OpenOptionsExt;
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .mode(0o600)
        .open(path)
}

#[cfg(not(unix))]
fn private_file(path: &Path) -> std::io::Result<std::fs::File> {
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn credentials_round_trip_privately() {
        let dir =
            std::env::temp_dir().join(format!("shapegram-credentials-{}", std::process::id()));
        let path = file_in(&dir.join("nested"));
        assert!(Credentials::load(&path).unwrap().repositories.is_empty());
        let mut credentials = Credentials::default();
        let login = Login {
            name: "ana".into(),
            id: 3,
            token: "sgr_x".into(),
        };
        credentials
            .repositories
            .insert("http://127.0.0.1:8080".into(), login.clone());
        credentials.save(&path).unwrap();
        // Saving again replaces the file (the temporary one does not linger).
        credentials.save(&path).unwrap();
        let read = Credentials::load(&path).unwrap();
        assert_eq!(read.repositories["http://127.0.0.1:8080"], login);
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
            assert_eq!(mode(&path), 0o600);
            assert_eq!(mode(&dir.join("nested")), 0o700);
        }
        assert_eq!(std::fs::read_dir(dir.join("nested")).unwrap().count(), 1);
        std::fs::write(&path, "{").unwrap();
        assert!(
            Credentials::load(&path)
                .unwrap_err()
                .contains("is not a credentials file")
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
