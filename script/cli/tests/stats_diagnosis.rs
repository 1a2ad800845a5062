//! `blocksmith run --stats [text|json]` says where a model is broken (issue 34): components
//! with their genus, boundary and handle loops, crossing faces, places where sheets touch —
//! each with a count and where.

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

/// Two cubes crossing each other, a torus, and a square sheet with an open boundary.
const BROKEN: &str = "combine([cube(2), cube(2).translate([1, 1, 1]), torus(3, 1, 24, 12).translate([10, 0, 0]),\n\
                      mesh([[0, 6, 0], [1, 6, 0], [1, 7, 0], [0, 7, 0]], [[0, 1, 2, 3]])])\n";

#[test]
fn stats_text_lists_each_kind_with_its_count_and_place() {
    let d = tempfile::tempdir().unwrap();
    let p = script(d.path(), "broken.rhai", BROKEN);
    let out = d.path().join("broken.obj");
    let o = blocksmith().arg("run").arg(&p).args(["-o"]).arg(&out).arg("--stats").output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = stdout(&o);
    for line in [
        "closed: no, manifold: yes, genus: 1",
        "components: 4",
        "  0: 6 faces, genus 0, closed, around (0, 0, 0)",
        "  2: 288 faces, genus 1, closed, around (10, 0, 0)",
        "  3: 1 faces, genus 0, 1 boundary loop, around (0.5, 6.5, 0)",
        "boundary loops: 1",
        "  0: 4 edges, length 4, around (0.5, 6.5, 0) (component 3)",
        "handle loops: 1",
        "  0: 12 edges, length 6.211657, around (13, 0, 0) (component 2)",
        "self-intersecting face pairs: 6",
        "non-manifold vertices (split on load): 0",
        "degenerate faces: 0",
    ] {
        assert!(text.lines().any(|l| l == line), "no line {line:?} in:\n{text}");
    }
}

#[test]
fn stats_json_holds_the_diagnosis() {
    let d = tempfile::tempdir().unwrap();
    let p = script(d.path(), "broken.rhai", BROKEN);
    let out = d.path().join("broken.obj");
    let o = blocksmith().arg("run").arg(&p).args(["--stats", "json", "-o"]).arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let g = &v["diagnosis"];
    assert_eq!(g["component_count"], 4);
    let genus: Vec<i64> = g["components"].as_array().unwrap().iter().map(|c| c["genus"].as_i64().unwrap()).collect();
    assert_eq!(genus, [0, 0, 1, 0]);
    assert_eq!((g["boundary_count"].as_u64(), g["handle_count"].as_u64()), (Some(1), Some(1)));
    assert_eq!(g["self_intersections"]["count"], 6);
    // Each crossing pairs a face of the first cube (0-5) with one of the second (6-11), at a
    // point inside both cubes' overlap [0, 1]³.
    for c in g["self_intersections"]["at"].as_array().unwrap() {
        let f = &c["faces"];
        assert!(f[0].as_u64().unwrap() < 6 && (6..12).contains(&f[1].as_u64().unwrap()), "{c}");
        assert!(
            c["at"].as_array().unwrap().iter().all(|x| (-1e-12..=1.0 + 1e-12).contains(&x.as_f64().unwrap())),
            "{c}"
        );
    }
    assert_eq!(v["repairs"], serde_json::json!([]));
}

/// A model written to STL with two cubes sharing a corner: reading it back splits the corner,
/// and the stats say so and where.
#[test]
fn stats_report_what_reading_back_repaired() {
    let d = tempfile::tempdir().unwrap();
    let p = script(d.path(), "corner.rhai", "combine([cube(1), cube(1).translate([1, 1, 1])])\n");
    let out = d.path().join("corner.stl");
    let o = blocksmith().arg("run").arg(&p).args(["--stats", "text", "-o"]).arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = stdout(&o);
    assert!(text.contains("repaired on reading back: split 1 non-manifold vertex into one per fan"), "{text}");
    assert!(text.contains("non-manifold vertices (split on load): 1\n  at (0.5, 0.5, 0.5)\n"), "{text}");
    assert!(text.contains("components: 2\n"), "{text}");
}
