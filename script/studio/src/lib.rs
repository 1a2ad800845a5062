//! blocksmith-studio: seeing a model. [`scene`] turns a run's value or a mesh file into named
//! layers; [`render`] draws them on the CPU (`blocksmith render`); [`session`] runs a recipe
//! again and again and keeps what is shown, [`watch`] runs it on save, and [`server`] shows it
//! in a browser page ([`assets`], the files under `script/studio/web/`, embedded), for
//! `blocksmith watch`, `view` and the REPL's `:show`.
//!
//! It depends on the bindings (`blocksmith-script`, whose runner it uses: one way to run a
//! recipe) and the kernel, and owns the web, watcher and image crates (httparse, tungstenite,
//! notify, image); nothing of the terminal. Who may read and drive a page is [`guard`]'s. The command line depends on it, never the reverse.

pub mod assets;
pub mod defects;
pub mod guard;
pub mod http;
pub mod recipe_lines;
pub mod render;
pub mod scene;
pub mod server;
pub mod session;
pub mod socket;
pub mod watch;

use std::collections::BTreeMap;
use std::path::Path;

use blocksmith_script::run::RunError;
use blocksmith_script::EngineOptions;

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
    let drawn = scene.layers.iter().map(scene::Layer::drawn).collect::<Result<Vec<_>, _>>()?;
    let meshes: Vec<&blocksmith_kernel::Mesh> = drawn.iter().collect();
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

/// `blocksmith watch` (a recipe, run again on save) and `blocksmith view` (a mesh file, read
/// again on save): serves the page on 127.0.0.1:`port`, prints its address (with the
/// session's token), opens it in the browser when `open`, and serves until the process is
/// stopped.
///
/// # Errors
/// A missing file, a port that cannot be bound, a folder that cannot be watched, or why the
/// server stopped.
pub fn serve(file: &Path, params: BTreeMap<String, String>, port: u16, open: bool) -> Result<(), String> {
    if !file.is_file() {
        return Err(format!("error: {}: no such file", file.display()));
    }
    let is_recipe = file.extension().is_some_and(|e| e.eq_ignore_ascii_case("rhai"));
    let source = if is_recipe {
        session::Source::Recipe(file.to_path_buf())
    } else {
        blocksmith_kernel::io::Format::from_path(file).map_err(|e| format!("error: {e}"))?;
        session::Source::File(file.to_path_buf())
    };
    let studio = server::Studio::bind(port)?;
    let session = session::Session::start(source, params);
    watch::watch(&session)?;
    let url = studio.url();
    eprintln!("showing {} at {url} (Ctrl-C stops)", file.display());
    if open {
        if let Err(hint) = open_browser(&url) {
            eprintln!("{hint}");
        }
    }
    studio.serve(&session)
}

/// Opens `url` with the desktop's opener, quietly (what it prints is not ours to show).
///
/// # Errors
/// A one-line hint to open the address by hand, when there is no desktop (no display on
/// Linux) or no opener.
pub fn open_browser(url: &str) -> Result<(), String> {
    let hint = "(no browser to open here: open the address above in one)".to_string();
    let opener = if cfg!(target_os = "macos") {
        "open"
    } else if cfg!(windows) {
        "explorer"
    } else {
        let display = ["DISPLAY", "WAYLAND_DISPLAY"].iter().any(|v| std::env::var_os(v).is_some_and(|d| !d.is_empty()));
        if !display {
            return Err(hint);
        }
        "xdg-open"
    };
    let child = std::process::Command::new(opener)
        .arg(url)
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .map_err(|_| hint)?;
    // Reaped when it ends, whatever it says.
    std::thread::spawn(move || {
        let mut child = child;
        let _ = child.wait();
    });
    Ok(())
}
