//! `blocksmith run --manifest FILE.json`: what a variant was made from, so it can be checked
//! and rebuilt — the recipe's hash, the hash of every file it imported or loaded (and of each
//! standard-library module, embedded in the binary), the parameters, the tool's version and
//! the output's hash. The same inputs give the same manifest, byte for byte (it holds no time).

use std::path::Path;

use serde_json::{json, Value};
use sha2::{Digest, Sha256};

use blocksmith_script::record::RunRecord;
use blocksmith_script::resolver::Resolver;
use blocksmith_script::run::RunError;

/// The SHA-256 of `bytes`, as 64 lower-case hex digits.
#[must_use]
pub fn sha256(bytes: &[u8]) -> String {
    Sha256::digest(bytes).iter().map(|b| format!("{b:02x}")).collect()
}

fn hash_file(path: &Path) -> Result<String, RunError> {
    std::fs::read(path)
        .map(|b| sha256(&b))
        .map_err(|e| RunError(format!("error: --manifest: cannot read {}: {e}", path.display())))
}

/// `path` relative to `base` when under it (so manifests do not depend on where the checkout
/// is), else as is.
fn shown(path: &Path, base: Option<&Path>) -> String {
    base.and_then(|b| path.strip_prefix(b).ok()).unwrap_or(path).display().to_string()
}

/// The manifest of a run of `recipe` (as given on the command line) that read what `record`
/// lists and wrote `output`. Input paths are relative to the recipe's directory when under it.
/// `rebuild` is the command that makes the same output again.
///
/// # Errors
/// A file that cannot be read to hash.
pub fn build(recipe: &Path, record: &RunRecord, output: Option<&Path>) -> Result<Value, RunError> {
    let base = record.inputs.first().and_then(|p| p.parent());
    let inputs: Vec<Value> = record
        .inputs
        .iter()
        .skip(1)
        .map(|p| Ok(json!({ "path": shown(p, base), "sha256": hash_file(p)? })))
        .collect::<Result<_, RunError>>()?;
    let stdlib: Vec<Value> = record
        .stdlib
        .iter()
        .map(|n| json!({ "module": n, "sha256": sha256(Resolver::stdlib_source(n).unwrap_or_default().as_bytes()) }))
        .collect();
    let mut rebuild = vec![json!("blocksmith"), json!("run"), json!(recipe.display().to_string())];
    for p in record.params.iter().filter(|p| p.set) {
        let text = p.value.as_str().map_or_else(|| p.value.to_string(), str::to_string);
        let text = text.trim_start_matches('[').trim_end_matches(']').to_string();
        rebuild.push(json!("--set"));
        rebuild.push(json!(format!("{}={text}", p.name)));
    }
    let output = match output {
        Some(out) => {
            rebuild.push(json!("-o"));
            rebuild.push(json!(out.display().to_string()));
            // A .gltf's model is also in its buffer files (the .bin beside it).
            let buffers: Vec<Value> = blocksmith_script::gltf_buffers::buffer_files(out)
                .iter()
                .map(|b| Ok(json!({ "path": b.display().to_string(), "sha256": hash_file(b)? })))
                .collect::<Result<_, RunError>>()?;
            let mut o = json!({ "path": out.display().to_string(), "sha256": hash_file(out)? });
            if !buffers.is_empty() {
                o["buffers"] = Value::Array(buffers);
            }
            o
        }
        None => Value::Null,
    };
    Ok(json!({
        "tool": { "name": "blocksmith", "version": env!("CARGO_PKG_VERSION") },
        "recipe": { "path": recipe.display().to_string(), "sha256": hash_file(recipe)? },
        "inputs": inputs,
        "stdlib": stdlib,
        "params": record.params.iter().map(|p| json!({ "name": p.name, "value": p.value, "set": p.set })).collect::<Vec<_>>(),
        "output": output,
        "rebuild": rebuild,
    }))
}

/// Writes `manifest` to `path` (pretty JSON, a final newline) through a temporary file renamed
/// into place, so an interrupted write never leaves half a manifest.
///
/// # Errors
/// The file cannot be written.
pub fn write(manifest: &Value, path: &Path) -> Result<(), RunError> {
    let err = |e: std::io::Error| RunError(format!("error: --manifest: cannot write {}: {e}", path.display()));
    let tmp = path.with_extension(format!("json.tmp{}", std::process::id()));
    std::fs::write(&tmp, format!("{manifest:#}\n")).map_err(err)?;
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        err(e)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sha256_matches_the_standard_test_vector() {
        // FIPS 180-2, appendix B.1: SHA-256("abc").
        assert_eq!(sha256(b"abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    }
}
