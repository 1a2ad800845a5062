//! `KHR_draco_mesh_compression`: a glTF primitive whose geometry is a Draco bitstream in a
//! buffer view (the extension's specification, §"Decoding"), decoded with `draco-core`, a pure
//! Rust decoder that reads what Google's Draco 1.5 writes (edgebreaker and sequential
//! connectivity, quantized and predicted attributes).
//!
//! Only what blocksmith keeps is taken: the positions (the attribute whose unique id the
//! extension maps to `POSITION`, dequantized to `f32` as the bitstream stores them) and the
//! triangles. The decoder is held to the memory budget before it allocates: the decoded faces
//! and attribute bytes may not pass what the budget has left beside the heap in use.

use draco_core::{DecodeLimits, DecoderBuffer, MeshDecoder};

/// The decoded geometry of one primitive: positions (file axes, `f32` widened) and triangle
/// indices into them.
pub(crate) struct Decoded {
    pub positions: Vec<[f32; 3]>,
    pub indices: Vec<u32>,
}

/// The extension object of a primitive: its buffer view and the unique id of its `POSITION`.
pub(crate) struct DracoPrimitive {
    pub buffer_view: usize,
    pub position_id: u32,
}

/// Reads the `KHR_draco_mesh_compression` object of a primitive's `extensions`, if present.
///
/// # Errors
/// A reason when the object is present but lacks its buffer view or `POSITION` id.
pub(crate) fn extension_of(
    others: &serde_json::Map<String, serde_json::Value>,
) -> Result<Option<DracoPrimitive>, String> {
    let Some(ext) = others.get("KHR_draco_mesh_compression") else { return Ok(None) };
    let index = |v: Option<&serde_json::Value>| v.and_then(serde_json::Value::as_u64);
    let buffer_view = index(ext.get("bufferView"))
        .and_then(|v| usize::try_from(v).ok())
        .ok_or("its KHR_draco_mesh_compression has no bufferView")?;
    let position_id = index(ext.get("attributes").and_then(|a| a.get("POSITION")))
        .and_then(|v| u32::try_from(v).ok())
        .ok_or("its KHR_draco_mesh_compression names no POSITION attribute")?;
    Ok(Some(DracoPrimitive { buffer_view, position_id }))
}

/// Decodes the Draco bitstream `bytes` of a primitive, taking the attribute of unique id
/// `position_id` as positions.
///
/// # Errors
/// A reason naming what is wrong: the bitstream does not decode (or is a point cloud), it
/// decodes to more than the memory budget allows, it has no such attribute or the attribute
/// is not three components.
pub(crate) fn decode(bytes: &[u8], position_id: u32) -> Result<Decoded, String> {
    // A face is 12 bytes decoded and about as much again in the decoder's tables; attribute
    // values are counted by the decoder itself. The room is what the budget has left beside
    // the heap in use (the primitives already decoded among it), so a file of many Draco
    // primitives is held to the budget as a whole, not each primitive to all of it.
    let in_use = crate::limits::heap_in_use().unwrap_or(0);
    let budget = crate::limits::memory_limit().saturating_sub(in_use);
    if budget == 0 {
        return Err(format!(
            "its Draco data cannot be decoded: the memory budget ({}) is already in use",
            crate::limits::human_bytes(crate::limits::memory_limit())
        ));
    }
    let limits = DecodeLimits::default()
        .with_max_faces(budget / 32)
        .with_max_points(budget / 32)
        .with_max_decoded_bytes(budget / 2);
    let mut buffer = DecoderBuffer::new(bytes).with_limits(limits);
    let mut mesh = draco_core::Mesh::new();
    MeshDecoder::new().decode(&mut buffer, &mut mesh).map_err(|e| format!("its Draco data does not decode ({e})"))?;
    if mesh.num_faces() == 0 {
        return Err("its Draco data holds no triangles (a point cloud)".into());
    }
    let att = mesh
        .attribute_by_unique_id(position_id)
        .ok_or_else(|| format!("its Draco data has no attribute {position_id}, which the extension names POSITION"))?;
    if att.num_components() != 3 {
        return Err(format!("its Draco POSITION has {} components (3 expected)", att.num_components()));
    }
    let n = mesh.num_points();
    let flat = att.read_f32s(n, 3);
    let positions: Vec<[f32; 3]> = flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    let mut indices = Vec::with_capacity(3 * mesh.num_faces());
    for f in mesh.faces() {
        for p in f {
            if p.0 as usize >= n {
                return Err(format!("its Draco data names point {} of {n}", p.0));
            }
            indices.push(p.0);
        }
    }
    Ok(Decoded { positions, indices })
}

#[cfg(test)]
mod tests {
    use std::path::{Path, PathBuf};

    use crate::io::{load, load_with, IoError, LoadOptions, Weld};
    use crate::math::Vec3;

    fn corpus(name: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/files").join(name)
    }

    /// The corpus's Draco sphere with its JSON edited by `edit` and its Draco data by `data`.
    fn edited(edit: impl FnOnce(&mut serde_json::Value), data: impl FnOnce(&mut Vec<u8>)) -> Vec<u8> {
        let glb = std::fs::read(corpus("draco_sphere.glb")).unwrap();
        let len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
        let mut doc: serde_json::Value = serde_json::from_slice(&glb[20..20 + len]).unwrap();
        let mut bin = glb[20 + len + 8..].to_vec();
        edit(&mut doc);
        data(&mut bin);
        doc["buffers"][0]["byteLength"] = bin.len().into();
        let mut text = serde_json::to_vec(&doc).unwrap();
        text.resize(text.len().next_multiple_of(4), b' ');
        bin.resize(bin.len().next_multiple_of(4), 0);
        let mut out = b"glTF".to_vec();
        out.extend(2u32.to_le_bytes());
        out.extend(((12 + 8 + text.len() + 8 + bin.len()) as u32).to_le_bytes());
        out.extend((text.len() as u32).to_le_bytes());
        out.extend(b"JSON");
        out.extend(text);
        out.extend((bin.len() as u32).to_le_bytes());
        out.extend(b"BIN\0");
        out.extend(bin);
        out
    }

    fn read(bytes: &[u8]) -> Result<crate::mesh::Mesh, IoError> {
        crate::io::gltf::read_gltf(bytes, None, Path::new("draco.glb"))
    }

    #[test]
    fn googles_draco_sphere_decodes_upright_and_welds_closed() {
        // An icosphere of radius 1.5 about glTF (10, −20, 5), i.e. kernel (10, −5, −20),
        // positions quantized to 14 bits over its 3-unit extent (steps of 1.8e-4).
        for name in ["draco_sphere.glb", "draco_sequential.glb"] {
            let m = load(corpus(name)).unwrap();
            assert!(m.is_closed() && m.is_manifold(), "{name}");
            assert_eq!((m.vertex_count(), m.face_count()), (162, 320), "{name}");
            assert!((m.bounds().center() - Vec3::new(10.0, -5.0, -20.0)).length() < 1e-3, "{name}");
            for p in m.positions() {
                let r = (*p - Vec3::new(10.0, -5.0, -20.0)).length();
                assert!((r - 1.5).abs() < 1e-3, "{name}: radius {r}");
            }
        }
        // Draco keeps one point per attribute combination: without welding the edgebreaker
        // file still reads, with as many vertices as the decoder gives.
        let raw = load_with(corpus("draco_sphere.glb"), &LoadOptions::DEFAULT.with_weld(Weld::Off)).unwrap();
        assert!(raw.vertex_count() >= 162);
    }

    #[test]
    fn the_extensions_attribute_map_is_honoured() {
        // The encoder numbered the normals 0 and the positions 1 (as the file says); POSITION
        // mapped to the normals' attribute gives the unit sphere about the origin.
        let sphere = std::fs::read(corpus("draco_sphere.glb")).unwrap();
        assert!(String::from_utf8_lossy(&sphere).contains(r#""attributes":{"POSITION":1,"NORMAL":0}"#));
        let bytes = edited(
            |d| {
                d["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["attributes"]["POSITION"] =
                    0.into()
            },
            |_| {},
        );
        let m = read(&bytes).unwrap();
        assert!(m.positions().iter().all(|p| (p.length() - 1.0).abs() < 1e-2), "{:?}", m.positions()[0]);
        // An id the data does not have.
        let bytes = edited(
            |d| {
                d["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["attributes"]["POSITION"] =
                    7.into()
            },
            |_| {},
        );
        let e = read(&bytes).unwrap_err();
        assert!(matches!(e, IoError::Gltf { .. }) && e.to_string().contains("no attribute 7"), "{e}");
    }

    #[test]
    fn broken_draco_data_is_a_gltf_error_naming_the_primitive() {
        // Cut short, and with its header overwritten: errors, never a panic.
        let cut = edited(|d| d["bufferViews"][0]["byteLength"] = 40.into(), |_| {});
        let garbage = edited(|_| {}, |b| b[..16].copy_from_slice(b"DRACO\x02\x02\x01\x01\x00\x00\xff\xff\xff\xff\xff"));
        let missing = edited(
            |d| d["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["bufferView"] = 9.into(),
            |_| {},
        );
        for bytes in [cut, garbage, missing] {
            let e = read(&bytes).unwrap_err();
            assert!(matches!(e, IoError::Gltf { .. }), "{e}");
            let text = e.to_string();
            assert!(text.starts_with("draco.glb: ") && text.contains("mesh 0 primitive 0: its Draco"), "{e}");
        }
        // Every truncation of the bitstream: an error or a mesh, never a panic.
        let glb = std::fs::read(corpus("draco_sequential.glb")).unwrap();
        let len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
        let drc = &glb[20 + len + 8 + 8..];
        for n in 0..drc.len().min(400) {
            let _ = super::decode(&drc[..n], 0);
        }
    }
}
