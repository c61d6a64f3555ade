//! How late rayon's helpers join a [`fastbrdf::par::for_each_part`] loop called from outside
//! the pool, with the helpers' linger ([`fastbrdf::par::linger`]) off and on: GGX Cook-Torrance `eval` over about 10^6 column elements in parts of 4096
//! (the Python package's batch).
//! 1. Calls one after another, each after a pause of 0 to 10 ms (linger off, then on): the
//!    median call time and delay from the call's start to a helper's first part, and the
//!    share of parts the calling thread ran.
//! 2. Calls now and then, as a script makes them between other work: after 50 ms idle, one
//!    call, a gap of 0 to 5 ms, and the timed call (median and best; off and on interleaved).
//!
//! Then the median time of `Kernel::eval_par` (a rayon parallel iterator) called back to back.
//! Run: `cargo run --release -p fastbrdf --example par_wake`.

mod common;

use common::{median, pair_columns};
use fastbrdf::ModelSpec;
use fastbrdf::batch::{Input, Kernel};
use fastbrdf::par::{linger_max, set_linger_max};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// One call's time (ms), the delay to a helper's first part (us; NaN: none joined) and the
/// share of parts the caller ran.
type Call = (f64, f64, f64);

fn main() {
    let n = 1usize << 20;
    const PART: usize = 4096;
    let k =
        Kernel::new(&ModelSpec::parse("cook-torrance", &[("d", "ggx"), ("alpha", "0.3")]).unwrap())
            .unwrap();
    // The pairs of `direction_pairs` (about n of them).
    let cols = pair_columns(n, 7);
    let n = cols[0].len();
    let mut out = vec![0.0f32; n];
    let on = linger_max();
    println!(
        "threads: {}, {} elements in parts of {PART}; linger on: at most {} us",
        rayon::current_num_threads(),
        n,
        on.as_micros()
    );
    let mut call = |linger: bool| -> Call {
        set_linger_max(if linger { on } else { Duration::ZERO });
        let caller = std::thread::current().id();
        let first_helper: Mutex<Option<Instant>> = Mutex::new(None);
        let by_caller = AtomicUsize::new(0);
        let parts: Vec<(usize, &mut [f32])> = out.chunks_mut(PART).enumerate().collect();
        let count = parts.len();
        let t = Instant::now();
        fastbrdf::par::for_each_part(
            parts,
            || {
                let mine = std::thread::current().id() == caller;
                if !mine {
                    first_helper
                        .lock()
                        .unwrap()
                        .get_or_insert_with(Instant::now);
                }
                mine
            },
            |mine, (i, o)| {
                if *mine {
                    by_caller.fetch_add(1, Ordering::Relaxed);
                }
                let (lo, hi) = (i * PART, i * PART + o.len());
                let c: Vec<&[f32]> = cols.iter().map(|c| &c[lo..hi]).collect();
                k.eval(Input::Dirs([c[0], c[1], c[2], c[3], c[4], c[5]]), o)
            },
        )
        .unwrap();
        let ms = t.elapsed().as_secs_f64() * 1e3;
        let h = first_helper.lock().unwrap().map_or(f64::NAN, |h| {
            h.saturating_duration_since(t).as_secs_f64() * 1e6
        });
        (
            ms,
            h,
            by_caller.load(Ordering::Relaxed) as f64 / count as f64,
        )
    };
    let col = |v: &[Call], f: fn(&Call) -> f64| median(v.iter().map(f).collect());
    println!("\n1. one call after another, each after a pause (medians of 31; off, then on)");
    println!("linger  pause_us  call_ms  helper_start_us  caller_share");
    for linger in [false, true] {
        for pause_us in [0u64, 20, 100, 300, 1000, 3000, 10000] {
            let v: Vec<Call> = (0..31)
                .map(|_| {
                    std::thread::sleep(Duration::from_micros(pause_us));
                    call(linger)
                })
                .collect();
            println!(
                "{:>6}  {pause_us:8}  {:7.3}  {:15.1}  {:12.2}",
                if linger { "on" } else { "off" },
                col(&v, |c| c.0),
                col(&v, |c| c.1),
                col(&v, |c| c.2)
            );
        }
    }
    println!("\n2. after 50 ms idle: a call, a gap, the timed call (median, best of 21)");
    println!(" gap_us  call_ms off (best)  on (best)  helper_start_us off  on");
    for gap_us in [0u64, 50, 200, 1000, 5000] {
        let (mut off, mut on) = (vec![], vec![]);
        for _ in 0..21 {
            for linger in [false, true] {
                std::thread::sleep(Duration::from_millis(50));
                call(linger);
                std::thread::sleep(Duration::from_micros(gap_us));
                let c = call(linger);
                if linger { on.push(c) } else { off.push(c) }
            }
        }
        let best = |v: &[Call]| v.iter().map(|c| c.0).fold(f64::INFINITY, f64::min);
        println!(
            "{gap_us:7}  {:7.3} ({:.3})  {:7.3} ({:.3})  {:9.1} {:9.1}",
            col(&off, |c| c.0),
            best(&off),
            col(&on, |c| c.0),
            best(&on),
            col(&off, |c| c.1),
            col(&on, |c| c.1)
        );
    }
    set_linger_max(on);
    // The library's own threaded call, back to back.
    let input = Input::Dirs([&cols[0], &cols[1], &cols[2], &cols[3], &cols[4], &cols[5]]);
    let times: Vec<f64> = (0..31)
        .map(|_| {
            let t = Instant::now();
            k.eval_par(input, &mut out).unwrap();
            t.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    println!("\nKernel::eval_par back to back: {:.3} ms", median(times));
}
