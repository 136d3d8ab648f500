//! Each file a scene names is read and parsed once per load, however many objects name it.
//!
//! A YAML scene may name one OBJ from 200 000 objects (through anchors and aliases), a Mitsuba
//! or pbrt scene one PLY, texture or serialized file from many shapes. The first use reads and
//! parses the file; later uses within the same load take a copy of the parsed result (its
//! warnings were given the first time, so they are not repeated).
//!
//! The cache lives for one load: [`LoadScope::begin`] opens it on this thread (loading is
//! single-threaded), its end drops it and hands back the [`LoadStats`]. Without an open scope
//! (a parser called on its own) nothing is cached. Entries are keyed by the file's canonical
//! path (so `a/../m.obj` and `m.obj` are one file) and by what changes the parse (an OBJ read
//! with or without its MTL materials, an image read raw or sRGB-decoded, a serialized mesh's
//! index). Only successes are cached: a failed parse fails the load. The parsed copies are
//! kept until the load ends: while loading, each file's data is held once more than it
//! would be without the cache (freed before the BVH is built).

use crate::error::LoadError;
use std::any::Any;
use std::cell::RefCell;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::rc::Rc;

/// What one load read from disk.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LoadStats {
    /// Files read from disk (the scene file, meshes, material libraries, images), each
    /// counted every time it is read.
    pub files_read: usize,
    /// Files parsed (meshes, material libraries, images; the scene file itself not counted).
    pub files_parsed: usize,
}

#[derive(Default)]
struct Cache {
    stats: LoadStats,
    /// The canonical path of each path as given (a `realpath` per distinct name only).
    canonical: HashMap<PathBuf, PathBuf>,
    /// Parsed results by (kind, canonical path, variant of the parse).
    parsed: HashMap<(&'static str, PathBuf, String), Rc<dyn Any>>,
}

thread_local! {
    static CACHE: RefCell<Option<Cache>> = const { RefCell::new(None) };
}

/// The cache of one load on this thread; see the module documentation.
pub(crate) struct LoadScope {
    /// False when a scope was already open (a load inside a load): the outer one owns it.
    owner: bool,
}

impl LoadScope {
    /// Opens the cache, unless one is open already.
    pub(crate) fn begin() -> Self {
        CACHE.with(|c| {
            let mut c = c.borrow_mut();
            let owner = c.is_none();
            if owner {
                *c = Some(Cache::default());
            }
            LoadScope { owner }
        })
    }

    /// Closes the cache (if this scope opened it) and returns what was read.
    pub(crate) fn end(self) -> LoadStats {
        let stats = CACHE.with(|c| c.borrow().as_ref().map(|c| c.stats.clone()));
        drop(self);
        stats.unwrap_or_default()
    }
}

impl Drop for LoadScope {
    fn drop(&mut self) {
        if self.owner {
            CACHE.with(|c| *c.borrow_mut() = None);
        }
    }
}

/// Counts one read of a file from disk (every reader calls it before reading).
pub(crate) fn note_read() {
    CACHE.with(|c| {
        if let Some(c) = c.borrow_mut().as_mut() {
            c.stats.files_read += 1;
        }
    });
}

/// The result of `parse` for the file at `path` read as `variant`, parsed at its first use
/// in this load and copied from the cache afterwards. `kind` separates the parsers ("obj",
/// "ply"...). Outside a [`LoadScope`], or when `path` has no canonical form (it does not
/// exist: `parse` then gives the error naming it), `parse` runs every time.
pub(crate) fn parsed<T: Clone + 'static>(
    kind: &'static str,
    path: &Path,
    variant: String,
    parse: impl FnOnce() -> Result<T, LoadError>,
) -> Result<T, LoadError> {
    let key = CACHE.with(|c| {
        let mut c = c.borrow_mut();
        let c = c.as_mut()?;
        let canonical = match c.canonical.get(path) {
            Some(p) => p.clone(),
            None => {
                let p = std::fs::canonicalize(path).ok()?;
                c.canonical.insert(path.to_path_buf(), p.clone());
                p
            }
        };
        Some((kind, canonical, variant))
    });
    let Some(key) = key else {
        return parse();
    };
    let hit = CACHE.with(|c| {
        let c = c.borrow();
        let found = c.as_ref()?.parsed.get(&key)?;
        found.downcast_ref::<T>().cloned()
    });
    if let Some(value) = hit {
        return Ok(value);
    }
    // The borrow is released while parsing: a parse may use the cache itself (an OBJ its
    // MTL libraries, an MTL material its images).
    let value = parse()?;
    CACHE.with(|c| {
        if let Some(c) = c.borrow_mut().as_mut() {
            c.stats.files_parsed += 1;
            c.parsed.insert(key, Rc::new(value.clone()));
        }
    });
    Ok(value)
}
