//! One subdivision run, for instruction counting: loads an OBJ file (with OpenSubdiv's `t crease`
//! tags, through the kernel's own reader) and runs, once, exactly what the criterion bench's
//! `subdiv/*_total` cases time (`kernel/benches/subdiv.rs`): `Refiner::new`, `refine_positions`
//! and `to_mesh` (the half-edge mesh built). That work sits alone in
//! [`blocksmith_subdiv_once_measured`], which is never inlined, so callgrind can count it and
//! nothing else (`--toggle-collect='*blocksmith_subdiv_once_measured*'`); freeing the refiner and
//! the mesh happens after it returns, as the bench and `tests/data/subdiv/osd_bench.cpp` leave
//! freeing out. `tests/data/subdiv/callgrind_vs_osd.sh` runs it beside osd_bench's counterpart.
//!
//!     cargo run --release -p blocksmith-kernel --example subdiv_once -- catmark FILE.obj 3 [hash]
//!     cargo run --release -p blocksmith-kernel --example subdiv_once -- --write-inputs DIR
//!
//! SCHEME is `catmark` (Catmull–Clark) or `loop`, as osd_bench names them. Prints
//! `SUBDIV_ONCE scheme=… F0=… V=… F=… H=… seconds=…`, and with `hash` also `hash=…`, a hash of
//! the whole result (every position's bits, every half-edge's origin, next, previous, twin,
//! face and sharpness, every vertex's half-edge and corner sharpness), so that a speed change
//! can be checked to leave the result bit for bit as it was. `--write-inputs DIR` writes the
//! bench's inputs (`ico6.obj`, `torus100k.obj`, `torus100k_semi.obj`) into DIR instead.

use std::hint::black_box;
use std::path::Path;
use std::time::Instant;

use blocksmith_kernel::subdiv::{Refiner, Scheme};
use blocksmith_kernel::Mesh;

#[path = "../benches/support/subdiv_inputs.rs"]
mod subdiv_inputs;

/// The measured work: the topology refined `levels` deep, the positions refined and the
/// half-edge mesh of the last level built. Returns the refiner and the mesh so that freeing
/// them is not counted.
#[inline(never)]
fn blocksmith_subdiv_once_measured(mesh: &Mesh, scheme: Scheme, levels: u32) -> (Refiner, Mesh) {
    let r = Refiner::new(mesh, scheme, levels).expect("refinable input");
    let p = r.refine_positions(mesh.positions());
    let m = r.to_mesh(p).expect("a valid refined mesh");
    (r, m)
}

/// FNV-1a over the whole mesh (see the module documentation).
fn mesh_hash(m: &Mesh) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    let mut eat = |x: u64| {
        for b in x.to_le_bytes() {
            h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
    };
    for p in m.positions() {
        eat(p.x.to_bits());
        eat(p.y.to_bits());
        eat(p.z.to_bits());
    }
    for v in 0..m.vertex_count() as u32 {
        eat(u64::from(m.vertex_halfedge(v)));
        eat(m.corner_sharpness(v).to_bits());
    }
    for e in 0..m.halfedge_count() as u32 {
        eat(u64::from(m.origin(e)));
        eat(u64::from(m.next(e)));
        eat(u64::from(m.prev(e)));
        eat(u64::from(m.twin(e)));
        eat(u64::from(m.face(e)));
        eat(m.edge_sharpness(e).to_bits());
    }
    for f in 0..m.face_count() as u32 {
        eat(u64::from(m.face_halfedge(f)));
    }
    h
}

fn fail(msg: &str) -> ! {
    eprintln!("subdiv_once: {msg}");
    std::process::exit(2);
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("--write-inputs") {
        let dir = args.get(1).unwrap_or_else(|| fail("--write-inputs needs a folder"));
        subdiv_inputs::write_inputs(Path::new(dir), &subdiv_inputs::inputs())
            .unwrap_or_else(|e| fail(&format!("cannot write the inputs to {dir}: {e}")));
        return;
    }
    let (scheme_name, file, levels, hash) = match &args[..] {
        [s, f, l] => (s, f, l, false),
        [s, f, l, h] if h == "hash" => (s, f, l, true),
        _ => fail("usage: subdiv_once catmark|loop FILE.obj LEVELS [hash], or subdiv_once --write-inputs DIR"),
    };
    let scheme = match scheme_name.as_str() {
        "catmark" => Scheme::CatmullClark,
        "loop" => Scheme::Loop,
        s => fail(&format!("unknown scheme {s:?} (catmark or loop)")),
    };
    let levels: u32 = levels.parse().unwrap_or_else(|_| fail(&format!("bad level count {levels:?}")));
    let bytes = std::fs::read(file).unwrap_or_else(|e| fail(&format!("cannot read {file}: {e}")));
    let mesh = blocksmith_kernel::io::obj::read_obj(&bytes, Path::new(file)).unwrap_or_else(|e| fail(&e.to_string()));
    let start = Instant::now();
    let (r, m) = blocksmith_subdiv_once_measured(black_box(&mesh), black_box(scheme), black_box(levels));
    let seconds = start.elapsed().as_secs_f64();
    let hash = if hash { format!(" hash={:016x}", mesh_hash(&m)) } else { String::new() };
    println!(
        "SUBDIV_ONCE scheme={scheme_name} F0={} V={} F={} H={} seconds={seconds:.5}{hash}",
        mesh.face_count(),
        m.vertex_count(),
        m.face_count(),
        m.halfedge_count()
    );
    drop(black_box((r, m)));
}
