//! `blocksmith lsp` in a real editor: Neovim, headless, with the README's set-up for Neovim
//! 0.7–0.9 (the version Debian 12 packages; `.ci/run` installs it). The README's Lua block is
//! the editor's `init.lua` as written; tests/lsp/neovim_driver.lua then asks through Neovim's
//! own LSP client for the diagnostics of a recipe, hover on a call and completion after `m.`,
//! and writes what Neovim received as JSON. Fails under CI without `nvim`; skips, saying so,
//! on a developer's machine without it.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

#[path = "support/child.rs"]
mod child;

/// The Lua block under the README's "Neovim 0.7 to 0.9" heading.
fn readme_setup() -> String {
    let readme = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../README.md")).unwrap();
    let at = readme.find("**Neovim 0.7 to 0.9**").expect("the README gives a Neovim 0.7 to 0.9 set-up");
    let rest = &readme[at..];
    let start = rest.find("```lua\n").expect("a Lua block") + "```lua\n".len();
    let end = rest[start..].find("```").expect("the block ends");
    rest[start..start + end].to_string()
}

#[test]
fn neovim_with_the_readme_set_up_gets_diagnostics_hover_and_completion() {
    if Command::new("nvim").arg("--version").output().is_err() {
        assert!(std::env::var_os("CI").is_none(), "CI must install Neovim (.ci/run)");
        eprintln!("skipped: no nvim on PATH");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("init.lua"), readme_setup()).unwrap();
    std::fs::write(dir.path().join("recipe.rhai"), "let m = cube(2);\nlet v = m.volume();\ncubee(1)\n").unwrap();
    let out = dir.path().join("out.json");
    let driver = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/lsp/neovim_driver.lua");
    // The README's set-up runs `blocksmith lsp` from PATH: this build's binary first.
    let bin_dir = Path::new(env!("CARGO_BIN_EXE_blocksmith")).parent().unwrap().to_path_buf();
    let path = std::env::join_paths(
        std::iter::once(bin_dir).chain(std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default())),
    )
    .unwrap();
    let mut nvim = Command::new("nvim")
        .args(["--headless", "-n", "-i", "NONE", "-u", "init.lua", "recipe.rhai", "-c"])
        .arg(format!("luafile {}", driver.display()))
        .current_dir(dir.path())
        .env("PATH", path)
        .env("BLOCKSMITH_NVIM_OUT", &out)
        .env("XDG_CONFIG_HOME", dir.path())
        .env("XDG_DATA_HOME", dir.path())
        .env("XDG_STATE_HOME", dir.path())
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("run nvim");
    let status = child::wait_within(&mut nvim, Duration::from_secs(120));
    if status.is_none() {
        let _ = nvim.kill();
        let _ = nvim.wait();
    }
    let text = std::fs::read_to_string(&out).unwrap_or_else(|_| panic!("Neovim wrote nothing ({status:?})"));
    let got: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(got["filetype"], "rhai", "{text}");
    assert_eq!(got["attached"], true, "the server attached to the buffer: {text}");
    // The unknown function, on its line, with the suggestion.
    let diagnostics = got["diagnostics"].as_array().unwrap();
    assert!(
        diagnostics.iter().any(|d| d["line"] == 2 && d["message"].as_str().unwrap().contains("did you mean `cube`")),
        "{text}"
    );
    // Hover on `cube` is `blocksmith doc cube`.
    let doc = Command::new(env!("CARGO_BIN_EXE_blocksmith")).args(["doc", "cube"]).output().unwrap();
    let doc = String::from_utf8(doc.stdout).unwrap();
    let hover = got["hover"]["contents"]["value"].as_str().unwrap_or_default();
    assert_eq!(hover.trim(), doc.trim(), "{text}");
    // Completion after `m.` offers the methods of a Mesh, and only names a script can write.
    let labels: Vec<&str> = got["completion"].as_array().unwrap().iter().filter_map(|c| c["label"].as_str()).collect();
    assert!(labels.contains(&"volume") && labels.contains(&"translate"), "{labels:?}");
    assert!(!labels.contains(&"cube"), "functions are not methods: {labels:?}");
    assert!(
        labels.iter().all(|l| l.chars().all(|c| c.is_alphanumeric() || c == '_')),
        "internal names leak: {labels:?}"
    );
}
