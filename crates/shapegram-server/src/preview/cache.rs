//! The previews made so far, in memory, bounded by their total size. Versions never change, so
//! an entry never goes stale: nothing is invalidated, only the least recently used entries make
//! room for new ones.

use std::collections::HashMap;

use axum::body::Bytes;

use super::Refusal;

/// What a preview came to: the GLB, or why the grammar does not derive. Both depend only on
/// the version's text, the seed and the step limit, so both are kept.
pub type Outcome = Result<Bytes, Refusal>;

/// A preview's key: the version's SHA-256 and the seed. The text's hash rather than the
/// version's number, so that a grammar deleted and published again under the same number
/// (once deletion exists) cannot be served its predecessor's preview.
pub type Key = (String, u64);

/// A least-recently-used cache of outcomes, at most `capacity` bytes of GLB and messages.
pub struct Cache {
    capacity: usize,
    size: usize,
    /// The entries and when each was last used (a counter, higher is more recent).
    entries: HashMap<Key, (Outcome, u64)>,
    clock: u64,
}

/// The bytes an outcome holds, for the bound.
fn weight(key: &Key, outcome: &Outcome) -> usize {
    let held = match outcome {
        Ok(glb) => glb.len(),
        Err(refusal) => {
            refusal.message.len()
                + refusal
                    .diagnostics
                    .iter()
                    .map(|p| p.message.len() + p.hints.iter().map(String::len).sum::<usize>())
                    .sum::<usize>()
        }
    };
    held + key.0.len() + 64
}

impl Cache {
    /// An empty cache holding at most `capacity` bytes.
    pub fn new(capacity: usize) -> Cache {
        Cache {
            capacity,
            size: 0,
            entries: HashMap::new(),
            clock: 0,
        }
    }

    /// The outcome kept for `key`, now the most recently used.
    pub fn get(&mut self, key: &Key) -> Option<Outcome> {
        self.clock += 1;
        let clock = self.clock;
        self.entries.get_mut(key).map(|(outcome, used)| {
            *used = clock;
            outcome.clone()
        })
    }

    /// Keeps `outcome`, dropping the least recently used entries until it fits; one larger than
    /// the whole cache is not kept.
    pub fn insert(&mut self, key: Key, outcome: Outcome) {
        let weight = weight(&key, &outcome);
        if weight > self.capacity {
            return;
        }
        if let Some((old, _)) = self.entries.remove(&key) {
            self.size -= self::weight(&key, &old);
        }
        // A linear scan per eviction: entries are previews of many kilobytes, so a cache of a
        // few dozen megabytes holds at most thousands.
        while self.size + weight > self.capacity {
            let Some(oldest) = self
                .entries
                .iter()
                .min_by_key(|(_, (_, used))| *used)
                .map(|(k, _)| k.clone())
            else {
                break;
            };
            if let Some((old, _)) = self.entries.remove(&oldest) {
                self.size -= self::weight(&oldest, &old);
            }
        }
        self.clock += 1;
        self.size += weight;
        self.entries.insert(key, (outcome, self.clock));
    }

    /// The bytes held.
    pub fn size(&self) -> usize {
        self.size
    }

    /// The number of entries.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether nothing is kept.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(name: &str) -> Key {
        (name.to_owned(), 0)
    }

    fn glb(n: usize) -> Outcome {
        Ok(Bytes::from(vec![0u8; n]))
    }

    #[test]
    fn the_least_recently_used_make_room_and_the_bound_holds() {
        // Three previews of 1,000 bytes fit in 3,500 bytes with their keys; a fourth does not.
        let mut cache = Cache::new(3_500);
        cache.insert(key("a"), glb(1_000));
        cache.insert(key("b"), glb(1_000));
        cache.insert(key("c"), glb(1_000));
        assert_eq!(cache.len(), 3);
        assert!(cache.get(&key("a")).is_some(), "a is now the most recent");
        cache.insert(key("d"), glb(1_000));
        assert_eq!(cache.len(), 3);
        assert!(
            cache.get(&key("b")).is_none(),
            "b was the least recently used"
        );
        for k in ["a", "c", "d"] {
            assert_eq!(cache.get(&key(k)).unwrap().unwrap().len(), 1_000, "{k}");
        }
        assert_eq!(cache.size(), 3 * (1_000 + 1 + 64));
    }

    #[test]
    fn an_outcome_larger_than_the_cache_is_not_kept_and_replacing_keeps_the_count() {
        let mut cache = Cache::new(2_000);
        cache.insert(key("big"), glb(5_000));
        assert!(cache.is_empty());
        cache.insert(key("a"), glb(100));
        cache.insert(key("a"), glb(200));
        assert_eq!(cache.len(), 1);
        assert_eq!(cache.size(), 200 + 1 + 64);
        let refused = Err(Refusal {
            message: "x does not derive".into(),
            diagnostics: Vec::new(),
        });
        cache.insert(key("b"), refused);
        assert_eq!(
            cache.get(&key("b")).unwrap().unwrap_err().message,
            "x does not derive"
        );
    }
}
