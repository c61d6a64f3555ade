//! Threads after `fork()`: rayon's global pool does not survive it. A child process made by
//! `fork()` (`multiprocessing`'s default start method on Linux before Python 3.14) after the
//! parent ran a threaded batch inherits a pool whose threads are gone, and its first threaded
//! call waited for them for ever. Work that may use rayon runs through [`run`]: in such a
//! child it runs inside a pool made for that process ([`install`](rayon::ThreadPool::install);
//! `RAYON_NUM_THREADS` threads, else one per core, as rayon's global pool), elsewhere as it is.

use std::sync::Mutex;

/// The pool made for a process other than the one that loaded the module (a child made by
/// `fork()`), with that process's id. Pools are leaked: one per generation of forks.
static POOLS: Mutex<Option<(u32, &'static rayon::ThreadPool)>> = Mutex::new(None);
/// The process that loaded the module.
static LOADED_BY: std::sync::OnceLock<u32> = std::sync::OnceLock::new();

/// Remembers the process that loads the module (called once, from the module's init).
pub(crate) fn loaded() {
    LOADED_BY.get_or_init(std::process::id);
}

/// The pool of this process when it is not the one that loaded the module, made at the first
/// call; `None` in the process that loaded it.
fn child_pool() -> Option<&'static rayon::ThreadPool> {
    let me = std::process::id();
    if LOADED_BY.get().is_none_or(|&p| p == me) {
        return None;
    }
    // Only forked processes take this lock, for as long as a pool takes to make. (A grandchild
    // forked while its parent's other thread held it would wait on it: not handled.)
    let mut pools = POOLS
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    match *pools {
        Some((pid, pool)) if pid == me => Some(pool),
        _ => {
            // As many threads as rayon's global pool would have (RAYON_NUM_THREADS, else the
            // cores).
            let pool = rayon::ThreadPoolBuilder::new()
                .thread_name(|i| format!("fastbrdf-{i}"))
                .build()
                .ok()?;
            let pool: &'static rayon::ThreadPool = Box::leak(Box::new(pool));
            *pools = Some((me, pool));
            Some(pool)
        }
    }
}

/// Runs `f`, which may use rayon: in a child process made by `fork()`, inside that process's
/// own pool; else here.
pub(crate) fn run<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    match child_pool() {
        Some(pool) => pool.install(f),
        None => f(),
    }
}
