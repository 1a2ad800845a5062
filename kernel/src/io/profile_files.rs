//! 2D profile files by extension: `.svg` ([`svg`](super::svg)) and `.dxf` ([`dxf`](super::dxf)).

use std::path::Path;

use super::{dxf, svg, uri, write_atomic, IoError};
use crate::profile::{Font, Profile};

/// The 2D formats, as told by the extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProfileFormat {
    /// Scalable Vector Graphics, `.svg`.
    Svg,
    /// AutoCAD Drawing Exchange Format (ASCII), `.dxf`.
    Dxf,
}

impl ProfileFormat {
    /// The 2D format of `path` by its extension, case-insensitive.
    ///
    /// # Errors
    /// [`IoError::Unsupported`] naming the 2D extensions known.
    pub fn from_path(path: &Path) -> Result<ProfileFormat, IoError> {
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
        match ext.as_str() {
            "svg" => Ok(ProfileFormat::Svg),
            "dxf" => Ok(ProfileFormat::Dxf),
            _ => Err(IoError::Unsupported {
                path: path.into(),
                reason: format!("unknown 2D file extension {ext:?} (known: .svg, .dxf)"),
            }),
        }
    }
}

/// Reads the region drawn in the file at `path`, by extension: `.svg` or `.dxf`.
///
/// # Errors
/// [`IoError::Unsupported`] for another extension, [`IoError::NotFound`] / [`IoError::Read`],
/// then the format's errors ([`svg::read_svg`], [`dxf::read_dxf`]).
///
/// See also [`save_profile`].
pub fn load_profile(path: impl AsRef<Path>) -> Result<Profile, IoError> {
    let path = path.as_ref();
    let format = ProfileFormat::from_path(path)?;
    let bytes = uri::read_regular(path).map_err(|e| e.into_io(path))?;
    match format {
        ProfileFormat::Svg => svg::read_svg(&bytes, path),
        ProfileFormat::Dxf => dxf::read_dxf(&bytes, path),
    }
}

/// Reads the font (TrueType `.ttf` or OpenType `.otf`) in the file at `path` for
/// [`text`](crate::profile::text): a regular file, refused before reading when it is larger
/// than the memory budget.
///
/// # Errors
/// [`IoError::NotFound`] / [`IoError::Read`], or [`IoError::Unsupported`] when the bytes are
/// not a font.
pub fn load_font(path: impl AsRef<Path>) -> Result<Font, IoError> {
    let path = path.as_ref();
    let bytes = uri::read_regular(path).map_err(|e| e.into_io(path))?;
    Font::from_bytes(bytes).map_err(|e| IoError::Unsupported { path: path.into(), reason: e.to_string() })
}

/// Writes `profile` to the file at `path`, by extension: `.svg` or `.dxf`, atomically (a
/// failing save leaves the old file as it was).
///
/// # Errors
/// [`IoError::Unsupported`] for another extension, [`IoError::Write`] when the file cannot be
/// written.
///
/// See also [`load_profile`].
pub fn save_profile(profile: &Profile, path: impl AsRef<Path>) -> Result<(), IoError> {
    let path = path.as_ref();
    let format = ProfileFormat::from_path(path)?;
    write_atomic(path, |w| {
        match format {
            ProfileFormat::Svg => svg::write_svg(profile, w),
            ProfileFormat::Dxf => dxf::write_dxf(profile, w),
        }
        .map_err(|source| IoError::Write { path: path.into(), source })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::profile::Vec2;

    #[test]
    fn a_profile_saved_and_loaded_by_extension_is_the_same_region() {
        let dir = tempfile::tempdir().unwrap();
        let p = Profile::rect(Vec2::ZERO, Vec2::new(3.0, 2.0)).unwrap();
        for name in ["a.svg", "a.DXF"] {
            let path = dir.path().join(name);
            save_profile(&p, &path).unwrap();
            assert_eq!(load_profile(&path).unwrap().area(), 6.0, "{name}");
        }
        let e = save_profile(&p, dir.path().join("a.png")).unwrap_err();
        assert!(e.to_string().ends_with("unknown 2D file extension \"png\" (known: .svg, .dxf)"), "{e}");
        assert!(matches!(load_profile(dir.path().join("missing.svg")), Err(IoError::NotFound { .. })));
    }
}
