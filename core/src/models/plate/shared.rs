//! Modal data shared by every engine of the process: a plugin's instances of the same model
//! hold one copy of its basis and of its tiers' coupling tensors, not one each.
//!
//! A [`Registry`] keeps *weak* references by key: an entry lives while some engine's modal
//! cache or bank holds it, and a build finds it there instead of building it again (the
//! worker's own cache, `basis::ModalCache`, keeps only the last basis it built). Worker
//! threads only (a short lock around a linear scan of a few entries; never the audio thread).

use std::sync::{Arc, Mutex, Weak};

/// Values of type `V` by key `K`, held weakly (module doc). Worker threads.
pub(crate) struct Registry<K, V> {
    entries: Mutex<Vec<(K, Weak<V>)>>,
}

impl<K: PartialEq, V> Registry<K, V> {
    /// An empty registry (a `static`).
    pub(crate) const fn new() -> Self {
        Self {
            entries: Mutex::new(Vec::new()),
        }
    }

    /// The value of `key` if an engine still holds it; drops the entries no one holds.
    pub(crate) fn get(&self, key: &K) -> Option<Arc<V>> {
        let mut entries = self.entries.lock().unwrap_or_else(|p| p.into_inner());
        entries.retain(|(_, w)| w.strong_count() > 0);
        entries
            .iter()
            .find(|(k, _)| k == key)
            .and_then(|(_, w)| w.upgrade())
    }

    /// Records `value` under `key` (replacing a dead entry of the same key).
    pub(crate) fn insert(&self, key: K, value: &Arc<V>) {
        let mut entries = self.entries.lock().unwrap_or_else(|p| p.into_inner());
        entries.retain(|(k, w)| w.strong_count() > 0 && *k != key);
        entries.push((key, Arc::downgrade(value)));
    }

    /// The value of `key`, built by `build` and recorded when no engine holds it.
    pub(crate) fn get_or_build<E>(
        &self,
        key: K,
        build: impl FnOnce() -> Result<V, E>,
    ) -> Result<Arc<V>, E> {
        if let Some(v) = self.get(&key) {
            return Ok(v);
        }
        let v = Arc::new(build()?);
        self.insert(key, &v);
        Ok(v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A value is found while held and rebuilt once dropped.
    #[test]
    fn entries_live_while_held() {
        let r: Registry<u32, String> = Registry::new();
        let a = r
            .get_or_build(1, || Ok::<_, ()>("one".to_string()))
            .unwrap();
        let b = r
            .get_or_build(1, || Ok::<_, ()>("other".to_string()))
            .unwrap();
        assert!(Arc::ptr_eq(&a, &b));
        drop((a, b));
        assert!(r.get(&1).is_none());
        let c = r
            .get_or_build(1, || Ok::<_, ()>("again".to_string()))
            .unwrap();
        assert_eq!(*c, "again");
    }
}
