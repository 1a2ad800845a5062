//! The studio's debugging views in a real browser (Debian's `chromium`, headless; skipped when
//! it is missing, except under CI=true).
//! - Defects: a model of four parts — an open square, two cubes that cross each other, a torus —
//!   shows its open boundary and the torus's handle loop as lines on the surface (checked in the
//!   scene and in the pixels drawn), the crossing faces, and its four components, each of which
//!   can be hidden on its own. A double torus and a voxel slab with two tunnels show four handle
//!   loops, each closed and on the screen.
//! - Provenance: a boolean result, drawn uncoloured, is coloured by operand on request (one
//!   colour per operand, the faces of the cut in the cutter's) and drawn as it was again after.

#[path = "support/browser.rs"]
mod browser;
#[path = "support/studio_watch.rs"]
mod studio_watch;
mod support;

use std::time::Duration;

use browser::Browser;
use serde_json::Value;
use studio_watch::watch;

fn numbers(v: &Value) -> Vec<f64> {
    v.as_array().unwrap_or_else(|| panic!("not an array: {v}")).iter().map(|x| x.as_f64().unwrap()).collect()
}

const RECIPE: &str = "\
let square = mesh([[5, 0, 0], [6, 0, 0], [6, 1, 0], [5, 1, 0]], [[0, 1, 2, 3]]);
let a = cube(1);
let b = cube(1).translate([0.5, 0.5, 0.5]);
let ring = torus(2, 0.5, 24, 12).translate([-6, 0, 0]);
combine([square, a, b, ring])
";

/// The studio of `text` (saved as `name` in a new folder) in a browser, its model drawn: the
/// folder and the server, to keep, and the page; `None` where no browser runs (see `Browser`).
fn studio_of(text: &str, name: &str) -> Option<(tempfile::TempDir, studio_watch::Watch, Browser)> {
    let dir = tempfile::tempdir().unwrap();
    let recipe = dir.path().join(name);
    std::fs::write(&recipe, text).unwrap();
    let w = watch(&recipe);
    let mut b = Browser::open(&w.url)?;
    b.wait("window.studio && studio.triangles > 0", Duration::from_secs(60));
    Some((dir, w, b))
}

/// Turns the defects view on and returns its state (without the three.js meshes).
fn defects_on(b: &mut Browser) -> Value {
    b.eval("document.getElementById('defects').click()");
    b.wait("studio.defects.loaded", Duration::from_secs(60));
    assert!(b.eval("studio.error").is_null(), "{}", b.eval("studio.error"));
    b.eval("JSON.parse(JSON.stringify(studio.defects, (k, v) => k === 'mesh' ? undefined : v))")
}

/// The magenta pixels (the handle loops' colour) within 3 pixels of where the page draws `p`,
/// after two animation frames (the view draws on the next one after a change).
fn magenta_near(b: &mut Browser, p: &[f64]) -> u64 {
    b.eval("new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(() => done(true))))");
    b.eval(&format!(
        "(() => {{ const c = document.querySelector('#view canvas'); const r = c.getBoundingClientRect();
           const [x, y] = studio.screenOf([{}, {}, {}]); const k = c.width / r.width;
           const o = document.createElement('canvas'); o.width = c.width; o.height = c.height;
           const g = o.getContext('2d'); g.drawImage(c, 0, 0);
           const px = g.getImageData(Math.round((x - r.left) * k) - 3, Math.round((y - r.top) * k) - 3, 7, 7).data;
           let n = 0; for (let i = 0; i < px.length; i += 4) if (px[i] > 120 && px[i + 1] < 90 && px[i + 2] > 120) n++;
           return n; }})()",
        p[0], p[1], p[2]
    ))
    .as_u64()
    .unwrap()
}

#[test]
fn the_defects_view_draws_boundaries_handle_loops_and_crossings_and_toggles_components() {
    let Some((_dir, _server, mut b)) = studio_of(RECIPE, "broken.rhai") else { return };
    let all = b.eval("studio.triangles").as_f64().unwrap();
    let state = defects_on(&mut b);
    let counts = &state["counts"];
    assert_eq!(
        (counts["component"].as_u64(), counts["boundary"].as_u64(), counts["handle"].as_u64()),
        (Some(4), Some(1), Some(1)),
        "{state}"
    );
    assert!(counts["self_intersection"].as_u64().unwrap() > 0, "{state}");
    assert!(state["crossings"].as_f64().unwrap() >= 12.0, "the crossing faces are drawn: {state}");
    assert_eq!(b.eval("document.getElementById('defects').getAttribute('aria-pressed')"), "true");

    // The square's boundary: four unit segments on its edges (z = 0, x in 5..6).
    let boundary = numbers(&b.eval("studio.defectSegments('boundaries')"));
    assert_eq!(boundary.len(), 4 * 6);
    for s in boundary.chunks_exact(6) {
        let len = ((s[0] - s[3]).powi(2) + (s[1] - s[4]).powi(2) + (s[2] - s[5]).powi(2)).sqrt();
        assert!((len - 1.0).abs() < 1e-5 && s[2] == 0.0 && s[0] >= 5.0, "{s:?}");
    }
    // The handle loop lies on the torus (0.5 from its core circle of radius 2 about x = -6) and
    // goes once round the tube: a short loop, not one round the whole ring.
    let handle = numbers(&b.eval("studio.defectSegments('handles')"));
    assert!(handle.len() >= 6 * 3, "{handle:?}");
    let mut length = 0.0;
    for s in handle.chunks_exact(6) {
        for p in [&s[..3], &s[3..]] {
            let (x, y, z) = (p[0] + 6.0, p[1], p[2]);
            let tube = (((x * x + y * y).sqrt() - 2.0).powi(2) + z * z).sqrt();
            assert!((tube - 0.5).abs() < 1e-4, "{p:?} is {tube} from the core");
        }
        length += ((s[0] - s[3]).powi(2) + (s[1] - s[4]).powi(2) + (s[2] - s[5]).powi(2)).sqrt();
    }
    assert!(length < 2.0 * std::f64::consts::PI * 0.5 * 1.1, "a loop round the tube, not the ring: {length}");

    // The loop is on the screen in its colour: magenta pixels where the page draws its first
    // segment's middle (lines are drawn over everything).
    let mid: Vec<f64> = (0..3).map(|i| (handle[i] + handle[i + 3]) / 2.0).collect();
    assert!(magenta_near(&mut b, &mid) > 0, "no magenta pixel near the handle loop's segment at {mid:?}");

    // Four components drawn in place of the model, together the model's triangles; hiding the
    // torus leaves the others.
    let components = state["components"].as_array().unwrap();
    assert_eq!(components.len(), 4);
    let triangles: Vec<f64> = components.iter().map(|c| c["triangles"].as_f64().unwrap()).collect();
    assert_eq!(triangles.iter().sum::<f64>(), all, "{triangles:?}");
    assert_eq!(b.eval("studio.triangles").as_f64().unwrap(), all);
    let ring = components.iter().position(|c| c["genus"] == 1).expect("the torus is the component of genus 1");
    b.eval(&format!("document.getElementById('component-{ring}').click()"));
    assert_eq!(b.eval(&format!("studio.defects.components[{ring}].visible")), false);
    assert_eq!(b.eval("studio.triangles").as_f64().unwrap(), all - triangles[ring]);
    assert_eq!(b.eval("studio.defects.components.filter((c) => c.mesh.visible).length"), 3);

    // Off again: the model as it was.
    b.eval("document.getElementById('defects').click()");
    b.wait("!studio.defects.on", Duration::from_secs(10));
    assert_eq!(b.eval("studio.triangles").as_f64().unwrap(), all);
    assert_eq!(b.eval("studio.defectSegments('handles').length"), 0);
}

/// A double torus (two tori united) and a voxel slab with two one-voxel tunnels.
const HANDLES: &str = "\
let dt = union(torus(3, 1, 24, 12), torus(3, 1, 24, 12).translate([5, 0, 0]));
let vx = voxels(16);
vx.fill_box([2, 2, 2], [14, 14, 6]);
for z in 2..6 {
    vx.set(5, 5, z, 0);
    vx.set(10, 10, z, 0);
}
let slab = vx.to_mesh(#{ surface: \"raw\" }).translate([0, 10, 0]);
combine([dt, slab])
";

/// The closed loops the segments `s` (six numbers each) make, as their segment counts; panics
/// when an end is not shared by exactly two segments.
fn loops_of(s: &[f64]) -> Vec<usize> {
    let key = |p: &[f64]| p.iter().map(|c| (c * 1e6).round() as i64).collect::<Vec<i64>>();
    let segments: Vec<[Vec<i64>; 2]> = s.chunks_exact(6).map(|c| [key(&c[..3]), key(&c[3..])]).collect();
    let mut at: std::collections::HashMap<Vec<i64>, Vec<usize>> = std::collections::HashMap::new();
    for (i, [a, b]) in segments.iter().enumerate() {
        at.entry(a.clone()).or_default().push(i);
        at.entry(b.clone()).or_default().push(i);
    }
    assert!(at.values().all(|v| v.len() == 2), "every end joins two segments");
    let mut seen = vec![false; segments.len()];
    let mut loops = Vec::new();
    for start in 0..segments.len() {
        if seen[start] {
            continue;
        }
        let (mut count, mut stack) = (0, vec![start]);
        while let Some(i) = stack.pop() {
            if std::mem::replace(&mut seen[i], true) {
                continue;
            }
            count += 1;
            for end in &segments[i] {
                stack.extend(at[end].iter().copied().filter(|&j| !seen[j]));
            }
        }
        loops.push(count);
    }
    loops
}

#[test]
fn the_handle_loops_of_a_double_torus_and_a_voxel_tunnel_are_drawn_one_closed_loop_each() {
    // Genus 2 and genus 2: four handles, each drawn as a closed loop on its surface, in the
    // loop colour on the screen.
    let Some((_dir, _server, mut b)) = studio_of(HANDLES, "handles.rhai") else { return };
    let state = defects_on(&mut b);
    assert_eq!(state["counts"]["handle"].as_u64(), Some(4), "{state}");
    let genus: Vec<i64> =
        state["components"].as_array().unwrap().iter().map(|c| c["genus"].as_i64().unwrap()).collect();
    assert_eq!(genus, [2, 2], "{state}");
    let handles = numbers(&b.eval("studio.defectSegments('handles')"));
    let loops = loops_of(&handles);
    assert_eq!(loops.len(), 4, "{loops:?}");
    // The voxel tunnels' loops are short (round one voxel column: at most 12 edges); the double
    // torus's go round its tubes or between its holes.
    assert!(loops.iter().filter(|&&n| n <= 12).count() >= 2, "{loops:?}");
    // The loops on the screen: magenta pixels at most of their segments' middles.
    let mut drawn = 0;
    for s in handles.chunks_exact(6) {
        let mid: Vec<f64> = (0..3).map(|i| (s[i] + s[i + 3]) / 2.0).collect();
        drawn += usize::from(magenta_near(&mut b, &mid) > 0);
    }
    assert!(drawn * 2 >= handles.len() / 6, "{drawn} of {} segments show magenta", handles.len() / 6);
}

#[test]
fn a_boolean_result_is_coloured_by_operand_on_request_and_uncoloured_again() {
    let dir = tempfile::tempdir().unwrap();
    let recipe = dir.path().join("cut.rhai");
    std::fs::write(&recipe, "cube(2) - cylinder(0.5, 3, 32)\n").unwrap();
    let w = watch(&recipe);
    let Some(mut b) = Browser::open(&w.url) else { return };
    b.wait("window.studio && studio.triangles > 0", Duration::from_secs(30));
    let triangles = b.eval("studio.triangles");
    assert_eq!(b.eval("document.getElementById('provenance-label').hidden"), false, "offered for a boolean result");
    assert_eq!(b.eval("studio.shownColours().length"), 0, "drawn uncoloured at first");
    b.eval("document.getElementById('provenance').click()");
    b.wait("studio.provenance === 1", Duration::from_secs(30));
    assert!(b.eval("studio.error").is_null(), "{}", b.eval("studio.error"));
    // Two operands, two colours: the cube's faces and the bore's.
    assert_eq!(b.eval("studio.shownColours().length"), 2, "{}", b.eval("studio.shownColours()"));
    assert_eq!(b.eval("studio.triangles"), triangles, "the same triangles, recoloured");
    assert_eq!(b.eval("document.getElementById('provenance-note').hidden"), false);
    b.eval("document.getElementById('provenance').click()");
    b.wait("studio.provenance === 0", Duration::from_secs(10));
    assert_eq!(b.eval("studio.shownColours().length"), 0);
    assert_eq!(b.eval("studio.triangles"), triangles);
    // A model from no boolean has no such view.
    std::fs::write(&recipe, "cube(2)\n").unwrap();
    b.wait("studio.triangles === 12", Duration::from_secs(30));
    assert_eq!(b.eval("document.getElementById('provenance-label').hidden"), true);
}
