//! The bindings are what a program embedding blocksmith links: the kernel, rhai and
//! serde_json, and nothing of a terminal, the web, a file watcher or images (those belong to
//! the studio and the command line). `cargo tree` of this crate's normal dependencies says so.

use std::collections::BTreeSet;
use std::process::Command;

/// Crates of the front ends: HTTP and WebSocket servers, terminal UI and line editing,
/// argument parsing, file watching, images, hashing for manifests, allocators.
const FRONT_END_CRATES: &[&str] = &[
    "tiny_http",
    "tungstenite",
    "hyper",
    "axum",
    "notify",
    "rustyline",
    "clap",
    "indicatif",
    "console",
    "crossterm",
    "termios",
    "ctrlc",
    "image",
    "png",
    "sha2",
    "mimalloc",
];

#[test]
fn the_bindings_link_no_http_terminal_watcher_or_image_crate() {
    let manifest = concat!(env!("CARGO_MANIFEST_DIR"), "/Cargo.toml");
    let out = Command::new(env!("CARGO"))
        .args(["tree", "--offline", "--manifest-path", manifest, "-p", "blocksmith-script", "-e", "normal"])
        .args(["--prefix", "none", "--format", "{p}"])
        .output()
        .expect("cargo tree runs");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "cargo tree failed: {}", String::from_utf8_lossy(&out.stderr));
    let crates: BTreeSet<&str> = text.lines().filter_map(|l| l.split_whitespace().next()).collect();
    // The tree is read: the crate and what it must link are there.
    for needed in ["blocksmith-script", "blocksmith-kernel", "rhai", "serde_json"] {
        assert!(crates.contains(needed), "{needed} missing from:\n{text}");
    }
    let front: Vec<&&str> = FRONT_END_CRATES.iter().filter(|c| crates.contains(**c)).collect();
    assert!(front.is_empty(), "the bindings link front-end crates {front:?}:\n{text}");
}
