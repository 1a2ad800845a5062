//! Tests of the instanced import ([`import_instances`]): translated copies of one mesh are
//! imported once and copied, giving exactly what one import of them all gives.

use super::*;

/// A triangulated icosphere of radius 0.5.
fn ball() -> Mesh {
    Mesh::icosphere(0.5, 2).triangulate().unwrap()
}

/// The leaves prepared as `evaluate` prepares them, with their first face tags.
fn prepared(leaves: &[(&Csg, Side)]) -> (Vec<Prepared>, Vec<u32>) {
    let prepared: Vec<Prepared> =
        leaves.iter().enumerate().map(|(k, (leaf, side))| prepare(leaf, *side, k as u32).unwrap()).collect();
    let offsets = prepared
        .iter()
        .scan(0u32, |tag, p| {
            let first = *tag;
            *tag += p.face_sources.len() as u32;
            Some(first)
        })
        .collect();
    (prepared, offsets)
}

/// Each triangle of `s` as its tag and its corners' coordinates (bits), from the smallest
/// corner on, sorted: what two imports must agree on whatever their orders.
fn triangles(s: &Solid) -> Vec<(u32, [[u64; 3]; 3])> {
    let t = s.paired_triangles();
    let mut out: Vec<(u32, [[u64; 3]; 3])> = t
        .corners
        .chunks_exact(3)
        .zip(&t.tags)
        .map(|(c, &tag)| {
            let mut corners = [0, 1, 2].map(|i| t.positions[c[i] as usize].to_array().map(f64::to_bits));
            let first = (0..3).min_by_key(|&i| corners[i]).unwrap_or(0);
            corners.rotate_left(first);
            (tag, corners)
        })
        .collect();
    out.sort_unstable();
    out
}

#[test]
fn translated_copies_import_once_and_exactly_as_one_import_would() {
    let s = ball();
    let centres = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.3], [2.0, 2.0, -0.7], [-3.25, 1.0, 0.1]];
    let mut leaves: Vec<Csg> = centres.iter().map(|&c| Csg::mesh(s.translate(Vec3::from(c)))).collect();
    // Not copies: the same triangles turned, and scaled.
    leaves.push(Csg::mesh(s.rotate(Vec3::Z, 30.0).translate(Vec3::new(6.0, 0.0, 0.0))));
    leaves.push(Csg::mesh(s.scale(Vec3::splat(1.5)).translate(Vec3::new(-6.0, 0.0, 0.0))));
    // And a box, of other triangles.
    leaves.push(Csg::mesh(Mesh::cuboid(Vec3::new(5.0, 5.0, 5.0), Vec3::new(6.0, 6.0, 6.0))));
    let sided: Vec<(&Csg, Side)> = leaves.iter().map(|l| (l, Side::Right)).collect();
    let (prepared, offsets) = prepared(&sided);
    let pieces: Vec<(usize, usize)> = (0..leaves.len()).map(|k| (k, 0)).collect();
    let classes = instance_classes(&pieces, &prepared, 1e-11);
    assert_eq!(classes, vec![vec![0, 1, 2, 3, 4]], "the five translates, and only they");
    let token = CancelToken::new();
    let stop = Stop::new();
    let bounds: Vec<Vec<Aabb>> = prepared.iter().map(Prepared::component_bounds).collect();
    let inputs =
        Inputs { prepared: &prepared, bounds: &bounds, leaves: &sided, offsets: &offsets, token: &token, stop: &stop };
    let instanced = import_instances(&pieces, 9, &inputs).unwrap().expect("the copies are instanced");
    let flat = import_flat(&pieces, 9, 0.0, &inputs).unwrap();
    assert_eq!(instanced.triangle_count(), flat.triangle_count());
    assert!((instanced.volume() - flat.volume()).abs() <= 1e-12 * flat.volume());
    // The same triangles at the same coordinates with the same tags: each copy keeps its own
    // positions and its own leaf's faces.
    assert_eq!(triangles(&instanced), triangles(&flat));
}

#[test]
fn a_group_without_copies_or_with_a_near_copy_is_imported_as_one() {
    let s = ball();
    let mut bent = s.translate(Vec3::new(3.0, 0.0, 0.0));
    let p = bent.position(5);
    bent.set_position(5, p + Vec3::new(1e-6, 0.0, 0.0)).unwrap();
    let leaves =
        [Csg::mesh(s.clone()), Csg::mesh(bent), Csg::mesh(s.rotate(Vec3::X, 90.0).translate(Vec3::splat(-3.0)))];
    let sided: Vec<(&Csg, Side)> = leaves.iter().map(|l| (l, Side::Left)).collect();
    let (prepared, offsets) = prepared(&sided);
    let pieces: Vec<(usize, usize)> = (0..leaves.len()).map(|k| (k, 0)).collect();
    assert!(instance_classes(&pieces, &prepared, 1e-11).is_empty());
    let token = CancelToken::new();
    let stop = Stop::new();
    let bounds: Vec<Vec<Aabb>> = prepared.iter().map(Prepared::component_bounds).collect();
    let inputs =
        Inputs { prepared: &prepared, bounds: &bounds, leaves: &sided, offsets: &offsets, token: &token, stop: &stop };
    assert!(import_instances(&pieces, 3, &inputs).unwrap().is_none());
}

/// Through a whole boolean: a block minus a pattern of translated balls. The volume is the
/// block's less the balls' (each wholly inside), every ball's faces name that ball's leaf and
/// lie on it, and the same tree gives the same mesh every time.
#[test]
fn a_pattern_of_copies_cut_from_a_block_keeps_each_copy_its_own_faces() {
    let s = ball();
    let centres: Vec<Vec3> = (0..12)
        .map(|i| Vec3::new((i % 4) as f64 * 1.5 - 2.25, (i / 4) as f64 * 1.5 - 1.5, 0.2 * (i % 3) as f64))
        .collect();
    let block = Csg::mesh(Mesh::cuboid(Vec3::new(-4.0, -3.0, -2.0), Vec3::new(4.0, 3.0, 2.0)));
    let balls = Csg::union_all(centres.iter().map(|&c| Csg::mesh(s.translate(c))).collect()).unwrap();
    let tree = block.difference(balls);
    let m = tree.evaluate().unwrap();
    assert!(m.is_closed() && m.is_manifold());
    assert_eq!(m.component_count(), 13, "the block's shell and twelve cavities");
    let expected = 8.0 * 6.0 * 4.0 - 12.0 * s.volume();
    assert!((m.volume() - expected).abs() < 1e-9, "{} != {expected}", m.volume());
    let sources = m.face_sources().unwrap();
    for f in 0..m.face_count() as u32 {
        match sources[f as usize] {
            FaceSource::Mesh { leaf: 0, .. } => {}
            FaceSource::Mesh { leaf, .. } => {
                let c = centres[leaf as usize - 1];
                for v in m.face_vertices(f) {
                    let r = m.position(v).distance(c);
                    assert!((r - 0.5).abs() < 1e-9, "face {f} of ball {leaf} at {r} from its centre");
                }
            }
            other => panic!("face {f}: {other:?}"),
        }
    }
    let again = tree.evaluate().unwrap();
    assert_eq!(again.positions(), m.positions());
    assert_eq!(again.face_sources(), m.face_sources());
}

#[test]
fn a_translated_copy_is_prepared_as_prepare_would_prepare_it() {
    let mut s = ball();
    s.set_edge_sharpness_halfedge(0, f64::INFINITY);
    s.set_edge_sharpness_halfedge(7, 2.0);
    s.set_corner_sharpness(3, 1.5);
    let leaves = [
        Csg::mesh(s.clone()),
        Csg::mesh(s.translate(Vec3::new(2.0, 0.0, 0.0))),
        Csg::mesh(s.translate(Vec3::new(-1.25, 3.5, 0.7))),
        Csg::mesh(s.rotate(Vec3::Y, 45.0).translate(Vec3::new(0.0, -3.0, 0.0))),
    ];
    let sided: Vec<(&Csg, Side)> = leaves.iter().map(|l| (l, Side::Right)).collect();
    assert_eq!(translated_copies(&sided), vec![None, Some(0), Some(0), None]);
    let first = prepare(&leaves[0], Side::Right, 0).unwrap();
    for (k, leaf) in leaves.iter().enumerate().take(3).skip(1) {
        let Csg::Mesh(m) = leaf else { unreachable!() };
        let moved = first.moved(m, Side::Right, k as u32, &order_by_x(s.positions()).unwrap()).unwrap();
        let fresh = prepare(leaf, Side::Right, k as u32).unwrap();
        assert_eq!(moved.positions, fresh.positions);
        assert_eq!(moved.triangles, fresh.triangles);
        assert_eq!(moved.faces, fresh.faces);
        assert_eq!(moved.face_sources, fresh.face_sources);
        assert_eq!(moved.creases, fresh.creases);
        assert_eq!(moved.creases.len(), 2);
        assert_eq!(moved.corners, fresh.corners);
        assert_eq!(moved.corners.len(), 1);
        assert_eq!(moved.components, fresh.components);
        assert_eq!(moved.pairs, fresh.pairs);
        assert_eq!((moved.leaf_span, moved.first_leaf_hint), (fresh.leaf_span, fresh.first_leaf_hint));
    }
}

/// Copies are found whatever first they copy: a rotated ball has the ball's counts but is a first
/// of its own, and its translates copy it, not the ball; a non-mesh leaf is nobody's copy.
#[test]
fn each_copy_names_the_first_it_is_a_translate_of() {
    let s = ball();
    let turned = s.rotate(Vec3::Y, 30.0);
    let leaves = [
        Csg::mesh(s.clone()),
        Csg::mesh(turned.clone()),
        Csg::mesh(turned.translate(Vec3::new(3.0, 0.0, 0.0))),
        Csg::mesh(s.translate(Vec3::new(0.0, 3.0, 0.0))),
        Csg::mesh(Mesh::cube(1.0).triangulate().unwrap()),
        Csg::mesh(turned.translate(Vec3::new(0.0, 0.0, -3.0))),
    ];
    let sided: Vec<(&Csg, Side)> = leaves.iter().map(|l| (l, Side::Right)).collect();
    assert_eq!(translated_copies(&sided), vec![None, None, Some(1), Some(0), None, Some(1)]);
    assert_eq!(in_order(&sided), vec![None, None, Some(1), Some(0), None, Some(1)]);
}

/// [`copies_in_order`] of the leaves.
fn in_order(leaves: &[(&Csg, Side)]) -> Vec<Option<usize>> {
    let meshes: Vec<Option<&Mesh>> = leaves.iter().map(|(leaf, _)| copyable(leaf)).collect();
    copies_in_order(&meshes)
}

/// The copies found all at once are the ones found in order: a pattern of balls among other
/// leaves (a cube, a block model, a ball's mirror image of the same counts that copies nothing
/// and sends the search back to the order), each arrangement with and without the odd ones.
#[test]
fn copies_found_at_once_are_the_copies_found_in_order() {
    let s = ball();
    let cube = Mesh::cube(1.0).triangulate().unwrap();
    let mirrored = s.scale(Vec3::new(-1.0, 1.0, 1.0));
    let pattern: Vec<Csg> = (0..12).map(|i| Csg::mesh(s.translate(Vec3::new(2.0 * f64::from(i), 1.0, -3.0)))).collect();
    let blocks = Csg::Blocks(Arc::new(BlockModel::new()), MeshOptions::default());
    for odd in [
        vec![],
        vec![Csg::mesh(cube.clone())],
        vec![Csg::mesh(cube.clone()), blocks.clone(), Csg::mesh(mirrored.clone())],
    ] {
        for at in [0, 5, 12] {
            let mut leaves: Vec<Csg> = pattern.clone();
            for (i, leaf) in odd.iter().enumerate() {
                leaves.insert((at + i).min(leaves.len()), leaf.clone());
            }
            let sided: Vec<(&Csg, Side)> = leaves.iter().map(|l| (l, Side::Left)).collect();
            let found = translated_copies(&sided);
            assert_eq!(found, in_order(&sided), "{} odd leaves at {at}", odd.len());
            assert_eq!(found.iter().filter(|f| f.is_some()).count(), 11, "{} odd leaves at {at}", odd.len());
        }
    }
}

/// Two vertices a rounding apart in x come together when moved far off: the copy touches itself
/// and is refused as `prepare` refuses it, though its original passed.
#[test]
fn a_copy_that_rounding_makes_touch_itself_is_refused_as_prepare_refuses_it() {
    // A box one rounding thick in x (from 1 to the next double), then moved 1024 along x, where
    // a rounding is 2^-42: each corner on one side lands on the one across from it.
    let thin = Mesh::cuboid(Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0 + f64::EPSILON, 1.0, 1.0)).triangulate().unwrap();
    let far = thin.translate(Vec3::new(1024.0, 0.0, 0.0));
    let first = prepare(&Csg::mesh(thin.clone()), Side::Right, 0).expect("the original is apart");
    let by_x = order_by_x(thin.positions()).unwrap();
    assert!(apart_along(thin.positions(), &by_x).unwrap());
    assert!(!apart_along(far.positions(), &by_x).unwrap(), "the copy's corners meet");
    let moved = first.moved(&far, Side::Right, 1, &by_x);
    let fresh = prepare(&Csg::mesh(far.clone()), Side::Right, 1);
    match (moved, fresh) {
        (Err(CsgError::NonManifold { leaf: 1, reason: a, .. }), Err(CsgError::NonManifold { reason: b, .. })) => {
            assert_eq!(a, b);
            assert!(a.contains("touches itself"), "{a}");
        }
        (moved, fresh) => panic!("moved: {:?}, prepared: {:?}", moved.err(), fresh.err()),
    }
    // Moved a little, the copy stays apart and is taken without a lookup.
    let near = thin.translate(Vec3::new(0.5, -2.0, 3.0));
    assert!(apart_along(near.positions(), &by_x).unwrap());
    first.moved(&near, Side::Right, 1, &by_x).expect("apart");
}

/// Walking a grid in x order: equal x in long runs, told apart by y and z; a repeated
/// position, an order that is not x's, or a short order cannot be told apart.
#[test]
fn positions_are_seen_apart_along_their_x_order() {
    let grid: Vec<Vec3> = (0..4)
        .flat_map(|i| (0..5).flat_map(move |j| (0..3).map(move |k| Vec3::new(i as f64, j as f64, k as f64))))
        .collect();
    let by_x = order_by_x(&grid).unwrap();
    assert!(apart_along(&grid, &by_x).unwrap());
    let mut twice = grid.clone();
    twice[17] = twice[4];
    assert!(!apart_along(&twice, &order_by_x(&twice).unwrap()).unwrap());
    let reversed: Vec<u32> = by_x.iter().rev().copied().collect();
    assert!(!apart_along(&grid, &reversed).unwrap());
    assert!(!apart_along(&grid, &by_x[1..]).unwrap());
    // -0.0 and 0.0 are two positions, as the lookup keys them.
    let zeros = [Vec3::new(0.0, 1.0, 1.0), Vec3::new(-0.0, 1.0, 1.0)];
    assert!(apart_along(&zeros, &order_by_x(&zeros).unwrap()).unwrap());
}

/// The copies' x order and walk stop with the cancellation token, as the per-vertex lookup
/// does: a walk polls every `POLL_EVERY` positions, the order before and after its sort.
#[test]
fn the_copies_walk_stops_when_cancelled() {
    let line: Vec<Vec3> =
        (0..crate::limits::POLL_EVERY as u32 + 2).map(|i| Vec3::new(f64::from(i), 0.0, 0.0)).collect();
    let by_x = order_by_x(&line).unwrap();
    assert!(apart_along(&line, &by_x).unwrap(), "apart, with no token");
    let interrupt = Arc::new(std::sync::atomic::AtomicBool::new(false));
    let token = CancelToken::with(Some(Arc::clone(&interrupt)), None, None);
    let _current = crate::limits::install(token);
    assert!(apart_along(&line, &by_x).unwrap(), "apart, with a token running");
    interrupt.store(true, std::sync::atomic::Ordering::Relaxed);
    assert!(matches!(apart_along(&line, &by_x), Err(LimitError::Stopped(_))), "the walk stops");
    assert!(matches!(order_by_x(&line), Err(LimitError::Stopped(_))), "the order stops");
    // Shorter than one run of polls, the walk finishes.
    assert_eq!(apart_along(&line[..100], &by_x[..100]).ok(), Some(true), "a walk of fewer positions");
}

/// A copy but for a non-finite coordinate is no copy: it is refused as `prepare` refuses it,
/// naming the vertex.
#[test]
fn a_copy_with_a_non_finite_coordinate_is_refused_as_any_leaf_is() {
    let s = ball();
    // (`set_position` refuses a NaN; a transform passes it on.)
    let bad = s.translate(Vec3::new(f64::NAN, 3.0, 0.0));
    let leaves = [Csg::mesh(s), Csg::mesh(bad)];
    let sided: Vec<(&Csg, Side)> = leaves.iter().map(|l| (l, Side::Right)).collect();
    assert_eq!(translated_copies(&sided), vec![None, None]);
    let [a, b] = leaves;
    match a.union(b).evaluate() {
        Err(CsgError::NonFinite { leaf: 1, vertex: 0, .. }) => {}
        other => panic!("{other:?}"),
    }
}
