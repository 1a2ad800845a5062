//! The files a `.gltf` refers to: its buffers that are not embedded (`data:` URIs) and so live
//! beside it, usually one `.bin`, and its images (textures). A manifest hashes the buffers with
//! the `.gltf` (the model is both), a run that loads a `.gltf` records them as files it read,
//! and `blocksmith view` of a `.gltf` shows it again when any of them is saved.

use std::path::{Component, Path, PathBuf};

use blocksmith_kernel::io::uri::percent_decode;

/// The buffer files of the `.gltf` at `path`, in the order its `buffers` list them: each URI
/// percent-decoded and taken relative to the file's folder. URIs that leave the folder
/// (absolute, `..`) are skipped, as the reader refuses them. Empty when the file cannot be
/// read or is not glTF JSON.
#[must_use]
pub fn buffer_files(path: &Path) -> Vec<PathBuf> {
    referred(path, "buffers")
}

/// The image files (textures) of the `.gltf` at `path`, as [`buffer_files`] lists buffers.
#[must_use]
pub fn image_files(path: &Path) -> Vec<PathBuf> {
    referred(path, "images")
}

/// The files the `uri`s of the `.gltf`'s array `list` name, as [`buffer_files`] describes.
fn referred(path: &Path, list: &str) -> Vec<PathBuf> {
    let Ok(text) = std::fs::read(path) else { return Vec::new() };
    let Ok(doc) = serde_json::from_slice::<serde_json::Value>(&text) else { return Vec::new() };
    let dir = path.parent().unwrap_or(Path::new(""));
    let entries = doc[list].as_array().cloned().unwrap_or_default();
    entries
        .iter()
        .filter_map(|b| b["uri"].as_str())
        .filter(|uri| !uri.starts_with("data:"))
        // Decoded as the loader decodes them (one decoder, the kernel's): a URI that does not
        // decode to UTF-8 names no file the loader would read.
        .filter_map(|uri| percent_decode(uri).ok())
        .map(PathBuf::from)
        .filter(|p| p.components().all(|c| matches!(c, Component::Normal(_) | Component::CurDir)))
        .map(|p| dir.join(p))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn buffers_beside_the_file_are_listed_and_embedded_or_escaping_ones_are_not() {
        let dir = tempfile::tempdir().unwrap();
        let gltf = dir.path().join("m.gltf");
        let doc = r#"{"buffers": [{"uri": "m%20data.bin"}, {"uri": "data:application/octet-stream;base64,AAAA"},
                     {"uri": "../outside.bin"}, {"uri": "/etc/passwd"}, {"uri": "sub/b.bin"}]}"#;
        std::fs::write(&gltf, doc).unwrap();
        assert_eq!(buffer_files(&gltf), [dir.path().join("m data.bin"), dir.path().join("sub/b.bin")]);
        std::fs::write(&gltf, "not json").unwrap();
        assert!(buffer_files(&gltf).is_empty());
    }

    #[test]
    fn images_are_listed_as_buffers_are_and_neither_list_takes_the_other() {
        let dir = tempfile::tempdir().unwrap();
        let gltf = dir.path().join("m.gltf");
        let doc = r#"{"buffers": [{"uri": "m.bin"}], "images": [{"uri": "wood%20grain.png"}, {"bufferView": 0},
                     {"uri": "data:image/png;base64,AAAA"}, {"uri": "../up.png"}]}"#;
        std::fs::write(&gltf, doc).unwrap();
        assert_eq!(image_files(&gltf), [dir.path().join("wood grain.png")]);
        assert_eq!(buffer_files(&gltf), [dir.path().join("m.bin")]);
    }
}
