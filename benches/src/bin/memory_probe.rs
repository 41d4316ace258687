//! `memory_probe MB...`: what memory costs on this machine at a given footprint: the rate at
//! which fresh pages are faulted in (the kernel zeroes each), and the time of a random
//! read within the whole block (20 million reads at xorshift addresses, each address
//! depending on the byte read before, so the reads wait for each other as the look-ups
//! of an intern table do: latency, not bandwidth). With
//! the command-line tool's allocator, so large blocks come as it gives them to the
//! derivation. It shows whether a derivation's time per unit of work may grow with its
//! footprint on this machine (BENCHMARKS.md, "Derivation at scale").

use std::time::Instant;

// The command-line tool's allocator.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() {
    let sizes: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    if sizes.is_empty() {
        eprintln!("usage: memory_probe MB [MB ...]");
        std::process::exit(2);
    }
    for mb in sizes {
        let n = mb << 20;
        let start = Instant::now();
        // Allocated zeroed (fresh pages are not touched yet); one write per 4 kB page
        // faults every page in, and the kernel zeroes it.
        let mut block = vec![0u8; n];
        let mut k = 0;
        while k < n {
            block[k] = 1;
            k += 4096;
        }
        let fault = start.elapsed().as_secs_f64();
        let reads = 20_000_000u32;
        let (mut x, mut sum) = (0x2545_f491_4f6c_dd1d_u64, 0u64);
        let start = Instant::now();
        for _ in 0..reads {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let byte = u64::from(block[(x % n as u64) as usize]);
            sum += byte;
            x ^= byte;
        }
        let read = start.elapsed().as_secs_f64() / f64::from(reads) * 1e9;
        println!(
            "{mb:6} MB: pages in at {:5.2} GB/s, a random read {read:5.1} ns ({sum} set bytes read)",
            mb as f64 / 1024.0 / fault
        );
    }
}
