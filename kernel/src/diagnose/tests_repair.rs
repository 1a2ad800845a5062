//! Tests of the repair of non-manifold polygons and of the loaders that use it.

use super::{repair_polygons, RepairOptions};
use crate::io::{self, IoError, LoadOptions};
use crate::math::Vec3;
use crate::mesh::Mesh;

fn v(x: f64, y: f64, z: f64) -> Vec3 {
    Vec3::new(x, y, z)
}

fn flat(faces: &[Vec<u32>]) -> (Vec<u32>, Vec<u32>) {
    (faces.iter().flatten().copied().collect(), faces.iter().map(|f| f.len() as u32).collect())
}

fn repair(p: &[Vec3], faces: &[Vec<u32>]) -> super::Repaired {
    let (i, a) = flat(faces);
    repair_polygons(p, &i, &a, RepairOptions::DEFAULT.with_reorient(true)).unwrap()
}

/// A unit cube's 8 corners offset by `o`, and its 12 outward triangles with vertex ids from
/// `base`.
fn cube(o: Vec3, base: u32) -> (Vec<Vec3>, Vec<Vec<u32>>) {
    let m = Mesh::cube(1.0).triangulate().unwrap();
    let p = m.positions().iter().map(|&q| q + Vec3::splat(0.5) + o).collect();
    let f = (0..m.face_count() as u32).map(|f| m.face_vertices(f).map(|x| x + base).collect()).collect();
    (p, f)
}

#[test]
fn a_bowtie_vertex_becomes_one_vertex_per_fan() {
    let p = vec![v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(1.0, 1.0, 0.0), v(-1.0, 0.0, 0.0), v(-1.0, -1.0, 0.0)];
    assert!(Mesh::from_polygons(p.clone(), &[[0, 1, 2], [0, 3, 4]]).is_err());
    let r = repair(&p, &[vec![0, 1, 2], vec![0, 3, 4]]);
    assert!(r.mesh.is_manifold());
    assert_eq!(r.mesh.vertex_count(), 6);
    // The copy sits where the vertex was, and names it.
    assert_eq!((r.mesh.position(5), r.vertex_from[5]), (p[0], 0));
    assert_eq!(r.mesh.positions()[..5], p[..]);
    assert_eq!(r.repairs.split_vertices.len(), 1);
    assert_eq!((r.repairs.split_vertices[0].vertex, r.repairs.split_vertices[0].fans), (0, 2));
    assert!(
        r.repairs.summary()[0].contains("split 1 non-manifold vertex into one per fan"),
        "{:?}",
        r.repairs.summary()
    );
}

#[test]
fn two_cubes_sharing_an_edge_come_apart_as_two_closed_cubes() {
    // Cube B sits diagonally against cube A: they share the edge x = 1, y = 1 (two vertices),
    // which then has four faces. Pairing around the edge keeps each cube's faces together.
    let (mut p, mut f) = cube(Vec3::ZERO, 0);
    let (pb, fb) = cube(v(1.0, 1.0, 0.0), 8);
    p.extend(pb);
    f.extend(fb);
    // Name B's copies of the shared corners by A's ids.
    let same: Vec<u32> = (0..16).map(|i| (0..i).find(|&j| p[j as usize] == p[i as usize]).unwrap_or(i)).collect();
    let f: Vec<Vec<u32>> = f.iter().map(|t| t.iter().map(|&x| same[x as usize]).collect()).collect();
    let r = repair(&p, &f);
    let m = &r.mesh;
    assert!(m.is_closed() && m.is_manifold());
    assert_eq!((m.component_count(), m.genus(), m.euler()), (2, 0, 4), "two spheres");
    assert!((m.volume() - 2.0).abs() < 1e-12, "both outward: {}", m.volume());
    assert_eq!(r.repairs.separated_edges.len(), 1);
    assert_eq!(r.repairs.separated_edges[0].faces, 4);
    assert_eq!(r.repairs.separated_edges[0].separated, 0, "all four faces paired, two by two");
    assert!(r.repairs.flipped.is_empty());
}

/// The faces of `p, f` whose corners all satisfy `on`.
fn faces_on(p: &[Vec3], f: &[Vec<u32>], on: impl Fn(Vec3) -> bool) -> Vec<Vec<u32>> {
    f.iter().filter(|t| t.iter().all(|&x| on(p[x as usize]))).cloned().collect()
}

/// Two unit cubes side by side along x, touching along the face x = 1, as a soup welded by
/// position: the shared face's triangles are A's and, when `same_diagonal`, B's are A's
/// reversed (coincident triangles), else B's own.
fn touching_cubes(same_diagonal: bool) -> (Vec<Vec3>, Vec<Vec<u32>>) {
    let (mut p, mut f) = cube(Vec3::ZERO, 0);
    let (pb, mut fb) = cube(v(1.0, 0.0, 0.0), 8);
    p.extend(pb);
    if same_diagonal {
        fb.retain(|t| !t.iter().all(|&x| p[x as usize].x == 1.0));
        fb.extend(faces_on(&p, &f, |q| q.x == 1.0).into_iter().map(|t| t.into_iter().rev().collect::<Vec<u32>>()));
    }
    f.extend(fb);
    let same: Vec<u32> = (0..16).map(|i| (0..i).find(|&j| p[j as usize] == p[i as usize]).unwrap_or(i)).collect();
    let f = f.iter().map(|t| t.iter().map(|&x| same[x as usize]).collect()).collect();
    (p, f)
}

#[test]
fn two_cubes_touching_along_a_face_come_apart_as_two_closed_cubes() {
    // Around each edge of the shared face, two faces leave in one direction (A's and B's
    // shared-face triangles): each must pair with its own cube's side, never with the other.
    for same_diagonal in [false, true] {
        let (p, f) = touching_cubes(same_diagonal);
        let r = repair(&p, &f);
        let m = &r.mesh;
        assert!(m.is_closed() && m.is_manifold(), "same diagonal {same_diagonal}");
        assert_eq!((m.component_count(), m.euler()), (2, 4), "two spheres, same diagonal {same_diagonal}");
        assert!((m.volume() - 2.0).abs() < 1e-12, "same diagonal {same_diagonal}: volume {}", m.volume());
        assert!(r.repairs.separated_edges.iter().all(|e| e.separated == 0), "{:?}", r.repairs.summary());
        assert!(r.repairs.flipped.is_empty());
        // And so as an STL, where the soup is welded by position.
        let dir = tempfile::tempdir().unwrap();
        let path = write(dir.path(), "touching.stl", &stl(&soup(&p, &f)));
        let (m, repairs) = io::load_report(&path, &LoadOptions::DEFAULT).unwrap();
        assert!(m.is_closed() && m.is_manifold(), "{:?}", repairs.summary());
        assert_eq!((m.component_count(), m.euler()), (2, 4), "{:?}", repairs.summary());
        assert!((m.volume() - 2.0).abs() < 1e-12, "volume {}", m.volume());
    }
}

#[test]
fn touching_cubes_turned_by_a_rounded_rotation_still_come_apart() {
    // A glTF node's −90° about x in floating point tilts each face by rounding (2e-16), so
    // the faces of one plane no longer lie exactly in it: found within an angle instead.
    let turn =
        crate::math::Quat::from_xyzw(-std::f64::consts::FRAC_1_SQRT_2, 0.0, 0.0, std::f64::consts::FRAC_1_SQRT_2);
    for same_diagonal in [false, true] {
        let (p, f) = touching_cubes(same_diagonal);
        let p: Vec<Vec3> = p.iter().map(|&q| turn * (q + v(0.1, 0.3, 0.7))).collect();
        let r = repair(&p, &f);
        let m = &r.mesh;
        assert!(m.is_closed() && m.is_manifold(), "same diagonal {same_diagonal}");
        assert_eq!((m.component_count(), m.euler()), (2, 4), "same diagonal {same_diagonal}");
        assert!((m.volume() - 2.0).abs() < 1e-9, "same diagonal {same_diagonal}: volume {}", m.volume());
    }
}

#[test]
fn a_stack_of_eight_cubes_comes_apart_as_eight_closed_cubes() {
    let (mut p, mut f) = (Vec::new(), Vec::new());
    for k in 0..8u32 {
        let (q, g) = cube(v(f64::from(k & 1), f64::from((k >> 1) & 1), f64::from(k >> 2)), 8 * k);
        p.extend(q);
        f.extend(g);
    }
    let same: Vec<u32> =
        (0..p.len() as u32).map(|i| (0..i).find(|&j| p[j as usize] == p[i as usize]).unwrap_or(i)).collect();
    let f: Vec<Vec<u32>> = f.iter().map(|t| t.iter().map(|&x| same[x as usize]).collect()).collect();
    let r = repair(&p, &f);
    let m = &r.mesh;
    assert!(m.is_closed() && m.is_manifold());
    assert_eq!((m.component_count(), m.euler()), (8, 16));
    assert!((m.volume() - 8.0).abs() < 1e-12, "volume {}", m.volume());
}

#[test]
fn a_fin_on_an_edge_is_separated_into_its_own_sheet() {
    let (mut p, mut f) = cube(Vec3::ZERO, 0);
    // A triangle on the cube's edge from vertex a to b, sticking out.
    let (a, b) = (f[0][0], f[0][1]);
    p.push(v(3.0, 3.0, 3.0));
    f.push(vec![a, b, 8]);
    let r = repair(&p, &f);
    assert!(r.mesh.is_manifold());
    assert_eq!(r.mesh.component_count(), 2);
    assert_eq!(r.mesh.boundary_loops().len(), 1, "the fin is an open triangle");
    assert_eq!(r.repairs.separated_edges[0].separated, 1);
    assert!(r.mesh.positions()[..9] == p[..], "no vertex moved");
}

#[test]
fn flipped_triangles_are_turned_to_agree_with_the_rest() {
    let (p, mut f) = cube(Vec3::ZERO, 0);
    f[3].reverse();
    f[7].reverse();
    assert!(Mesh::from_polygons(p.clone(), &f).is_err());
    let r = repair(&p, &f);
    assert!(r.mesh.is_closed() && r.mesh.is_manifold());
    assert!((r.mesh.volume() - 1.0).abs() < 1e-12);
    assert_eq!(r.repairs.flipped.len(), 1);
    assert_eq!((r.repairs.flipped[0].faces.clone(), r.repairs.flipped[0].of), (vec![3, 7], 12));
    assert_eq!(r.flipped.iter().filter(|&&x| x).count(), 2);
}

#[test]
fn faces_repeating_a_vertex_are_dropped() {
    let (p, mut f) = cube(Vec3::ZERO, 0);
    f.push(vec![0, 1, 0]);
    f.push(vec![2, 3]);
    let r = repair(&p, &f);
    assert!(r.mesh.is_closed());
    assert_eq!(r.mesh.face_count(), 12);
    assert_eq!(r.repairs.dropped_faces.iter().map(|d| d.0).collect::<Vec<_>>(), vec![12, 13]);
}

#[test]
fn a_moebius_band_is_cut_where_no_orientation_agrees() {
    // A band of 6 quads whose ends join with a half twist.
    let n = 6;
    let mut p = Vec::new();
    for i in 0..n {
        let t = std::f64::consts::TAU * f64::from(i) / f64::from(n);
        let (c, s) = (t.cos(), t.sin());
        let w = (t / 2.0).cos() * 0.3;
        let h = (t / 2.0).sin() * 0.3;
        p.push(v(c * (1.0 + w), s * (1.0 + w), h));
        p.push(v(c * (1.0 - w), s * (1.0 - w), -h));
    }
    let mut f = Vec::new();
    for i in 0..n {
        let (a, b) = (2 * i, 2 * i + 1);
        let (c, d) = if i + 1 < n { (2 * i + 2, 2 * i + 3) } else { (1, 0) };
        f.push(vec![a, c, d, b]);
    }
    let r = repair(&p, &f);
    assert!(r.mesh.is_manifold());
    assert_eq!(r.repairs.unorientable_cuts, 1);
    assert_eq!(r.mesh.face_count(), 6);
}

#[test]
fn a_valid_mesh_is_returned_as_it_is() {
    let (p, f) = cube(Vec3::ZERO, 0);
    let r = repair(&p, &f);
    assert!(r.repairs.is_empty());
    assert_eq!(r.mesh, Mesh::from_polygons(p, &f).unwrap());
}

fn write(dir: &std::path::Path, name: &str, bytes: &[u8]) -> std::path::PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

fn stl(tris: &[[Vec3; 3]]) -> Vec<u8> {
    let mut b = vec![0u8; 80];
    b.extend((tris.len() as u32).to_le_bytes());
    for t in tris {
        b.extend([0u8; 12]);
        for q in t {
            for c in [q.x, q.y, q.z] {
                b.extend((c as f32).to_le_bytes());
            }
        }
        b.extend([0u8; 2]);
    }
    b
}

fn soup(p: &[Vec3], f: &[Vec<u32>]) -> Vec<[Vec3; 3]> {
    f.iter().map(|t| [p[t[0] as usize], p[t[1] as usize], p[t[2] as usize]]).collect()
}

#[test]
fn a_weld_never_joins_two_cubes_into_a_bowtie() {
    // Two cubes whose corners are 2⁻³⁰ apart at the origin (under the weld's 1e-8 of the
    // diagonal, and apart as written, even in f32): the weld would join them into a bowtie
    // vertex; it keeps them apart, silently.
    let (mut p, mut f) = cube(Vec3::splat(-1.0), 0);
    let (pb, fb) = cube(Vec3::splat(2f64.powi(-30)), 8);
    p.extend(pb);
    f.extend(fb);
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "corner.stl", &stl(&soup(&p, &f)));
    let (m, repairs) = io::load_report(&path, &LoadOptions::DEFAULT).unwrap();
    assert!(repairs.is_empty(), "{:?}", repairs.summary());
    assert!(m.is_closed() && m.is_manifold());
    assert_eq!((m.component_count(), m.vertex_count(), m.genus()), (2, 16, 0));
    // Touching exactly as written is the file's own bowtie: repaired with a report, or
    // refused with `repair: false`.
    let (mut p, mut f) = cube(Vec3::ZERO, 0);
    let (pb, fb) = cube(v(1.0, 1.0, 1.0), 8);
    p.extend(pb);
    f.extend(fb);
    let path = write(dir.path(), "touch.stl", &stl(&soup(&p, &f)));
    let (m, repairs) = io::load_report(&path, &LoadOptions::DEFAULT).unwrap();
    assert!(m.is_closed() && m.is_manifold() && m.component_count() == 2);
    assert_eq!(repairs.split_vertices.len(), 1);
    assert_eq!(repairs.split_vertices[0].at, v(1.0, 1.0, 1.0));
    let e = io::load_with(&path, &LoadOptions::DEFAULT.with_repair(false)).unwrap_err();
    assert!(matches!(e, IoError::NotManifold { .. }), "{e}");
    assert!(e.to_string().contains("without `repair: false`"), "{e}");
}

#[test]
fn an_obj_keeps_its_vertex_ids_through_a_repair() {
    let dir = tempfile::tempdir().unwrap();
    let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv -1 0 0\nv -1 -1 0\nf 1 2 3\nf 1 4 5\n";
    let path = write(dir.path(), "bowtie.obj", text.as_bytes());
    let (m, repairs) = io::load_report(&path, &LoadOptions::DEFAULT).unwrap();
    assert_eq!(m.vertex_count(), 6);
    assert_eq!(m.face_vertices(0).collect::<Vec<_>>(), vec![0, 1, 2]);
    assert_eq!(m.face_vertices(1).collect::<Vec<_>>(), vec![5, 3, 4]);
    assert_eq!(repairs.summary().len(), 1);
    assert!(io::load_with(&path, &LoadOptions::DEFAULT.with_repair(false)).is_err());
}

/// The OBJ text of `tris`, each triangle with corners of its own (as a converter from STL
/// writes it), and `extra` lines after.
fn obj_soup(tris: &[[Vec3; 3]], extra: &str) -> String {
    let mut text = String::new();
    for t in tris {
        for q in t {
            text += &format!("v {} {} {}\n", q.x, q.y, q.z);
        }
    }
    for k in 0..tris.len() {
        text += &format!("f {} {} {}\n", 3 * k + 1, 3 * k + 2, 3 * k + 3);
    }
    text + extra
}

#[test]
fn an_obj_or_3mf_of_corners_apart_is_welded_as_an_stl_is() {
    // Touching cubes written per triangle: welded, and repaired as the STL of the same
    // triangles is (two closed cubes); without the weld, 24 separate triangles.
    let (p, f) = touching_cubes(false);
    let tris = soup(&p, &f);
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "soup.obj", obj_soup(&tris, "").as_bytes());
    let (m, _) = io::load_report(&path, &LoadOptions::DEFAULT).unwrap();
    assert!(m.is_closed() && m.is_manifold());
    assert_eq!((m.component_count(), m.euler()), (2, 4));
    let stl_path = write(dir.path(), "soup.stl", &stl(&tris));
    assert_eq!(io::load(&stl_path).unwrap().vertex_count(), m.vertex_count());
    let apart = io::load_with(&path, &LoadOptions::DEFAULT.with_weld(io::Weld::Off)).unwrap();
    assert_eq!((apart.component_count(), apart.vertex_count()), (24, 72));
    // The same as 3MF.
    let tmf = write(dir.path(), "soup.3mf", &[]);
    io::save(&apart, &tmf).unwrap();
    let m3 = io::load(&tmf).unwrap();
    assert!(m3.is_closed() && m3.is_manifold());
    assert_eq!((m3.component_count(), m3.vertex_count()), (2, m.vertex_count()));
}

#[test]
fn an_obj_with_subdivision_tags_is_not_welded() {
    // Its tags name its vertex ids: a weld would renumber them. One cube written per triangle
    // with a corner tag on vertex 5 stays 12 triangles apart, the tag on vertex 5.
    let (p, f) = cube(Vec3::ZERO, 0);
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "tagged.obj", obj_soup(&soup(&p, &f), "t corner 1/1/0 5 4\n").as_bytes());
    let m = io::load(&path).unwrap();
    assert_eq!((m.vertex_count(), m.component_count()), (36, 12));
    assert_eq!(m.corner_sharpness(5), 4.0);
}
