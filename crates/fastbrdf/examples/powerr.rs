fn main() {
    for y in [1.0f32, 1.5, 7.0, 20.0, 100.0, 1000.0, 10000.0] {
        let (mut w, mut wl, mut at) = (0.0f64, 0.0f64, 0.0f32);
        for i in 1..=400_000 {
            let x = i as f32 / 400_000.0;
            let want = (x as f64).powf(y as f64);
            if want < 1e-9 {
                continue;
            }
            let rel = (fastbrdf::batch::math::pow(x, y) as f64 - want).abs() / want;
            if rel > w {
                w = rel;
                at = x;
            }
            let lr = (fastbrdf::batch::math::log2(x) as f64 - (x as f64).log2()).abs();
            wl = wl.max(lr);
        }
        let lib = (1..=400_000)
            .map(|i| i as f32 / 400_000.0)
            .filter(|x| (*x as f64).powf(y as f64) >= 1e-9)
            .map(|x| {
                ((x.powf(y)) as f64 - (x as f64).powf(y as f64)).abs() / (x as f64).powf(y as f64)
            })
            .fold(0.0, f64::max);
        println!(
            "y={y}: fast pow max rel {w:.3e} at x={at}; libm powf max rel {lib:.3e}; log2 max abs {wl:.2e}"
        );
    }
}
