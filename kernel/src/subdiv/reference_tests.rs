//! Comparisons with OpenSubdiv (double precision), Blender's subdivision (OpenSubdiv, float32)
//! and pymeshlab's Loop, from the reference files in `tests/data/subdiv/` (made by
//! `make_refs.py` there). Vertex orders differ between tools, so vertices are matched by position:
//! every one of ours must have a reference vertex within the tolerance, and every reference vertex
//! must be matched exactly once.

use std::collections::HashMap;
use std::path::PathBuf;

use crate::math::Vec3;
use crate::mesh::Mesh;

use super::ring::mesh_ring;
use super::topology::Rule;
use super::LimitEvaluator;

struct Section {
    name: String,
    level: u32,
    faces: usize,
    points: Vec<Vec3>,
}

struct Reference {
    mesh: Mesh,
    sections: Vec<Section>,
}

impl Reference {
    fn section(&self, name: &str, level: u32) -> Option<&Section> {
        self.sections.iter().find(|s| s.name == name && s.level == level)
    }
}

fn load(file: &str) -> Reference {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../tests/data/subdiv").join(file);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let (mut verts, mut faces, mut creases, mut corners) = (Vec::new(), Vec::<Vec<u32>>::new(), Vec::new(), Vec::new());
    let mut sections: Vec<Section> = Vec::new();
    let num = |s: &str| s.parse::<f64>().unwrap();
    for line in text.lines() {
        let p: Vec<&str> = line.split_whitespace().collect();
        match p.first().copied() {
            Some("v") => verts.push(Vec3::new(num(p[1]), num(p[2]), num(p[3]))),
            Some("f") => faces.push(p[1..].iter().map(|x| x.parse().unwrap()).collect()),
            Some("crease") => creases.push([p[1].parse().unwrap(), p[2].parse().unwrap()]),
            Some("corner") => corners.push(p[1].parse::<u32>().unwrap()),
            Some("p") => sections.last_mut().unwrap().points.push(Vec3::new(num(p[1]), num(p[2]), num(p[3]))),
            Some("level" | "limit" | "limit_normal" | "bpy_limit") => sections.push(Section {
                name: p[0].to_string(),
                level: p[1].parse().unwrap(),
                faces: p[3].parse().unwrap(),
                points: Vec::new(),
            }),
            _ => {}
        }
    }
    let mut mesh = Mesh::from_polygons(verts, &faces).unwrap();
    mesh.crease_edges(&creases).unwrap();
    for c in corners {
        mesh.set_corner(c, true);
    }
    Reference { mesh, sections }
}

/// For each of `ours`, the index of the reference point within `tol` (panics naming the first
/// miss); checks that the matching is one-to-one.
fn match_points(what: &str, ours: &[Vec3], refs: &[Vec3], tol: f64) -> Vec<usize> {
    assert_eq!(ours.len(), refs.len(), "{what}: {} vertices, reference has {}", ours.len(), refs.len());
    let cell = 1e-3;
    let key = |p: Vec3| ((p.x / cell).floor() as i64, (p.y / cell).floor() as i64, (p.z / cell).floor() as i64);
    let mut grid: HashMap<(i64, i64, i64), Vec<usize>> = HashMap::new();
    for (i, &p) in refs.iter().enumerate() {
        grid.entry(key(p)).or_default().push(i);
    }
    let mut used = vec![false; refs.len()];
    let mut worst = 0.0f64;
    let out = ours
        .iter()
        .enumerate()
        .map(|(i, &p)| {
            let (kx, ky, kz) = key(p);
            let mut best = (f64::INFINITY, usize::MAX);
            for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        for &j in grid.get(&(kx + dx, ky + dy, kz + dz)).map_or(&[][..], |v| &v[..]) {
                            let d = (refs[j] - p).length();
                            if d < best.0 {
                                best = (d, j);
                            }
                        }
                    }
                }
            }
            assert!(
                best.0 <= tol,
                "{what}: our vertex {i} at {p} has no reference vertex within {tol:e} (nearest {:e})",
                best.0
            );
            assert!(!used[best.1], "{what}: reference vertex {} matched twice", best.1);
            used[best.1] = true;
            worst = worst.max(best.0);
            best.1
        })
        .collect();
    eprintln!("{what}: {} vertices matched, max distance {worst:.2e}", ours.len());
    out
}

fn check_levels(file: &str, scheme_loop: bool) -> Reference {
    let r = load(file);
    for s in r.sections.iter().filter(|s| s.name == "level") {
        let m = if scheme_loop { r.mesh.loop_subdivide(s.level) } else { r.mesh.catmull_clark(s.level) }.unwrap();
        assert_eq!(m.face_count(), s.faces, "{file} level {}: face count", s.level);
        match_points(&format!("{file} level {}", s.level), m.positions(), &s.points, 1e-9);
    }
    // Limit positions of the level-1 vertices (OpenSubdiv's masks), and normals where the
    // conventions coincide: smooth vertices and boundary vertices (one sector).
    let m1 = if scheme_loop { r.mesh.loop_subdivide(1) } else { r.mesh.catmull_clark(1) }.unwrap();
    let (lim, nrm) = if scheme_loop {
        (m1.loop_limit().unwrap(), m1.loop_limit_normals().unwrap())
    } else {
        (m1.catmull_clark_limit().unwrap(), m1.catmull_clark_limit_normals().unwrap())
    };
    let refs = r.section("limit", 1).unwrap();
    let idx = match_points(&format!("{file} limit of level 1"), lim.positions(), &refs.points, 1e-9);
    let ref_n = &r.section("limit_normal", 1).unwrap().points;
    let mut compared = 0;
    for v in 0..m1.vertex_count() as u32 {
        let ring = mesh_ring(&m1, v);
        let sharp = ring.topo.sharp.iter().filter(|&&s| s).count();
        let one_sector = ring.topo.rule() == Rule::Crease && ring.topo.face.iter().any(|&f| !f);
        if (ring.topo.rule() == Rule::Smooth && sharp == 0) || one_sector {
            let d = (nrm[v as usize] - ref_n[idx[v as usize]]).length();
            assert!(
                d < 1e-9,
                "{file}: normal of level-1 vertex {v}: ours {} vs {} ({d:e})",
                nrm[v as usize],
                ref_n[idx[v as usize]]
            );
            compared += 1;
        }
    }
    assert!(compared > 0);
    r
}

#[test]
fn catmull_clark_matches_opensubdiv_and_blender() {
    for name in ["cube", "cube_crease", "torus_mixed", "grid"] {
        let file = format!("cc_{name}.txt");
        let r = check_levels(&file, false);
        // Blender's limit surface at level 2 (float32 output): the limit of our level-2 vertices,
        // and our evaluator at the same parameters.
        let b = r.section("bpy_limit", 2).unwrap();
        let lim = r.mesh.catmull_clark(2).unwrap().catmull_clark_limit().unwrap();
        match_points(&format!("{file} bpy limit 2"), lim.positions(), &b.points, 1e-6);
        let (base, n) = if r.mesh.is_quad_mesh() { (r.mesh.clone(), 4) } else { (r.mesh.catmull_clark(1).unwrap(), 2) };
        let ev = LimitEvaluator::new(&base).unwrap();
        let mut samples = Vec::new();
        for f in 0..base.face_count() as u32 {
            for j in 0..=n {
                for i in 0..=n {
                    samples
                        .push(ev.eval(f, f64::from(i) / f64::from(n), f64::from(j) / f64::from(n)).unwrap().position);
                }
            }
        }
        // Shared edges and corners repeat: compare each sample with its nearest reference point.
        let mut uniq: Vec<Vec3> = Vec::new();
        for s in samples {
            if !uniq.iter().any(|u| (*u - s).length() < 1e-9) {
                uniq.push(s);
            }
        }
        match_points(&format!("{file} evaluator vs bpy limit"), &uniq, &b.points, 1e-6);
    }
}

#[test]
fn loop_matches_pymeshlab_and_opensubdiv() {
    for name in ["icosahedron", "torus_tri", "grid_tri", "octahedron_crease"] {
        check_levels(&format!("loop_{name}.txt"), true);
    }
}
