//! The binary under hostile input: saves that fail leave the old file, test output stays in
//! its directory, long work stops on request, and no request aborts the process.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn blocksmith() -> Command {
    Command::new(env!("CARGO_BIN_EXE_blocksmith"))
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A failure: non-zero exit, no panic or abort, and the message expected.
fn assert_fails_with(o: &Output, needle: &str) {
    let err = stderr(o);
    assert!(!o.status.success(), "expected failure, got success; stderr:\n{err}");
    assert!(o.status.code().is_some(), "killed by a signal: {:?}\n{err}", o.status);
    assert!(!err.contains("panicked"), "a panic reached the user:\n{err}");
    assert!(err.contains(needle), "expected {needle:?} in:\n{err}");
}

fn entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> =
        std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    names
}

#[cfg(unix)]
#[test]
fn a_save_cut_short_by_the_file_size_limit_leaves_the_old_file_and_no_partial_file() {
    // `ulimit -f 64` allows 32 KiB per file (512-byte blocks); the icosphere's GLB is about
    // 0.5 MB. SIGXFSZ is ignored so that the write fails with EFBIG instead of killing us.
    let d = tempfile::tempdir().unwrap();
    let recipe = write(d.path(), "big.rhai", "icosphere(1, 5)\n");
    let old = write(d.path(), "old.glb", "the old file");
    let o = Command::new("sh")
        .arg("-c")
        .arg("trap '' XFSZ; ulimit -f 64; exec \"$0\" run \"$1\" -o \"$2\"")
        .arg(env!("CARGO_BIN_EXE_blocksmith"))
        .arg(&recipe)
        .arg(&old)
        .output()
        .unwrap();
    assert_fails_with(&o, "old.glb: cannot write the file");
    assert_eq!(std::fs::read_to_string(&old).unwrap(), "the old file");
    assert_eq!(entries(d.path()), ["big.rhai", "old.glb"]);
}

#[test]
fn test_output_cannot_escape_the_out_directory() {
    let d = tempfile::tempdir().unwrap();
    let tests = d.path().join("a/b");
    std::fs::create_dir_all(&tests).unwrap();
    write(&tests, "escape.rhai", "cube(1).save(\"../../x.obj\");\n");
    write(&tests, "inside.rhai", "cube(1).save(\"sub/../y.obj\");\n");
    let out = tests.join("out");
    let o = blocksmith().arg("test").arg(&tests).arg("--out").arg(&out).output().unwrap();
    let report = String::from_utf8_lossy(&o.stdout);
    assert!(report.contains("leaves the output directory"), "{report}");
    assert!(report.lines().last() == Some("1 passed, 1 failed"), "{report}");
    assert!(out.join("y.obj").exists());
    assert!(!d.path().join("a/x.obj").exists() && !tests.join("x.obj").exists());
}

/// Runs `recipe` (written to a fresh directory beside a copy of the examples' `_plant.rhai`)
/// with `args`, returning the output and the seconds it took.
fn run_recipe(recipe: &str, args: &[&str]) -> (Output, f64) {
    let d = tempfile::tempdir().unwrap();
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples");
    std::fs::copy(examples.join("_plant.rhai"), d.path().join("_plant.rhai")).unwrap();
    let p = write(d.path(), "r.rhai", recipe);
    let start = std::time::Instant::now();
    let o = blocksmith().arg("run").arg(&p).args(args).output().unwrap();
    (o, start.elapsed().as_secs_f64())
}

#[test]
fn requests_over_the_memory_budget_are_refused_naming_the_estimate_and_the_budget() {
    // Each count is allowed alone; the product (1e10 quads, terabytes) is refused by the
    // default budget before anything is allocated.
    for (recipe, what) in [
        ("uv_sphere(1, 100000, 100000)", "uv_sphere: a 100000 × 100000 UV sphere needs an estimated"),
        ("torus(2, 1, 100000, 100000)", "torus: a 100000 × 100000 torus needs an estimated"),
        ("polar_sphere(1, 100000, 100000)", "polar_sphere: a 100000 × 100000 UV sphere needs an estimated"),
    ] {
        let (o, _) = run_recipe(recipe, &[]);
        assert_fails_with(&o, what);
        assert_fails_with(&o, "TiB, over the memory budget of");
    }
    // A budget set on the command line: subdivision, voxel meshing, a boolean and an
    // L-system whose cap was raised are each refused before they would pass it.
    for (recipe, what) in [
        (
            "cube(2).catmull_clark(9)",
            "catmull_clark: the result of 9 subdivision levels (1572864 faces) needs an estimated",
        ),
        ("icosphere(1, 5).loop_subdivide(4)", "loop_subdivide: the result of 4 subdivision levels"),
        (
            "let v = voxels(256); for z in 0..128 { v.fill_box([0, 0, 2 * z], [256, 256, 2 * z + 1]); } v.to_mesh()",
            "to_mesh: the marching-cubes surface (",
        ),
        (
            "icosphere(1, 8) - icosphere(1, 8).translate([0.5, 0, 0])",
            "a boolean of 2621440 triangles needs an estimated",
        ),
        (
            "lsystem(#{ axiom: \"A\", rules: #{ A: \"AA\" }, max_modules: 9223372036854775807 }).derive(40)",
            "the derived string (",
        ),
    ] {
        let (o, _) = run_recipe(recipe, &["--memory-limit", "256M"]);
        assert_fails_with(&o, what);
        assert_fails_with(&o, "over the memory budget of 256 MiB (raise it with --memory-limit)");
    }
    let (o, _) = run_recipe("cube(1)", &["--memory-limit", "lots"]);
    assert_fails_with(&o, "expected a size such as 512M, 8G or 1T");
}

/// Block meshing with a tiny tolerance and the deepest kd-trees runs for minutes; every limit
/// stops it while it runs.
const ENDLESS_MESHING: &str =
    "let b = blocks(); b.add(block([-1, -1, -1], [1, 1, 1])); b.mesh(#{ tolerance: 1e-12, max_depth: 14 })";

#[test]
fn the_timeout_and_the_operation_limit_stop_long_kernel_work() {
    let (o, seconds) = run_recipe(ENDLESS_MESHING, &["--timeout", "1"]);
    assert_fails_with(&o, "mesh: time limit reached (--timeout 1)");
    // Stopped within a fraction of a second of the limit: the start-up and the generous
    // margin of a loaded debug build aside, far from the minutes the work would take.
    assert!(seconds < 20.0, "stopped after {seconds} s");
    let (o, _) = run_recipe(ENDLESS_MESHING, &["--max-operations", "100000"]);
    assert_fails_with(&o, "mesh: operation limit reached (--max-operations 100000)");
    let (o, _) = run_recipe("cube(1)", &["--timeout=-3"]);
    assert_fails_with(&o, "expected a number of seconds");
}

#[test]
fn absurd_step_counts_and_durations_are_refused_at_the_call_naming_the_option() {
    let plant = "import \"_plant\" as plant;\nlet pm = plant::plant(2.0, 0.08, 8, 9);\n\
                 let anim = animation(pm, #{ root: 0 });\n";
    let (o, _) = run_recipe(&format!("{plant}anim.add(gravity(#{{ dt: 1e-300 }}));\nanim.frames(2, 1.0 / 24)\n"), &[]);
    assert_fails_with(&o, "frames: `dt` 1e-300 makes 4.1666666666666664e298 simulation steps per frame");
    assert_fails_with(&o, "over the cap of 100000: use a larger `dt`");
    let (o, _) = run_recipe(&format!("{plant}anim.add(growth(#{{ speed: 1e-300 }}));\nanim\n"), &[]);
    assert_fails_with(
        &o,
        "growth: `speed` must be a number from 0.001 to 1000000000 (growing takes 1 / speed), got 1e-300",
    );
}

#[test]
fn primitives_out_of_range_are_catchable_errors_not_panics() {
    let recipe = "let caught = [];\n\
                  for r in [1e155, 1e-300] { try { icosphere(r, 2); } catch (e) { caught.push(e); } }\n\
                  assert_eq(caught.len(), 2);\n\
                  assert(caught[0].contains(\"icosphere: argument `radius` must be between 1e-100 and 1e100, got 1e155\"), caught[0]);\n\
                  try { cube(1e200) } catch (e) { assert(e.contains(\"got 1e200\"), e); }\n\
                  cube(1)\n";
    let (o, _) = run_recipe(recipe, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
}
