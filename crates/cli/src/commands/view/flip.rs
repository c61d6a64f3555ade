//! FLIP off the pictures' critical path (issue 30). FLIP (NVIDIA's reference implementation,
//! single-threaded) took 45% of the page's full picture when `/api/render` computed it before
//! answering; RMSE and PSNR take milliseconds. So `/api/render` hands each finished picture to
//! this pool, and the pool's threads compute `compare::metrics` (the function `fastbrdf
//! compare` calls, so the numbers are the CLI's) of each model against the reference:
//! - as soon as a model's picture exists (the reference is rendered first), so FLIP runs while
//!   the next models render, and different models' FLIPs run on different threads. One image's
//!   FLIP is never split: its filters reach across any tile border, so tiles would not give the
//!   whole image's number;
//! - at a lower CPU priority (nice +10 on Linux) than the renders and the HTTP threads, so the
//!   pictures are not slowed by the numbers that follow them.
//!
//! `/api/render?flip=later` answers with the pictures, RMSE and PSNR and a job id;
//! `/api/flip?job=ID` waits for the job and answers the whole metrics. Bounds: at most
//! [`FLIP_JOBS`] jobs hold pictures (a render that finds them all taken computes FLIP itself,
//! as before, inside its render slot: back-pressure, never unbounded memory); a client's newer
//! generation cancels its older jobs' remaining work (their answer is 409); the results of the
//! last [`KEPT_RESULTS`] jobs are kept (a few numbers each).

use fastbrdf_render::compare::{self, Metrics};
use std::collections::{HashMap, VecDeque};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::{Duration, Instant};

/// Jobs holding pictures at once (being rendered or waiting for FLIP).
pub const FLIP_JOBS: usize = 4;
/// Finished jobs whose metrics are kept for `/api/flip`.
pub const KEPT_RESULTS: usize = 256;

/// How a job ended.
#[derive(Clone, Debug)]
pub enum Outcome {
    /// Each model's metrics against the reference, in the request's order, and the seconds of
    /// FLIP work (summed over models).
    Done(Vec<Metrics>, f64),
    /// Its client asked for a newer generation before the job finished.
    Superseded,
    /// Its render failed or was dropped.
    Cancelled,
    /// FLIP panicked (the pool's thread goes on).
    Failed,
}

/// What [`Flips::wait`] found.
#[derive(Debug)]
pub enum Waited {
    /// The job's client and generation, and how it ended.
    Ended(String, u64, Outcome),
    /// No such job: never made, or its result is no longer kept.
    Unknown,
    /// Still computing at the deadline.
    Pending,
    /// The waiting request's client has gone.
    Gone,
}

struct Job {
    client: String,
    generation: u64,
    size: (u32, u32),
    names: Vec<String>,
    reference: Option<Arc<Vec<u8>>>,
    tests: Vec<Option<Arc<Vec<u8>>>>,
    metrics: Vec<Option<Metrics>>,
    seconds: f64,
}

#[derive(Default)]
struct Inner {
    next: u64,
    open: HashMap<u64, Job>,
    /// (job, model) pairs whose pictures are all there, oldest first.
    tasks: VecDeque<(u64, usize)>,
    results: HashMap<u64, (String, u64, Outcome)>,
    order: VecDeque<u64>,
    /// FLIPs computed by the pool since it started (tests read it).
    computed: u64,
    stopped: bool,
}

/// The pool: its jobs, and threads that compute their FLIPs.
pub struct Flips {
    inner: Mutex<Inner>,
    work: Condvar,
    ended: Condvar,
}

impl Flips {
    /// A pool with `threads` worker threads (0: nothing runs until [`Flips::run_one`] is
    /// called, for tests).
    pub fn new(threads: usize) -> Arc<Self> {
        let f = Arc::new(Self {
            inner: Mutex::new(Inner {
                next: 1,
                ..Inner::default()
            }),
            work: Condvar::new(),
            ended: Condvar::new(),
        });
        for k in 0..threads {
            let pool = f.clone();
            let spawned = std::thread::Builder::new()
                .name(format!("fastbrdf-flip-{k}"))
                .spawn(move || {
                    lower_priority(FLIP_NICE);
                    while pool.next_task(true).is_some_and(|t| pool.run(t)) {}
                });
            // Without threads (none could start) the renders compute FLIP themselves.
            if spawned.is_err() {
                break;
            }
        }
        f
    }

    fn lock(&self) -> MutexGuard<'_, Inner> {
        self.inner.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Stops the threads (after the FLIP each may be computing).
    pub fn stop(&self) {
        self.lock().stopped = true;
        self.work.notify_all();
    }

    /// A job for `names` (the models, in order) against a reference, pictures `size`; None
    /// when [`FLIP_JOBS`] jobs hold pictures already.
    pub fn open(
        &self,
        client: &str,
        generation: u64,
        size: (u32, u32),
        names: &[String],
    ) -> Option<u64> {
        let mut g = self.lock();
        if g.open.len() >= FLIP_JOBS {
            return None;
        }
        let id = g.next;
        g.next += 1;
        g.open.insert(
            id,
            Job {
                client: client.to_string(),
                generation,
                size,
                names: names.to_vec(),
                reference: None,
                tests: vec![None; names.len()],
                metrics: vec![None; names.len()],
                seconds: 0.0,
            },
        );
        Some(id)
    }

    /// Hands over a picture (sRGB 8-bit RGB): the reference (`model` None) or model `k`; the
    /// pairs now complete become tasks.
    pub fn picture(&self, job: u64, model: Option<usize>, px: Arc<Vec<u8>>) {
        let mut g = self.lock();
        let Some(j) = g.open.get_mut(&job) else {
            return;
        };
        let ready: Vec<usize> = match model {
            None => {
                j.reference = Some(px);
                (0..j.tests.len())
                    .filter(|&k| j.tests[k].is_some())
                    .collect()
            }
            Some(k) => {
                j.tests[k] = Some(px);
                if j.reference.is_some() {
                    vec![k]
                } else {
                    vec![]
                }
            }
        };
        g.tasks.extend(ready.into_iter().map(|k| (job, k)));
        drop(g);
        self.work.notify_all();
    }

    /// Ends a job that will not be finished (its render failed or was dropped).
    pub fn cancel(&self, job: u64) {
        self.end(job, Outcome::Cancelled);
    }

    /// `client` has asked for `generation`: its older open jobs end as superseded.
    pub fn supersede(&self, client: &str, generation: u64) {
        let stale: Vec<u64> = self
            .lock()
            .open
            .iter()
            .filter(|(_, j)| j.client == client && j.generation < generation)
            .map(|(&id, _)| id)
            .collect();
        for id in stale {
            self.end(id, Outcome::Superseded);
        }
    }

    fn end(&self, job: u64, outcome: Outcome) {
        let mut g = self.lock();
        let Some(j) = g.open.remove(&job) else {
            return;
        };
        g.tasks.retain(|t| t.0 != job);
        g.results.insert(job, (j.client, j.generation, outcome));
        g.order.push_back(job);
        while g.order.len() > KEPT_RESULTS {
            if let Some(old) = g.order.pop_front() {
                g.results.remove(&old);
            }
        }
        drop(g);
        self.ended.notify_all();
    }

    /// Waits until `job` has ended, at most until `deadline`, giving up when `gone()` says
    /// the waiting request's client has gone (asked every 100 ms).
    pub fn wait(&self, job: u64, deadline: Instant, gone: &dyn Fn() -> bool) -> Waited {
        let mut g = self.lock();
        loop {
            if let Some((c, generation, o)) = g.results.get(&job) {
                return Waited::Ended(c.clone(), *generation, o.clone());
            }
            if !g.open.contains_key(&job) {
                return Waited::Unknown;
            }
            if gone() {
                return Waited::Gone;
            }
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return Waited::Pending;
            }
            g = self
                .ended
                .wait_timeout(g, left.min(Duration::from_millis(100)))
                .unwrap_or_else(|e| e.into_inner())
                .0;
        }
    }

    /// FLIPs the pool has computed.
    #[cfg(test)]
    pub fn computed(&self) -> u64 {
        self.lock().computed
    }

    /// The next task (waiting for one if `block`); None when stopped, or none waits and not
    /// `block`.
    fn next_task(&self, block: bool) -> Option<(u64, usize)> {
        let mut g = self.lock();
        loop {
            if g.stopped {
                return None;
            }
            if let Some(t) = g.tasks.pop_front() {
                return Some(t);
            }
            if !block {
                return None;
            }
            g = self.work.wait(g).unwrap_or_else(|e| e.into_inner());
        }
    }

    /// Computes one task (outside the lock) and records it; true (the worker goes on).
    fn run(&self, (job, k): (u64, usize)) -> bool {
        let input = {
            let g = self.lock();
            g.open.get(&job).and_then(|j| {
                Some((
                    j.names[k].clone(),
                    j.reference.clone()?,
                    j.tests[k].clone()?,
                    j.size,
                ))
            })
        };
        // The job ended meanwhile (superseded, cancelled): nothing to do.
        let Some((name, r, t, (w, h))) = input else {
            return true;
        };
        let t0 = Instant::now();
        let m = std::panic::catch_unwind(|| compare::metrics(&name, &r, &t, w, h));
        let seconds = t0.elapsed().as_secs_f64();
        let Ok(m) = m else {
            self.end(job, Outcome::Failed);
            return true;
        };
        let mut g = self.lock();
        g.computed += 1;
        let Some(j) = g.open.get_mut(&job) else {
            return true;
        };
        j.metrics[k] = Some(m);
        j.seconds += seconds;
        if j.metrics.iter().all(Option::is_some) {
            let done = Outcome::Done(j.metrics.iter().flatten().cloned().collect(), j.seconds);
            drop(g);
            self.end(job, done);
        }
        true
    }

    /// Runs one waiting task on this thread; false when none waits (tests drive a pool of no
    /// threads with it).
    #[cfg(test)]
    pub fn run_one(&self) -> bool {
        self.next_task(false).is_some_and(|t| self.run(t))
    }
}

/// How much lower the FLIP threads' CPU priority is (nice +10: about a tenth of a nice-0
/// thread's share of a core they compete for).
pub const FLIP_NICE: i32 = 10;

/// Lowers this thread's CPU priority by `nice`, so that FLIP takes the cores the renders
/// leave. Linux only (elsewhere `setpriority` would lower the whole process); raising
/// niceness needs no privilege.
fn lower_priority(nice: i32) {
    #[cfg(not(target_os = "linux"))]
    let _ = nice;
    #[cfg(target_os = "linux")]
    // SAFETY: gettid, getpriority and setpriority only read their arguments; a failure leaves
    // the priority as it was.
    unsafe {
        let tid = libc::gettid() as libc::id_t;
        // Relative to the server's own niceness (a thread starts with the process's).
        let now = libc::getpriority(libc::PRIO_PROCESS, tid);
        libc::setpriority(libc::PRIO_PROCESS, tid, (now + nice).min(19));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn px(v: u8) -> Arc<Vec<u8>> {
        Arc::new(vec![v; 16 * 16 * 3])
    }

    fn ended(f: &Flips, job: u64) -> Outcome {
        match f.wait(job, Instant::now(), &|| false) {
            Waited::Ended(_, _, o) => o,
            w => panic!("job {job}: {w:?}"),
        }
    }

    #[test]
    fn a_model_is_computed_once_it_and_the_reference_are_there() {
        let f = Flips::new(0);
        let names = ["a".to_string(), "b".to_string()];
        let job = f.open("c", 1, (16, 16), &names).unwrap();
        // A model's picture before the reference's: nothing to compute yet.
        f.picture(job, Some(1), px(10));
        assert!(!f.run_one());
        f.picture(job, None, px(0));
        assert!(f.run_one() && !f.run_one());
        assert!(matches!(
            f.wait(job, Instant::now(), &|| false),
            Waited::Pending
        ));
        f.picture(job, Some(0), px(0));
        assert!(f.run_one());
        let Outcome::Done(m, _) = ended(&f, job) else {
            panic!()
        };
        let want = compare::metrics("b", &px(0), &px(10), 16, 16);
        assert_eq!((m[0].flip, m[1].model.as_str()), (0.0, "b"));
        assert_eq!((m[1].flip, m[1].rmse), (want.flip, want.rmse));
        assert_eq!(f.computed(), 2);
    }

    #[test]
    fn jobs_are_bounded_and_ended_ones_free_their_place() {
        let f = Flips::new(0);
        let names = ["a".to_string()];
        let jobs: Vec<u64> = (0..FLIP_JOBS)
            .map(|k| f.open("c", k as u64, (16, 16), &names).unwrap())
            .collect();
        assert!(f.open("d", 0, (16, 16), &names).is_none());
        f.cancel(jobs[0]);
        assert!(matches!(ended(&f, jobs[0]), Outcome::Cancelled));
        // Generation FLIP_JOBS - 1 supersedes the older ones of client c, not itself.
        f.supersede("c", FLIP_JOBS as u64 - 1);
        for &j in &jobs[1..FLIP_JOBS - 1] {
            assert!(matches!(ended(&f, j), Outcome::Superseded));
        }
        let last = jobs[FLIP_JOBS - 1];
        assert!(matches!(
            f.wait(last, Instant::now(), &|| false),
            Waited::Pending
        ));
        assert!(matches!(
            f.wait(last, Instant::now() + Duration::from_secs(60), &|| true),
            Waited::Gone
        ));
        assert!(f.open("d", 0, (16, 16), &names).is_some());
        assert!(matches!(
            f.wait(u64::MAX, Instant::now(), &|| false),
            Waited::Unknown
        ));
        // Only the last KEPT_RESULTS results are kept.
        for _ in 0..KEPT_RESULTS {
            let j = f.open("e", 0, (16, 16), &names).unwrap();
            f.cancel(j);
        }
        assert!(matches!(
            f.wait(jobs[0], Instant::now(), &|| false),
            Waited::Unknown
        ));
    }
}
