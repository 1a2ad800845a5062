//! Tests of components, boundary loops, handle loops and the defect list.

use super::handle_loops::cut_genus;
use super::{boundary_loops, components, defects, handle_loops, DefectKind};
use crate::math::Vec3;
use crate::mesh::Mesh;
use crate::voxel::{Voxels, DEFAULT_ISO};

/// The genus of `m` cut along every loop (checks that the loops cut the surface to genus 0).
fn genus_after_cutting(m: &Mesh, loops: &[super::HandleLoop]) -> i64 {
    let mut cut = vec![false; m.halfedge_count()];
    for l in loops {
        for &h in &l.halfedges {
            cut[h as usize] = true;
            cut[m.twin(h) as usize] = true;
        }
    }
    let faces: Vec<u32> = (0..m.face_count() as u32).collect();
    cut_genus(m, &faces, &cut).unwrap()
}

/// Each loop is closed: its half-edges run head to tail back to the start.
fn assert_closed_loops(m: &Mesh, loops: &[super::HandleLoop]) {
    for l in loops {
        for (i, &h) in l.halfedges.iter().enumerate() {
            let next = l.halfedges[(i + 1) % l.halfedges.len()];
            assert_eq!(m.target(h), m.origin(next), "loop {l:?}");
        }
    }
}

/// A 16³ voxel slab with `tunnels` square holes through it (each a handle), as its marching
/// cubes surface.
fn slab_with_tunnels(tunnels: usize) -> Mesh {
    let mut vx = Voxels::new(32).unwrap();
    vx.fill_box(Vec3::new(4.0, 4.0, 8.0), Vec3::new(28.0, 12.0 + 4.0 * tunnels as f64, 14.0)).unwrap();
    for t in 0..tunnels as i64 {
        for x in 8..10 {
            for y in 7 + 4 * t..9 + 4 * t {
                for z in 8..14 {
                    vx.set(x, y, z, 0).unwrap();
                }
            }
        }
    }
    vx.to_mesh(0, DEFAULT_ISO).unwrap()
}

#[test]
fn a_torus_has_one_handle_loop_around_its_tube() {
    // Major radius 2, minor 0.5: the meridian (about 2π·0.5 ≈ 3.1, shorter than the
    // longitude's 2π·1.5 at the inner equator) is the loop around the handle.
    let m = Mesh::torus(2.0, 0.5, 48, 16);
    assert_eq!(m.genus(), 1);
    let loops = handle_loops(&m).unwrap();
    assert_eq!(loops.len(), 1);
    assert_closed_loops(&m, &loops);
    assert!(loops[0].length < 3.2, "{}", loops[0].length);
    assert_eq!(genus_after_cutting(&m, &loops), 0);
}

#[test]
fn a_double_torus_and_a_voxel_slab_with_tunnels_are_cut_to_genus_zero() {
    for tunnels in [1, 2, 3] {
        let m = slab_with_tunnels(tunnels);
        assert!(m.is_closed() && m.is_manifold());
        assert_eq!(m.genus(), tunnels as i64);
        let loops = handle_loops(&m).unwrap();
        assert_eq!(loops.len(), tunnels);
        assert_closed_loops(&m, &loops);
        assert_eq!(genus_after_cutting(&m, &loops), 0, "{tunnels} tunnels");
        // Each loop goes around a tunnel: it is short (a tunnel's wall is 2×2 voxels, its
        // loops about 8 voxels around; the slab is 24 long) and lies near the tunnel column.
        for l in &loops {
            assert!(l.length < 12.0, "{tunnels}: {:?}", loops.iter().map(|l| l.length).collect::<Vec<_>>());
            let c = l.vertices.iter().map(|&v| m.position(v)).sum::<Vec3>() / l.vertices.len() as f64;
            assert!((c.x - 9.0).abs() < 3.0, "{c}");
        }
    }
}

#[test]
fn components_come_apart_with_their_attributes() {
    let a = Mesh::cube(1.0);
    let b = Mesh::icosphere(0.5, 1).map_positions(|p| p + Vec3::new(3.0, 0.0, 0.0));
    let mut both = Mesh::combine(&[&a, &b]).unwrap();
    both.set_vertex_colors(Some(vec![[0.5, 0.25, 1.0, 1.0]; both.vertex_count()])).unwrap();
    let parts = components(&both).unwrap();
    assert_eq!(parts.len(), 2);
    assert_eq!((parts[0].face_count(), parts[1].face_count()), (a.face_count(), b.face_count()));
    assert!((parts[0].volume() - a.volume()).abs() < 1e-12 && (parts[1].volume() - b.volume()).abs() < 1e-12);
    assert_eq!(parts[1].vertex_colors().unwrap()[0], [0.5, 0.25, 1.0, 1.0]);
}

#[test]
fn defects_list_boundaries_touching_sheets_crossings_and_handles() {
    // An open box (a cube without its top face), a bowtie pair of triangles, and a torus.
    let cube = Mesh::cube(1.0);
    let mut faces = cube.to_polygons();
    let top = (0..6).find(|&f| cube.face_normal(f).z > 0.5).unwrap() as usize;
    faces.remove(top);
    let open = Mesh::from_polygons(cube.positions().to_vec(), &faces).unwrap();
    let p = vec![
        Vec3::new(5.0, 0.0, 0.0),
        Vec3::new(6.0, 0.0, 0.0),
        Vec3::new(6.0, 1.0, 0.0),
        Vec3::new(5.0, 0.0, 0.0),
        Vec3::new(4.0, 0.0, 0.0),
        Vec3::new(4.0, -1.0, 0.0),
    ];
    let bowtie = Mesh::from_polygons(p, &[[0, 1, 2], [3, 4, 5]]).unwrap();
    let torus = Mesh::torus(2.0, 0.5, 24, 8).map_positions(|p| p + Vec3::new(0.0, 10.0, 0.0));
    let m = Mesh::combine(&[&open, &bowtie, &torus]).unwrap();
    let d = defects(&m).unwrap();
    let count = |k: DefectKind| d.iter().filter(|x| x.kind == k).count();
    assert_eq!(count(DefectKind::Component), 4);
    assert_eq!(count(DefectKind::Boundary), 3, "the box's rim and the two triangles");
    assert_eq!(count(DefectKind::NonManifoldVertex), 1);
    assert_eq!(count(DefectKind::Handle), 1);
    assert_eq!(count(DefectKind::SelfIntersection), 0);
    let bow = d.iter().find(|x| x.kind == DefectKind::NonManifoldVertex).unwrap();
    assert_eq!(bow.position, Vec3::new(5.0, 0.0, 0.0));
    let genus: Vec<i64> = d.iter().filter_map(|x| x.genus).collect();
    assert_eq!(genus, vec![0, 0, 0, 1]);
    // The rim runs around the box's top: four vertices at z = 0.5.
    let rim = boundary_loops(&open);
    assert_eq!(rim.len(), 1);
    assert!(rim[0].len() == 4 && rim[0].iter().all(|&v| open.position(v).z > 0.0));
}

#[test]
fn a_closed_sphere_has_no_defects() {
    assert!(defects(&Mesh::icosphere(1.0, 3)).unwrap().is_empty());
}

#[test]
fn a_dented_sphere_reports_its_crossings() {
    let mut m = Mesh::icosphere(1.0, 2);
    let top = (0..m.vertex_count() as u32).max_by(|&a, &b| m.position(a).z.total_cmp(&m.position(b).z)).unwrap();
    m.set_position(top, Vec3::new(0.0, 0.0, -1.5)).unwrap();
    let d = defects(&m).unwrap();
    assert!(!d.is_empty() && d.iter().all(|x| x.kind == DefectKind::SelfIntersection));
    assert_eq!(d.len(), super::self_intersections(&m).unwrap().len());
}
