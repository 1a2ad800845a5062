//! Parameters and variants end to end: `blocksmith params`, typed and checked `--set`, unknown
//! names, `run --stats json` and `run --manifest`.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn blocksmith() -> Command {
    Command::new(env!("CARGO_BIN_EXE_blocksmith"))
}

fn script(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
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

const TABLE: &str = "let size = param(\"size\", 2.0, #{ min: 0.5, max: 10, step: 0.5, doc: \"edge length\" });\n\
                     let wood = param(\"wood\", \"oak\", #{ choices: [\"oak\", \"pine\"] });\n\
                     let legs = param(\"legs\", 4, #{ min: 3, max: 8 });\n\
                     let at = param(\"at\", vec3(0, 0, 1));\n\
                     cube(size).translate(at)\n";

#[test]
fn params_lists_type_default_range_and_doc_as_text_and_json() {
    let d = tempfile::tempdir().unwrap();
    let p = script(d.path(), "table.rhai", TABLE);
    let o = blocksmith().arg("params").arg(&p).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let expected = "  name  type    default        range                doc\n\
                    \x20 size  float   2.0            0.5 to 10, step 0.5  edge length\n\
                    \x20 wood  choice  \"oak\"          \"oak\" | \"pine\"\n\
                    \x20 legs  int     4              3 to 8\n\
                    \x20 at    vec3    [0.0,0.0,1.0]\n";
    assert_eq!(stdout(&o), expected);
    let o = blocksmith().arg("params").arg(&p).args(["--format", "json"]).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let params = v["params"].as_array().unwrap();
    assert_eq!(params.len(), 4);
    assert_eq!(params[0]["kind"], "float");
    assert_eq!(params[0]["step"], 0.5);
    assert_eq!(params[1]["choices"], serde_json::json!(["oak", "pine"]));
    assert_eq!(params[3]["default"], serde_json::json!([0.0, 0.0, 1.0]));
    // `run --params` is the same listing.
    let o = blocksmith().arg("run").arg(&p).arg("--params").output().unwrap();
    assert_eq!((o.status.success(), stdout(&o)), (true, expected.to_string()), "{}", stderr(&o));
    let o = blocksmith().arg("run").arg(&p).args(["--params", "json"]).output().unwrap();
    assert_eq!(serde_json::from_str::<serde_json::Value>(&stdout(&o)).unwrap(), v);
    assert_fails_with(
        &blocksmith().arg("run").arg(&p).arg("--params").args(["-o", "x.stl"]).output().unwrap(),
        "--output",
    );
}

#[test]
fn set_values_are_typed_and_checked_at_the_param_call() {
    let d = tempfile::tempdir().unwrap();
    let p = script(d.path(), "table.rhai", TABLE);
    let run = |set: &str| blocksmith().arg("run").arg(&p).args(["--set", set]).output().unwrap();
    assert_fails_with(&run("legs=2.5"), "table.rhai:3:");
    assert_fails_with(&run("legs=2.5"), "param: `legs` must be an integer from 3 to 8 (default 4), got `2.5`");
    assert_fails_with(&run("legs=9"), "must be an integer from 3 to 8 (default 4), got `9`");
    let size = "param: `size` must be a number from 0.5 to 10, in steps of 0.5 from 0.5 (default 2.0)";
    assert_fails_with(&run("size=abc"), &format!("{size}, got `abc`"));
    assert_fails_with(&run("size=2.2"), &format!("{size}, got `2.2`"));
    assert!(run("size=9.5").status.success());
    assert_fails_with(&run("wood=elm"), "param: `wood` must be one of oak, pine (default \"oak\"), got `elm`");
    assert_fails_with(&run("at=1,2"), "param: `at` must be three numbers x,y,z (default [0.0,0.0,1.0]), got `1,2`");
    let o = run("at=1,2,3");
    assert!(o.status.success(), "{}", stderr(&o));
    let o = run("wood=pine");
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn an_unknown_set_name_fails_with_the_parameters_and_a_did_you_mean() {
    let d = tempfile::tempdir().unwrap();
    let p = script(d.path(), "table.rhai", TABLE);
    let out = d.path().join("never.glb");
    let o = blocksmith().arg("run").arg(&p).args(["--set", "lgs=5", "-o"]).arg(&out).output().unwrap();
    assert_fails_with(&o, "--set lgs: the recipe has no parameter `lgs` (did you mean `legs`?)");
    assert_fails_with(&o, "its parameters are:");
    assert!(stderr(&o).contains("edge length"), "{}", stderr(&o));
    assert!(!out.exists(), "a model was written for a misspelt parameter");
}

#[test]
fn stats_json_prints_the_written_models_facts() {
    let d = tempfile::tempdir().unwrap();
    let p = script(d.path(), "table.rhai", TABLE);
    let out = d.path().join("cube.obj");
    let o =
        blocksmith().arg("run").arg(&p).args(["--set", "size=3", "--stats", "json", "-o"]).arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    // A cube of edge 3 moved by (0, 0, 1): 8 vertices, 12 edges, 6 quads, closed genus 0,
    // volume 27, area 54, bounds [-1.5, 1.5] × [-1.5, 1.5] × [-0.5, 2.5].
    assert_eq!((v["vertices"].as_u64(), v["edges"].as_u64(), v["faces"].as_u64()), (Some(8), Some(12), Some(6)));
    assert_eq!(
        (v["closed"].as_bool(), v["manifold"].as_bool(), v["genus"].as_i64()),
        (Some(true), Some(true), Some(0))
    );
    assert!((v["volume"].as_f64().unwrap() - 27.0).abs() < 1e-9, "{v}");
    assert!((v["area"].as_f64().unwrap() - 54.0).abs() < 1e-9, "{v}");
    assert_eq!(v["bounds"]["min"], serde_json::json!([-1.5, -1.5, -0.5]));
    assert_eq!(v["bounds"]["max"], serde_json::json!([1.5, 1.5, 2.5]));
    assert!(v["run_time_s"].as_f64().unwrap() >= 0.0);
    let o = blocksmith().arg("run").arg(&p).args(["--stats", "json"]).output().unwrap();
    assert_fails_with(&o, "--output");
}

/// A recipe that prints does not spoil the stats: with `--stats json` on standard output, its
/// `print` and `debug` lines go to standard error, and `… --stats json | jq` reads JSON alone.
#[test]
fn stats_json_stays_alone_on_stdout_when_the_recipe_prints() {
    let d = tempfile::tempdir().unwrap();
    let p = script(
        d.path(),
        "noisy.rhai",
        "print(\"building\");\ndebug(42);\nlet m = cube(2);\nprint(`volume ${m.volume()}`);\nm\n",
    );
    let out = d.path().join("noisy.stl");
    let o = blocksmith().arg("run").arg(&p).args(["--stats", "json", "-o"]).arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("standard output is the stats alone");
    assert!((v["volume"].as_f64().unwrap() - 8.0).abs() < 1e-6, "{v}");
    let err = stderr(&o);
    assert!(err.contains("building") && err.contains("volume 8.0") && err.contains("42"), "{err}");
    // Without --stats, print stays on standard output.
    let o = blocksmith().arg("run").arg(&p).arg("-o").arg(&out).output().unwrap();
    assert!(stdout(&o).contains("building") && !stderr(&o).contains("building"), "{}", stdout(&o));
}

/// A relation between parameters (`param_check`) is reported at its line, with the
/// parameters' values, by `run` and `params`, before the modeling after it runs.
#[test]
fn param_check_reports_a_bad_combination_before_modeling() {
    let d = tempfile::tempdir().unwrap();
    let gear = "let teeth = param(\"teeth\", 12, #{ min: 6, max: 60 });\n\
                let bore = param(\"bore\", 3.0, #{ min: 0, max: 50 });\n\
                let root = teeth - 2.5;\n\
                param_check(bore < root, `the bore (${bore}) must be smaller than the root circle (${root})`);\n\
                print(\"modeling\");\n\
                cylinder(root / 2, 1, 32) - cylinder(bore / 2, 3, 32)\n";
    let p = script(d.path(), "gear.rhai", gear);
    let out = d.path().join("gear.stl");
    let o = blocksmith().arg("run").arg(&p).args(["--set", "bore=20", "-o"]).arg(&out).output().unwrap();
    assert_fails_with(
        &o,
        "gear.rhai:4:1: error: param_check: the bore (20.0) must be smaller than the root circle (9.5)",
    );
    assert_fails_with(&o, "(with teeth = 12, bore = 20.0 (--set))");
    assert!(!stdout(&o).contains("modeling") && !out.exists(), "the recipe ran on");
    let o = blocksmith().arg("params").arg(&p).args(["--set", "bore=20"]).output().unwrap();
    assert_fails_with(&o, "param_check: the bore (20.0)");
    // As JSON: the parameters and each check with its outcome and line, the error named, and
    // the command still failing.
    let o = blocksmith().arg("params").arg(&p).args(["--set", "bore=20", "--format", "json"]).output().unwrap();
    assert!(!o.status.success());
    let listing: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(listing["params"][1]["value"], 20.0);
    assert_eq!(
        listing["checks"],
        serde_json::json!([{ "message": "the bore (20.0) must be smaller than the root circle (9.5)", "passed": false, "line": 4 }])
    );
    assert!(listing["error"].as_str().unwrap().contains("param_check: the bore (20.0)"), "{listing}");
    let o = blocksmith().arg("params").arg(&p).args(["--format", "json"]).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let listing: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(listing["checks"][0]["passed"], true);
    assert!(listing.get("error").is_none());
    // A good combination runs.
    let o = blocksmith().arg("run").arg(&p).args(["--set", "bore=4", "-o"]).arg(&out).output().unwrap();
    assert!(o.status.success() && out.exists(), "{}", stderr(&o));
}

/// The manifest of one run, read back.
fn manifest(recipe: &Path, out: &Path, sets: &[&str]) -> String {
    let m = out.with_extension("json");
    let mut cmd = blocksmith();
    cmd.arg("run").arg(recipe).arg("-o").arg(out).arg("--manifest").arg(&m);
    for s in sets {
        cmd.args(["--set", s]);
    }
    let o = cmd.output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::read_to_string(&m).unwrap()
}

#[test]
fn a_manifest_changes_when_an_imported_or_loaded_file_changes_and_only_then() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    script(dir, "part.rhai", "fn side() { 2.0 }\n");
    let wrote =
        blocksmith().arg("run").arg(script(dir, "base.rhai", "cube(1)")).arg("-o").arg(dir.join("base.obj")).output();
    assert!(wrote.unwrap().status.success());
    let recipe = script(
        dir,
        "r.rhai",
        "import \"part\" as part;\nimport \"check\" as check;\nlet k = param(\"k\", 1.0);\n\
         let b = load(\"base.obj\");\ncube(part::side() * k)\n",
    );
    let out = dir.join("r.obj");
    let first = manifest(&recipe, &out, &["k=1.5"]);
    let v: serde_json::Value = serde_json::from_str(&first).unwrap();
    let paths: Vec<&str> = v["inputs"].as_array().unwrap().iter().map(|i| i["path"].as_str().unwrap()).collect();
    assert_eq!(paths, ["part.rhai", "base.obj"]);
    assert_eq!(v["stdlib"][0]["module"], "check");
    assert_eq!(v["params"], serde_json::json!([{ "name": "k", "value": 1.5, "set": true }]));
    assert_eq!(v["tool"]["version"], env!("CARGO_PKG_VERSION"));
    assert_eq!(v["output"]["sha256"].as_str().unwrap().len(), 64);
    assert_eq!((&v["rebuild"][3], &v["rebuild"][4]), (&serde_json::json!("--set"), &serde_json::json!("k=1.5")));
    // Same inputs, same manifest, byte for byte — also after a file is rewritten unchanged.
    assert_eq!(manifest(&recipe, &out, &["k=1.5"]), first);
    std::fs::write(dir.join("part.rhai"), "fn side() { 2.0 }\n").unwrap();
    assert_eq!(manifest(&recipe, &out, &["k=1.5"]), first);
    // An edit of the imported module that leaves the output alone still changes its hash.
    std::fs::write(dir.join("part.rhai"), "// the side\nfn side() { 2.0 }\n").unwrap();
    let edited = manifest(&recipe, &out, &["k=1.5"]);
    let e: serde_json::Value = serde_json::from_str(&edited).unwrap();
    assert_ne!(e["inputs"][0]["sha256"], v["inputs"][0]["sha256"]);
    assert_eq!((&e["inputs"][1], &e["output"], &e["recipe"]), (&v["inputs"][1], &v["output"], &v["recipe"]));
    // So does a changed loaded file; and a changed parameter changes the parameters and output.
    std::fs::write(dir.join("base.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let l: serde_json::Value = serde_json::from_str(&manifest(&recipe, &out, &["k=1.5"])).unwrap();
    assert_ne!(l["inputs"][1]["sha256"], e["inputs"][1]["sha256"]);
    assert_eq!(l["inputs"][0], e["inputs"][0]);
    let k: serde_json::Value = serde_json::from_str(&manifest(&recipe, &out, &["k=2"])).unwrap();
    assert_ne!(k["output"]["sha256"], l["output"]["sha256"]);
    assert_eq!(k["params"][0]["value"], 2.0);
}

#[test]
fn a_gltf_is_hashed_with_its_buffer_files_written_or_loaded() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    // Written: the manifest's output is the .gltf and the .bin beside it.
    let recipe = script(dir, "r.rhai", "cube(param(\"k\", 1.0))");
    let out = dir.join("r.gltf");
    let v: serde_json::Value = serde_json::from_str(&manifest(&recipe, &out, &[])).unwrap();
    let buffers = v["output"]["buffers"].as_array().unwrap();
    assert_eq!(buffers.len(), 1, "{v}");
    let bin = std::path::PathBuf::from(buffers[0]["path"].as_str().unwrap());
    assert_eq!(bin.extension().and_then(|e| e.to_str()), Some("bin"));
    let bytes = std::fs::read(&bin).unwrap();
    assert_eq!(buffers[0]["sha256"].as_str().unwrap(), sha256_hex(&bytes));
    // Loaded: the .bin is a file the run read; a change to it alone changes the manifest.
    let loader = script(dir, "l.rhai", "load(\"r.gltf\")");
    let lout = dir.join("l.stl");
    let first: serde_json::Value = serde_json::from_str(&manifest(&loader, &lout, &[])).unwrap();
    let paths: Vec<&str> = first["inputs"].as_array().unwrap().iter().map(|i| i["path"].as_str().unwrap()).collect();
    assert_eq!(paths, ["r.gltf", bin.file_name().unwrap().to_str().unwrap()]);
    let moved = blocksmith().arg("run").arg(&recipe).args(["--set", "k=2", "-o"]).arg(dir.join("k2.gltf")).output();
    assert!(moved.unwrap().status.success());
    // The buffer is named by its content (`k2.HASH.bin`), so a .gltf and its buffer change
    // together: find the one k2.gltf names.
    let k2_name = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok().and_then(|e| e.file_name().into_string().ok()))
        .find(|n| n.starts_with("k2.") && n.ends_with(".bin"))
        .expect("k2's buffer");
    let k2_bin = std::fs::read(dir.join(k2_name)).unwrap();
    assert_eq!(k2_bin.len(), bytes.len(), "same layout, other positions");
    std::fs::write(&bin, k2_bin).unwrap();
    let second: serde_json::Value = serde_json::from_str(&manifest(&loader, &lout, &[])).unwrap();
    assert_eq!(second["inputs"][0], first["inputs"][0], "the .gltf itself is unchanged");
    assert_ne!(second["inputs"][1]["sha256"], first["inputs"][1]["sha256"]);
}

/// SHA-256 in lower-case hex, as manifests write it.
fn sha256_hex(bytes: &[u8]) -> String {
    use sha2::Digest;
    sha2::Sha256::digest(bytes).iter().map(|b| format!("{b:02x}")).collect()
}
