//! Timing shared by the benchmarks that print side-by-side figures of their own.

use std::hint::black_box;
use std::time::{Duration, Instant};

/// Best wall time of `f` over `runs` runs.
pub fn best<R>(runs: usize, mut f: impl FnMut() -> R) -> Duration {
    (0..runs)
        .map(|_| {
            let t = Instant::now();
            black_box(f());
            t.elapsed()
        })
        .min()
        .unwrap_or_default()
}
