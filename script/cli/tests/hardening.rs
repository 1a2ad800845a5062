//! The binary under hostile input: saves that fail leave the old file, test output stays in
//! its directory, long work stops on request, and no request aborts the process.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

#[path = "support/repl.rs"]
mod repl;
use repl::repl;

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
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
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
            "lsystem(#{ axiom: \"A\", rules: #{ A: \"AA\" }, max_modules: 9223372036854775807 }).derive(40)",
            "the derived string (",
        ),
    ] {
        let (o, _) = run_recipe(recipe, &["--memory-limit", "256M"]);
        assert_fails_with(&o, what);
        assert_fails_with(&o, "over the memory budget of 256 MiB (raise it with --memory-limit)");
    }
    // The boolean's inputs (about 400 MiB) fit a budget of 1 GiB; its work would not.
    let (o, _) = run_recipe("icosphere(1, 8) - icosphere(1, 8).translate([0.5, 0, 0])", &["--memory-limit", "1G"]);
    assert_fails_with(
        &o,
        "a boolean of 2621440 triangles needs an estimated 2.50 GiB, over the memory budget of 1.00 GiB",
    );
    let (o, _) = run_recipe("cube(1)", &["--memory-limit", "lots"]);
    assert_fails_with(&o, "expected a size such as 512M, 8G or 1T");
}

/// Block meshing with a tiny tolerance and the deepest kd-trees runs for minutes; every limit
/// stops it while it runs.
const ENDLESS_MESHING: &str =
    "let b = blocks(); b.add(block([-1, -1, -1], [1, 1, 1])); b.mesh(#{ tolerance: 1e-12, max_depth: 14 })";

#[test]
fn the_timeout_and_the_operation_limit_stop_long_kernel_work() {
    // The seconds are named as given (1.793, not the 1.7930000000000001 its f64 reads as).
    let (o, seconds) = run_recipe(ENDLESS_MESHING, &["--timeout", "1.793"]);
    assert_fails_with(&o, "mesh: time limit reached (--timeout 1.793)");
    // Stopped within a fraction of a second of the limit: the start-up and the generous
    // margin of a loaded debug build aside, far from the minutes the work would take.
    assert!(seconds < 20.0, "stopped after {seconds} s");
    let (o, _) = run_recipe(ENDLESS_MESHING, &["--max-operations", "100000"]);
    assert_fails_with(&o, "mesh: operation limit reached (--max-operations 100000)");
    let (o, _) = run_recipe("cube(1)", &["--timeout=-3"]);
    assert_fails_with(&o, "expected a number of seconds");
}

#[test]
fn the_timeout_stops_a_boolean_inside_the_engine() {
    // Each difference of two 327,680-triangle spheres runs for seconds in a debug build, nearly
    // all of it inside the engine (imports, intersections, assembly): the deadline lands there.
    let recipe = "let a = icosphere(1, 7); let b = a.translate([0.3, 0.2, 0.1]); loop { a - b; }";
    let (o, seconds) = run_recipe(recipe, &["--timeout", "2.5"]);
    assert_fails_with(&o, "-: time limit reached (--timeout 2.5)");
    // Within a fraction of a second of the deadline (a generous margin for a loaded debug
    // build; the release figure is in the hardening notes), not after the boolean.
    assert!(seconds < 2.5 + 2.0, "stopped after {seconds} s");
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

#[test]
fn script_data_is_held_to_the_memory_budget_without_walking_it_on_every_call() {
    // Doubling a nested array or growing a map: each stops at the budget (checked on every
    // step against the heap in use) with the error naming it.
    for recipe in
        ["let a = [0]; loop { a = [a, a]; }", "let m = #{}; let i = 0; loop { m[`k${i}`] = [i, i, i, i]; i += 1; }"]
    {
        let (o, _) = run_recipe(recipe, &["--memory-limit", "32M"]);
        assert_fails_with(&o, "is over the memory budget of 32.0 MiB (raise it with --memory-limit)");
    }
    // Joining doubles data in one step: the result is estimated before it is allocated and
    // refused, catchably, naming the estimate and the budget (checked after the step, it would
    // have passed the budget up to three times over).
    let recipe = "let caught = [];\n\
                  let a = [0]; try { loop { a += a; } } catch (e) { caught.push(e); } a = ();\n\
                  let a = [0]; try { loop { a = a + a; } } catch (e) { caught.push(e); } a = ();\n\
                  let a = [0]; try { loop { a.append(a); } } catch (e) { caught.push(e); } a = ();\n\
                  let s = \"ab\"; try { loop { s += s; } } catch (e) { caught.push(e); } s = ();\n\
                  let s = \"ab\"; try { loop { s = s + s; } } catch (e) { caught.push(e); } s = ();\n\
                  let b = blob(1); try { loop { b += b; } } catch (e) { caught.push(e); } b = ();\n\
                  let a = []; try { loop { a.pad(a.len() + 100000, 0); } } catch (e) { caught.push(e); } a = ();\n\
                  assert_eq(caught.len(), 7);\n\
                  let starts = [\"+=: an array of \", \"+: an array of \", \"append: an array of \",\n\
                                \"+=: a string of \", \"+: a string of \", \"+=: a BLOB of \", \"pad: padding an array to \"];\n\
                  for i in 0..7 {\n\
                      assert(starts.some(|s| caught[i].starts_with(s)), caught[i]);\n\
                      assert(caught[i].contains(\"needs an estimated\"), caught[i]);\n\
                      assert(caught[i].contains(\"over the memory budget of 32.0 MiB (raise it with --memory-limit)\"), caught[i]);\n\
                  }\n\
                  cube(1)\n";
    let (o, _) = run_recipe(recipe, &["--memory-limit", "32M"]);
    assert!(o.status.success(), "{}", stderr(&o));
    // Functions growing by a size they are given are refused before allocating, catchably.
    let recipe = "let caught = [];\n\
                  try { blob(1000000000000); } catch (e) { caught.push(e); }\n\
                  try { [].pad(1000000000000, [1, 2]); } catch (e) { caught.push(e); }\n\
                  try { let s = \"ab\"; s.pad(1000000000000, \"xy\"); } catch (e) { caught.push(e); }\n\
                  try { let s = \"a\"; s.pad(100000, 'a'); s.replace(\"a\", s); } catch (e) { caught.push(e); }\n\
                  assert_eq(caught.len(), 4);\n\
                  assert(caught[0].starts_with(\"blob: a BLOB of 1000000000000 bytes needs an estimated 931 GiB\"), caught[0]);\n\
                  assert(caught[1].starts_with(\"pad: padding an array to 1000000000000 elements\"), caught[1]);\n\
                  assert(caught[2].starts_with(\"pad: padding a string to 1000000000000 characters\"), caught[2]);\n\
                  assert(caught[3].starts_with(\"replace: the replaced string (100000 replacements)\"), caught[3]);\n\
                  // An empty padding pads nothing (it used to loop for ever).\n\
                  let s = \"ab\"; s.pad(10, \"\"); assert_eq(s, \"ab\");\n\
                  // Pushing is linear (it was quadratic: the time limit would stop it).\n\
                  let a = []; for i in 0..300000 { a.push(i); } assert_eq(a.len(), 300000);\n\
                  cube(1)\n";
    let (o, _) = run_recipe(recipe, &["--memory-limit", "32M", "--timeout", "120"]);
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn deep_nesting_is_a_catchable_error_not_a_stack_overflow() {
    // Arrays and maps nested 5,000 deep: comparing and printing them is refused, catchably;
    // making, copying and dropping them works.
    let recipe = "let a = []; let b = []; let m = #{};\n\
                  for i in 0..5000 { a = [a]; b = [b]; m = #{ m: m }; }\n\
                  let caught = [];\n\
                  try { a == b; } catch (e) { caught.push(e); }\n\
                  try { a != b; } catch (e) { caught.push(e); }\n\
                  try { a.to_string(); } catch (e) { caught.push(e); }\n\
                  try { m.to_debug(); } catch (e) { caught.push(e); }\n\
                  try { m == m; } catch (e) { caught.push(e); }\n\
                  try { print(a); } catch (e) { caught.push(e); }\n\
                  try { debug(a); } catch (e) { caught.push(e); }\n\
                  try { print(m); } catch (e) { caught.push(e); }\n\
                  try { debug(m); } catch (e) { caught.push(e); }\n\
                  try { m.to_json(); } catch (e) { caught.push(e); }\n\
                  assert_eq(caught.len(), 10);\n\
                  for e in caught { assert(e.contains(\"nests arrays and maps more than 500 deep\"), e); }\n\
                  assert(caught[5].starts_with(\"print: \") && caught[6].starts_with(\"debug: \"), caught[5]);\n\
                  assert(caught[9].starts_with(\"to_json: \"), caught[9]);\n\
                  let c = a; let n = 0; while c.len() > 0 { c = c[0]; n += 1; } assert_eq(n, 5000);\n\
                  // Interpolation cannot be refused (Rhai falls back to its own text of the value,\n\
                  // on the command's large stack).\n\
                  let s = `${a}`; assert(s.len() >= 10000, `${s.len()}`);\n\
                  let s = `${m}`; assert(s.len() >= 10000, `${s.len()}`);\n\
                  // Shallower data prints as before.\n\
                  print([1, [2]]); debug(#{ x: [3] }); assert_eq(#{ x: [3] }.to_json(), \"{\\\"x\\\":[3]}\");\n\
                  // Shallower data compares and prints as before.\n\
                  assert([1, [2, #{ x: [3] }]] == [1, [2, #{ x: [3] }]]);\n\
                  assert_eq(`${[1, \"a\", #{ b: [2.5] }]}`, \"[1, \\\"a\\\", #{\\\"b\\\": [2.5]}]\");\n\
                  cube(1)\n";
    let (o, _) = run_recipe(recipe, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    // An L-system parameter nested 10,000 deep is refused naming the limit.
    let deep = format!("F({}x{})", "(".repeat(10_000), ")".repeat(10_000));
    let recipe = format!("lsystem(#{{ axiom: \"A(1)\", rules: #{{ \"A(x)\": \"{deep}\" }} }})");
    let (o, _) = run_recipe(&recipe, &[]);
    assert_fails_with(&o, "the expression is too large: more than 256 operands");
}

#[test]
fn messages_name_the_real_cause_once() {
    let ls = "let ls = lsystem(#{ axiom: \"F\", rules: #{ F: \"F[+F]F\" } });\n";
    // A failing size closure is named as such, with what it threw.
    let (o, _) = run_recipe(&format!("{ls}ls.grow(2, #{{ radius: |s| {{ throw \"boom\" }} }})"), &[]);
    assert_fails_with(&o, "grow: radius at step 0 for `F`: the closure `radius` raised: boom");
    assert!(!stderr(&o).contains("probability"), "{}", stderr(&o));
    // A limit reached inside a closure says which limit, not "Script terminated".
    let (o, _) = run_recipe(
        &format!("{ls}ls.grow(2, #{{ radius: |s| {{ let x = 0; loop {{ x += 1; }} }} }})"),
        &["--max-operations", "10000"],
    );
    assert_fails_with(&o, "operation limit reached (--max-operations 10000)");
    assert!(!stderr(&o).contains("Script terminated"), "{}", stderr(&o));
    // An option's element is quoted once.
    let (o, _) = run_recipe("let v = voxels(8); v.sculpt(voxels(4), #{ at: [1, \"x\", 0] })", &[]);
    assert_fails_with(&o, "sculpt: option `at[1]` must be a number, got a string");
}

#[test]
fn values_out_of_range_are_refused_at_the_call_naming_the_argument() {
    let recipe = "let caught = [];\n\
                  try { cube(1).scale(1e300).scale(1e300); } catch (e) { caught.push(e); }\n\
                  try { cube(1).translate([1.7e308, 0, 0]).translate([1e308, 0, 0]); } catch (e) { caught.push(e); }\n\
                  let pm = polar_sphere(1, 8, 4);\n\
                  try { pm.scale([9, 10, 11, 12, 13, 14, 15, 16], 0); } catch (e) { caught.push(e); }\n\
                  assert_eq(caught.len(), 3);\n\
                  assert(caught[0].contains(\"scale: argument `factor` [1e300, 1e300, 1e300] takes vertex 0 to [-inf, -inf, -inf]\"), caught[0]);\n\
                  assert(caught[1].starts_with(\"translate: argument `offset` [1e308, 0, 0] takes vertex\"), caught[1]);\n\
                  assert(caught[2].contains(\"scale: argument `factor` is 0\"), caught[2]);\n\
                  // A huge or tiny axis is a direction like any other.\n\
                  let p = cube(2).translate([5, 0, 0]);\n\
                  for axis in [[0, 0, 1e300], [0, 0, 1e-200]] {\n\
                      assert_near(p.rotate(axis, 90).bounds().min, vec3(-1, 4, -1), 1e-12);\n\
                  }\n\
                  cube(1)\n";
    let (o, _) = run_recipe(recipe, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
}

#[cfg(unix)]
#[test]
fn an_interrupt_stops_a_long_icosphere_in_the_repl_and_keeps_the_session() {
    use std::io::{Read, Write};
    use std::process::Stdio;
    let d = tempfile::tempdir().unwrap();
    let mut child = repl(d.path(), Stdio::piped());
    let mut stdin = child.stdin.take().unwrap();
    // Nine levels are about 5M triangles, a second or two each even in a debug build with
    // optimised dependencies; forty of them in a row take far longer than the bound below.
    stdin.write_all(b"let n = 0; for i in 0..40 { n += icosphere(1, 9).triangle_count(); }\n").unwrap();
    stdin.flush().unwrap();
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let start = std::time::Instant::now();
    let sent = Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap();
    assert!(sent.success());
    stdin.write_all(b"1 + 41\n").unwrap();
    drop(stdin);
    let mut out = String::new();
    child.stdout.take().unwrap().read_to_string(&mut out).unwrap();
    let seconds = start.elapsed().as_secs_f64();
    let status = child.wait().unwrap();
    assert!(status.code().is_some(), "killed by a signal: {status:?}");
    assert!(out.contains("interrupted"), "{out}");
    assert!(out.contains("=> 42"), "the session went on: {out}");
    // Far less than the forty icospheres would take: the interrupt stopped the work.
    assert!(seconds < 10.0, "the session came back after {seconds} s");
}
