//! The gallery (`docs/gallery.md`, made by `docs/gallery.sh`) stays current: it shows every
//! example recipe, each picture is what `blocksmith render` draws today, byte for byte, and
//! each shows the model (enough pixels differ from the background).

use std::path::{Path, PathBuf};
use std::process::Command;

use blocksmith_studio::render::BACKGROUND;

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).ancestors().nth(2).unwrap().to_path_buf()
}

/// The recipes of `examples/` (helpers named `_*.rhai` are not recipes), by name.
fn recipes() -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(workspace().join("examples"))
        .unwrap()
        .filter_map(Result::ok)
        .filter_map(|e| e.file_name().to_str().map(str::to_string))
        .filter(|n| n.ends_with(".rhai") && !n.starts_with('_'))
        .map(|n| n.trim_end_matches(".rhai").to_string())
        .collect();
    names.sort();
    names
}

#[test]
fn the_gallery_shows_every_example_as_render_draws_it() {
    let gallery = std::fs::read_to_string(workspace().join("docs/gallery.md")).unwrap();
    let out_dir = workspace().join("target/test-output/gallery");
    std::fs::create_dir_all(&out_dir).unwrap();
    let background = BACKGROUND.map(|x| (x.sqrt() * 255.0 + 0.5) as u8);
    let mut problems = Vec::new();
    let names = recipes();
    assert!(names.len() >= 20, "only {} recipes", names.len());
    for name in &names {
        if !gallery.contains(&format!("![{name}](gallery/{name}.png)")) {
            problems.push(format!("{name}: not in docs/gallery.md"));
        }
        let out = out_dir.join(format!("{name}.png"));
        let o = Command::new(env!("CARGO_BIN_EXE_blocksmith"))
            .arg("render")
            .arg(workspace().join("examples").join(format!("{name}.rhai")))
            .args(["--size", "320x240", "-o"])
            .arg(&out)
            .output()
            .unwrap();
        if !o.status.success() {
            problems.push(format!("{name}: render failed:\n{}", String::from_utf8_lossy(&o.stderr)));
            continue;
        }
        let drawn = std::fs::read(&out).unwrap();
        let picture = image::load_from_memory(&drawn).unwrap().to_rgb8();
        let covered = picture.pixels().filter(|p| p.0 != background).count();
        let share = covered as f64 / f64::from(picture.width() * picture.height());
        if share < 0.01 {
            problems.push(format!("{name}: only {:.1} % of the picture shows the model", share * 100.0));
        }
        match std::fs::read(workspace().join(format!("docs/gallery/{name}.png"))) {
            Ok(committed) if committed == drawn => {}
            Ok(_) => problems.push(format!("{name}: docs/gallery/{name}.png is out of date")),
            Err(_) => problems.push(format!("{name}: docs/gallery/{name}.png is missing")),
        }
    }
    assert!(problems.is_empty(), "{}\n(run `bash docs/gallery.sh` after changing a recipe)", problems.join("\n"));
}
