//! The `blocksmith` binary end to end: bad input ends in a clear message and a non-zero exit,
//! never a panic or a hang; good input writes files.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

#[path = "support/repl.rs"]
mod repl;
use repl::repl;

fn blocksmith() -> Command {
    Command::new(env!("CARGO_BIN_EXE_blocksmith"))
}

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).ancestors().nth(2).unwrap().to_path_buf()
}

fn script(dir: &tempfile::TempDir, name: &str, text: &str) -> PathBuf {
    let p = dir.path().join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A failure: non-zero exit, no panic, and the message expected.
fn assert_fails_with(o: &Output, needle: &str) {
    let err = stderr(o);
    assert!(!o.status.success(), "expected failure, got success; stderr:\n{err}");
    assert!(!err.contains("panicked"), "a panic reached the user:\n{err}");
    assert!(err.contains(needle), "expected {needle:?} in:\n{err}");
}

#[test]
fn syntax_error_shows_file_line_column_source_and_caret() {
    let d = tempfile::tempdir().unwrap();
    let p = script(&d, "bad.rhai", "let a = 1;\nlet b = (a + ;\n");
    let o = blocksmith().arg("run").arg(&p).output().unwrap();
    assert_fails_with(&o, "bad.rhai:2:");
    let err = stderr(&o);
    assert!(err.contains("2 | let b = (a + ;"), "{err}");
    assert!(err.lines().any(|l| l.trim_end().ends_with('^')), "{err}");
}

#[test]
fn unknown_function_is_named() {
    let d = tempfile::tempdir().unwrap();
    let p = script(&d, "f.rhai", "let m = cube(1);\nm.smooth_please(3)\n");
    let o = blocksmith().arg("run").arg(&p).output().unwrap();
    assert_fails_with(&o, "f.rhai:2:3: error: Mesh has no method `smooth_please` (see `blocksmith doc Mesh`)");
}

#[test]
fn wrong_argument_type_names_function_and_argument() {
    let d = tempfile::tempdir().unwrap();
    let p = script(&d, "t.rhai", "icosphere(\"one\", 2)\n");
    let o = blocksmith().arg("run").arg(&p).output().unwrap();
    assert_fails_with(&o, "icosphere: argument `radius` must be a number, got a string");
}

#[test]
fn unknown_option_key_lists_valid_keys() {
    let d = tempfile::tempdir().unwrap();
    let p = script(&d, "o.rhai", "mesh([[0,0,0],[1,0,0],[0,1,0]], [[0,1,2]], #{ corner: [0] })\n");
    let o = blocksmith().arg("run").arg(&p).output().unwrap();
    assert_fails_with(&o, "unknown option `corner`; valid options are: colors, corners, creases");
}

#[test]
fn infinite_loop_stops_at_max_operations() {
    let d = tempfile::tempdir().unwrap();
    let p = script(&d, "loop.rhai", "let f = |x| x + 1;\nlet n = 0;\nloop { n = f.call(n); }\n");
    let o = blocksmith().arg("run").arg(&p).args(["--max-operations", "20000"]).output().unwrap();
    assert_fails_with(&o, "operation limit reached (--max-operations 20000)");
}

#[test]
fn missing_script_and_unknown_output_extension_are_errors() {
    let o = blocksmith().args(["run", "no/such/recipe.rhai"]).output().unwrap();
    assert_fails_with(&o, "no/such/recipe.rhai: error: cannot read the script");
    let d = tempfile::tempdir().unwrap();
    let p = script(&d, "c.rhai", "cube(1)\n");
    let out = d.path().join("cube.xyz");
    let o = blocksmith().arg("run").arg(&p).arg("-o").arg(&out).output().unwrap();
    assert_fails_with(&o, "cube.xyz");
}

#[test]
fn nothing_to_save_is_an_error() {
    let d = tempfile::tempdir().unwrap();
    let p = script(&d, "u.rhai", "let m = cube(1);\n");
    let o = blocksmith().arg("run").arg(&p).arg("-o").arg(d.path().join("x.glb")).output().unwrap();
    assert_fails_with(&o, "the script's last value is empty");
}

#[test]
fn set_parameters_reach_param() {
    let d = tempfile::tempdir().unwrap();
    let p = script(&d, "p.rhai", "let n = param(\"n\", 3);\nassert_eq(n, 7);\nlet s = param(\"s\", 1.0);\nassert_eq(type_of(s), \"f64\");\ncube(s)\n");
    let o = blocksmith().arg("run").arg(&p).args(["--set", "n=7", "--set", "s=2"]).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("Mesh(8 vertices"), "{}", stderr(&o));
}

#[test]
fn hello_recipe_writes_a_glb() {
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("hello.glb");
    let o = blocksmith().arg("run").arg(workspace().join("examples/hello.rhai")).arg("-o").arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let bytes = std::fs::read(&out).unwrap();
    assert_eq!(&bytes[..4], b"glTF");
}

#[test]
fn a_value_holding_script_closures_is_written_after_the_script_ends() {
    // The animation's modifier is a closure of the script: `-o` writes the value after the run,
    // and the closure must still find its function.
    let d = tempfile::tempdir().unwrap();
    let p = script(
        &d,
        "wave.rhai",
        "let pm = polar_sphere(0.2, 8, 6);\nlet a = animation(pm);\nlet k = 0.5;\na.add(modifier(|n, t, s| #{ position: s.position + vec3(k * t, 0, 0) }));\na\n",
    );
    let out = d.path().join("wave.glb");
    let o = blocksmith().arg("run").arg(&p).arg("-o").arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(&std::fs::read(&out).unwrap()[..4], b"glTF");
}

#[test]
fn import_finds_files_next_to_the_script_then_the_stdlib() {
    let d = tempfile::tempdir().unwrap();
    script(&d, "shapes.rhai", "fn pillar(h) { box([0, 0, 0], [1, 1, h]) }\n");
    let p = script(
        &d,
        "main.rhai",
        "import \"shapes\" as s;\nlet m = s::pillar(4);\nassert_near(m.volume(), 4.0, 1e-12);\nm\n",
    );
    let o = blocksmith().arg("run").arg(&p).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let p = script(&d, "missing.rhai", "import \"nowhere\" as n;\n");
    let o = blocksmith().arg("run").arg(&p).output().unwrap();
    assert_fails_with(&o, "module \"nowhere\" not found");
}

#[test]
fn test_command_with_a_relative_directory_resolves_imports_next_to_each_test() {
    // `blocksmith test sub` from the parent: `sub/t.rhai` imports `../lib/shapes`, which must be
    // found relative to the test file, not joined to the directory twice.
    let d = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(d.path().join("sub")).unwrap();
    std::fs::create_dir_all(d.path().join("lib")).unwrap();
    script(&d, "lib/shapes.rhai", "fn slab() { box([0, 0, 0], [2, 1, 1]) }\n");
    script(&d, "sub/t.rhai", "import \"../lib/shapes\" as s;\nassert_near(s::slab().volume(), 2.0, 1e-12);\n");
    let o = blocksmith().current_dir(d.path()).arg("test").arg("sub").output().unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{out}{}", stderr(&o));
    assert!(out.lines().last() == Some("1 passed, 0 failed"), "{out}");
}

#[test]
fn test_command_counts_passes_and_failures() {
    let d = tempfile::tempdir().unwrap();
    script(&d, "good.rhai", "assert_eq(1 + 1, 2);\n");
    script(&d, "bad.rhai", "assert_eq(cube(1).face_count, 5);\n");
    script(&d, "_helper.rhai", "this is not rhai at all (\n");
    let o = blocksmith().arg("test").arg(d.path()).arg("--out").arg(d.path().join("out")).output().unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(!o.status.success());
    assert!(out.lines().last() == Some("1 passed, 1 failed"), "{out}");
    assert!(out.contains("left:  6"), "{out}");
}

#[test]
fn doc_prints_one_function_and_refuses_unknown_names() {
    let o = blocksmith().args(["doc", "icosphere"]).output().unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success());
    assert!(out.starts_with("icosphere(radius: number, subdivisions: int) -> Mesh"), "{out}");
    assert!(out.contains("geodesic sphere"), "{out}");
    let o = blocksmith().args(["doc", "icospher"]).output().unwrap();
    assert_fails_with(&o, "no function, type or module named `icospher` (did you mean: icosphere?)");
}

#[test]
fn doc_signatures_read_as_scripts_write_them() {
    let o = blocksmith().arg("doc").output().unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success());
    assert!(out.contains("\nblocks() -> BlockModel\n"), "a function without parameters keeps its ()");
    assert!(out.contains("\npolar_octahedron() -> PolarMesh\n"));
    assert!(
        out.contains("cylinder(radius: number, height: number, segments: int) -> Mesh"),
        "no Rust-side `segments_`"
    );
    let signatures: Vec<&str> = out.lines().filter(|l| !l.is_empty() && !l.starts_with(' ')).collect();
    assert!(signatures.len() > 100, "{}", signatures.len());
    for s in signatures {
        assert!(!s.contains("nothing ->") && !s.ends_with("nothing"), "`nothing` glued to a name: {s}");
        // Standard-library functions are named `module::function`; types never have a path.
        let types = s.split_once('(').map_or(s, |(_, rest)| rest);
        assert!(!types.contains("::"), "a Rust module path: {s}");
        assert!(!s.contains("-> ()"), "an arrow to nothing: {s}");
    }
}

#[test]
fn doc_of_a_type_lists_its_methods_and_properties() {
    let o = blocksmith().args(["doc", "Mesh"]).output().unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{out}");
    assert!(out.starts_with("Mesh: "), "{out}");
    for method in ["translate(", "catmull_clark(", "volume(", "get vertex_count(", "crease("] {
        assert!(
            out.lines().any(|l| l.trim_start().starts_with(method) || l.contains(&format!(" {method}"))),
            "{method} missing:\n{out}"
        );
    }
    assert!(!out.contains("(pm: PolarMesh"), "only the type's own methods:\n{out}");
    let o = blocksmith().args(["doc", "PolarMesh"]).output().unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success() && out.contains("to_mesh("), "{out}");
}

#[test]
fn repl_reads_piped_input_and_keeps_definitions() {
    use std::io::Write;
    let d = tempfile::tempdir().unwrap();
    let mut child = repl(d.path(), Stdio::piped());
    let input =
        "fn side(n) {\n  n * 2\n}\nlet c = cube(side(1));\nc.volume()\nc.oops()\nc\n:save c.obj\n:save small.stl cube(1)\n:doc area\n:quit\n";
    child.stdin.take().unwrap().write_all(input.as_bytes()).unwrap();
    let o = child.wait_with_output().unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    // The failed entry is named by its line of the input, and fails the run.
    assert!(!o.status.success() && stderr(&o).contains("1 of the entries failed"), "{out}{}", stderr(&o));
    assert!(out.contains("=> 8.0"), "{out}");
    assert!(out.contains("<stdin>:6:3: error: Mesh has no method `oops` (`loops` is a method of PolarMesh)"), "{out}");
    // `:save` says which value it wrote: the last one, or the expression given.
    assert!(out.contains("wrote c.obj: the last value, Mesh(8 vertices"), "{out}");
    assert!(out.contains("wrote small.stl: `cube(1)`, Mesh(8 vertices"), "{out}");
    assert!(out.contains("The total surface area."), "{out}");
    assert!(d.path().join("c.obj").exists());
}

#[test]
fn a_reader_that_stops_early_ends_the_command_quietly() {
    // `blocksmith doc | head -1`: the pipe closes after the first line.
    let mut child = Command::new(env!("CARGO_BIN_EXE_blocksmith"))
        .arg("doc")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = [0u8; 16];
    std::io::Read::read_exact(child.stdout.as_mut().unwrap(), &mut first).unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(out.status.success(), "{:?} {stderr}", out.status);
}

/// Large blocks go to the C library's malloc, which keeps freed memory for reuse; the binary
/// hands it back to the system once the large blocks in use stop changing
/// (script/cli/src/allocator.rs): after a REPL entry, not at exit only.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
#[test]
fn memory_a_recipe_freed_goes_back_to_the_system_once_idle() {
    use std::io::{BufRead, BufReader, Write};
    use std::time::{Duration, Instant};
    let d = tempfile::tempdir().unwrap();
    let mut child = repl(d.path(), Stdio::null());
    let resident = |pid: u32| -> u64 {
        let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap();
        let kib = status.lines().find_map(|l| l.strip_prefix("RssAnon:")).unwrap();
        kib.split_whitespace().next().unwrap().parse::<u64>().unwrap() * 1024
    };
    let (lines, seen) = std::sync::mpsc::channel();
    let stdout = child.stdout.take().unwrap();
    std::thread::spawn(move || BufReader::new(stdout).lines().map_while(Result::ok).for_each(|l| drop(lines.send(l))));
    let mut stdin = child.stdin.take().unwrap();
    // 327,680 triangles: some 50 MB of mesh.
    stdin.write_all(b"let s = icosphere(1.0, 7);\ns.face_count\n").unwrap();
    let deadline = Instant::now() + Duration::from_secs(120);
    while !seen.recv_timeout(Duration::from_secs(120)).unwrap().contains("327680") {
        assert!(Instant::now() < deadline, "no answer from the REPL");
    }
    let held = resident(child.id());
    stdin.write_all(b"s = 0;\n").unwrap();
    let start = Instant::now();
    let mut now = held;
    while start.elapsed() < Duration::from_secs(30) {
        now = resident(child.id());
        if now + (30 << 20) < held {
            break;
        }
        std::thread::sleep(Duration::from_millis(200));
    }
    stdin.write_all(b":quit\n").unwrap();
    drop(stdin);
    let _ = child.wait();
    assert!(now + (30 << 20) < held, "resident {held} B with the mesh, {now} B 30 s after it was dropped");
}
