//! Precomputation time of the Taylor terms (f64 FFTs, all cores): patch sizes × term counts, median of runs.
//!
//! `cargo bench --bench precompute` (release); `-- --quick` for fewer runs. Prints a markdown table.
//!
//! Why not criterion: ported to it (flat sampling, ten samples, one process), it measured 5–17 % above this
//! harness's medians on the same machine in alternating runs (256²×40: 54.5–54.6 against 48.9–50.3 ms; 1024²×40:
//! 929–933 against 881–883 ms): its many back-to-back iterations measure a sustained load, not the one
//! precomputation a user waits for, so it would not keep the figures the README quotes.

use std::time::Instant;

use diffract::physics::heightfield::HeightField;
use diffract::physics::taylor::TaylorTerms;

/// A deterministic rough surface (an LCG): the timing does not depend on the heights.
fn patch(n: usize) -> HeightField {
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let h = (0..n * n)
        .map(|_| {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 * 0.4
        })
        .collect();
    HeightField::new(n, n, 0.065, 0.065, h).expect("valid patch")
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    println!("Taylor-term precomputation, f64, {cores} threads (median of runs)\n");
    println!("| patch | terms | runs | median ms | ms per term | MiB of f32 texels |");
    println!("|---|---|---|---|---|---|");
    for n in [256usize, 512, 1024] {
        let hf = patch(n);
        for terms in [10usize, 20, 40] {
            let runs = if quick || n == 1024 { 3 } else { 5 };
            let times: Vec<f64> = (0..runs)
                .map(|_| {
                    let start = Instant::now();
                    let t = TaylorTerms::compute(&hf, terms - 1, None).expect("precompute");
                    std::hint::black_box(&t);
                    start.elapsed().as_secs_f64() * 1e3
                })
                .collect();
            let ms = diffract::io::stats::median(&times).expect("at least one run");
            let mib = (terms * n * n * 8) as f64 / (1 << 20) as f64;
            println!("| {n}² | {terms} | {runs} | {ms:.1} | {:.2} | {mib:.0} |", ms / terms as f64);
        }
    }
}
