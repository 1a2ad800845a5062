//! The voxel recipes (Heurtebise & Thon Figs. 7 and 8) run end to end through the binary; each
//! recipe checks its own result (closed, manifold, genus, Euler
//! characteristic, volumes) and fails the run if a check fails.
//! Both run at their default sizes (Fig. 7 at the paper's 256³; about a quarter of a second in a
//! debug build) and at a smaller `--set size=…`, since every length in them scales with the grid.

use std::path::{Path, PathBuf};
use std::process::Command;

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).ancestors().nth(2).unwrap().to_path_buf()
}

/// Runs `examples/{name}` with `sets` and checks that it succeeded.
fn run_recipe(name: &str, sets: &[&str]) {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_blocksmith"));
    cmd.arg("run").arg(workspace().join("examples").join(name));
    for s in sets {
        cmd.arg("--set").arg(s);
    }
    let o = cmd.output().unwrap();
    assert!(o.status.success(), "{name} {sets:?} failed:\n{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn fig7_chain_and_ball_recipe_holds_at_256_and_128() {
    run_recipe("fig7_chain_ball.rhai", &[]);
    run_recipe("fig7_chain_ball.rhai", &["size=128"]);
}

#[test]
fn fig8_custom_tool_recipe_holds_at_128_and_64() {
    run_recipe("fig8_custom_tool.rhai", &[]);
    run_recipe("fig8_custom_tool.rhai", &["size=64"]);
}
