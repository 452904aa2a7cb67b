//! API tokens: `sgr_` + 32 base62 characters of secret (about 190 random bits from the operating
//! system's CSPRNG) + 6 base62 characters of CRC-32 over the rest, so that secret scanners can
//! recognise a leaked token and the server rejects a mistyped one before any lookup. Only the
//! token's SHA-256 is stored, and looked up through a unique index.

use sha2::{Digest, Sha256};

const PREFIX: &str = "sgr_";
const SECRET_LEN: usize = 32;
const CHECK_LEN: usize = 6;
/// Length of a whole token.
pub const TOKEN_LEN: usize = PREFIX.len() + SECRET_LEN + CHECK_LEN;
const BASE62: &[u8; 62] = b"0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz";

/// A new random token.
pub fn generate() -> Result<String, getrandom::Error> {
    let mut token = String::with_capacity(TOKEN_LEN);
    token.push_str(PREFIX);
    while token.len() < PREFIX.len() + SECRET_LEN {
        let mut bytes = [0u8; 64];
        getrandom::fill(&mut bytes)?;
        // Rejection sampling: 248 = 4 × 62, so every character is equally likely.
        for b in bytes {
            if b < 248 && token.len() < PREFIX.len() + SECRET_LEN {
                token.push(BASE62[usize::from(b % 62)] as char);
            }
        }
    }
    token.push_str(&checksum(&token));
    Ok(token)
}

/// Whether `token` has a token's form and checksum.
pub fn well_formed(token: &str) -> bool {
    token.len() == TOKEN_LEN
        && token.starts_with(PREFIX)
        && token[PREFIX.len()..]
            .bytes()
            .all(|b| b.is_ascii_alphanumeric())
        && token[TOKEN_LEN - CHECK_LEN..] == checksum(&token[..TOKEN_LEN - CHECK_LEN])
}

/// What a token list shows of a token.
pub fn display_prefix(token: &str) -> String {
    token.chars().take(PREFIX.len() + 4).collect()
}

/// SHA-256 of a token: what the database holds.
pub fn hash(token: &str) -> [u8; 32] {
    Sha256::digest(token.as_bytes()).into()
}

/// SHA-256 in lower-case hex.
pub fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

fn checksum(text: &str) -> String {
    let mut n = crc32(text.as_bytes());
    let mut out = [b'0'; CHECK_LEN];
    for c in out.iter_mut().rev() {
        *c = BASE62[(n % 62) as usize];
        n /= 62;
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// CRC-32 (IEEE), bit by bit: tokens are short.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc32_of_the_check_string() {
        assert_eq!(crc32(b"123456789"), 0xCBF4_3926);
    }

    #[test]
    fn tokens_are_well_formed_and_distinct() {
        let a = generate().unwrap();
        let b = generate().unwrap();
        assert_ne!(a, b);
        assert_eq!(a.len(), TOKEN_LEN);
        assert!(well_formed(&a) && well_formed(&b));
        // One changed character breaks the checksum.
        let mut bad = a.clone().into_bytes();
        bad[10] = if bad[10] == b'x' { b'y' } else { b'x' };
        assert!(!well_formed(&String::from_utf8(bad).unwrap()));
        assert!(!well_formed("sgr_"));
        assert!(!well_formed(&a.replace("sgr_", "ghp_")));
    }
}
