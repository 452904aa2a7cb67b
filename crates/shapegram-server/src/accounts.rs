//! Names and passwords. Names of accounts and grammars follow crates.io's rules: ASCII letters,
//! digits, `-` and `_`, starting with a letter; `-` and `_` and upper and lower case are the same
//! name (the canonical form is unique). Passwords are hashed with argon2id (OWASP's parameters,
//! the `argon2` crate's defaults: 19 MiB, 2 passes, 1 lane) into PHC strings, off the async
//! threads and a few at a time, since each hash takes 19 MiB and tens of milliseconds.

use std::sync::{Arc, OnceLock};

use argon2::Argon2;
use argon2::password_hash::{PasswordHash, PasswordHasher, PasswordVerifier, SaltString};
use tokio::sync::Semaphore;

/// Longest account name (as GitHub's).
pub const MAX_ACCOUNT_NAME: usize = 39;
/// Longest grammar name (as crates.io's).
pub const MAX_GRAMMAR_NAME: usize = 64;
/// Shortest password, in characters.
pub const MIN_PASSWORD: usize = 8;
/// Longest password, in characters.
pub const MAX_PASSWORD: usize = 1024;

/// The canonical form of a name (lower case, `_` as `-`): what tells names apart.
pub fn canon(name: &str) -> String {
    name.to_ascii_lowercase().replace('_', "-")
}

/// The canonical form of a valid name, or why it is not one.
pub fn canonical_name(what: &str, name: &str, max: usize) -> Result<String, String> {
    if name.is_empty() {
        return Err(format!("{what} name is empty"));
    }
    if name.len() > max {
        return Err(format!("{what} name is longer than {max} characters"));
    }
    if !name.as_bytes()[0].is_ascii_alphabetic() {
        return Err(format!("{what} name must start with an ASCII letter"));
    }
    if let Some(c) = name
        .chars()
        .find(|c| !(c.is_ascii_alphanumeric() || *c == '-' || *c == '_'))
    {
        return Err(format!(
            "{what} name has the character {c:?}: use ASCII letters, digits, `-` and `_`"
        ));
    }
    Ok(canon(name))
}

/// Hashes and checks passwords, a few at a time.
#[derive(Clone)]
pub struct Passwords {
    permits: Arc<Semaphore>,
}

impl Passwords {
    /// At most `concurrent` hashes at once (each needs 19 MiB).
    pub fn new(concurrent: usize) -> Passwords {
        Passwords {
            permits: Arc::new(Semaphore::new(concurrent.max(1))),
        }
    }

    /// The PHC string of a new password.
    pub async fn hash(&self, password: String) -> Result<String, String> {
        let _permit = self.permits.acquire().await.map_err(|e| e.to_string())?;
        tokio::task::spawn_blocking(move || hash_now(&password))
            .await
            .map_err(|e| e.to_string())?
    }

    /// Whether `password` matches `phc`. With `None` (no such account) the work is done
    /// against a dummy hash, so that timing does not tell which names exist.
    pub async fn verify(&self, password: String, phc: Option<String>) -> bool {
        let Ok(_permit) = self.permits.acquire().await else {
            return false;
        };
        tokio::task::spawn_blocking(move || {
            let known = phc.is_some();
            let phc = phc.unwrap_or_else(|| dummy_hash().to_owned());
            let ok = PasswordHash::new(&phc).is_ok_and(|h| {
                Argon2::default()
                    .verify_password(password.as_bytes(), &h)
                    .is_ok()
            });
            known && ok
        })
        .await
        .unwrap_or(false)
    }
}

/// Whether a stored hash was made with other than the current algorithm and parameters (then
/// login hashes the password again).
pub fn needs_rehash(phc: &str) -> bool {
    let Ok(hash) = PasswordHash::new(phc) else {
        return true;
    };
    let current = argon2::Params::default();
    let param = |name: &str| hash.params.get_decimal(name);
    hash.algorithm != argon2::Algorithm::Argon2id.ident()
        || param("m") != Some(current.m_cost())
        || param("t") != Some(current.t_cost())
        || param("p") != Some(current.p_cost())
}

fn hash_now(password: &str) -> Result<String, String> {
    let mut salt = [0u8; 16];
    getrandom::fill(&mut salt).map_err(|e| e.to_string())?;
    let salt = SaltString::encode_b64(&salt).map_err(|e| e.to_string())?;
    Argon2::default()
        .hash_password(password.as_bytes(), &salt)
        .map(|h| h.to_string())
        .map_err(|e| e.to_string())
}

fn dummy_hash() -> &'static str {
    static DUMMY: OnceLock<String> = OnceLock::new();
    DUMMY.get_or_init(|| hash_now("not a password of anyone").unwrap_or_default())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_follow_crates_io_rules() {
        assert_eq!(
            canonical_name("grammar", "Chair_Basic", 64).unwrap(),
            "chair-basic"
        );
        for bad in ["", "1chair", "-chair", "chair basic", "chäir", "a/b", "a.b"] {
            assert!(canonical_name("grammar", bad, 64).is_err(), "{bad}");
        }
        assert!(canonical_name("grammar", &"a".repeat(65), 64).is_err());
    }

    async fn phc_again(p: &Passwords) -> String {
        p.hash("another".into()).await.unwrap()
    }

    #[test]
    fn passwords_hash_to_argon2id_phc_strings_and_verify() {
        let rt = tokio::runtime::Builder::new_current_thread()
            .build()
            .unwrap();
        rt.block_on(async {
            let p = Passwords::new(2);
            let phc = p.hash("correct horse".into()).await.unwrap();
            assert!(phc.starts_with("$argon2id$v=19$m=19456,t=2,p=1$"), "{phc}");
            assert!(p.verify("correct horse".into(), Some(phc.clone())).await);
            assert!(!p.verify("wrong horse".into(), Some(phc)).await);
            assert!(!p.verify("correct horse".into(), None).await);
            assert!(!needs_rehash(&phc_again(&p).await));
            let weak = "$argon2id$v=19$m=8,t=1,p=1$c2FsdHNhbHQ$0Yq6eFEBcmBnHWgsdmJ7Ig";
            assert!(needs_rehash(weak));
            assert!(needs_rehash(
                "$argon2i$v=19$m=19456,t=2,p=1$c2FsdHNhbHQ$0Yq6eFEBcmBnHWgsdmJ7Ig"
            ));
            assert!(needs_rehash("not a hash"));
        });
    }
}
