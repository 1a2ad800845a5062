//! The page's files, embedded in the binary (`script/web/`): the studio works offline on a
//! fresh machine. Only these exact paths are served; nothing is read from disk.

/// A file of the page: its URL path, media type and bytes.
pub struct Asset {
    pub path: &'static str,
    pub media_type: &'static str,
    pub bytes: &'static [u8],
}

macro_rules! assets {
    ($(($path:literal, $media:expr)),* $(,)?) => {
        &[$(Asset { path: $path, media_type: $media, bytes: include_bytes!(concat!("../web", $path)) }),*]
    };
}

const JS: &str = "text/javascript; charset=utf-8";

/// Every file of the page; `/` is `index.html`.
pub const ASSETS: &[Asset] = assets![
    ("/index.html", "text/html; charset=utf-8"),
    ("/studio.css", "text/css; charset=utf-8"),
    ("/app.js", JS),
    ("/viewer.js", JS),
    ("/measure.js", JS),
    ("/defects.js", JS),
    ("/fit.js", JS),
    ("/controls.js", JS),
    ("/connection.js", JS),
    ("/vendor/three/three.module.js", JS),
    ("/vendor/three/three.core.js", JS),
    ("/vendor/three/jsm/controls/OrbitControls.js", JS),
    ("/vendor/three/jsm/loaders/GLTFLoader.js", JS),
    ("/vendor/three/jsm/utils/BufferGeometryUtils.js", JS),
    ("/vendor/three/jsm/utils/SkeletonUtils.js", JS),
    ("/vendor/three/LICENSE", "text/plain; charset=utf-8"),
];

/// The asset at URL path `path` (exact match; `/` is the page).
#[must_use]
pub fn find(path: &str) -> Option<&'static Asset> {
    let path = if path == "/" { "/index.html" } else { path };
    ASSETS.iter().find(|a| a.path == path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_page_and_its_modules_are_embedded_and_only_they_are_found() {
        assert!(find("/").unwrap().bytes.starts_with(b"<!doctype html>"));
        assert!(find("/vendor/three/three.core.js").unwrap().bytes.len() > 1_000_000);
        assert!(ASSETS.iter().filter(|a| a.media_type.starts_with("text/javascript")).all(|a| a.media_type == JS));
        for bad in ["/../Cargo.toml", "/vendor/three/../../Cargo.toml", "//etc/passwd", "/index.html/", ""] {
            assert!(find(bad).is_none(), "{bad}");
        }
    }
}
