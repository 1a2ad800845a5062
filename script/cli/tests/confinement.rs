//! A recipe from someone else: it reads and writes only inside its project (the nearest folder
//! above it holding `.git` or `blocksmith.toml`, else its own folder) and the paths the command
//! line names, whatever path it writes — absolute, `..`, through a link, `~`; the allow flags
//! and `blocksmith.toml` widen that; `params`, `render` and `watch` write nothing; no save
//! replaces the recipe or a read-only file; a run writes a bounded number of files.

use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn blocksmith(home: &Path) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_blocksmith"));
    c.env("HOME", home);
    c
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn assert_refused(o: &Output, needles: &[&str]) {
    let err = stderr(o);
    assert!(!o.status.success(), "expected a refusal, got success:\n{err}");
    assert!(!err.contains("panicked"), "{err}");
    for n in needles {
        assert!(err.contains(n), "expected {n:?} in:\n{err}");
    }
}

/// A folder holding a project `proj` (marked by `.git`), a folder `other` beside it and a home
/// folder `home`, all real paths.
struct World {
    _dir: tempfile::TempDir,
    proj: PathBuf,
    other: PathBuf,
    home: PathBuf,
}

fn world() -> World {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path().canonicalize().unwrap();
    let (proj, other, home) = (root.join("proj"), root.join("other"), root.join("home"));
    for d in [&proj.join(".git"), &proj.join("recipes"), &other, &home] {
        std::fs::create_dir_all(d).unwrap();
    }
    World { _dir: dir, proj, other, home }
}

#[test]
fn saves_outside_the_project_are_refused_however_the_path_is_written() {
    let w = world();
    std::os::unix::fs::symlink(&w.other, w.proj.join("recipes/link")).unwrap();
    // Why each escapes: absolute; `..` past the project (the recipe is in recipes/, the
    // project is the folder holding .git); a link inside the project pointing out of it.
    let cases = [
        format!("{}/x.obj", w.other.display()),
        "../../other/x.obj".to_string(),
        "link/x.obj".to_string(),
        "missing/../../../other/x.obj".to_string(),
    ];
    for path in &cases {
        let recipe = write(&w.proj.join("recipes"), "r.rhai", &format!("cube(1).save(\"{path}\");\n1\n"));
        let o = blocksmith(&w.home).arg("run").arg(&recipe).output().unwrap();
        assert_refused(&o, &["outside the project", "--allow-write"]);
        assert!(!w.other.join("x.obj").exists(), "{path} was written");
    }
    // `~` is not the home folder in a script: it stays a folder of that name in the project.
    let recipe = write(&w.proj.join("recipes"), "r.rhai", "cube(1).save(\"~/x.obj\");\n1\n");
    let o = blocksmith(&w.home).arg("run").arg(&recipe).current_dir(&w.proj).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(w.proj.join("~/x.obj").exists() && !w.home.join("x.obj").exists());
    // Inside the project every way of writing works.
    let recipe =
        write(&w.proj.join("recipes"), "r.rhai", "cube(1).save(\"../a.obj\");\ncube(1).save(\"b/c.obj\");\n1\n");
    let o = blocksmith(&w.home).arg("run").arg(&recipe).current_dir(w.proj.join("recipes")).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(w.proj.join("a.obj").exists() && w.proj.join("recipes/b/c.obj").exists());
}

#[test]
fn loads_and_imports_outside_the_project_are_refused_until_allowed() {
    let w = world();
    write(&w.other, "lib.rhai", "fn two() { 2 }\n");
    let mesh = w.other.join("m.obj");
    let made = write(&w.other, "make.rhai", &format!("cube(1).save(\"{}\");\n1\n", mesh.display()));
    assert!(blocksmith(&w.home).arg("run").arg(&made).output().unwrap().status.success());
    let load = write(&w.proj, "load.rhai", &format!("load(\"{}\")\n", mesh.display()));
    let o = blocksmith(&w.home).arg("run").arg(&load).output().unwrap();
    assert_refused(&o, &["load: ", "outside the project", &format!("--allow-read {}", w.other.display())]);
    let o = blocksmith(&w.home).arg("run").arg(&load).arg("--allow-read").arg(&w.other).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    // Imports obey the same rule as loads.
    let import = write(&w.proj, "import.rhai", "import \"../other/lib\" as lib;\nlib::two()\n");
    let o = blocksmith(&w.home).arg("run").arg(&import).output().unwrap();
    assert_refused(&o, &["import: ", "outside the project", "--allow-read"]);
    let o = blocksmith(&w.home).arg("run").arg(&import).arg("--allow-read").arg(&w.other).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn the_allow_flags_and_blocksmith_toml_widen_the_project() {
    let w = world();
    let target = w.other.join("x.obj");
    let recipe = write(&w.proj, "r.rhai", &format!("cube(1).save(\"{}\");\n1\n", target.display()));
    let o = blocksmith(&w.home).arg("run").arg(&recipe).arg("--allow-write").arg(&w.other).output().unwrap();
    assert!(o.status.success() && target.exists(), "{}", stderr(&o));
    std::fs::remove_file(&target).unwrap();
    // The same grant in the project's blocksmith.toml, relative to it.
    write(&w.proj, "blocksmith.toml", "[access]\nallow_write = [\"../other\"]  # renders\n");
    let o = blocksmith(&w.home).arg("run").arg(&recipe).output().unwrap();
    assert!(o.status.success() && target.exists(), "{}", stderr(&o));
    // A mistake in the file is named with its line.
    write(&w.proj, "blocksmith.toml", "[access]\nallow_writ = [\"../other\"]\n");
    let o = blocksmith(&w.home).arg("run").arg(&recipe).output().unwrap();
    assert_refused(&o, &["blocksmith.toml:2: unknown key `allow_writ`"]);
    // `-o` and `--manifest` are named by the user: writable wherever they are.
    std::fs::remove_file(w.proj.join("blocksmith.toml")).unwrap();
    let plain = write(&w.proj, "plain.rhai", "cube(1)\n");
    let (out, manifest) = (w.other.join("o.glb"), w.other.join("m.json"));
    let o = blocksmith(&w.home).arg("run").arg(&plain).arg("-o").arg(&out).arg("--manifest").arg(&manifest).output();
    let o = o.unwrap();
    assert!(o.status.success() && out.exists() && manifest.exists(), "{}", stderr(&o));
}

#[test]
fn params_render_and_watch_runs_write_nothing() {
    let w = world();
    let recipe = write(&w.proj, "r.rhai", "let s = param(\"s\", 1.0);\ncube(s).save(\"saved.obj\");\ncube(s)\n");
    let o = blocksmith(&w.home).arg("params").arg(&recipe).current_dir(&w.proj).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("not written: saved.obj"), "{}", stderr(&o));
    let o = blocksmith(&w.home).arg("run").arg(&recipe).arg("--params").current_dir(&w.proj).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let png = w.proj.join("r.png");
    let mut render = blocksmith(&w.home);
    let o = render.arg("render").arg(&recipe).arg("-o").arg(&png).args(["--size", "32x24"]).current_dir(&w.proj);
    let o = o.output().unwrap();
    assert!(o.status.success() && png.exists(), "{}", stderr(&o));
    assert!(!w.proj.join("saved.obj").exists(), "a listing or a picture performed the recipe's save");
    // The studio's runs (`watch`) report saves the same way.
    let options = blocksmith_script::EngineOptions {
        context: blocksmith_script::RunContext {
            access: blocksmith_script::access::Access::default().reporting(),
            ..Default::default()
        },
        ..Default::default()
    };
    let scene = blocksmith_studio::scene::from_recipe(&recipe, options).unwrap();
    assert!(scene.warnings.iter().any(|w| w.contains("not written")), "{:?}", scene.warnings);
    assert!(!w.proj.join("saved.obj").exists() && !Path::new("saved.obj").exists());
}

#[test]
fn no_run_replaces_its_recipe_an_import_or_a_read_only_file() {
    let w = world();
    write(&w.proj, "lib.rhai", "fn one() { 1 }\n");
    let recipe = write(&w.proj, "r.rhai", "import \"lib\" as lib;\ncube(lib::one())\n");
    let source = std::fs::read_to_string(&recipe).unwrap();
    for args in [vec!["-o", "r.rhai"], vec!["--manifest", "r.rhai"], vec!["-o", "lib.rhai"]] {
        let o = blocksmith(&w.home).arg("run").arg(&recipe).args(&args).current_dir(&w.proj).output().unwrap();
        assert_refused(&o, &["the recipe or a module it imports"]);
    }
    let o = blocksmith(&w.home).arg("render").arg(&recipe).args(["-o", "r.rhai"]).current_dir(&w.proj).output();
    assert_refused(&o.unwrap(), &["-o: not writing"]);
    let own = write(&w.proj, "own.rhai", "import \"lib\" as lib;\ncube(1).save(\"lib.rhai\");\n1\n");
    let o = blocksmith(&w.home).arg("run").arg(&own).current_dir(&w.proj).output().unwrap();
    assert_refused(&o, &["the recipe or a module it imports"]);
    assert_eq!(std::fs::read_to_string(&recipe).unwrap(), source);
    // A file without write permission (mode 444) is never replaced, by a save or by -o.
    let locked = w.proj.join("locked.obj");
    std::fs::write(&locked, "keep").unwrap();
    std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o444)).unwrap();
    let saver = write(&w.proj, "s.rhai", "cube(1).save(\"locked.obj\");\n1\n");
    let o = blocksmith(&w.home).arg("run").arg(&saver).current_dir(&w.proj).output().unwrap();
    assert_refused(&o, &["read-only"]);
    let o = blocksmith(&w.home).arg("run").arg(&recipe).args(["-o", "locked.obj"]).current_dir(&w.proj).output();
    assert_refused(&o.unwrap(), &["read-only"]);
    assert_eq!(std::fs::read_to_string(&locked).unwrap(), "keep");
}

#[test]
fn a_run_writes_at_most_its_limit_of_files() {
    let w = world();
    let recipe = write(&w.proj, "r.rhai", "for i in 0..400 { cube(1).save(`out/f${i}.obj`); }\n1\n");
    let o = blocksmith(&w.home).arg("run").arg(&recipe).current_dir(&w.proj).output().unwrap();
    assert_refused(&o, &["written 100 files", "--max-writes"]);
    assert_eq!(std::fs::read_dir(w.proj.join("out")).unwrap().count(), 100);
    let mut more = blocksmith(&w.home);
    let o = more.arg("run").arg(&recipe).args(["--max-writes", "400"]).current_dir(&w.proj).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    // The byte limit stops the run once it is reached.
    let mut small = blocksmith(&w.home);
    let o = small.arg("run").arg(&recipe).args(["--max-write-size", "1K"]).current_dir(&w.proj).output().unwrap();
    assert_refused(&o, &["bytes, its limit", "--max-write-size"]);
}

#[test]
fn an_obj_and_its_material_library_pass_the_same_checks() {
    // A coloured OBJ writes `STEM.mtl` beside it: a read-only library refuses the save (the
    // OBJ is not written either), by a recipe's save and by -o; a writable one is written
    // with it, also beside a host-named -o file.
    let w = world();
    let locked = w.proj.join("locked.mtl");
    std::fs::write(&locked, "keep").unwrap();
    std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o444)).unwrap();
    let saver = write(&w.proj, "s.rhai", "cube(1).color(\"#ff0000\").save(\"locked.obj\");\n1\n");
    let o = blocksmith(&w.home).arg("run").arg(&saver).current_dir(&w.proj).output().unwrap();
    assert_refused(&o, &["save:", "the material library beside the .obj", "read-only"]);
    let coloured =
        write(&w.proj, "c.rhai", "#{ body: cube(1).color(\"#ff0000\"), lid: cube(1).translate([2, 0, 0]) }\n");
    let o = blocksmith(&w.home).arg("run").arg(&coloured).args(["-o", "locked.obj"]).current_dir(&w.proj).output();
    assert_refused(&o.unwrap(), &["read-only"]);
    assert!(!w.proj.join("locked.obj").exists());
    assert_eq!(std::fs::read_to_string(&locked).unwrap(), "keep");
    let o = blocksmith(&w.home).arg("run").arg(&coloured).args(["-o", "out/parts.obj"]).current_dir(&w.proj).output();
    let o = o.unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let mtl = std::fs::read_to_string(w.proj.join("out/parts.mtl")).unwrap();
    assert!(mtl.contains("newmtl #ff0000"), "{mtl}");
    let obj = std::fs::read_to_string(w.proj.join("out/parts.obj")).unwrap();
    assert!(obj.contains("mtllib parts.mtl") && obj.contains("o body") && obj.contains("o lid"), "{obj}");
}
