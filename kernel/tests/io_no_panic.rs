//! The readers never panic: random byte strings and randomly damaged valid files (bytes
//! flipped, cut short, spans repeated) each give `Ok` or `Err`, for every format: OBJ, STL
//! (binary and ASCII), PLY (three encodings), glTF (GLB and JSON) and 3MF (the zip damaged, and
//! the model XML inside damaged then zipped again).
//!
//! The random source is the kernel's fixed-seed SplitMix64, so a failure reproduces. Set `IO_FUZZ_CASES` to
//! run more cases than the default 300 per input (e.g. 100000), and `IO_FUZZ_SEED` for other ones.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

use blocksmith_kernel::io::{gltf, obj, ply, stl, threemf, PlyEncoding};
use blocksmith_kernel::math::SplitMix64;
use blocksmith_kernel::{Mesh, Vec3};

fn random_bytes(rng: &mut SplitMix64, text_like: bool) -> Vec<u8> {
    let len = rng.below(300);
    (0..len)
        .map(|_| if text_like { b"vft0123456789 .-/#\nenaglTFsolid"[rng.below(31)] } else { rng.next_u64() as u8 })
        .collect()
}

fn damaged(rng: &mut SplitMix64, valid: &[u8]) -> Vec<u8> {
    let mut b = valid.to_vec();
    match rng.below(4) {
        0 => {
            for _ in 0..1 + rng.below(4) {
                let i = rng.below(b.len());
                b[i] = rng.next_u64() as u8;
            }
        }
        1 => b.truncate(rng.below(b.len())),
        2 => {
            let i = rng.below(b.len());
            let j = (i + rng.below(40)).min(b.len());
            let span = b[i..j].to_vec();
            b.splice(i..i, span);
        }
        _ => {
            // Damage a little-endian u32 somewhere (counts, lengths, indices).
            let i = rng.below(b.len().saturating_sub(4));
            let v = [0u32, 1, 3, 0xFFFF, 0xFFFF_FFFF, rng.next_u64() as u32][rng.below(6)];
            b[i..i + 4].copy_from_slice(&v.to_le_bytes());
        }
    }
    b
}

fn never_panics(name: &str, valid: &[u8], text_like: bool, read: impl Fn(&[u8]) -> bool) {
    let seed: u64 = std::env::var("IO_FUZZ_SEED").ok().and_then(|v| v.parse().ok()).unwrap_or(0x9E37_79B9_7F4A_7C15);
    let mut rng = SplitMix64::new(seed.wrapping_add(name.len() as u64));
    let cases: usize = std::env::var("IO_FUZZ_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(300);
    let mut accepted = 0;
    for i in 0..cases {
        let bytes = if i % 2 == 0 { random_bytes(&mut rng, text_like) } else { damaged(&mut rng, valid) };
        match catch_unwind(AssertUnwindSafe(|| read(&bytes))) {
            Ok(ok) => accepted += usize::from(ok),
            Err(_) => panic!("{name}: the reader panicked on case {i}: {:?}", String::from_utf8_lossy(&bytes)),
        }
    }
    // Sanity: the undamaged file reads.
    assert!(read(valid), "{name}: the valid file must read");
    eprintln!("{name}: {accepted} of {cases} junk inputs were accepted");
}

fn sample() -> Mesh {
    let mut m = Mesh::cylinder(1.0, 2.0, 6).translate(Vec3::new(0.5, 0.0, 0.0));
    m.crease_edges(&[[0, 1]]).unwrap();
    m.set_vertex_colors(Some(vec![[0.5, 0.25, 1.0, 1.0]; m.vertex_count()])).unwrap();
    m
}

#[test]
fn obj_reader_never_panics() {
    let mut valid = Vec::new();
    obj::write_obj(&sample(), &mut valid).unwrap();
    // Texture and normal indices too (tobj can overflow on those, so they must not reach it).
    let text = String::from_utf8(valid).unwrap().replacen(
        "\nf 1 2 8 7\n",
        "\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/-5/1 8//-7 7/0/0\n",
        1,
    );
    assert!(text.contains("vt 0 0"));
    let valid = text.into_bytes();
    let p = Path::new("fuzz.obj");
    never_panics("obj", &valid, true, |b| obj::read_obj(b, p).is_ok());
}

#[test]
fn stl_reader_never_panics() {
    let mut valid = Vec::new();
    stl::write_stl(&sample(), &mut valid, Path::new("fuzz.stl")).unwrap();
    let p = Path::new("fuzz.stl");
    never_panics("stl", &valid, false, |b| stl::read_stl(b, p).is_ok());
    let ascii = b"solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid\n";
    never_panics("ascii stl", ascii, true, |b| stl::read_stl(b, p).is_ok());
}

#[test]
fn ply_reader_never_panics() {
    let p = Path::new("fuzz.ply");
    for (enc, text_like) in
        [(PlyEncoding::Ascii, true), (PlyEncoding::BinaryLittleEndian, false), (PlyEncoding::BinaryBigEndian, false)]
    {
        let mut valid = Vec::new();
        ply::write_ply(&sample(), &mut valid, enc, p).unwrap();
        never_panics("ply", &valid, text_like, |b| ply::read_ply(b, p).is_ok());
    }
}

#[test]
fn gltf_reader_never_panics() {
    let mut glb = Vec::new();
    gltf::write_glb(&sample(), &mut glb, Path::new("fuzz.glb")).unwrap();
    let p = Path::new("fuzz.glb");
    never_panics("glb", &glb, false, |b| gltf::read_gltf(b, None, p).is_ok());
    // The JSON form with the buffer embedded as a data URI (damage hits the JSON text).
    let (json, bin) = gltf::gltf_json_and_buffer(&sample(), "x.bin", p).unwrap();
    let text = String::from_utf8(json)
        .unwrap()
        .replace("\"x.bin\"", &format!("\"data:application/octet-stream;base64,{}\"", base64(&bin.unwrap())));
    never_panics("gltf", text.as_bytes(), true, |b| gltf::read_gltf(b, None, p).is_ok());
}

fn base64(bytes: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for c in bytes.chunks(3) {
        let n =
            (u32::from(c[0]) << 16) | (u32::from(*c.get(1).unwrap_or(&0)) << 8) | u32::from(*c.get(2).unwrap_or(&0));
        for k in 0..4 {
            if k <= c.len() {
                out.push(A[(n >> (18 - 6 * k)) as usize & 63] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[test]
fn threemf_reader_never_panics() {
    let p = Path::new("fuzz.3mf");
    let mut valid = Vec::new();
    threemf::write_3mf(&sample(), &mut valid, p).unwrap();
    // The package itself damaged: the zip reader's errors.
    never_panics("3mf", &valid, false, |b| threemf::read_3mf(b, p).is_ok());
    // The model XML damaged inside an intact package: the model reader's errors.
    let parts = unzip(&valid);
    let model = parts.iter().position(|(n, _)| n.ends_with(".model")).unwrap();
    let xml = parts[model].1.clone();
    never_panics("3mf model", &xml, true, |b| {
        let mut parts = parts.clone();
        parts[model].1 = b.to_vec();
        threemf::read_3mf(&zip_stored(&parts), p).is_ok()
    });
}

fn unzip(bytes: &[u8]) -> Vec<(String, Vec<u8>)> {
    use std::io::Read;
    let mut z = zip::ZipArchive::new(std::io::Cursor::new(bytes)).unwrap();
    (0..z.len())
        .map(|i| {
            let mut f = z.by_index(i).unwrap();
            let mut data = Vec::new();
            f.read_to_end(&mut data).unwrap();
            (f.name().unwrap().to_string(), data)
        })
        .collect()
}

fn zip_stored(parts: &[(String, Vec<u8>)]) -> Vec<u8> {
    use std::io::Write;
    let mut w = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let o = zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Stored);
    for (name, data) in parts {
        w.start_file(name.as_str(), o).unwrap();
        w.write_all(data).unwrap();
    }
    w.finish().unwrap().into_inner()
}
