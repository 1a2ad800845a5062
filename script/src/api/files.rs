//! `load` and `save`: mesh files by extension (`.obj`, `.glb`, `.gltf`, `.stl`).

use std::fs;
use std::path::PathBuf;

use blocksmith_kernel::{io, Mesh};
use rhai::plugin::*;

use super::mesh::SharedMesh;
use crate::context::RunContext;
use crate::convert::{fail, ScriptResult};

/// The file a script names by `path` for writing: a relative path goes under the run's output
/// directory; missing parent directories are created. Errors name `func`.
///
/// # Errors
/// A relative path leaving the output directory, or a directory that cannot be created.
pub fn output_file(ctx: &NativeCallContext, func: &str, path: &str) -> ScriptResult<PathBuf> {
    let p = match RunContext::of(ctx).output_path(path) {
        Ok(p) => p,
        Err(e) => return fail(func, e),
    };
    if let Some(dir) = p.parent().filter(|d| !d.as_os_str().is_empty()) {
        if let Err(e) = fs::create_dir_all(dir) {
            return fail(func, format!("cannot create directory {}: {e}", dir.display()));
        }
    }
    Ok(p)
}

/// Writes `mesh` to the script path `path` by extension: a relative path goes under the run's
/// output directory, and missing parent directories are created. Errors name `func`.
///
/// # Errors
/// A directory that cannot be created, or the kernel's file error.
pub fn write_mesh(ctx: &NativeCallContext, func: &str, mesh: &Mesh, path: &str) -> ScriptResult<()> {
    let p = output_file(ctx, func, path)?;
    match io::save(mesh, &p) {
        Ok(()) => Ok(()),
        Err(e) => fail(func, e),
    }
}

#[export_module]
pub mod files_api {
    use super::*;

    /// Reads a mesh file: OBJ (polygons kept), glTF (`.gltf` with its buffers) or GLB, or
    /// STL. A relative path is tried from the working directory, then next to the script. A
    /// missing file, an unknown extension or a malformed file is an error naming the path and
    /// the reason.
    ///
    /// ```rhai
    /// let c = cube(2);
    /// c.save("doc_example_cube.obj");
    /// let back = load("doc_example_cube.obj");
    /// assert_eq(back.face_count, 6);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn load(ctx: NativeCallContext, path: &str) -> ScriptResult<SharedMesh> {
        let run = RunContext::of(&ctx);
        let p = run.input_path(path);
        if p.exists() {
            run.record.input(&p);
        }
        match io::load(&p) {
            Ok(m) => Ok(SharedMesh::new(m)),
            Err(e) => fail("load", e),
        }
    }

    /// Writes a mesh by extension: `.obj` (polygons), `.glb`, `.gltf` (+ `.bin`), `.stl`
    /// (binary, triangulated). A relative path goes under the output directory (the working
    /// directory, or the test output directory under `blocksmith test`). Parent directories are
    /// created. Also callable as `mesh.save(path)`.
    ///
    /// ```rhai
    /// save(icosphere(1, 1), "doc_example_ico.glb");
    /// ```
    #[rhai_fn(return_raw)]
    pub fn save(ctx: NativeCallContext, mesh: &mut SharedMesh, path: &str) -> ScriptResult<()> {
        write_mesh(&ctx, "save", &mesh.0, path)
    }
}
