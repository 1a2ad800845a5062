//! The subdivision speed inputs, shared by `benches/subdiv.rs` (criterion) and
//! `examples/subdiv_once.rs` (one run for callgrind), so both time the very same meshes and
//! write the very same OBJ files for OpenSubdiv's side (`tests/data/subdiv/osd_bench.cpp`).
//!
//! - `ico6`: the icosphere with 6 subdivisions (40,962 vertices, 81,920 triangles);
//! - `torus100k`: a 320 × 320 quad torus (102,400 quads, all regular);
//! - `torus100k_semi`: the same torus with 20 loops around the tube (6,400 edges) of sharpness
//!   2.5, so every level meets semi-sharp creases and the last blends the rules.
//!
//! Included with `#[path]` (a folder without `main.rs` is not a bench target of its own).

use std::path::Path;

use blocksmith_kernel::io::obj::write_obj;
use blocksmith_kernel::Mesh;

/// The 320 × 320 torus with the loops around the tube at every 16th step along it creased with
/// sharpness 2.5.
pub fn semi_sharp_torus() -> Mesh {
    let mut torus = Mesh::torus(2.0, 0.5, 320, 320);
    let id = |i: u32, j: u32| i * 320 + j % 320;
    let loops: Vec<[u32; 2]> =
        (0..320).step_by(16).flat_map(|i| (0..320).map(move |j| [id(i, j), id(i, j + 1)])).collect();
    torus.crease_edges_sharpness(&loops, 2.5).unwrap();
    torus
}

/// The three inputs by name, in the order the bench runs them.
pub fn inputs() -> Vec<(&'static str, Mesh)> {
    vec![
        ("ico6", Mesh::icosphere(1.0, 6)),
        ("torus100k", Mesh::torus(2.0, 0.5, 320, 320)),
        ("torus100k_semi", semi_sharp_torus()),
    ]
}

/// Writes `inputs` as `NAME.obj` files (crease tags included) into `dir`.
pub fn write_inputs(dir: &Path, inputs: &[(&str, Mesh)]) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    for (name, mesh) in inputs {
        let mut bytes = Vec::new();
        write_obj(mesh, &mut bytes)?;
        std::fs::write(dir.join(format!("{name}.obj")), bytes)?;
    }
    Ok(())
}
