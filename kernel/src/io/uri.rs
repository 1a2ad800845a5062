//! Where a file may point to other files: a glTF's buffer URIs, resolved only to what the file
//! may name — its own GLB chunk, a `data:` URI, or a regular file inside the glTF's own folder —
//! and read only up to the declared length.
//!
//! A URI is relative-reference text (RFC 3986 §4.2): it is percent-decoded ([`percent_decode`]),
//! then refused when it has a scheme other than `data:` (`file:`, `http:`…), is absolute
//! (`/etc/passwd`, `\\x`, `C:`), or has a `..` segment; the resolved file must then lie inside the
//! folder once symbolic links are followed (a link pointing out is refused), and be a regular file
//! (no device, FIFO or folder) at least as long as the buffer's `byteLength`, of which exactly that
//! many bytes are read (glTF 2.0 §3.6.1.1, §3.6.1.2: "byteLength … the length of the buffer").

use std::fs::File;
use std::io::Read;
use std::path::{Component, Path, PathBuf};
use std::string::FromUtf8Error;

use super::IoError;

/// The bytes of every buffer of `doc`, by buffer index, each exactly its declared length
/// (padded with zeros to a multiple of 4, as the gltf crate's reader expects).
///
/// `base` is the glTF's folder (`None` when read from bytes: only embedded buffers and `data:`
/// URIs then); `blob` is the GLB's binary chunk.
///
/// # Errors
/// [`IoError::Gltf`] naming the buffer: a refused URI (see the module), a missing or short
/// file or chunk (naming the buffer's file), an unreadable file, an invalid `data:` URI.
pub(crate) fn read_buffers(
    doc: &gltf::Document,
    base: Option<&Path>,
    blob: Option<Vec<u8>>,
    path: &Path,
) -> Result<Vec<Vec<u8>>, IoError> {
    let mut blob = blob;
    let mut out = Vec::with_capacity(doc.buffers().len());
    for buffer in doc.buffers() {
        let len = buffer.length();
        let fail = |reason: String| IoError::Gltf {
            path: path.into(),
            reason: format!("buffer {}: {reason}", buffer.index()),
        };
        let mut data = match buffer.source() {
            gltf::buffer::Source::Bin => {
                let mut b = blob.take().ok_or_else(|| fail("the GLB has no binary chunk".into()))?;
                if b.len() < len {
                    return Err(fail(format!("the binary chunk has {} bytes, the buffer declares {len}", b.len())));
                }
                b.truncate(len);
                b
            }
            gltf::buffer::Source::Uri(uri) => {
                let b = if let Some(rest) = strip_prefix_ignore_case(uri, "data:") {
                    decode_data_uri(rest).map_err(&fail)?
                } else {
                    let file = resolve(base, uri).map_err(&fail)?;
                    // The error is about the .gltf being loaded (its message starts with that
                    // path) and names the buffer file it could not get.
                    read_exactly(&file, len as u64).map_err(|e| match e {
                        ReadError::Io(e) if e.kind() == std::io::ErrorKind::NotFound => {
                            fail(format!("its file {} is not found", file.display()))
                        }
                        ReadError::Io(e) => fail(format!("cannot read its file {}: {e}", file.display())),
                        ReadError::Reason(r) => fail(format!("{}: {r}", file.display())),
                    })?
                };
                if b.len() < len {
                    return Err(fail(format!("the data URI holds {} bytes, the buffer declares {len}", b.len())));
                }
                b
            }
        };
        data.truncate(len);
        data.resize(len.div_ceil(4) * 4, 0);
        out.push(data);
    }
    Ok(out)
}

fn strip_prefix_ignore_case<'a>(s: &'a str, prefix: &str) -> Option<&'a str> {
    let head = s.get(..prefix.len())?;
    head.eq_ignore_ascii_case(prefix).then(|| &s[prefix.len()..])
}

/// The file inside `base` that the relative URI `uri` names.
///
/// # Errors
/// The reason it is refused (see the module).
pub(crate) fn resolve(base: Option<&Path>, uri: &str) -> Result<PathBuf, String> {
    let shown = format!("{uri:.80}");
    let decoded = percent_decode(uri).map_err(|_| format!("the URI {shown} does not decode to UTF-8"))?;
    // A scheme is letters, digits, `+ - .` before the first `:` (RFC 3986 §3.1); a one-letter
    // one is a Windows drive.
    if let Some((scheme, _)) = uri.split_once(':') {
        if !scheme.is_empty()
            && scheme.chars().all(|c| c.is_ascii_alphanumeric() || "+-.".contains(c))
            && !scheme.contains('/')
        {
            return Err(format!(
                "the URI {shown} has the scheme `{scheme}:`; only relative file names and data: URIs are read"
            ));
        }
    }
    let relative = Path::new(&decoded);
    if decoded.starts_with('/') || decoded.starts_with('\\') || relative.is_absolute() {
        return Err(format!("the URI {shown} is an absolute path; only files in the glTF's folder are read"));
    }
    if decoded.contains('\0') {
        return Err(format!("the URI {shown} holds a NUL byte"));
    }
    for c in relative.components() {
        match c {
            Component::Normal(_) | Component::CurDir => {}
            Component::ParentDir => {
                return Err(format!("the URI {shown} leaves the glTF's folder (`..`); only files in it are read"))
            }
            Component::RootDir | Component::Prefix(_) => {
                return Err(format!("the URI {shown} is an absolute path; only files in the glTF's folder are read"))
            }
        }
    }
    let base = base.ok_or_else(|| format!("the URI {shown} names an external file, which needs a folder"))?;
    let base = if base.as_os_str().is_empty() { Path::new(".") } else { base };
    let joined = base.join(relative);
    // Symbolic links may point anywhere: compare the real paths.
    let (real_base, real) = match (base.canonicalize(), joined.canonicalize()) {
        (Ok(b), Ok(f)) => (b, f),
        // Missing: reported by the read as not found, naming the file.
        _ => return Ok(joined),
    };
    if !real.starts_with(&real_base) {
        return Err(format!(
            "the URI {shown} leads out of the glTF's folder through a symbolic link (to {}); only files in it are read",
            real.display()
        ));
    }
    Ok(real)
}

/// Decodes the percent escapes of `text` (RFC 3986 §2.1): each `%` followed by two hexadecimal
/// digits (either case) stands for the byte they spell; everything else, a `%` without two
/// hexadecimal digits after it included, is kept as it is. `+` stays `+` (a space only in HTML
/// forms, not in URIs).
///
/// # Errors
/// When the decoded bytes are not UTF-8 (`%FF`, half of a two-byte character): the
/// [`FromUtf8Error`], whose [`FromUtf8Error::as_bytes`] are the decoded bytes, for a caller that
/// wants a lossy reading (`String::from_utf8_lossy`).
///
/// ```
/// use blocksmith_kernel::io::uri::percent_decode;
///
/// assert_eq!(percent_decode("my%20model%2Ebin").unwrap(), "my model.bin");
/// assert_eq!(percent_decode("100%").unwrap(), "100%");
/// assert!(percent_decode("%FF").is_err());
/// ```
pub fn percent_decode(text: &str) -> Result<String, FromUtf8Error> {
    let hex = |b: u8| char::from(b).to_digit(16);
    let bytes = text.as_bytes();
    let mut decoded = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if let (b'%', Some(&[hi, lo])) = (bytes[i], bytes.get(i + 1..i + 3)) {
            if let (Some(hi), Some(lo)) = (hex(hi), hex(lo)) {
                decoded.push((hi * 16 + lo) as u8);
                i += 3;
                continue;
            }
        }
        decoded.push(bytes[i]);
        i += 1;
    }
    String::from_utf8(decoded)
}

/// Why [`read_exactly`] failed: the file system's error, or a file that is not what it must be.
pub(crate) enum ReadError {
    Io(std::io::Error),
    Reason(String),
}

/// The first `len` bytes of the regular file at `path`, which must hold at least that many.
/// The size is checked before reading, so a device or a growing file cannot make it read more.
pub(crate) fn read_exactly(path: &Path, len: u64) -> Result<Vec<u8>, ReadError> {
    let file = File::open(path).map_err(ReadError::Io)?;
    let size = regular_size(&file)?;
    if size < len {
        return Err(ReadError::Reason(format!("the file has {size} bytes, the buffer declares {len}")));
    }
    let mut data = Vec::new();
    data.try_reserve_exact(len as usize).map_err(|_| ReadError::Reason(format!("cannot hold {len} bytes")))?;
    file.take(len).read_to_end(&mut data).map_err(ReadError::Io)?;
    if (data.len() as u64) < len {
        return Err(ReadError::Reason(format!("the file ended after {} of {len} bytes", data.len())));
    }
    Ok(data)
}

/// The whole regular file at `path`, refused when its size is over the memory budget.
pub(crate) fn read_regular(path: &Path) -> Result<Vec<u8>, ReadError> {
    let file = File::open(path).map_err(ReadError::Io)?;
    let size = regular_size(&file)?;
    crate::limits::check_memory(|| format!("the file's {size} bytes"), size as f64)
        .map_err(|e| ReadError::Reason(e.to_string()))?;
    let mut data = Vec::new();
    data.try_reserve_exact(size as usize).map_err(|_| ReadError::Reason(format!("cannot hold {size} bytes")))?;
    file.take(size).read_to_end(&mut data).map_err(ReadError::Io)?;
    Ok(data)
}

impl ReadError {
    /// The [`IoError`] of a failed read of `path`.
    pub(crate) fn into_io(self, path: &Path) -> IoError {
        match self {
            ReadError::Io(e) => IoError::from_read(path, e),
            ReadError::Reason(r) => {
                IoError::Read { path: path.into(), source: std::io::Error::new(std::io::ErrorKind::InvalidData, r) }
            }
        }
    }
}

fn regular_size(file: &File) -> Result<u64, ReadError> {
    let meta = file.metadata().map_err(ReadError::Io)?;
    if !meta.is_file() {
        return Err(ReadError::Reason("not a regular file (a folder, device or pipe)".into()));
    }
    Ok(meta.len())
}

/// The bytes of a `data:` URI after the `data:` (RFC 2397): `[mediatype];base64,DATA`.
fn decode_data_uri(rest: &str) -> Result<Vec<u8>, String> {
    let (head, data) = rest.split_once(',').ok_or("the data: URI has no `,`")?;
    if !head.to_ascii_lowercase().ends_with(";base64") {
        return Err("the data: URI is not base64-encoded (glTF 2.0 §3.6.1.2)".into());
    }
    decode_base64(data.trim_end_matches('=')).ok_or_else(|| "the data: URI is not valid base64".into())
}

/// Standard base64 (RFC 4648 §4) without the padding.
fn decode_base64(text: &str) -> Option<Vec<u8>> {
    let value = |c: u8| -> Option<u32> {
        Some(match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return None,
        } as u32)
    };
    let bytes = text.as_bytes();
    if bytes.len() % 4 == 1 {
        return None;
    }
    let mut out = Vec::with_capacity(bytes.len() / 4 * 3 + 2);
    for chunk in bytes.chunks(4) {
        let mut acc = 0u32;
        for (i, &c) in chunk.iter().enumerate() {
            acc |= value(c)? << (18 - 6 * i);
        }
        let n = chunk.len() - 1;
        out.extend_from_slice(&acc.to_be_bytes()[1..1 + n]);
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_decodes_every_padding_length() {
        assert_eq!(decode_base64("TWFu").unwrap(), b"Man");
        assert_eq!(decode_base64("TWE").unwrap(), b"Ma");
        assert_eq!(decode_base64("TQ").unwrap(), b"M");
        assert_eq!(decode_base64("").unwrap(), b"");
        assert!(decode_base64("TWFuT").is_none() && decode_base64("T*Fu").is_none());
        assert_eq!(decode_data_uri("application/octet-stream;base64,AAAAAA==").unwrap(), vec![0; 4]);
        assert!(decode_data_uri("text/plain,abc").is_err());
    }

    #[test]
    fn uris_leaving_the_folder_are_refused_whatever_their_spelling() {
        let dir = tempfile::tempdir().unwrap();
        for uri in [
            "../../etc/passwd",
            "/etc/passwd",
            "file:///etc/passwd",
            "FILE:/etc/passwd",
            "http://example.com/x.bin",
            "%2Fetc%2Fpasswd",
            "a/../../x.bin",
            "%2e%2e/x.bin",
            "C:/x.bin",
            "\\\\server\\share\\x.bin",
        ] {
            let e = resolve(Some(dir.path()), uri).unwrap_err();
            assert!(e.contains("only"), "{uri}: {e}");
        }
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        std::fs::write(dir.path().join("sub/b.bin"), b"1234").unwrap();
        assert!(resolve(Some(dir.path()), "sub/b.bin").unwrap().ends_with("sub/b.bin"));
        assert!(resolve(Some(dir.path()), "./sub/%62.bin").unwrap().ends_with("sub/b.bin"));
    }

    #[test]
    fn escapes_decode_in_either_case_and_invalid_ones_stay_as_they_are() {
        assert_eq!(percent_decode("a%2fb%2Fc%20d").unwrap(), "a/b/c d");
        assert_eq!(percent_decode("%C3%A9t%c3%a9").unwrap(), "été");
        // Not two hexadecimal digits after the `%` (a sign is not a digit, `+` is not a space):
        // nothing is decoded there.
        for kept in ["%", "100%", "%2", "a%2", "%zz", "%g0", "%+1", "%-1", "% 1", "1+1", "%%41"] {
            let want = kept.replace("%%41", "%A");
            assert_eq!(percent_decode(kept).unwrap(), want, "{kept}");
        }
        // A multi-byte character right after an unfinished escape is not split.
        assert_eq!(percent_decode("%é").unwrap(), "%é");
        assert_eq!(percent_decode("").unwrap(), "");
    }

    #[test]
    fn escapes_that_do_not_make_utf8_are_an_error_holding_the_bytes() {
        // 0xFF is never UTF-8; 0xC3 starts a two-byte character that does not follow.
        for (text, bytes) in [("%FF", &b"\xFF"[..]), ("a%C3", b"a\xC3"), ("%C3x", b"\xC3x"), ("%80", b"\x80")] {
            let e = percent_decode(text).unwrap_err();
            assert_eq!(e.as_bytes(), bytes, "{text}");
        }
    }

    #[test]
    fn a_uri_not_decoding_to_utf8_is_refused() {
        let e = resolve(Some(Path::new(".")), "a%ffb.bin").unwrap_err();
        assert!(e.contains("UTF-8"), "{e}");
    }

    #[test]
    fn load_reads_a_gltf_buffer_only_inside_its_folder() {
        // A saved .gltf whose buffer URI is rewritten to point out of its folder, at a file
        // holding the same bytes: the load must fail instead of reading it.
        let dir = tempfile::tempdir().unwrap();
        let sub = dir.path().join("sub");
        std::fs::create_dir(&sub).unwrap();
        let path = sub.join("m.gltf");
        crate::io::save(&crate::Mesh::cube(1.0), &path).unwrap();
        // The buffer is `m.HASH.bin` (see `save_gltf_pair`).
        let name = std::fs::read_dir(&sub)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .find(|n| n.ends_with(".bin"))
            .unwrap();
        std::fs::copy(sub.join(&name), dir.path().join("secret.bin")).unwrap();
        let json = std::fs::read_to_string(&path).unwrap().replace(&format!("\"{name}\""), "\"m.bin\"");
        std::fs::rename(sub.join(&name), sub.join("m.bin")).unwrap();
        std::fs::write(&path, &json).unwrap();
        assert!(crate::io::load(&path).is_ok());
        let outside = dir.path().join("secret.bin").display().to_string();
        for uri in ["../secret.bin", outside.as_str(), &format!("file://{outside}"), "sub/../../secret.bin"] {
            std::fs::write(&path, json.replace("\"m.bin\"", &format!("{uri:?}"))).unwrap();
            let e = crate::io::load(&path).unwrap_err();
            assert!(matches!(e, IoError::Gltf { .. }) && e.to_string().contains("buffer 0: the URI"), "{uri}: {e}");
        }
        // A data: URI is read, and a short one refused.
        let bin = std::fs::read(sub.join("m.bin")).unwrap();
        let data = format!("data:application/octet-stream;base64,{}", encode_base64(&bin));
        std::fs::write(&path, json.replace("\"m.bin\"", &format!("{data:?}"))).unwrap();
        assert_eq!(crate::io::load(&path).unwrap().face_count(), 6);
        let short = format!("data:application/octet-stream;base64,{}", encode_base64(&bin[..bin.len() - 4]));
        std::fs::write(&path, json.replace("\"m.bin\"", &format!("{short:?}"))).unwrap();
        assert!(crate::io::load(&path).unwrap_err().to_string().contains("the buffer declares"));
    }

    fn encode_base64(bytes: &[u8]) -> String {
        const A: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        let mut s = String::new();
        for c in bytes.chunks(3) {
            let n = (c[0] as u32) << 16 | (*c.get(1).unwrap_or(&0) as u32) << 8 | *c.get(2).unwrap_or(&0) as u32;
            for i in 0..=c.len() {
                s.push(A[(n >> (18 - 6 * i) & 63) as usize] as char);
            }
        }
        s
    }

    #[cfg(unix)]
    #[test]
    fn a_symbolic_link_out_of_the_folder_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        std::os::unix::fs::symlink("/etc/hostname", dir.path().join("out.bin")).unwrap();
        let e = resolve(Some(dir.path()), "out.bin").unwrap_err();
        assert!(e.contains("symbolic link"), "{e}");
    }

    #[cfg(unix)]
    #[test]
    fn a_device_is_not_read_and_reads_stop_at_the_declared_length() {
        // /dev/zero never ends: refused before any read, not read until memory runs out.
        assert!(matches!(read_exactly(Path::new("/dev/zero"), 48), Err(ReadError::Reason(r)) if r.contains("regular")));
        assert!(matches!(read_regular(Path::new("/dev/zero")), Err(ReadError::Reason(_))));
        let dir = tempfile::tempdir().unwrap();
        let f = dir.path().join("b.bin");
        std::fs::write(&f, [7u8; 100]).unwrap();
        assert_eq!(read_exactly(&f, 48).ok().unwrap().len(), 48);
        assert!(matches!(read_exactly(&f, 101), Err(ReadError::Reason(r)) if r.contains("100 bytes")));
        assert_eq!(read_regular(&f).ok().unwrap().len(), 100);
        let e = crate::io::load("/dev/zero/x.obj").unwrap_err();
        assert!(matches!(e, IoError::Read { .. } | IoError::NotFound { .. }), "{e}");
    }
}
