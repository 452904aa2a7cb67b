//! Fail points for the crash test: named places in a publish where a server started with
//! `SHAPEGRAM_FAILPOINT=publish:NAME` stops and waits, so that the test can kill it with SIGKILL
//! exactly there and check what the database kept.
//!
//! The variable is read once, at start-up ([`FailPoints::from_env`]); no request can set or
//! reach it, and a server started without it never stops anywhere. An unknown name refuses to
//! start, so that a misspelt test does not pass by never stopping. Every store calls
//! [`FailPoints::hit`] at the same places of its publish, so the test runs on either backend.

use std::fmt;

/// The environment variable naming the fail point.
pub const ENV: &str = "SHAPEGRAM_FAILPOINT";

/// A place in a publish.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FailPoint {
    /// Before the transaction begins.
    BeforeTransaction,
    /// After the version's row is inserted, before its rule index.
    AfterInsertVersion,
    /// After the rule index, before the publish log.
    AfterRuleIndex,
    /// Everything written, just before COMMIT.
    BeforeCommit,
    /// Just after COMMIT, before the answer.
    AfterCommit,
}

impl FailPoint {
    /// Every fail point, in the order a publish reaches them.
    pub const ALL: [FailPoint; 5] = [
        FailPoint::BeforeTransaction,
        FailPoint::AfterInsertVersion,
        FailPoint::AfterRuleIndex,
        FailPoint::BeforeCommit,
        FailPoint::AfterCommit,
    ];

    /// The name `SHAPEGRAM_FAILPOINT` takes.
    pub fn name(self) -> &'static str {
        match self {
            FailPoint::BeforeTransaction => "publish:before-transaction",
            FailPoint::AfterInsertVersion => "publish:after-insert-version",
            FailPoint::AfterRuleIndex => "publish:after-rule-index",
            FailPoint::BeforeCommit => "publish:before-commit",
            FailPoint::AfterCommit => "publish:after-commit",
        }
    }

    /// The fail point of a name.
    pub fn parse(name: &str) -> Option<FailPoint> {
        FailPoint::ALL.into_iter().find(|p| p.name() == name)
    }
}

impl fmt::Display for FailPoint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The fail point a server stops at, if any (none in production).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FailPoints {
    armed: Option<FailPoint>,
}

impl FailPoints {
    /// No fail point: a publish never stops.
    pub const NONE: FailPoints = FailPoints { armed: None };

    /// Stops at `point`.
    pub fn at(point: FailPoint) -> FailPoints {
        FailPoints { armed: Some(point) }
    }

    /// From `SHAPEGRAM_FAILPOINT` (unset or empty: none); an unknown name is an error.
    pub fn from_env() -> Result<FailPoints, String> {
        match std::env::var(ENV) {
            Ok(name) if name.is_empty() => Ok(FailPoints::NONE),
            Ok(name) => FailPoint::parse(&name).map(FailPoints::at).ok_or_else(|| {
                let known: Vec<&str> = FailPoint::ALL.iter().map(|p| p.name()).collect();
                format!(
                    "{ENV}={name} is no fail point (known: {})",
                    known.join(", ")
                )
            }),
            Err(std::env::VarError::NotPresent) => Ok(FailPoints::NONE),
            Err(std::env::VarError::NotUnicode(_)) => Err(format!("{ENV} is not UTF-8")),
        }
    }

    /// At `point`: when it is the armed one, says so on stderr and never returns, holding
    /// whatever the caller holds (an open transaction) until the process is killed.
    pub async fn hit(self, point: FailPoint) {
        if self.armed == Some(point) {
            eprintln!("shapegram serve: fail point {point} reached");
            std::future::pending::<()>().await;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for point in FailPoint::ALL {
            assert_eq!(FailPoint::parse(point.name()), Some(point));
        }
        assert_eq!(FailPoint::parse("publish:after-comit"), None);
    }

    #[tokio::test]
    async fn an_unarmed_point_passes() {
        FailPoints::at(FailPoint::AfterCommit)
            .hit(FailPoint::BeforeCommit)
            .await;
        FailPoints::NONE.hit(FailPoint::AfterCommit).await;
    }
}
