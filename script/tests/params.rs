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
}

#[test]
fn set_values_are_typed_and_checked_at_the_param_call() {
    let d = tempfile::tempdir().unwrap();
    let p = script(d.path(), "table.rhai", TABLE);
    let run = |set: &str| blocksmith().arg("run").arg(&p).args(["--set", set]).output().unwrap();
    assert_fails_with(&run("legs=2.5"), "table.rhai:3:");
    assert_fails_with(&run("legs=2.5"), "param: `legs` must be an integer from 3 to 8 (default 4), got `2.5`");
    assert_fails_with(&run("legs=9"), "must be an integer from 3 to 8 (default 4), got `9`");
    assert_fails_with(&run("size=abc"), "param: `size` must be a number from 0.5 to 10 (default 2.0), got `abc`");
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
