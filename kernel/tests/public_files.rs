//! Public mesh files as other tools wrote them (issue 34): trimesh's test models, Khronos glTF
//! samples and OpenSubdiv's regression shapes, in tests/data/public/ with their sources and
//! licences (SOURCES.md there).
//!
//! Each file named in tests/data/public/expected.json loads with the default options as a
//! manifold with the triangles, components, boundary edges and Euler characteristic written
//! there, repaired (with a report) exactly where it says, or is refused with its error where it
//! says. Those numbers were written by `tests/data/compare_loads_trimesh.py --write-expected`,
//! which also compares each file with trimesh 5.2 (CI runs it with `--check`): they agree with
//! trimesh's wherever trimesh's mesh is a manifold (after each vertex shared by several fans is
//! split into one per fan, where that is all that keeps it from one), and the `trimesh` field says
//! which. Every mesh file in the folder must be named, so a file added needs its numbers.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use blocksmith_kernel::io::{self, LoadOptions};
use blocksmith_kernel::Mesh;

const EXTENSIONS: [&str; 6] = ["stl", "obj", "glb", "gltf", "ply", "3mf"];

fn corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/public")
}

fn expected() -> BTreeMap<String, serde_json::Value> {
    let text = std::fs::read_to_string(corpus().join("expected.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

/// Every mesh file under the corpus, as `folder/name`.
fn mesh_files() -> Vec<String> {
    let mut out = Vec::new();
    for folder in std::fs::read_dir(corpus()).unwrap() {
        let folder = folder.unwrap().path();
        if !folder.is_dir() {
            continue;
        }
        for f in std::fs::read_dir(&folder).unwrap() {
            let f = f.unwrap().path();
            let ext = f.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
            if EXTENSIONS.contains(&ext.as_str()) {
                out.push(f.strip_prefix(corpus()).unwrap().to_string_lossy().replace('\\', "/"));
            }
        }
    }
    out.sort();
    out
}

fn boundary_edges(m: &Mesh) -> usize {
    m.boundary_loops().iter().map(Vec::len).sum()
}

#[test]
fn every_file_of_the_corpus_has_its_numbers() {
    let named: Vec<String> = expected().into_keys().collect();
    assert_eq!(mesh_files(), named, "tests/data/public/expected.json names every mesh file, and no other");
    assert!(named.len() >= 100, "{} files", named.len());
}

#[test]
fn public_files_load_as_manifolds_with_the_numbers_trimesh_agrees_with() {
    let mut failures = Vec::new();
    let mut compared = 0;
    for (name, want) in expected() {
        let path = corpus().join(&name);
        let got = io::load_report(&path, &LoadOptions::DEFAULT);
        if let Some(reason) = want.get("refused").and_then(|r| r.as_str()) {
            match got {
                Err(e) => {
                    let said = e.to_string();
                    if !said.ends_with(reason) {
                        failures.push(format!("{name}: refused as {said}, not {reason}"));
                    }
                }
                Ok(_) => failures.push(format!("{name}: loads, expected refused ({reason})")),
            }
            continue;
        }
        let (m, repairs) = match got {
            Ok(r) => r,
            Err(e) => {
                failures.push(format!("{name}: refused: {e}"));
                continue;
            }
        };
        let number = |k: &str| want[k].as_i64().unwrap();
        let have = [
            ("triangles", m.triangle_count() as i64),
            ("components", m.component_count() as i64),
            ("boundary_edges", boundary_edges(&m) as i64),
            ("euler", m.euler()),
        ];
        for (k, v) in have {
            if v != number(k) {
                failures.push(format!("{name}: {k} {v}, expected {}", number(k)));
            }
        }
        if !m.is_manifold() {
            failures.push(format!("{name}: not a manifold"));
        }
        if repairs.is_empty() == want["repaired"].as_bool().unwrap() {
            failures.push(format!("{name}: repairs {:?}, expected repaired: {}", repairs.summary(), want["repaired"]));
        }
        compared += usize::from(want["trimesh"].as_str().unwrap().starts_with("agrees"));
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(compared >= 90, "{compared} files agree with trimesh");
}

#[test]
fn files_trimesh_reads_only_after_splits_are_named_with_what_was_split() {
    // Suzanne's eyes touch her head at one vertex each (a weld joins them into bowties, and
    // keeps them apart); the teapot is one bowtie as written; trimesh's stacked boxes and the
    // building of three storeys are solids touching along faces.
    let e = expected();
    let verdict = |f: &str| e[f]["trimesh"].as_str().unwrap().to_string();
    assert_eq!(verdict("trimesh/monkey.glb"), "agrees after each shared vertex is split into one per fan");
    assert_eq!(verdict("trimesh/teapot.stl"), "agrees after each shared vertex is split into one per fan");
    let building = io::load(corpus().join("trimesh/no_indices_3storybuilding.glb")).unwrap();
    assert!(building.is_closed() && building.is_manifold());
    assert_eq!((building.component_count(), building.genus()), (6, 0), "two rooms a storey, each closed");
    let boxes = io::load(corpus().join("trimesh/not_convex.obj")).unwrap();
    assert!(boxes.is_closed() && boxes.is_manifold());
    assert_eq!(boxes.component_count(), 8);
    assert!(boxes.volume() > 0.0);
}
