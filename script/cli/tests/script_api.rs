//! The script API as a newcomer meets it through the `blocksmith` binary: dropped results are
//! reported before the script runs, errors show what exists, values describe themselves.

use std::path::PathBuf;
use std::process::{Command, Output};

fn blocksmith() -> Command {
    Command::new(env!("CARGO_BIN_EXE_blocksmith"))
}

fn script(dir: &tempfile::TempDir, name: &str, text: &str) -> PathBuf {
    let p = dir.path().join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The REPL's output for `entries` piped to it, without a history file.
fn repl_piped(entries: &str) -> Output {
    use std::io::Write;
    let mut child = blocksmith()
        .arg("repl")
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .env("BLOCKSMITH_HISTORY", "/dev/null")
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(entries.as_bytes()).unwrap();
    child.wait_with_output().unwrap()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

#[test]
fn run_warns_of_a_dropped_transform_and_test_refuses_it() {
    let d = tempfile::tempdir().unwrap();
    let dropped = script(&d, "dropped.rhai", "let c = cube(2);\nc.translate([5, 0, 0]);\nc\n");
    let o = blocksmith().arg("run").arg(&dropped).output().unwrap();
    let err = stderr(&o);
    // A warning: the run still succeeds.
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("dropped.rhai:2:3: warning: the result of `translate` is dropped and `c` is unchanged")
            && err.contains("write `c = c.translate(…);`")
            && err.contains("2 | c.translate([5, 0, 0]);"),
        "{err}"
    );
    let kept = script(&d, "kept.rhai", "let c = cube(2);\nc = c.translate([5, 0, 0]);\nc\n");
    let o = blocksmith().arg("run").arg(&kept).output().unwrap();
    assert!(o.status.success() && !stderr(&o).contains("warning"), "{}", stderr(&o));
    // In a test, the same line is an error.
    let o = blocksmith().arg("test").arg(&dropped).arg(&kept).output().unwrap();
    let out = stdout(&o);
    assert!(!o.status.success(), "{out}");
    assert!(out.contains("FAIL") && out.contains("dropped.rhai:2:3: error: the result of `translate`"), "{out}");
    assert!(out.contains("1 passed, 1 failed"), "{out}");
}

#[test]
fn a_block_chain_on_a_variable_edits_it_and_an_edit_of_a_model_s_copy_is_reported() {
    let d = tempfile::tempdir().unwrap();
    let p = script(
        &d,
        "chain.rhai",
        "let b = block([0, 0, 0], [1, 1, 1]);\nb.subdivide(\"+z\", 2, 2).sharp_all();\n\
         assert(b.is_sharp(\"+x+y\") && b.subface_count(\"+z\") == 4, \"b has both\");\n\
         let m = blocks();\nm.add(b);\nm\n",
    );
    let o = blocksmith().arg("test").arg(&p).output().unwrap();
    assert!(o.status.success() && !stderr(&o).contains("warning"), "{}{}", stdout(&o), stderr(&o));
    // `m.block(0)` is a copy: editing it changes nothing the model holds.
    let p =
        script(&d, "copy.rhai", "let m = blocks();\nm.add(block([0, 0, 0], [1, 1, 1]));\nm.block(0).sharp_all();\nm\n");
    let o = blocksmith().arg("run").arg(&p).output().unwrap();
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("copy.rhai:3:12: warning: `sharp_all` changes the new value that `block` returned")
            && err.contains("keep it first: `let y = m.block(…); y.sharp_all();`"),
        "{err}"
    );
}

#[test]
fn the_repl_warns_of_a_dropped_result() {
    let o = repl_piped("let c = cube(2);\nc.scale(2);\nc = c.scale(2);\n");
    let out = stdout(&o);
    assert_eq!(out.matches("warning: the result of `scale` is dropped").count(), 1, "{out}");
}

#[test]
fn a_call_that_fits_no_signature_shows_the_signatures_and_the_misfit() {
    let d = tempfile::tempdir().unwrap();
    let p = script(&d, "cyl.rhai", "let c = cylinder(1, 2, 16.5);\nc\n");
    let o = blocksmith().arg("run").arg(&p).output().unwrap();
    let err = stderr(&o);
    assert!(!o.status.success());
    assert!(
        err.contains("cyl.rhai:1:9: error: cylinder(int, int, float) matches no signature of `cylinder`: argument 3 `segments` must be an integer, got a float"),
        "{err}"
    );
    // The caret under the call, then the signatures.
    let caret = err.find('^').unwrap();
    let sigs = err
        .find("signatures of `cylinder`:\n  cylinder(radius: number, height: number, segments: int) -> Mesh")
        .unwrap();
    assert!(caret < sigs, "{err}");
}

#[test]
fn unknown_names_are_suggested_in_run_test_and_the_repl() {
    let d = tempfile::tempdir().unwrap();
    let p = script(&d, "typo.rhai", "let t = tours(2, 0.5, 24, 12);\nt\n");
    let o = blocksmith().arg("run").arg(&p).output().unwrap();
    assert!(
        stderr(&o).contains("typo.rhai:1:9: error: unknown function `tours` (did you mean `torus`?)"),
        "{}",
        stderr(&o)
    );
    let o = blocksmith().arg("test").arg(&p).output().unwrap();
    assert!(stdout(&o).contains("unknown function `tours` (did you mean `torus`?)"), "{}", stdout(&o));
    let out = stdout(&repl_piped("let m = cube(1);\nm.volum\nm.subdivide(\"+z\", 2, 2)\n"));
    assert!(out.contains("Mesh has no property `volum` (did you mean the method `.volume()`?)"), "{out}");
    assert!(out.contains("`subdivide` is a method of Block, not of Mesh; for a Mesh see `loop_subdivide`"), "{out}");
}

#[test]
fn ending_with_a_value_that_cannot_be_saved_says_how_to_get_one() {
    let d = tempfile::tempdir().unwrap();
    let p = script(&d, "vx.rhai", "let vx = voxels(8);\nvx.fill_sphere([4, 4, 4], 3);\nvx\n");
    let o = blocksmith().arg("run").arg(&p).arg("-o").arg(d.path().join("vx.glb")).output().unwrap();
    let err = stderr(&o);
    assert!(err.contains("cannot write a Voxels to") && err.contains("end the script with its `.to_mesh()`"), "{err}");
    let p = script(&d, "bm.rhai", "let m = blocks();\nm.add(block([0, 0, 0], [1, 1, 1]));\nm\n");
    let o = blocksmith().arg("run").arg(&p).arg("-o").arg(d.path().join("bm.glb")).output().unwrap();
    let err = stderr(&o);
    assert!(err.contains("cannot write a BlockModel") && err.contains("its `.mesh()`"), "{err}");
}

#[test]
fn a_syntax_error_in_an_imported_module_points_into_the_module() {
    let d = tempfile::tempdir().unwrap();
    script(&d, "legs.rhai", "fn leg(h) {\n    let x = h +;\n    x\n}\n");
    let p = script(&d, "table.rhai", "let top = cube(1);\nimport \"legs\" as legs;\ntop\n");
    let o = blocksmith().arg("run").arg(&p).output().unwrap();
    let err = stderr(&o);
    assert!(!o.status.success());
    assert!(err.contains("legs.rhai:2:16: error: Unexpected ';'"), "{err}");
    assert!(err.contains("2 |     let x = h +;"), "{err}");
    assert!(err.contains("table.rhai:2:8: note: imported here"), "{err}");
    // A module whose `{` is never closed says so, at the brace.
    script(&d, "open.rhai", "fn g(x) {\n    x * 2\n");
    let p = script(&d, "uses_open.rhai", "import \"open\" as o;\no::g(1)\n");
    let o = blocksmith().arg("run").arg(&p).output().unwrap();
    let err = stderr(&o);
    assert!(err.contains("open.rhai:1:9: error: missing `}`: the `{` here is never closed"), "{err}");
}

#[test]
fn run_makes_the_output_folder_and_test_explains_its_default_directory() {
    let d = tempfile::tempdir().unwrap();
    let p = script(&d, "c.rhai", "cube(1)\n");
    let out = d.path().join("out").join("c.glb");
    let o = blocksmith().arg("run").arg(&p).arg("-o").arg(&out).output().unwrap();
    assert!(o.status.success() && out.exists(), "{}", stderr(&o));
    // Outside a checkout, `blocksmith test` says its default is ./tests, relative to here.
    let o = blocksmith().arg("test").current_dir(d.path()).output().unwrap();
    assert!(!o.status.success());
    assert!(stderr(&o).contains("runs the .rhai files under ./tests (relative to where it is run)"), "{}", stderr(&o));
}

#[test]
fn imported_modules_and_function_style_calls_are_linted_too() {
    let d = tempfile::tempdir().unwrap();
    script(
        &d,
        "parts.rhai",
        "fn leg(h) {\n    let l = box([0, 0, 0], [0.2, 0.2, h]);\n    l.translate([1, 0, 0]);\n    l\n}\n",
    );
    let main = script(
        &d,
        "main.rhai",
        "import \"parts\" as parts;\ncube(2);\nlet m = cube(1);\ncrease(m, [[0, 1]]);\nparts::leg(1)\n",
    );
    let o = blocksmith().arg("run").arg(&main).arg("-o").arg(d.path().join("out.obj")).output().unwrap();
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    // The module's dropped transform is reported at its own line; the constructor's dropped
    // value in the script too; the in-place crease of a variable is not.
    assert!(
        err.contains("parts.rhai:3:7: warning: the result of `translate` is dropped and `l` is unchanged"),
        "{err}"
    );
    assert!(err.contains("main.rhai:2:1: warning: the result of `cube` is dropped"), "{err}");
    assert_eq!(err.matches("warning").count(), 2, "{err}");
    // In a test, both are errors.
    let o = blocksmith().arg("test").arg(&main).output().unwrap();
    let out = stdout(&o);
    assert!(
        out.contains("parts.rhai:3:7: error: the result of `translate`") && out.contains("0 passed, 1 failed"),
        "{out}"
    );
}

#[test]
fn blocks_touching_without_connecting_are_reported_by_mesh() {
    let d = tempfile::tempdir().unwrap();
    let table = |top_divisions: i32| {
        format!(
            "let m = blocks();\nm.allow(0, 0);\nm.add(block([0, 0, 1], [2, 2, 1.2]).subdivide(\"-z\", {top_divisions}, {top_divisions}));\n\
             for p in [[0, 0], [1.8, 0], [0, 1.8], [1.8, 1.8]] {{\n    m.add(block([p[0], p[1], 0], [p[0] + 0.2, p[1] + 0.2, 1]));\n}}\n\
             let s = m.mesh(#{{ tolerance: 0.01 }});\nprint(m.unconnected());\ns\n"
        )
    };
    let loose = script(&d, "loose.rhai", &table(1));
    let o = blocksmith().arg("run").arg(&loose).arg("-o").arg(d.path().join("loose.obj")).output().unwrap();
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(stdout(&o).contains("[1, 2, 3, 4]"), "{}", stdout(&o));
    assert_eq!(err.matches("warning: mesh: block").count(), 4, "{err}");
    assert!(
        err.contains("loose.rhai:7:11: warning: mesh: block 1 touches block 0 but does not connect to it")
            && err.contains(
                "nearest miss: block 1's +z sub-face 0 and block 0's -z sub-face 0, 0 apart along the normal"
            )
            && err.contains("subdivide block 0's -z face 6 × 6 — `b.subdivide(\"-z\", 6, 6)` before adding it")
            && err.contains("`m.connect(1, \"+z\", 0, 0, \"-z\", 0)`"),
        "{err}"
    );
    // Shown as the lint's warnings are: the source line and a caret under the call.
    assert!(err.contains("7 | let s = m.mesh(#{ tolerance: 0.01 });\n") && err.contains("|           ^"), "{err}");
    // The advice, applied, leaves nothing to report (as does any grid with centres over the legs).
    let advised = script(&d, "advised.rhai", &table(6));
    let o = blocksmith().arg("run").arg(&advised).arg("-o").arg(d.path().join("advised.obj")).output().unwrap();
    assert!(o.status.success() && !stderr(&o).contains("warning"), "{}", stderr(&o));
    let fixed = script(&d, "fixed.rhai", &table(10));
    let o = blocksmith().arg("run").arg(&fixed).arg("-o").arg(d.path().join("fixed.obj")).output().unwrap();
    assert!(o.status.success() && !stderr(&o).contains("warning"), "{}", stderr(&o));
    assert!(stdout(&o).contains("[]"), "{}", stdout(&o));
    // In a test they are errors, unless the test takes them and checks them.
    let o = blocksmith().arg("test").arg(&loose).arg(&fixed).output().unwrap();
    let out = stdout(&o);
    assert!(!o.status.success(), "{out}");
    assert!(
        out.contains("loose.rhai:7:11: error: mesh: block 1 touches block 0")
            && out.contains("takes them with `take_warnings()`")
            && out.contains("1 passed, 1 failed"),
        "{out}"
    );
    let taken = script(
        &d,
        "taken.rhai",
        &table(1).replace(
            "\ns\n",
            "\nlet w = take_warnings();\nassert_eq(w.len(), 4);\nassert(w[0].starts_with(\"7:11: mesh: block 1 touches\"), w[0]);\ns\n",
        ),
    );
    let o = blocksmith().arg("test").arg(&taken).output().unwrap();
    assert!(o.status.success(), "{}", stdout(&o));
    // The REPL shows them after the entry, as it shows the lint's.
    let entries = "let m = blocks();\nm.allow(0, 0);\nm.add(block([0, 0, 1], [2, 2, 1.2]));\n\
                   m.add(block([0, 0, 0], [0.2, 0.2, 1]));\nlet s = m.mesh();\nlet t = m.mesh();\n";
    let o = repl_piped(entries);
    let out = stdout(&o);
    assert_eq!(out.matches(":11: warning: mesh: block 1 touches block 0").count(), 2, "{out}");
    assert!(out.contains("<stdin>:5:11: warning: mesh: block 1") && out.contains("| let t = m.mesh();"), "{out}");
    assert!(!stderr(&o).contains("warning"), "{}", stderr(&o));
}

#[test]
fn the_reference_opens_with_the_editing_rule_and_signatures_show_numbers() {
    let o = blocksmith().arg("doc").output().unwrap();
    let out = stdout(&o);
    assert!(out.starts_with("How values change"), "{}", &out[..out.len().min(300)]);
    assert!(out.contains("  Mesh: A Mesh is a value"), "no Mesh rule");
    assert!(out.contains("cylinder(radius: number, height: number, segments: int) -> Mesh"));
    let o = blocksmith().arg("doc").arg("PolarMesh").output().unwrap();
    let out = stdout(&o);
    assert!(
        out.contains("A PolarMesh is edited in place")
            && out.contains("scale_vertices(pm: PolarMesh, verts: array, factor: number|Vec3)"),
        "{out}"
    );
}
