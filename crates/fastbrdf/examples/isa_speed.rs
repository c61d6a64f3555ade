use fastbrdf::batch::{Input, Isa, Kernel};
fn main() {
    let n = 4096;
    let x: Vec<f32> = (0..n).map(|i| (i as f32 + 0.5) / n as f32).collect();
    let mut out = vec![0.0f32; n];
    for id in ["pow", "beckmann", "sg", "power16", "flog"] {
        let k = Kernel::new(id, &[]).unwrap();
        for isa in Isa::available() {
            let t = std::time::Instant::now();
            for _ in 0..2000 {
                k.eval_with(isa, Input::Cos(&x), &mut out).unwrap();
                std::hint::black_box(&out);
            }
            let s = t.elapsed().as_secs_f64();
            println!(
                "{id:<10} {:<9} {:.2} G/s  ({:.1} cycles/elem at 3.9 GHz)",
                isa.name(),
                2000.0 * n as f64 / s / 1e9,
                s * 3.9e9 / (2000.0 * n as f64)
            );
        }
    }
}
