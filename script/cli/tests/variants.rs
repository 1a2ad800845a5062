//! Thousands of variants on an existing scheduler: GNU parallel runs 20 seeds of a recipe at
//! once and gets the bytes (models and manifests) of 20 runs one after another. Each variant is
//! one deterministic process, so any scheduler (parallel, a Slurm array, a Kubernetes Indexed
//! Job — see deploy/) gives the same files.
//!
//! Skipped with a message only when `parallel` is missing and `CI` is unset; CI installs it.

use std::path::{Path, PathBuf};
use std::process::Command;

const SEEDS: u32 = 20;

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).ancestors().nth(2).unwrap().to_path_buf()
}

fn has_parallel() -> bool {
    Command::new("parallel").arg("--version").output().is_ok_and(|o| o.status.success())
}

/// Every file of `dir`, by name, with its bytes.
fn files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut v: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .map(|p| (p.file_name().unwrap().to_string_lossy().into_owned(), std::fs::read(&p).unwrap()))
        .collect();
    v.sort();
    v
}

#[test]
fn twenty_seeds_under_gnu_parallel_match_sequential_runs_byte_for_byte() {
    if !has_parallel() {
        assert!(std::env::var_os("CI").is_none(), "CI must have GNU parallel (.ci/run installs it)");
        eprintln!("skipped: GNU parallel is not installed (apt-get install parallel)");
        return;
    }
    let bin = env!("CARGO_BIN_EXE_blocksmith");
    let recipe = workspace().join("examples/customizer_towers.rhai");
    let d = tempfile::tempdir().unwrap();
    let (seq, par) = (d.path().join("seq"), d.path().join("par"));
    std::fs::create_dir_all(&seq).unwrap();
    std::fs::create_dir_all(&par).unwrap();
    for seed in 1..=SEEDS {
        let o = Command::new(bin)
            .current_dir(&seq)
            .arg("run")
            .arg(&recipe)
            .args([
                "--set",
                &format!("seed={seed}"),
                "-o",
                &format!("{seed}.glb"),
                "--manifest",
                &format!("{seed}.json"),
            ])
            .output()
            .unwrap();
        assert!(o.status.success(), "seed {seed}: {}", String::from_utf8_lossy(&o.stderr));
    }
    // The command of the README, with 4 jobs at once.
    let o = Command::new("parallel")
        .current_dir(&par)
        .args(["--will-cite", "--halt", "now,fail=1", "-j", "4", bin, "run"])
        .arg(&recipe)
        .args(["--set", "seed={}", "-o", "{}.glb", "--manifest", "{}.json", ":::"])
        .args((1..=SEEDS).map(|s| s.to_string()))
        .output()
        .unwrap();
    assert!(o.status.success(), "parallel: {}", String::from_utf8_lossy(&o.stderr));
    let (a, b) = (files(&seq), files(&par));
    assert_eq!(a.len(), 2 * SEEDS as usize);
    let names: Vec<&String> = a.iter().map(|(n, _)| n).collect();
    assert_eq!(names, b.iter().map(|(n, _)| n).collect::<Vec<_>>());
    for ((name, x), (_, y)) in a.iter().zip(&b) {
        assert!(x == y, "{name} differs between the sequential and the parallel run");
    }
    // The seeds make different variants, and each manifest names its seed and output hash.
    let models: std::collections::BTreeSet<&Vec<u8>> =
        a.iter().filter(|(n, _)| n.ends_with(".glb")).map(|(_, x)| x).collect();
    assert_eq!(models.len(), SEEDS as usize, "two seeds gave the same model");
    let m: serde_json::Value = serde_json::from_slice(&std::fs::read(par.join("7.json")).unwrap()).unwrap();
    assert_eq!(m["params"][0], serde_json::json!({ "name": "seed", "value": 7, "set": true }));
    let glb = std::fs::read(par.join("7.glb")).unwrap();
    assert_eq!(m["output"]["sha256"], sha256_hex(&glb));
}

/// SHA-256 in lower-case hex, as manifests write it.
fn sha256_hex(bytes: &[u8]) -> String {
    use sha2::Digest;
    sha2::Sha256::digest(bytes).iter().map(|b| format!("{b:02x}")).collect()
}
