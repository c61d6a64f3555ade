//! Parallel loops in which the calling thread takes part.
//!
//! A rayon parallel iterator called from a thread outside rayon's pool (the Python thread, a
//! command's main thread) hands the whole loop to the pool, sleeps, and is woken when the
//! pool is done. On the project's 2-core VM that round trip cost about 0.27 ms (an empty
//! `rayon::join` from outside the pool; 5-15 us from one of its workers), an eighth of a
//! 2 ms batch of 10^6 elements. [`for_each_part`] lets the caller work from the start: it
//! spawns helpers into the pool, claims parts from a shared counter as they do, and once the
//! parts are all claimed spins (a part lasts tens of microseconds) until the helpers' last
//! ones are done, so that neither side waits for a wake-up it could have skipped.
//!
//! After such a call the helpers **linger** ([`linger`]): they keep looking for work, spinning,
//! for as long as the call lasted (at most [`LINGER_MAX`], or `FASTBRDF_LINGER_US`
//! microseconds; 0 turns it off), so that the next call finds them awake. On the project's
//! 2-core VM, after an idle moment, a helper that went to sleep between two calls 50 us to 5 ms
//! apart took about 2 ms to join the second (its virtual CPU had halted), and a 2 ms batch of
//! 10^6 elements then took 4.1-4.2 ms; with the linger, 2.1-2.4 ms (`cargo run --release -p
//! fastbrdf --example par_wake`). Dr.Jit's worker spins about 20 ms after each call (measured by
//! `python/examples/sample_cost.py`) and OpenMP's for a while by default, for the same reason.

use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Mutex, OnceLock};
use std::time::{Duration, Instant};

/// How many times [`for_each_part`]'s caller spins for the helpers' last parts before it
/// yields between checks: about 50 us (a pause is tens of cycles), a few parts' time.
const SPINS: u32 = 1 << 12;

/// Runs `f(state, part)` for every part of `parts`, on the calling thread and on up to
/// (rayon's thread count - 1) helpers in rayon's pool, each thread with its own `init()`
/// state (made when it claims its first part). Parts are claimed in order from a shared
/// counter, so which thread runs a part varies; a result must not depend on it. The first
/// error stops the claiming and is returned (parts already running finish).
pub fn for_each_part<P: Send, S, E: Send>(
    parts: Vec<P>,
    init: impl Fn() -> S + Sync,
    f: impl Fn(&mut S, P) -> Result<(), E> + Sync,
) -> Result<(), E> {
    let n = parts.len();
    let slots: Vec<Mutex<Option<P>>> = parts.into_iter().map(|p| Mutex::new(Some(p))).collect();
    let (next, done) = (AtomicUsize::new(0), AtomicUsize::new(0));
    let failed = AtomicBool::new(false);
    let error: Mutex<Option<E>> = Mutex::new(None);
    // Counts a claimed part as done when dropped, so that a part that panics is counted too
    // and the caller's spin below ends (the scope then resumes the panic) instead of spinning
    // for ever.
    struct Done<'a>(&'a AtomicUsize);
    impl Drop for Done<'_> {
        fn drop(&mut self) {
            self.0.fetch_add(1, Ordering::Release);
        }
    }
    let work = || {
        let mut state = None;
        loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            if i >= n || failed.load(Ordering::Relaxed) {
                return;
            }
            let _done = Done(&done);
            let part = slots[i]
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .take();
            if let Some(part) = part {
                let s = state.get_or_insert_with(&init);
                if let Err(e) = f(s, part) {
                    failed.store(true, Ordering::Relaxed);
                    error
                        .lock()
                        .unwrap_or_else(std::sync::PoisonError::into_inner)
                        .get_or_insert(e);
                }
            }
        }
    };
    let helpers = rayon::current_num_threads().min(n).saturating_sub(1);
    if helpers == 0 {
        work();
    } else {
        let start = Instant::now();
        rayon::in_place_scope(|scope| {
            for _ in 0..helpers {
                scope.spawn(|_| work());
            }
            work();
            // Every part is claimed: wait for the helpers' last ones by spinning rather than
            // by the scope's sleep (a part is short). After an error, the scope waits. Past
            // SPINS the thread yields between checks: a helper the system took off its core
            // (another process on a 2-core machine) may need this core to finish.
            let mut spins = 0;
            while done.load(Ordering::Acquire) < n && !failed.load(Ordering::Relaxed) {
                if spins < SPINS {
                    spins += 1;
                    std::hint::spin_loop();
                } else {
                    std::thread::yield_now();
                }
            }
        });
        if rayon::current_thread_index().is_none() {
            linger(helpers, start.elapsed().min(linger_max()));
        }
    }
    match error
        .into_inner()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
    {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// The longest [`linger`] by default: 5 ms, a quarter of Dr.Jit's spin.
pub const LINGER_MAX: Duration = Duration::from_millis(5);

/// The longest linger now: [`set_linger_max`]'s, else `FASTBRDF_LINGER_US` microseconds when
/// that is set (read at the first call), else [`LINGER_MAX`]. A value that is not a whole
/// number of microseconds leaves the default, with one line on stderr naming it.
pub fn linger_max() -> Duration {
    let ns = LINGER_MAX_NS.load(Ordering::Relaxed);
    if ns != UNSET {
        return Duration::from_nanos(ns);
    }
    let var = std::env::var_os("FASTBRDF_LINGER_US");
    let (d, bad) = match linger_from_env(var.as_deref()) {
        Ok(d) => (d, None),
        Err(msg) => (LINGER_MAX, Some(msg)),
    };
    // A setter that ran meanwhile wins; the thread that sets the value says what was wrong.
    let set = LINGER_MAX_NS.compare_exchange(
        UNSET,
        nanos(d).min(UNSET - 1),
        Ordering::Relaxed,
        Ordering::Relaxed,
    );
    if let (Ok(_), Some(msg)) = (set, bad) {
        eprintln!("fastbrdf: {msg}");
    }
    Duration::from_nanos(LINGER_MAX_NS.load(Ordering::Relaxed))
}

/// `FASTBRDF_LINGER_US`'s value as the longest linger: unset, [`LINGER_MAX`]; a whole number
/// of microseconds (spaces around it allowed), that; anything else, what is wrong with it.
fn linger_from_env(value: Option<&std::ffi::OsStr>) -> Result<Duration, String> {
    let Some(v) = value else {
        return Ok(LINGER_MAX);
    };
    v.to_str()
        .and_then(|s| s.trim().parse::<u64>().ok())
        .map(Duration::from_micros)
        .ok_or_else(|| {
            format!(
                "FASTBRDF_LINGER_US={:?} is not a whole number of microseconds (0 turns the \
                 linger off); the default {} us applies",
                v,
                LINGER_MAX.as_micros()
            )
        })
}

/// Sets the longest linger for the rest of the process, whatever `FASTBRDF_LINGER_US` says;
/// `Duration::ZERO` also ends the lingers running now.
pub fn set_linger_max(d: Duration) {
    LINGER_MAX_NS.store(nanos(d).min(UNSET - 1), Ordering::Relaxed);
    if d.is_zero() {
        LINGER_UNTIL.store(0, Ordering::SeqCst);
    }
}

const UNSET: u64 = u64::MAX;
static LINGER_MAX_NS: AtomicU64 = AtomicU64::new(UNSET);

/// `d` in nanoseconds, saturating.
fn nanos(d: Duration) -> u64 {
    u64::try_from(d.as_nanos()).unwrap_or(u64::MAX)
}

/// The process's clock for [`LINGER_UNTIL`]: nanoseconds since its first use.
fn clock_ns() -> u64 {
    static EPOCH: OnceLock<Instant> = OnceLock::new();
    nanos(EPOCH.get_or_init(Instant::now).elapsed())
}

/// When the lingering helpers stop ([`clock_ns`]); calls only move it later. The deadline
/// and [`LINGERING`] are read and written in sequential consistency: a call that moves the
/// deadline and a helper that gives up its place must not both miss the other's write.
static LINGER_UNTIL: AtomicU64 = AtomicU64::new(0);
/// How many helpers linger now.
static LINGERING: AtomicUsize = AtomicUsize::new(0);

thread_local! {
    /// Whether this thread is lingering (a copy that reaches it inside its own linger, through
    /// `rayon::yield_now`, returns at once).
    static HERE: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Keeps up to `helpers` of rayon's threads looking for work (spinning, running any job that
/// comes: the next call's parts) for `d` from now, then lets them sleep. Each worker of the
/// pool gets its own copy (`rayon::spawn_broadcast`: another thread cannot run it, so the
/// lingers do not pile up on one thread), and the first `helpers` to start take the places;
/// the others return at once. Lingering helpers have their end moved. Does nothing when `d`
/// or `helpers` is zero.
pub fn linger(helpers: usize, d: Duration) {
    if d.is_zero() || helpers == 0 {
        return;
    }
    LINGER_UNTIL.fetch_max(clock_ns().saturating_add(nanos(d)), Ordering::SeqCst);
    if LINGERING.load(Ordering::SeqCst) < helpers {
        rayon::spawn_broadcast(move |_| linger_here(helpers));
    }
}

/// Takes one of `helpers` places.
fn take_place(helpers: usize) -> bool {
    LINGERING
        .fetch_update(Ordering::SeqCst, Ordering::SeqCst, |k| {
            (k < helpers).then_some(k + 1)
        })
        .is_ok()
}

/// One worker's linger ([`linger`]): until the shared end, and for at most the longest
/// linger at a time: a worker that took its copy while waiting inside a `join` or a scope
/// (the copy runs there too) is held no longer than that. Past it, with the shared end
/// still ahead, it hands over to a fresh copy, which the worker runs once it is free.
fn linger_here(helpers: usize) {
    if HERE.get() || !take_place(helpers) {
        return;
    }
    #[cfg(test)]
    tests::held_by();
    HERE.set(true);
    let own_end = clock_ns().saturating_add(nanos(linger_max()));
    let mut handed_over = false;
    loop {
        loop {
            let now = clock_ns();
            if now >= LINGER_UNTIL.load(Ordering::SeqCst) {
                break;
            }
            if now >= own_end {
                handed_over = true;
                break;
            }
            if rayon::yield_now() != Some(rayon::Yield::Executed) {
                for _ in 0..64 {
                    std::hint::spin_loop();
                }
            }
        }
        LINGERING.fetch_sub(1, Ordering::SeqCst);
        // A call that ended just now may have moved the end and found every place taken:
        // take one again.
        if handed_over || clock_ns() >= LINGER_UNTIL.load(Ordering::SeqCst) || !take_place(helpers)
        {
            break;
        }
    }
    HERE.set(false);
    if handed_over {
        rayon::spawn_broadcast(move |_| linger_here(helpers));
    }
}

/// How many helpers linger now.
#[cfg(test)]
fn lingering() -> usize {
    LINGERING.load(Ordering::SeqCst)
}

#[cfg(test)]
mod tests {
    use super::for_each_part;
    use std::sync::Mutex;
    use std::thread::ThreadId;

    /// The tests here run one at a time: the linger's settings and counts are the process's.
    static SERIAL: Mutex<()> = Mutex::new(());

    /// FASTBRDF_LINGER_US: unset, the default; a whole number, that many microseconds; else
    /// an error that names the variable and its value.
    #[test]
    fn linger_env_values() {
        use super::{LINGER_MAX, linger_from_env};
        use std::ffi::OsStr;
        use std::time::Duration;
        assert_eq!(linger_from_env(None), Ok(LINGER_MAX));
        let us = |s: &str| linger_from_env(Some(OsStr::new(s)));
        assert_eq!(us(" 250 "), Ok(Duration::from_micros(250)));
        assert_eq!(us("0"), Ok(Duration::ZERO));
        for bad in ["", "5ms", "-1", "1.5", "x"] {
            let e = us(bad).unwrap_err();
            assert!(e.contains(&format!("FASTBRDF_LINGER_US={bad:?}")), "{e}");
            assert!(e.contains("5000 us"), "{e}");
        }
    }

    fn serial() -> std::sync::MutexGuard<'static, ()> {
        SERIAL
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// The threads that took a place to linger, in order (see [`super::linger_here`]).
    static HOLDERS: Mutex<Vec<ThreadId>> = Mutex::new(Vec::new());

    pub(super) fn held_by() {
        HOLDERS
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .push(std::thread::current().id());
    }

    /// Every part runs once, each thread with its own state, and the first error is returned
    /// with the later parts left unclaimed.
    #[test]
    fn every_part_runs_once_and_an_error_stops_the_rest() {
        let _serial = serial();
        for n in [0usize, 1, 2, 3, 64, 1000] {
            let mut out = vec![0u32; n];
            let parts: Vec<(usize, &mut u32)> = out.iter_mut().enumerate().collect();
            for_each_part(
                parts,
                || 0usize,
                |count, (i, o)| {
                    *count += 1;
                    *o += i as u32 + 1;
                    Ok::<(), ()>(())
                },
            )
            .unwrap();
            assert!(
                out.iter().enumerate().all(|(i, &o)| o == i as u32 + 1),
                "n {n}"
            );
        }
        let ran = std::sync::atomic::AtomicUsize::new(0);
        let r = for_each_part(
            (0..10_000).collect(),
            || (),
            |_, i: usize| {
                ran.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                if i == 10 { Err(i) } else { Ok(()) }
            },
        );
        assert_eq!(r, Err(10));
        assert!(ran.load(std::sync::atomic::Ordering::Relaxed) < 10_000);
    }

    /// A part that panics reaches the caller as a panic (the Python package turns it into an
    /// exception) rather than leaving it spinning: on the caller's own thread, and on a
    /// helper's (the first part a helper claims panics; parts last 20 us, so a helper joins).
    #[test]
    fn a_panicking_part_panics_the_caller() {
        let _serial = serial();
        let caller = std::thread::current().id();
        let helpers = rayon::current_num_threads() > 1;
        for on_helper in [false, true] {
            let r = std::panic::catch_unwind(|| {
                for_each_part(
                    (0..2000).collect(),
                    || (),
                    |_, i: usize| {
                        std::thread::sleep(std::time::Duration::from_micros(20));
                        let here = std::thread::current().id() == caller;
                        let bad = if on_helper && helpers { !here } else { i == 0 };
                        assert!(!bad, "part {i}");
                        Ok::<(), ()>(())
                    },
                )
            });
            assert!(r.is_err(), "on a helper: {on_helper}");
        }
    }

    /// After a call from outside the pool the helpers linger, never more of them than the
    /// call's helpers however many calls come, and stop once the linger ends; with the
    /// longest linger set to zero none lingers. (The global setting is changed once each way
    /// here; the other tests' calls only linger as it says.)
    #[test]
    fn helpers_linger_within_their_count_and_stop() {
        use super::{LINGER_MAX, lingering, set_linger_max};
        use std::time::{Duration, Instant};
        let _serial = serial();
        let helpers = rayon::current_num_threads().saturating_sub(1);
        let call = || {
            for_each_part(
                (0..8).collect(),
                || (),
                |_, _: usize| {
                    std::thread::sleep(Duration::from_micros(50));
                    Ok::<(), ()>(())
                },
            )
            .unwrap()
        };
        let settles = |what: &str| {
            let t = Instant::now();
            while lingering() > 0 {
                assert!(
                    t.elapsed() < Duration::from_secs(10),
                    "{what}: still lingering"
                );
                std::thread::sleep(Duration::from_millis(1));
            }
        };
        set_linger_max(Duration::from_millis(20));
        let mut seen = 0;
        for _ in 0..300 {
            call();
            let k = lingering();
            assert!(k <= helpers, "{k} lingering, {helpers} helpers");
            seen = seen.max(k);
        }
        if helpers > 0 {
            assert!(seen > 0, "no helper ever lingered");
        }
        settles("linger of 20 ms");
        set_linger_max(Duration::ZERO);
        settles("linger turned off");
        for _ in 0..100 {
            call();
            assert_eq!(lingering(), 0);
        }
        set_linger_max(LINGER_MAX);
    }

    /// Each lingering helper is a thread of its own: on a pool of 3 threads with places for 4,
    /// the copies (one per worker) take a place on each of the 3 threads, and a second round of
    /// copies while they linger takes no more (a copy that reaches a lingering thread, through
    /// its `yield_now`, returns at once). Only the pool's threads are counted: a linger of the
    /// global pool left by another test may hold a place too.
    #[test]
    fn each_lingering_helper_is_a_thread_of_its_own() {
        use super::{LINGER_MAX, LINGER_UNTIL, clock_ns, linger_here, lingering, set_linger_max};
        use std::sync::atomic::Ordering;
        use std::time::{Duration, Instant};
        let _serial = serial();
        /// Ends every linger when the test ends, passed or not.
        struct End;
        impl Drop for End {
            fn drop(&mut self) {
                set_linger_max(Duration::ZERO);
                let t = Instant::now();
                while lingering() > 0 && t.elapsed() < Duration::from_secs(10) {
                    std::thread::sleep(Duration::from_millis(1));
                }
                set_linger_max(LINGER_MAX);
            }
        }
        let _end = End;
        set_linger_max(Duration::from_secs(2));
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        let mut threads = pool.broadcast(|_| std::thread::current().id());
        threads.sort_by_key(|id| format!("{id:?}"));
        let in_pool = || {
            let h = HOLDERS.lock().unwrap();
            h.iter()
                .filter(|id| threads.contains(id))
                .copied()
                .collect::<Vec<_>>()
        };
        HOLDERS.lock().unwrap().clear();
        LINGER_UNTIL.fetch_max(clock_ns() + 1_000_000_000, Ordering::SeqCst);
        pool.spawn_broadcast(|_| linger_here(4));
        let t = Instant::now();
        while in_pool().len() < 3 && t.elapsed() < Duration::from_secs(5) {
            std::thread::sleep(Duration::from_millis(1));
        }
        pool.spawn_broadcast(|_| linger_here(4));
        std::thread::sleep(Duration::from_millis(50));
        let mut holders = in_pool();
        holders.sort_by_key(|id| format!("{id:?}"));
        assert_eq!(holders, threads, "the pool's threads holding a place");
    }
}
