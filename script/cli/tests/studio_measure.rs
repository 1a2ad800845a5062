//! The studio page's measure tool in a real browser (Debian's `chromium`, headless; skipped when
//! it is missing, except under CI=true), driven by real mouse events at points near where the
//! page draws a model's corners, edges and faces: snapping, distances, a face's area and normal,
//! a circle fitted to a ring of rim vertices, and the `assert_near` line it writes, run through
//! `blocksmith run` as a recipe line.

#[path = "support/browser.rs"]
mod browser;
#[path = "support/studio_watch.rs"]
mod studio_watch;
mod support;

use std::path::Path;
use std::process::Command;
use std::time::Duration;

use browser::Browser;
use serde_json::{json, Value};
use studio_watch::{watch, Watch};

/// The page of a studio watching a recipe of `source`, with the measure tool on; None where
/// chromium is missing.
fn measuring(dir: &Path, source: &str) -> Option<(Watch, Browser)> {
    let recipe = dir.join("model.rhai");
    std::fs::write(&recipe, source).unwrap();
    let w = watch(&recipe);
    let mut b = Browser::open(&w.url)?;
    b.wait("window.studio && studio.triangles > 0", Duration::from_secs(30));
    b.eval("document.getElementById('measure').click()");
    assert_eq!(b.eval("studio.measure.on"), true);
    Some((w, b))
}

/// A real click (`shift`: with the shift key) `offset` CSS pixels from where the page draws
/// kernel point `p`; the measure tool's state once the click is measured.
fn click_near(b: &mut Browser, p: [f64; 3], offset: (f64, f64), shift: bool) -> Value {
    let before = b.eval("studio.measure.clicks").as_u64().unwrap();
    let xy = b.eval(&format!("studio.screenOf([{}, {}, {}])", p[0], p[1], p[2]));
    let (x, y) = (xy[0].as_f64().unwrap() + offset.0, xy[1].as_f64().unwrap() + offset.1);
    for kind in ["mousePressed", "mouseReleased"] {
        b.call(
            "Input.dispatchMouseEvent",
            json!({ "type": kind, "x": x, "y": y, "button": "left", "buttons": 1, "clickCount": 1,
                    "modifiers": if shift { 8 } else { 0 } }),
        );
    }
    b.wait(&format!("studio.measure.clicks > {before}"), Duration::from_secs(10));
    let state = b.eval("studio.measure");
    assert!(b.eval("studio.error").is_null(), "{}", b.eval("studio.error"));
    state
}

fn vec(v: &Value) -> Vec<f64> {
    v.as_array().unwrap_or_else(|| panic!("not an array: {v}")).iter().map(|x| x.as_f64().unwrap()).collect()
}

/// Asserts `got` is within `eps` of `want`, component by component, printing both and the difference.
fn assert_close(what: &str, got: &[f64], want: &[f64], eps: f64) {
    assert_eq!(got.len(), want.len(), "{what}: {got:?} against {want:?}");
    for (g, w) in got.iter().zip(want) {
        assert!((g - w).abs() <= eps, "{what}: {got:?}, expected {want:?} (differ by {} > {eps})", (g - w).abs());
    }
}

/// Runs `line` in a recipe `let m = {model}; line; m` through `blocksmith run` (in a folder of
/// its own: a file written beside the watched recipe would make the studio run it again):
/// whether it succeeded, and what it printed.
fn run_line(model: &str, line: &str) -> (bool, String) {
    let dir = tempfile::tempdir().unwrap();
    let dir = dir.path();
    let recipe = dir.join("check.rhai");
    std::fs::write(&recipe, format!("let m = {model};\n{line}\nm\n")).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_blocksmith"))
        .arg("run")
        .arg(&recipe)
        .arg("-o")
        .arg(dir.join("check.glb"))
        .output()
        .unwrap();
    (o.status.success(), String::from_utf8_lossy(&o.stderr).into_owned())
}

#[test]
fn measure_snaps_to_a_cubes_corners_and_edges_and_reads_its_faces() {
    let dir = tempfile::tempdir().unwrap();
    let Some((_w, mut b)) = measuring(dir.path(), "cube(2)\n") else { return };
    // The camera looks from +x, −y, above, so the edge x = 1, z = 1 between the +x and top faces
    // is in sight. Clicks 5 pixels off its two corners snap to them (they are drawn a hundred
    // pixels and more apart): the edge is the cube's side, 2 long, along +y.
    let first = click_near(&mut b, [1.0, -1.0, 1.0], (4.0, 3.0), false);
    assert_eq!(first["points"][0]["kind"], "vertex", "{first}");
    assert_close("first corner", &vec(&first["points"][0]["point"]), &[1.0, -1.0, 1.0], 0.0);
    assert!(first["distance"].is_null());
    let m = click_near(&mut b, [1.0, 1.0, 1.0], (-3.0, 4.0), false);
    assert_eq!(m["points"][1]["kind"], "vertex", "{m}");
    assert_close("second corner", &vec(&m["points"][1]["point"]), &[1.0, 1.0, 1.0], 0.0);
    assert_close("distance", &[m["distance"].as_f64().unwrap()], &[2.0], 1e-9);
    assert_close("deltas", &vec(&m["deltas"]), &[0.0, 2.0, 0.0], 1e-9);
    // The line the page writes, as the brief's example, and its copy.
    let line = m["assert"].as_str().unwrap().to_string();
    assert_eq!(line, "assert_near(distance(vec3(1, -1, 1), vec3(1, 1, 1)), 2.0, 1e-6);");
    b.eval("document.getElementById('measure-copy').click()");
    b.wait("studio.measure.copied", Duration::from_secs(5));
    assert_eq!(b.eval("studio.measure.copied"), json!({ "text": line, "clipboard": true }));
    let origin = b.eval("location.origin");
    b.call("Browser.grantPermissions", json!({ "permissions": ["clipboardReadWrite"], "origin": origin }));
    assert_eq!(b.eval("navigator.clipboard.readText()"), json!(line));
    assert_eq!(b.eval("document.getElementById('measure-assert').textContent"), json!(line));
    // It runs as a recipe line, and a wrong distance in it fails the run: the line checks.
    let (ok, said) = run_line("cube(2)", &line);
    assert!(ok, "{line}: {said}");
    let (ok, said) = run_line("cube(2)", &line.replace("2.0,", "2.5,"));
    assert!(!ok && said.contains("assert_near"), "{said}");

    // A click 4 pixels off the edge, away from its corners: the point of the edge (x = 1, z = 1),
    // about where the click was along it.
    let m = click_near(&mut b, [1.0, 0.3, 1.0], (3.0, 3.0), false);
    assert_eq!(m["points"].as_array().unwrap().len(), 1, "a third click starts a new pair: {m}");
    assert_eq!(m["points"][0]["kind"], "edge", "{m}");
    let p = vec(&m["points"][0]["point"]);
    assert_close("on the edge", &[p[0], p[2]], &[1.0, 1.0], 1e-6);
    assert!((p[1] - 0.3).abs() < 0.1, "{p:?}");

    // Clicks inside three faces, far from their edges: each face is a 2 × 2 square, area 4, its
    // normal the unit axis it faces (two triangles of one quad, not one triangle of area 2).
    for (at, normal) in
        [([0.2, 0.1, 1.0], [0.0, 0.0, 1.0]), ([1.0, 0.1, -0.3], [1.0, 0.0, 0.0]), ([0.2, -1.0, -0.2], [0.0, -1.0, 0.0])]
    {
        let m = click_near(&mut b, at, (0.0, 0.0), false);
        let last = m["points"].as_array().unwrap().last().unwrap().clone();
        assert_eq!(last["kind"], "face", "{m}");
        assert_close("face area", &[m["area"].as_f64().unwrap()], &[4.0], 1e-9);
        assert_close("face normal", &vec(&m["normal"]), &normal, 1e-12);
        assert_eq!(m["face"]["polygon"], true, "{m}");
        assert_eq!(m["face"]["triangles"], 2, "{m}");
    }
    // Measuring is not picking: no recipe line was looked up for any of these clicks.
    assert!(b.eval("studio.picked").is_null());
}

#[test]
fn a_ring_of_rim_vertices_fits_the_cylinders_circle() {
    use std::f64::consts::TAU;
    let dir = tempfile::tempdir().unwrap();
    let model = "cylinder(1.5, 2, 32)";
    let Some((_w, mut b)) = measuring(dir.path(), &format!("{model}\n")) else { return };
    // The top rim: vertex k at 1.5 (cos, sin)(2π k / 32), z = 1 (kernel/src/mesh/primitives.rs).
    // Eight of them, shift-clicked 3 pixels off (neighbours are tens of pixels apart).
    let rim = |k: u32| {
        let phi = TAU * f64::from(k) / 32.0;
        [1.5 * phi.cos(), 1.5 * phi.sin(), 1.0]
    };
    for (i, k) in [0, 3, 7, 11, 15, 19, 23, 27].into_iter().enumerate() {
        let m = click_near(&mut b, rim(k), (2.0, -2.0), true);
        let ring = m["ring"].as_array().unwrap();
        assert_eq!(ring.len(), i + 1, "{m}");
        // The vertices as drawn: f32 positions, within 1e-7 of the kernel's.
        assert_close(&format!("rim vertex {k}"), &vec(&ring[i]), &rim(k), 1e-6);
        assert!(m["points"].as_array().unwrap().is_empty(), "a shift-click is not a point of a pair: {m}");
    }
    b.eval("document.getElementById('fit-circle').click()");
    let m = b.eval("studio.measure");
    // The points lie on the circle of radius 1.5 about (0, 0, 1) in the plane z = 1, up to the
    // f32 rounding of their coordinates (~1e-7): an exact fit there.
    let circle = &m["circle"];
    assert_close("radius", &[circle["radius"].as_f64().unwrap()], &[1.5], 1e-6);
    assert_close("centre", &vec(&circle["centre"]), &[0.0, 0.0, 1.0], 1e-6);
    assert_close("circle normal", &vec(&circle["normal"]), &[0.0, 0.0, 1.0], 1e-6);
    let line = m["assert"].as_str().unwrap().to_string();
    // The centre and radius rounded to 7 digits; the points are that close to the circle.
    assert_eq!(line, "assert_near(distance(vec3(0, 0, 1), vec3(1.5, 0, 1)), 1.5, 1e-6);", "{m}");
    let (ok, said) = run_line(model, &line);
    assert!(ok, "{line}: {said}");

    // A click on the top cap: its face is the 32-gon, area ½ · 32 · 1.5² · sin(2π / 32), not
    // one triangle of its fan.
    let m = click_near(&mut b, [0.3, 0.2, 1.0], (0.0, 0.0), false);
    let area = 0.5 * 32.0 * 1.5 * 1.5 * (TAU / 32.0).sin();
    assert_close("cap area", &[m["area"].as_f64().unwrap()], &[area], 1e-9);
    assert_close("cap normal", &vec(&m["normal"]), &[0.0, 0.0, 1.0], 1e-12);
    assert_eq!(m["face"]["triangles"], 30, "{m}");
}
