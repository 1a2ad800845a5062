//! One step of the mesh_core bench, once, so that `/usr/bin/time -v` can report its peak
//! memory: `cargo run --release -p blocksmith-kernel --example mesh_core_peak -- STEP MESH`.
//!
//! STEP: `generate` (the inputs only), `build`, `measures`, `write-glb`, `write-obj`,
//! `read-glb`, `read-obj` (reading the files the write steps or the bench left in
//! target/bench-data/). MESH: `quads` (1M quads) or `tris` (1M triangles). REPEAT (default 1)
//! runs the step that many times. Prints one line `MESH_CORE_PEAK step=… mesh=… faces=…
//! seconds=… min=…` (median and fastest run of the step alone, without generating the inputs).

use std::f64::consts::TAU;
use std::path::PathBuf;
use std::time::Instant;

use blocksmith_kernel::io::{load, save};
use blocksmith_kernel::{Mesh, Vec3};

/// The bench's torus grid (see benches/mesh_core.rs).
fn torus_grid(n: u32, m: u32, triangles: bool) -> (Vec<Vec3>, Vec<u32>, Vec<u32>) {
    let mut positions = Vec::with_capacity((n * m) as usize);
    for i in 0..n {
        let u = TAU * f64::from(i) / f64::from(n);
        for j in 0..m {
            let v = TAU * f64::from(j) / f64::from(m);
            let r = 2.0 + 0.5 * v.cos();
            positions.push(Vec3::new(r * u.cos(), r * u.sin(), 0.5 * v.sin()));
        }
    }
    let id = |i: u32, j: u32| (i % n) * m + j % m;
    let mut indices = Vec::new();
    let mut arities = Vec::new();
    for i in 0..n {
        for j in 0..m {
            let q = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
            if triangles {
                indices.extend_from_slice(&[q[0], q[1], q[2], q[0], q[2], q[3]]);
                arities.extend_from_slice(&[3, 3]);
            } else {
                indices.extend_from_slice(&q);
                arities.push(4);
            }
        }
    }
    (positions, indices, arities)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (step, which, repeat) = match args.as_slice() {
        [s, m] => (s.as_str(), m.as_str(), 1),
        [s, m, r] => (s.as_str(), m.as_str(), r.parse()?),
        _ => return Err("usage: mesh_core_peak STEP quads|tris [REPEAT]".into()),
    };
    let (name, triangles) = match which {
        "quads" => ("quads_1m", false),
        "tris" => ("tris_1m", true),
        _ => return Err(format!("unknown mesh {which:?} (quads or tris)").into()),
    };
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/bench-data");
    std::fs::create_dir_all(&dir)?;
    let file = |ext: &str| dir.join(format!("{name}.{ext}"));
    let needs_mesh = matches!(step, "build" | "measures" | "write-glb" | "write-obj");
    let (positions, indices, arities) = if needs_mesh || step == "generate" {
        torus_grid(1000, if triangles { 500 } else { 1000 }, triangles)
    } else {
        Default::default()
    };
    let mesh = if needs_mesh && step != "build" {
        Some(Mesh::from_indexed(positions.clone(), &indices, &arities)?)
    } else {
        None
    };
    let mut seconds = Vec::new();
    let mut faces = 0;
    for _ in 0..repeat {
        let start = Instant::now();
        faces = run_step(step, mesh.as_ref(), &positions, &indices, &arities, &file)?;
        seconds.push(start.elapsed().as_secs_f64());
    }
    seconds.sort_by(f64::total_cmp);
    println!(
        "MESH_CORE_PEAK step={step} mesh={which} faces={faces} seconds={:.3} min={:.3} runs={repeat}",
        seconds[seconds.len() / 2],
        seconds[0]
    );
    Ok(())
}

/// Runs one step once and returns the number of faces it handled.
fn run_step(
    step: &str,
    mesh: Option<&Mesh>,
    positions: &[Vec3],
    indices: &[u32],
    arities: &[u32],
    file: &dyn Fn(&str) -> PathBuf,
) -> Result<usize, Box<dyn std::error::Error>> {
    Ok(match step {
        "generate" => arities.len(),
        "build" => Mesh::from_indexed(positions.to_vec(), indices, arities)?.face_count(),
        "measures" => {
            let m = mesh.ok_or("no mesh")?;
            let all = m.measures();
            assert!(all.volume > 0.0 && all.genus == 1);
            all.faces
        }
        "write-glb" | "write-obj" => {
            let m = mesh.ok_or("no mesh")?;
            save(m, file(&step[6..]))?;
            m.face_count()
        }
        "read-glb" | "read-obj" => load(file(&step[5..]))?.face_count(),
        _ => return Err(format!("unknown step {step:?}").into()),
    })
}
