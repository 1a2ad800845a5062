//! Small files that declare huge costs (issue 33) are refused by the memory budget before
//! anything is reserved, or finish in time: a glTF's sparse accessor and its instance count,
//! an OBJ's long faces written as STL. Its own test binary: the budget (128 MiB here, as
//! `--memory-limit 128M`) is process-wide.

use std::path::Path;
use std::time::Instant;

use blocksmith_kernel::io::gltf::read_gltf;
use blocksmith_kernel::limits::set_memory_limit;

/// A GLB of the JSON `json` and the binary chunk `bin`.
fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let mut j = json.as_bytes().to_vec();
    j.resize(j.len().div_ceil(4) * 4, b' ');
    let mut b = bin.to_vec();
    b.resize(b.len().div_ceil(4) * 4, 0);
    let total = 12 + 8 + j.len() + 8 + b.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(j.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&j);
    out.extend_from_slice(&(b.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&b);
    out
}

/// A one-triangle mesh (three positions in buffer view 0, no indices) instanced by `nodes`
/// nodes of the scene, 2 apart in x.
fn instanced_triangle(nodes: usize) -> Vec<u8> {
    // Each moved apart, so that the weld keeps them.
    let node_list: Vec<String> =
        (0..nodes).map(|i| format!("{{\"mesh\":0,\"translation\":[{},0,0]}}", 2 * i)).collect();
    let node_list = node_list.join(",");
    let scene: Vec<String> = (0..nodes).map(|i| i.to_string()).collect();
    let json = format!(
        "{{\"asset\":{{\"version\":\"2.0\"}},\"buffers\":[{{\"byteLength\":36}}],\
         \"bufferViews\":[{{\"buffer\":0,\"byteLength\":36}}],\
         \"accessors\":[{{\"bufferView\":0,\"componentType\":5126,\"type\":\"VEC3\",\"count\":3,\
         \"min\":[0,0,0],\"max\":[1,1,0]}}],\
         \"meshes\":[{{\"primitives\":[{{\"attributes\":{{\"POSITION\":0}}}}]}}],\
         \"nodes\":[{node_list}],\"scenes\":[{{\"nodes\":[{}]}}],\"scene\":0}}",
        scene.join(",")
    );
    let bin: Vec<u8> = [0f32, 0., 0., 1., 0., 0., 0., 1., 0.].iter().flat_map(|v| v.to_le_bytes()).collect();
    glb(&json, &bin)
}

/// A GLB whose one POSITION accessor has `count` elements, all zeros but for one sparse
/// substitution (no buffer view), its mesh instanced by `nodes` nodes.
fn sparse(count: usize, nodes: usize) -> Vec<u8> {
    let list = vec!["{\"mesh\":0}"; nodes].join(",");
    let roots: Vec<String> = (0..nodes).map(|i| i.to_string()).collect();
    let json = format!(
        "{{\"asset\":{{\"version\":\"2.0\"}},\"buffers\":[{{\"byteLength\":16}}],\
         \"bufferViews\":[{{\"buffer\":0,\"byteLength\":4}},{{\"buffer\":0,\"byteOffset\":4,\"byteLength\":12}}],\
         \"accessors\":[{{\"componentType\":5126,\"type\":\"VEC3\",\"count\":{count},\
         \"min\":[0,0,0],\"max\":[1,1,1],\"sparse\":{{\"count\":1,\
         \"indices\":{{\"bufferView\":0,\"componentType\":5125}},\"values\":{{\"bufferView\":1}}}}}}],\
         \"meshes\":[{{\"primitives\":[{{\"attributes\":{{\"POSITION\":0}}}}]}}],\
         \"nodes\":[{list}],\"scenes\":[{{\"nodes\":[{}]}}],\"scene\":0}}",
        roots.join(",")
    );
    let bin: Vec<u8> = [0u32.to_le_bytes(), 1f32.to_le_bytes(), 1f32.to_le_bytes(), 1f32.to_le_bytes()].concat();
    glb(&json, &bin)
}

#[test]
fn a_sparse_accessor_of_3e8_elements_is_refused_before_reserving() {
    // 520 bytes: a POSITION accessor of count 3·10⁸ with no buffer view, made of zeros but for
    // one sparse substitution. Reading reserved 7.2 GB for it and aborted.
    set_memory_limit(128 << 20);
    let bytes = sparse(300_000_000, 1);
    assert!(bytes.len() < 1024, "{}", bytes.len());
    let e = read_gltf(&bytes, None, Path::new("sparse.glb")).unwrap_err().to_string();
    assert!(e.contains("300000000 vertices") && e.contains("over the memory budget"), "{e}");
}

#[test]
fn instances_are_counted_against_the_budget_before_placing() {
    // 400,000 instances of one triangle: 1.2 million vertices, ~130 MB placed, welded and
    // built, over 128 MiB (it reached 440–492 MiB before). 1,000 instances are read.
    set_memory_limit(128 << 20);
    // Its JSON alone (800,000 objects and arrays: a node and its translation each) is refused
    // before parsing, which took ~430 MiB.
    let e = read_gltf(&instanced_triangle(400_000), None, Path::new("many.glb")).unwrap_err().to_string();
    assert!(e.contains("JSON of 800") && e.contains("over the memory budget"), "{e}");
    // 1,000 instances of a sparse mesh of 200,000 (zero) positions parse in little memory,
    // and what they would place — 2·10⁸ vertices — is refused before any is read.
    let e = read_gltf(&sparse(200_000, 1000), None, Path::new("many.glb")).unwrap_err().to_string();
    assert!(e.contains("1000 mesh instances") && e.contains("over the memory budget"), "{e}");
    let m = read_gltf(&instanced_triangle(1000), None, Path::new("few.glb")).unwrap();
    assert_eq!(m.face_count(), 1000);
}

#[test]
fn an_obj_of_two_20000_corner_faces_saves_as_stl() {
    // The disk of issue 33 (1.1 MB): a 20,000-gon star and its reverse. Its STL needs the
    // triangulation's fallback for the back face, which held k² triangles (an abort at 1.8 GB);
    // now a bounded number of O(k) fans, under the 128 MiB budget.
    set_memory_limit(128 << 20);
    let k = 20_000;
    let mut obj = String::new();
    for i in 0..k {
        let a = i as f64 * std::f64::consts::TAU / k as f64;
        let r = if i % 2 == 0 { 1.0 } else { 0.8 };
        obj.push_str(&format!("v {} {} 0\n", r * a.cos(), r * a.sin()));
    }
    let front: Vec<String> = (1..=k).map(|i| i.to_string()).collect();
    let back: Vec<String> = std::iter::once(1).chain((2..=k).rev()).map(|i| i.to_string()).collect();
    obj.push_str(&format!("f {}\nf {}\n", front.join(" "), back.join(" ")));
    let dir = tempfile::tempdir().unwrap();
    let (src, out) = (dir.path().join("disk.obj"), dir.path().join("disk.stl"));
    std::fs::write(&src, obj).unwrap();
    let m = blocksmith_kernel::io::load(&src).unwrap();
    assert_eq!((m.face_count(), m.vertex_count()), (2, k));
    let t = Instant::now();
    blocksmith_kernel::io::save(&m, &out).unwrap();
    assert!(t.elapsed().as_secs_f64() < 10.0, "{:?}", t.elapsed());
    // The front k − 2 triangles, the back cut about its centre: k more.
    let back_in = blocksmith_kernel::io::load(&out).unwrap();
    assert_eq!(back_in.face_count(), 2 * k - 2);
}
