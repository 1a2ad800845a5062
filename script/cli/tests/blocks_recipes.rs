//! The block recipes' parameters through the command line: the Fig. 17 staircase with
//! `--set steps=12` has 12 blocks (one per tread) and writes a closed solid whose volume is
//! exactly that of its 12 treads; `--set turn=8` winds it and it stays one closed piece.

use std::path::{Path, PathBuf};
use std::process::Command;

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).ancestors().nth(2).unwrap().to_path_buf()
}

/// Runs the staircase with `sets`, writing `file`; returns its printed line and the mesh read back.
fn staircase(sets: &[&str], file: &str) -> (String, blocksmith_kernel::Mesh) {
    let out_dir = workspace().join("target/test-output/examples");
    std::fs::create_dir_all(&out_dir).unwrap();
    let out = out_dir.join(file);
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_blocksmith"));
    cmd.arg("run").arg(workspace().join("examples/blocks_fig17_staircase.rhai"));
    for s in sets {
        cmd.args(["--set", s]);
    }
    let o = cmd.arg("-o").arg(&out).output().unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(o.status.success(), "{sets:?}:\n{stdout}\n{}", String::from_utf8_lossy(&o.stderr));
    (stdout, blocksmith_kernel::io::load(&out).unwrap())
}

#[test]
fn the_staircase_takes_its_steps_from_the_command_line() {
    let (line, mesh) = staircase(&["steps=12"], "blocks_fig17_staircase_12_steps.glb");
    assert!(line.contains("blocks_fig17_staircase: 12 blocks,"), "{line}");
    assert!(mesh.is_closed() && mesh.is_manifold() && mesh.genus() == 0 && mesh.euler() == 2);
    // Twelve treads 1.2 wide, two goings of 0.28 deep, 0.18 high; glTF stores f32 positions.
    let v = 12.0 * 1.2 * 0.56 * 0.18;
    assert!((mesh.volume() - v).abs() < 1e-5 * v, "volume {} for {v}", mesh.volume());
    let (line, mesh) = staircase(&["steps=12", "turn=8"], "blocks_fig17_staircase_12_winding.glb");
    assert!(line.contains("12 blocks"), "{line}");
    assert!(mesh.is_closed() && mesh.is_manifold() && mesh.euler() == 2);
    let o = Command::new(env!("CARGO_BIN_EXE_blocksmith"))
        .arg("run")
        .arg(workspace().join("examples/blocks_fig17_staircase.rhai"))
        .args(["--set", "steps=0", "-o"])
        .arg(workspace().join("target/test-output/examples/never_written.glb"))
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("steps must be a whole number of at least 1, got 0"));
}

/// The same recipe gives the same bytes: the tree (kd-trees built in parallel) and the terrain
/// (a displacement closure, built serially), each run twice.
#[test]
fn block_recipes_are_reproducible() {
    let out_dir = workspace().join("target/test-output/repeat");
    std::fs::create_dir_all(&out_dir).unwrap();
    for recipe in ["blocks_fig15_tree", "blocks_fig14_terrain"] {
        let run = |k: usize| {
            let out = out_dir.join(format!("{recipe}_{k}.glb"));
            let o = Command::new(env!("CARGO_BIN_EXE_blocksmith"))
                .arg("run")
                .arg(workspace().join("examples").join(format!("{recipe}.rhai")))
                .arg("-o")
                .arg(&out)
                .output()
                .unwrap();
            assert!(o.status.success(), "{recipe}:\n{}", String::from_utf8_lossy(&o.stderr));
            std::fs::read(&out).unwrap()
        };
        assert!(run(0) == run(1), "{recipe}: two runs wrote different bytes");
    }
}
