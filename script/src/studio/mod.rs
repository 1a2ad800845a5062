//! The studio: seeing a model. [`scene`] turns a run's value or a mesh file into named
//! layers; [`render`] draws them on the CPU (`blocksmith render`).

pub mod render;
pub mod scene;

use std::path::Path;

use crate::run::RunError;
use crate::EngineOptions;

/// `blocksmith render`: runs the recipe (or reads the mesh file) at `input` and writes the
/// picture of all its layers to `out` as PNG. Returns a one-line summary.
///
/// # Errors
/// The run's or file's error, or the PNG write's.
pub fn render_to_png(
    input: &Path,
    options: EngineOptions,
    out: &Path,
    (width, height): (u32, u32),
    view: render::View,
) -> Result<String, RunError> {
    let scene = scene::open(input, options)?;
    let meshes: Vec<&blocksmith_kernel::Mesh> = scene.layers.iter().map(|l| &l.mesh).collect();
    let picture = render::render(&meshes, width, height, view);
    let png = picture.png();
    blocksmith_kernel::io::write_atomic(out, |w| {
        std::io::Write::write_all(w, &png)
            .map_err(|source| blocksmith_kernel::io::IoError::Write { path: out.into(), source })
    })
    .map_err(|e| RunError(format!("error: {e}")))?;
    let triangles: usize = meshes.iter().map(|m| m.triangle_count()).sum();
    Ok(format!("wrote {} ({width}x{height}, {triangles} triangles)", out.display()))
}
