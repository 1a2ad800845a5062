//! Load (and weld) a mesh file several times and print the median time: the blocksmith side of
//! tests/data/files/bench_load.py, which times trimesh on the same files.
//!
//!     cargo run --release --example load_weld -- FILE [RUNS]
//!
//! Prints `BLOCKSMITH_LOAD file=… median_s=… min_s=… vertices=… faces=… closed=…`.

use std::time::Instant;

fn main() {
    let mut args = std::env::args().skip(1);
    let Some(path) = args.next() else {
        eprintln!("usage: load_weld FILE [RUNS]");
        std::process::exit(2);
    };
    let runs: usize = args.next().and_then(|r| r.parse().ok()).unwrap_or(5);
    let mut times = Vec::with_capacity(runs);
    let mut last = None;
    for _ in 0..runs {
        let start = Instant::now();
        let mesh = match blocksmith_kernel::io::load(&path) {
            Ok(m) => m,
            Err(e) => {
                eprintln!("{e}");
                std::process::exit(1);
            }
        };
        times.push(start.elapsed().as_secs_f64());
        last = Some(mesh);
    }
    times.sort_by(f64::total_cmp);
    let m = last.expect("at least one run");
    println!(
        "BLOCKSMITH_LOAD file={path} median_s={:.4} min_s={:.4} vertices={} faces={} closed={}",
        times[times.len() / 2],
        times[0],
        m.vertex_count(),
        m.face_count(),
        m.is_closed()
    );
}
