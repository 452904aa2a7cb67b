//! Who may do what. Reads are decided inside the store's SQL (every read takes a
//! [`Viewer`](crate::store::Viewer)), so that nothing invisible is ever loaded:
//!
//! | grammar visibility | who sees it (and all its versions) |
//! | --- | --- |
//! | `public` | everyone, signed in or not |
//! | `friends` | its owner and the owner's friends (an accepted request, either way) |
//! | `private` | its owner |
//!
//! Something a viewer may not see answers 404, exactly as something that does not exist, so
//! that names do not leak. Writes are decided here, before the store is called: 401 without
//! a valid token, 403 for an action on something visible that the caller may not do.

use crate::error::ApiError;
use crate::store::Account;

/// What a caller asks to do.
#[derive(Clone, Copy, Debug)]
pub enum Action<'a> {
    /// Publish a version of a grammar in the namespace of the account with this canonical name.
    Publish { owner_canon: &'a str },
    /// Yank or unyank a version of a grammar owned by the account with this canonical name.
    Yank { owner_canon: &'a str },
    /// Rename a grammar owned by the account with this canonical name.
    Rename { owner_canon: &'a str },
}

/// Whether `actor` may do `action`: only the owner of a namespace publishes into it and yanks
/// its versions (publisher roles for others come later). Yanking something the actor may not
/// see is decided before, as not found.
pub fn check(actor: &Account, actor_canon: &str, action: Action<'_>) -> Result<(), ApiError> {
    match action {
        Action::Publish { owner_canon } if owner_canon == actor_canon => Ok(()),
        Action::Publish { .. } => Err(ApiError::forbidden(format!(
            "{} may publish only under their own name",
            actor.name
        ))),
        Action::Yank { owner_canon } if owner_canon == actor_canon => Ok(()),
        Action::Yank { .. } => Err(ApiError::forbidden(format!(
            "only the grammar's owner yanks its versions, and {} is not",
            actor.name
        ))),
        Action::Rename { owner_canon } if owner_canon == actor_canon => Ok(()),
        Action::Rename { .. } => Err(ApiError::forbidden(format!(
            "only the grammar's owner renames it, and {} is not",
            actor.name
        ))),
    }
}
