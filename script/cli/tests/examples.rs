//! Every recipe in `examples/` runs through the binary at its default parameters and writes a
//! `.glb` under `target/test-output/examples/` (which CI hands to the Khronos validator). Each
//! recipe asserts its own structure (closed, manifold, genus…), so a run that succeeds has passed
//! those checks too; the file written must be a glTF binary with at least one triangle.

use std::path::{Path, PathBuf};
use std::process::Command;

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).ancestors().nth(2).unwrap().to_path_buf()
}

/// Runs `examples/{recipe}.rhai` with `--set` values `sets`, writing its value to `out`.
fn run_recipe(recipe: &str, sets: &[&str], out: &std::path::Path) -> std::process::Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_blocksmith"));
    cmd.arg("run").arg(workspace().join("examples").join(format!("{recipe}.rhai")));
    for set in sets {
        cmd.args(["--set", set]);
    }
    cmd.arg("-o").arg(out).output().unwrap()
}

#[test]
fn every_example_recipe_runs_and_writes_a_glb() {
    let examples = workspace().join("examples");
    let out_dir = workspace().join("target/test-output/examples");
    std::fs::create_dir_all(&out_dir).unwrap();
    let mut recipes: Vec<PathBuf> = std::fs::read_dir(&examples)
        .unwrap()
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "rhai"))
        // `_name.rhai` files are helpers the recipes import, not recipes.
        .filter(|p| !p.file_name().and_then(|n| n.to_str()).is_some_and(|n| n.starts_with('_')))
        .collect();
    recipes.sort();
    assert!(recipes.len() >= 7, "only {} recipes found", recipes.len());
    let mut failures = Vec::new();
    for recipe in &recipes {
        let stem = recipe.file_stem().unwrap().to_string_lossy().into_owned();
        let out = out_dir.join(format!("{stem}.glb"));
        let o =
            Command::new(env!("CARGO_BIN_EXE_blocksmith")).arg("run").arg(recipe).arg("-o").arg(&out).output().unwrap();
        let stderr = String::from_utf8_lossy(&o.stderr);
        if !o.status.success() || stderr.contains("panicked") {
            failures.push(format!("{stem}:\n{stderr}"));
            continue;
        }
        let bytes = std::fs::read(&out).unwrap();
        // GLB header: magic, version 2, then the JSON chunk.
        if bytes.len() < 20 || &bytes[..4] != b"glTF" || bytes[4..8] != 2u32.to_le_bytes() {
            failures.push(format!("{stem}: {} is not a glTF 2.0 binary", out.display()));
        }
    }
    assert!(failures.is_empty(), "{} recipes failed:\n{}", failures.len(), failures.join("\n"));
}

/// Recipes take their knobs from `--set`: the gear with 16 teeth and the ladder with 8 rungs
/// still pass their own structural checks (one feature per tooth, genus = rungs − 1), and the
/// written model grows with them.
#[test]
fn recipe_parameters_come_from_the_command_line() {
    let out_dir = workspace().join("target/test-output/examples");
    std::fs::create_dir_all(&out_dir).unwrap();
    for (recipe, set, file) in [("gear", "teeth=16", "gear_16_teeth.glb"), ("ladder", "rungs=8", "ladder_8_rungs.glb")]
    {
        let out = out_dir.join(file);
        let o = run_recipe(recipe, &[set], &out);
        assert!(o.status.success(), "{recipe} --set {set}:\n{}", String::from_utf8_lossy(&o.stderr));
        let default = out_dir.join(format!("{recipe}_default.glb"));
        assert!(run_recipe(recipe, &[], &default).status.success());
        let (big, small) = (std::fs::metadata(&out).unwrap().len(), std::fs::metadata(&default).unwrap().len());
        assert!(big > small, "{recipe} --set {set} wrote {big} bytes, the default {small}");
    }
}

/// The animation recipes' variants: linear growth (Fig. 9.2), growth under gravity (Fig. 9.5,
/// drag 0.5) and the smooth shrub growing (its skin carried through subdivision) pass their own
/// checks too, and write their animations (which CI hands to the Khronos validator).
#[test]
fn animation_recipe_variants_run() {
    let out_dir = workspace().join("target/test-output/examples");
    std::fs::create_dir_all(&out_dir).unwrap();
    for (recipe, set, file) in [
        ("plant_growth", "curve=linear", "plant_growth_linear.glb"),
        ("plant_gravity", "grow=true", "plant_grow_and_fall.glb"),
        ("lsystem_smooth", "animate=true", "lsystem_smooth_growing.glb"),
    ] {
        let out = out_dir.join(file);
        let o = run_recipe(recipe, &[set], &out);
        assert!(o.status.success(), "{recipe} --set {set}:\n{}", String::from_utf8_lossy(&o.stderr));
        assert_eq!(&std::fs::read(&out).unwrap()[..4], b"glTF");
    }
}

/// The flat-pack box laid out flat is a Profile, and `-o` writes it as a laser cutter's DXF or
/// SVG; both read back to the five panels: the same contours (two sides, two ends with a hand
/// hole each, a bottom) and the same area, which the recipe itself checks against the panels.
#[test]
fn the_flat_pack_layout_exports_as_dxf_and_svg_and_reads_back() {
    let out_dir = workspace().join("target/test-output/examples");
    std::fs::create_dir_all(&out_dir).unwrap();
    let mut areas = Vec::new();
    for ext in ["dxf", "svg"] {
        let out = out_dir.join(format!("flatpack_box_layout.{ext}"));
        let o = run_recipe("flatpack_box", &["layout=true"], &out);
        assert!(o.status.success(), "{ext}:\n{}", String::from_utf8_lossy(&o.stderr));
        let check = out_dir.join(format!("flatpack_read_{ext}.rhai"));
        std::fs::write(
            &check,
            format!("let p = load({:?});\n[p.contours().len(), p.area()]", out.display().to_string()),
        )
        .unwrap();
        let o = Command::new(env!("CARGO_BIN_EXE_blocksmith")).arg("run").arg(&check).output().unwrap();
        let text = String::from_utf8_lossy(&o.stderr).into_owned();
        assert!(o.status.success(), "{ext}: {text}");
        // `run` without -o describes the value: `[7, 1661.43…]`.
        assert!(text.contains("[7, "), "{ext}: five panels and two holes, got {text}");
        areas.push(text.trim().trim_start_matches("[7, ").trim_end_matches(']').parse::<f64>().unwrap());
    }
    // Default 30 × 20 × 12 box of 0.6 sheet: 2·30·12 + 2·(19.4·12 − slot) + 29.4·19.4.
    assert!((areas[0] - areas[1]).abs() < 1e-6, "{areas:?}");
    assert!(areas[0] > 1650.0 && areas[0] < 1750.0, "{areas:?}");
}
