//! Tests of CSG evaluation: exact volumes on boxes, genus, provenance, creases, bad input.

use super::{Csg, CsgError, Side};
use crate::blocks::test_models::{along_box_edge, sharp_box};
use crate::blocks::{Block, BlockModel, Face, MeshOptions, SubFaceRef};
use crate::mesh::{FaceSource, Mesh};
use crate::Vec3;

fn cuboid(a: [f64; 3], b: [f64; 3]) -> Csg {
    Csg::mesh(Mesh::cuboid(Vec3::from(a), Vec3::from(b)))
}

fn unit() -> Csg {
    cuboid([0.0; 3], [1.0; 3])
}

/// Evaluates and checks what every result must be: closed, manifold, a triangle mesh with a
/// known source on every face.
fn eval(c: &Csg) -> Mesh {
    let m = c.evaluate().unwrap();
    assert!(m.is_closed() && m.is_manifold() && m.is_triangle_mesh());
    let s = m.face_sources().unwrap();
    assert_eq!(s.len(), m.face_count());
    assert!(s.iter().all(|s| s.leaf().is_some()), "every face knows its input");
    m
}

#[test]
fn exact_volumes_on_boxes() {
    let cases = [
        (unit().union(cuboid([0.5; 3], [1.5; 3])), 2.0 - 0.125, 0),
        (unit().difference(cuboid([0.5; 3], [1.5; 3])), 1.0 - 0.125, 0),
        (unit().intersection(cuboid([0.5; 3], [1.5; 3])), 0.125, 0),
        // Touching faces: a union through a shared face is one box, an intersection empty.
        (unit().union(cuboid([1.0, 0.0, 0.0], [2.0, 1.0, 1.0])), 2.0, 0),
        (unit().difference(cuboid([1.0, 0.0, 0.0], [2.0, 1.0, 1.0])), 1.0, 0),
        // Identical operands.
        (unit().union(unit()), 1.0, 0),
        (unit().intersection(unit()), 1.0, 0),
        // A flush pocket (coplanar top faces).
        (unit().difference(cuboid([0.25, 0.25, 0.5], [0.75, 0.75, 1.0])), 0.875, 0),
    ];
    for (i, (c, volume, genus)) in cases.into_iter().enumerate() {
        let m = eval(&c);
        assert!((m.volume() - volume).abs() < 1e-12, "case {i}: {} != {volume}", m.volume());
        assert_eq!(m.genus(), genus, "case {i}");
        assert_eq!(m.component_count(), 1, "case {i}");
    }
}

#[test]
fn empty_results_are_meshes_without_faces() {
    // The last two only touch over part of a face: Manifold leaves a flat shell of two coincident
    // sheets there, which regularisation drops.
    for c in [
        unit().difference(unit()),
        unit().intersection(cuboid([1.0, 0.0, 0.0], [2.0, 1.0, 1.0])),
        cuboid([-0.5, 0.0, -0.25], [0.25, 0.75, 1.0]).intersection(cuboid([-0.75, -0.25, -1.0], [0.75, 0.0, 0.0])),
        unit().intersection(cuboid([0.25, 1.0, 0.25], [0.75, 2.0, 0.75])),
    ] {
        let m = c.evaluate().unwrap();
        assert_eq!((m.face_count(), m.volume()), (0, 0.0));
    }
}

#[test]
fn the_result_is_the_mesh_from_indexed_builds_from_its_triangles() {
    // The result is built from the engine's own pairing of its half-edges (no search for
    // twins); from_indexed, which searches, must find the same mesh. The second case leaves a
    // flat shell (where the unit box touches the box beside it) beside a solid part: the shell is
    // dropped and the kept triangles' pairs renumbered.
    let sphere = Csg::mesh(Mesh::icosphere(0.4, 3).translate(Vec3::new(0.5, 0.5, 1.0)));
    let far = |x: f64| cuboid([x, 0.0, 0.0], [x + 1.0, 1.0, 1.0]);
    let cases = [
        (unit().difference(sphere), None),
        (unit().union(far(3.0)).intersection(far(1.0).union(cuboid([3.5, 0.0, 0.0], [5.0, 1.0, 1.0]))), Some(0.5)),
    ];
    for (i, (c, volume)) in cases.into_iter().enumerate() {
        let m = eval(&c);
        assert_eq!(m.component_count(), 1, "case {i}");
        if let Some(v) = volume {
            assert!((m.volume() - v).abs() < 1e-12, "case {i}: {}", m.volume());
        }
        let corners: Vec<u32> = (0..m.face_count() as u32).flat_map(|f| m.face_vertices(f)).collect();
        let rebuilt = Mesh::from_indexed(m.positions().to_vec(), &corners, &vec![3; m.face_count()]).unwrap();
        assert_eq!(m.halfedge_count(), rebuilt.halfedge_count(), "case {i}");
        for h in 0..m.halfedge_count() as u32 {
            let at = |m: &Mesh| (m.origin(h), m.twin(h), m.next(h), m.prev(h), m.face(h));
            assert_eq!(at(&m), at(&rebuilt), "case {i}, half-edge {h}");
        }
        for v in 0..m.vertex_count() as u32 {
            assert_eq!(m.vertex_halfedge(v), rebuilt.vertex_halfedge(v), "case {i}, vertex {v}");
        }
    }
}

#[test]
fn through_hole_has_genus_one() {
    let m = eval(&unit().difference(cuboid([0.25, 0.25, -1.0], [0.75, 0.75, 2.0])));
    assert_eq!(m.genus(), 1);
    assert!((m.volume() - 0.75).abs() < 1e-12);
}

#[test]
fn provenance_names_the_input_and_its_face() {
    let a = Mesh::cuboid(Vec3::ZERO, Vec3::ONE);
    let b = Mesh::cuboid(Vec3::splat(0.5), Vec3::splat(1.5));
    let m = eval(&Csg::mesh(a.clone()).difference(Csg::mesh(b.clone())));
    for (f, s) in m.face_sources().unwrap().iter().enumerate() {
        let FaceSource::Mesh { leaf, face } = *s else { panic!("{s:?}") };
        let src = if leaf == 0 { &a } else { &b };
        // The output triangle lies in the plane of the input face it names.
        let (n, p) = (src.face_normal(face), src.position(src.face_vertices(face).next().unwrap()));
        for v in m.face_vertices(f as u32) {
            assert!((m.position(v) - p).dot(n).abs() < 1e-12);
        }
        // The cutter's faces face inward in a difference.
        assert_eq!(m.face_normal(f as u32).dot(n) < 0.0, leaf == 1);
    }
    // Three faces of the box and three of the cutter show.
    let leaves: std::collections::BTreeSet<_> = m.face_sources().unwrap().iter().copied().collect();
    assert_eq!(leaves.len(), 9);
}

#[test]
fn earlier_results_keep_their_sources_and_leaves_are_renumbered() {
    let first = eval(&unit().difference(cuboid([0.8; 3], [2.0; 3])));
    let m = eval(&cuboid([-1.0, 0.2, 0.2], [0.5, 0.8, 0.8]).union(Csg::mesh(first)));
    let leaves: std::collections::BTreeSet<u32> =
        m.face_sources().unwrap().iter().filter_map(FaceSource::leaf).collect();
    assert_eq!(leaves.into_iter().collect::<Vec<_>>(), vec![0, 1, 2]);
}

fn block_model(min: [f64; 3], max: [f64; 3], smooth: bool) -> BlockModel {
    let mut b = Block::from_bounds(Vec3::from(min), Vec3::from(max)).unwrap();
    for f in Face::ALL {
        b.subdivide(f, 2, 2).unwrap();
    }
    if smooth {
        b.smooth_all();
    } else {
        b.sharp_all();
    }
    let mut m = BlockModel::new();
    m.add(b);
    m
}

#[test]
fn block_leaves_keep_their_sub_faces() {
    let sharp = block_model([0.0; 3], [2.0; 3], false);
    let c = Csg::blocks(sharp, MeshOptions::DEFAULT).difference(cuboid([1.5, 1.5, 1.5], [3.0; 3]));
    let m = eval(&c);
    assert!((m.volume() - (8.0 - 0.125)).abs() < 1e-9, "{}", m.volume());
    let subs: std::collections::BTreeSet<SubFaceRef> = m
        .face_sources()
        .unwrap()
        .iter()
        .filter_map(|s| match s {
            FaceSource::Block { sub_face, .. } => Some(SubFaceRef::try_from(*sub_face).unwrap()),
            _ => None,
        })
        .collect();
    assert_eq!(subs.len(), 24, "every sub-face of the 2×2 grids shows");
}

#[test]
fn crease_tags_come_through_on_the_edges_they_lie_on() {
    let mut body = Mesh::cuboid(Vec3::ZERO, Vec3::splat(2.0));
    body.crease_all();
    let m = eval(&Csg::mesh(body).difference(cuboid([1.5; 3], [3.0; 3])));
    // The nine edges of the box that stay whole, and pieces of the three the notch cuts.
    assert!(m.crease_count() >= 12, "{}", m.crease_count());
    let on_box_edge =
        |x: Vec3| [x.x, x.y, x.z].iter().filter(|c| c.abs() < 1e-12 || (*c - 2.0).abs() < 1e-12).count() >= 2;
    for h in m.edges().filter(|&h| m.is_crease(h)) {
        let (p, q) = (m.position(m.origin(h)), m.position(m.target(h)));
        assert!(on_box_edge(p) && on_box_edge(q), "crease {p} {q} off the box's edges");
    }
    // Every remaining piece of a box edge is tagged: total creased length 12·2 − 3·0.5.
    let len: f64 = m
        .edges()
        .filter(|&h| m.is_crease(h))
        .map(|h| (m.position(m.origin(h)) - m.position(m.target(h))).length())
        .sum();
    assert!((len - 22.5).abs() < 1e-12, "{len}");
}

#[test]
fn semi_sharp_creases_and_corners_keep_their_sharpness_through_a_boolean() {
    // A box whose edges along x are 1.5 sharp and the others 3.25, with a 2.7 corner at the
    // origin: the notch cuts three edges; every surviving piece keeps its edge's sharpness, the
    // corner at the origin keeps its own, and the notch's new vertices and edges get none.
    let mut body = Mesh::cuboid(Vec3::ZERO, Vec3::splat(2.0));
    let edges: Vec<u32> = body.edges().collect();
    for h in edges {
        let d = body.position(body.target(h)) - body.position(body.origin(h));
        body.set_edge_sharpness_halfedge(h, if d.x != 0.0 { 1.5 } else { 3.25 });
    }
    let origin = (0..8).find(|&v| body.position(v) == Vec3::ZERO).unwrap();
    body.set_corner_sharpness(origin, 2.7);
    let m = eval(&Csg::mesh(body).difference(cuboid([1.5; 3], [3.0; 3])));
    let mut len = [0.0, 0.0];
    for h in m.edges().filter(|&h| m.is_crease(h)) {
        let d = m.position(m.target(h)) - m.position(m.origin(h));
        let want = if d.x != 0.0 { 1.5 } else { 3.25 };
        assert_eq!(m.edge_sharpness(h), want, "edge {d}");
        len[usize::from(want == 3.25)] += d.length();
    }
    // Four x edges of 2, one cut to 1.5 (the notch takes 0.5 of it); eight others likewise.
    assert!((len[0] - 7.5).abs() < 1e-12 && (len[1] - 15.0).abs() < 1e-12, "{len:?}");
    for v in 0..m.vertex_count() as u32 {
        let want = if m.position(v) == Vec3::ZERO { 2.7 } else { 0.0 };
        assert_eq!(m.corner_sharpness(v), want, "vertex {v} at {}", m.position(v));
    }
    assert!(m.has_semi_sharp());
}

#[test]
fn semi_sharp_block_edges_keep_their_sharpness_through_a_boolean() {
    // A block with every edge at 1.5, cut at a corner: the surviving pieces of its edges are
    // creases of 1.5, the cut's new edges are none.
    let mut b = Block::from_bounds(Vec3::ZERO, Vec3::ONE).unwrap();
    for e in crate::blocks::Edge::all() {
        b.set_sharpness(e, 1.5).unwrap();
    }
    let mut model = BlockModel::new();
    model.add(b);
    let m = eval(&Csg::blocks(model, MeshOptions::DEFAULT.with_tolerance(1e-3)).difference(cuboid([0.8; 3], [2.0; 3])));
    let creases = m.crease_sharpnesses();
    assert!(!creases.is_empty());
    assert!(creases.iter().all(|&(_, s)| s == 1.5), "{creases:?}");
}

#[test]
fn smooth_blocks_are_tessellated_first_with_their_options() {
    let opts = MeshOptions::DEFAULT.with_tolerance(1e-3);
    let t = block_model([-1.0; 3], [1.0; 3], true).tessellate(&opts, None).unwrap();
    // A lone leaf is its tessellation.
    let alone = eval(&Csg::blocks(block_model([-1.0; 3], [1.0; 3], true), opts));
    assert_eq!(alone.face_count(), t.mesh.face_count());
    assert!((alone.volume() - t.mesh.volume()).abs() < 1e-12);
    // Cut in half by a box: the result is closed (no cracks at the seam) and has half the volume.
    let half = eval(
        &Csg::blocks(block_model([-1.0; 3], [1.0; 3], true), opts).intersection(cuboid([0.0, -2.0, -2.0], [2.0; 3])),
    );
    assert!(
        (half.volume() - t.mesh.volume() / 2.0).abs() < 1e-3 * t.mesh.volume(),
        "{} vs {}",
        half.volume(),
        t.mesh.volume()
    );
}

#[test]
fn bad_input_names_the_side() {
    let mut open = Mesh::cuboid(Vec3::ZERO, Vec3::ONE).to_polygons();
    open.pop();
    let open = Mesh::from_polygons(Mesh::cuboid(Vec3::ZERO, Vec3::ONE).positions().to_vec(), &open).unwrap();
    let e = unit().union(Csg::mesh(open.clone())).evaluate().unwrap_err();
    assert_eq!(e, CsgError::OpenMesh { side: Side::Right, leaf: 1, boundary_edges: 4 });
    assert!(e.to_string().contains("right operand"), "{e}");
    let e = Csg::mesh(open).difference(unit()).evaluate().unwrap_err();
    assert!(matches!(e, CsgError::OpenMesh { side: Side::Left, leaf: 0, .. }), "{e}");

    let e = unit().difference(Csg::mesh(Mesh::default())).evaluate().unwrap_err();
    assert_eq!(e, CsgError::EmptyOperand { side: Side::Right, leaf: 1 });
    let e = Csg::blocks(BlockModel::new(), MeshOptions::DEFAULT).union(unit()).evaluate().unwrap_err();
    assert_eq!(e, CsgError::EmptyOperand { side: Side::Left, leaf: 0 });

    // Two boxes meeting along an edge, as one mesh: geometrically non-manifold there.
    let two = Mesh::combine(&[
        &Mesh::cuboid(Vec3::ZERO, Vec3::ONE),
        &Mesh::cuboid(Vec3::new(1.0, 1.0, 0.0), Vec3::new(2.0, 2.0, 1.0)),
    ])
    .unwrap();
    let e = unit().intersection(Csg::mesh(two)).evaluate().unwrap_err();
    assert!(matches!(&e, CsgError::NonManifold { side: Side::Right, leaf: 1, .. }), "{e}");
    assert!(e.to_string().contains("touches itself"), "{e}");

    let nan =
        Mesh::cuboid(Vec3::ZERO, Vec3::ONE).map_positions(|p| if p == Vec3::ONE { Vec3::splat(f64::NAN) } else { p });
    let e = Csg::mesh(nan).union(unit()).evaluate().unwrap_err();
    assert!(matches!(e, CsgError::NonFinite { side: Side::Left, leaf: 0, .. }), "{e}");
}

#[test]
fn the_same_tree_gives_the_same_mesh() {
    // Many leaves and block components, imported in parallel: the result must not depend on
    // which thread came first.
    let mut model = BlockModel::new();
    for i in 0..6 {
        let x = f64::from(i) * 1.5;
        model.add(Block::from_bounds(Vec3::new(x, 0.0, 0.0), Vec3::new(x + 1.0, 1.0, 1.0)).unwrap());
    }
    let spheres: Vec<Csg> =
        (0..8).map(|i| Csg::mesh(Mesh::icosphere(0.4, 2).translate(Vec3::new(f64::from(i) * 1.1, 0.5, 1.0)))).collect();
    let tree =
        Csg::blocks(model, MeshOptions::DEFAULT.with_tolerance(0.01)).difference(Csg::union_all(spheres).unwrap());
    let first = eval(&tree);
    for _ in 0..4 {
        assert_eq!(eval(&tree), first);
    }
}

#[test]
fn the_engine_gets_one_face_per_flat_region_of_one_source() {
    use super::tree::coplanar_faces;
    let faces_of = |m: &Mesh, sources: &[FaceSource], any: bool| {
        let tris: Vec<[u32; 3]> = (0..m.face_count() as u32)
            .map(|f| {
                let v: Vec<u32> = m.face_vertices(f).collect();
                [v[0], v[1], v[2]]
            })
            .collect();
        let (faces, face_sources, creases) = coplanar_faces(m, &tris, sources, any).unwrap();
        assert_eq!(faces.len(), tris.len());
        assert_eq!(face_sources.len() as u32, faces.iter().max().unwrap() + 1);
        (face_sources.len(), creases.len())
    };
    // An all-sharp block: one face per sub-face (its 8+ triangles are coplanar), and the
    // creases along the box's edges lie between faces.
    let model = sharp_box([-0.1, 0.2, 0.3], [0.3, 0.7, 1.1], &[(Face::PosZ, 2, 3)]);
    let t = model.tessellate(&MeshOptions::DEFAULT, None).unwrap();
    let sources: Vec<FaceSource> =
        t.triangle_sources.iter().map(|&r| FaceSource::Block { leaf: 0, sub_face: r.into() }).collect();
    let (faces, creases) = faces_of(&t.mesh, &sources, false);
    assert_eq!(faces, 5 + 6);
    assert_eq!(creases, t.mesh.crease_count());
    // A plain triangle mesh: its coplanar regions, whatever the sources say.
    let cube = Mesh::cuboid(Vec3::ZERO, Vec3::ONE).triangulate_with_sources().unwrap().0;
    let own: Vec<FaceSource> = (0..12).map(|face| FaceSource::Mesh { leaf: 0, face }).collect();
    assert_eq!(faces_of(&cube, &own, true).0, 6);
    assert_eq!(faces_of(&cube, &own, false).0, 12);
    // A crease between coplanar triangles keeps them apart; a sphere's triangles all differ.
    let mut creased = cube.clone();
    creased.crease_all();
    assert_eq!(faces_of(&creased, &own, true), (12, 18));
    let ball = Mesh::icosphere(1.0, 2);
    let own: Vec<FaceSource> = (0..ball.face_count() as u32).map(|face| FaceSource::Mesh { leaf: 0, face }).collect();
    assert_eq!(faces_of(&ball, &own, true).0, ball.face_count());
}

#[test]
fn coplanar_triangles_of_one_source_are_cut_as_one_face() {
    // A sharp block cut at a corner: the cut faces are re-triangulated as whole faces, each
    // output triangle still naming its sub-face.
    let model = sharp_box([0.0; 3], [1.0; 3], &[(Face::PosZ, 2, 2)]);
    let m = eval(&Csg::blocks(model, MeshOptions::DEFAULT).difference(cuboid([0.8; 3], [2.0; 3])));
    assert!((m.volume() - (1.0 - 0.008)).abs() < 1e-12, "{}", m.volume());
    let out = m.face_sources().unwrap();
    let on = |face: Face, sub: u32| {
        out.iter()
            .filter(|s| matches!(s, FaceSource::Block { sub_face, .. } if usize::from(sub_face.face) == face.index() && sub_face.sub == sub))
            .count()
    };
    assert!((0..4).all(|sub| on(Face::PosZ, sub) > 0));
    assert!(Face::ALL.iter().all(|&f| on(f, 0) > 0));
    assert!(m.is_closed() && m.genus() == 0);
    // The block's sharp edges come through as creases: all twelve, less the three 0.2 pieces
    // the corner took; the cut's own edges are no creases (the cutting box has none).
    let p = m.positions();
    let creases = m.crease_pairs();
    let length: f64 = creases.iter().map(|&[a, b]| p[a as usize].distance(p[b as usize])).sum();
    assert!((length - (12.0 - 3.0 * 0.2)).abs() < 1e-9, "crease length {length}");
    assert!(creases.iter().all(|&[a, b]| along_box_edge(p[a as usize], p[b as usize], [0.0; 3], [1.0; 3])));
}

#[test]
fn booleans_beyond_the_precision_limit_are_refused_naming_it() {
    // Two boxes 2 across overlapping by half: right at 1e10 from the origin, refused at 1e12
    // (the engine would merge them into a wrong volume or nothing).
    let at =
        |offset: f64, dx: f64| cuboid([offset + dx, offset, offset], [offset + dx + 2.0, offset + 2.0, offset + 2.0]);
    let near = eval(&at(1e10, 0.0).union(at(1e10, 1.0)));
    assert!((near.volume() - 12.0).abs() < 1e-3, "{}", near.volume());
    for c in [at(1e12, 0.0).union(at(1e12, 1.0)), at(1e12, 0.0).difference(at(1e12, 1.0))] {
        let e = c.evaluate().unwrap_err();
        assert!(matches!(e, CsgError::Precision { .. }), "{e:?}");
        let msg = e.to_string();
        assert!(msg.contains("spans 2 at coordinates up to 1.00e12") && msg.contains("(the precision limit)"), "{msg}");
    }
}

#[test]
fn operands_the_engine_would_merge_away_are_refused_never_empty() {
    // Two unit boxes overlapping by half at 1e12 (issue 33): the engine's import merges each
    // into nothing (its resolution there is 1), so the union had 0 faces and no error. Each
    // operand is refused by the precision limit instead, like the 2-unit boxes.
    let o = 1e12;
    let a = cuboid([o, o, o], [o + 1.0, o + 1.0, o + 1.0]);
    let b = cuboid([o + 0.5, o, o], [o + 1.5, o + 1.0, o + 1.0]);
    for c in [a.clone().union(b.clone()), a.clone().difference(b.clone()), a.intersection(b)] {
        let e = c.evaluate().unwrap_err();
        assert!(matches!(e, CsgError::Precision { .. }), "{e:?}");
        assert!(e.to_string().contains("spans 1 at coordinates up to 1.00e12"), "{e}");
    }
    // At 1e8 the same boxes unite exactly.
    let o = 1e8;
    let u = eval(
        &cuboid([o, o, o], [o + 1.0, o + 1.0, o + 1.0]).union(cuboid([o + 0.5, o, o], [o + 1.5, o + 1.0, o + 1.0])),
    );
    assert!((u.volume() - 1.5).abs() < 1e-6, "{}", u.volume());
}

#[test]
fn a_stopped_token_stops_the_evaluation_with_its_reason() {
    use crate::limits::{install, CancelToken, LimitError, StopReason};
    use std::sync::atomic::AtomicBool;
    use std::sync::Arc;
    let _current = install(CancelToken::with(Some(Arc::new(AtomicBool::new(true))), None, None));
    for tree in [
        unit().difference(cuboid([0.5; 3], [2.0; 3])),
        Csg::blocks(block_model([0.0; 3], [1.0; 3], false), MeshOptions::DEFAULT),
    ] {
        let e = tree.evaluate().unwrap_err();
        assert_eq!(e, CsgError::Limit(LimitError::Stopped(StopReason::Interrupted)));
    }
}
