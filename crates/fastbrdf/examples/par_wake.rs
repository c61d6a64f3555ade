//! How late rayon's helpers join a [`fastbrdf::par::for_each_part`] loop called from outside
//! the pool, by the idle time before the call: GGX Cook-Torrance `eval` over about 10^6
//! column elements in parts of 4096 (the Python package's batch), each call after a pause of
//! 0 to 10 ms. Prints, per pause, the median call time, the median delay from the call's
//! start to a helper's first part, and the share of parts the calling thread ran; then the
//! median time of `Kernel::eval_par` (a rayon parallel iterator) on the same input called
//! back to back.
//! Run: `cargo run --release -p fastbrdf --example par_wake`.

mod common;

use common::{median, pair_columns};
use fastbrdf::ModelSpec;
use fastbrdf::batch::{Input, Kernel};
use std::sync::Mutex;
use std::time::{Duration, Instant};

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
    println!(
        "threads: {}, {} elements in parts of {PART}",
        rayon::current_num_threads(),
        n
    );
    println!("pause_us  call_ms  helper_start_us  caller_share");
    for pause_us in [0u64, 20, 100, 300, 1000, 3000, 10000] {
        let (mut calls, mut starts, mut shares) = (vec![], vec![], vec![]);
        for _ in 0..31 {
            std::thread::sleep(Duration::from_micros(pause_us));
            let caller = std::thread::current().id();
            let first_helper: Mutex<Option<Instant>> = Mutex::new(None);
            let by_caller = std::sync::atomic::AtomicUsize::new(0);
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
                        by_caller.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    }
                    let (lo, hi) = (i * PART, i * PART + o.len());
                    let c: Vec<&[f32]> = cols.iter().map(|c| &c[lo..hi]).collect();
                    k.eval(Input::Dirs([c[0], c[1], c[2], c[3], c[4], c[5]]), o)
                },
            )
            .unwrap();
            calls.push(t.elapsed().as_secs_f64() * 1e3);
            let h = first_helper.lock().unwrap().map_or(f64::NAN, |h| {
                h.saturating_duration_since(t).as_secs_f64() * 1e6
            });
            starts.push(h);
            shares.push(by_caller.load(std::sync::atomic::Ordering::Relaxed) as f64 / count as f64);
        }
        println!(
            "{pause_us:8}  {:7.3}  {:15.1}  {:12.2}",
            median(calls),
            median(starts),
            median(shares)
        );
    }
    // The library's own threaded call, back to back.
    let input = Input::Dirs([&cols[0], &cols[1], &cols[2], &cols[3], &cols[4], &cols[5]]);
    let times: Vec<f64> = (0..31)
        .map(|_| {
            let t = Instant::now();
            k.eval_par(input, &mut out).unwrap();
            t.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    println!("Kernel::eval_par back to back: {:.3} ms", median(times));
}
