//! One list of what is wrong with a mesh, each with its elements and a position to show.

use super::handle_loops::{component_genus, handle_loops};
use super::self_intersections::crossings;
use super::triangle_pair::is_degenerate;
use crate::math::{IdMap, Vec3};
use crate::mesh::{Mesh, MeshError, NONE};

/// What kind of defect (see [`Defect::elements`] for what each names).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum DefectKind {
    /// An open boundary loop: its vertices in order.
    Boundary,
    /// Vertices at one position that are not one vertex: where sheets touch (a non-manifold
    /// vertex of the file, split on load): the vertices.
    NonManifoldVertex,
    /// Edges at one position that are not one edge: where faces beyond two met on an edge
    /// (separated on load): the edges' vertex pairs, flattened `[a0, b0, a1, b1, …]`.
    NonManifoldEdge,
    /// Two faces crossing or touching away from what they share: `[f, g]`.
    SelfIntersection,
    /// A face of zero area (its corners collinear) or with two corners at one position: `[f]`.
    DegenerateFace,
    /// A connected component: its faces. Listed when the mesh has more than one, or one with
    /// a boundary or a handle ([`Defect::genus`] says how many).
    Component,
    /// A loop of edges around a handle ([`super::handle_loops`]): its vertices in order.
    Handle,
}

impl DefectKind {
    /// The kind's name in scripts: `"boundary"`, `"non_manifold_vertex"`, `"non_manifold_edge"`,
    /// `"self_intersection"`, `"degenerate_face"`, `"component"`, `"handle"`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            DefectKind::Boundary => "boundary",
            DefectKind::NonManifoldVertex => "non_manifold_vertex",
            DefectKind::NonManifoldEdge => "non_manifold_edge",
            DefectKind::SelfIntersection => "self_intersection",
            DefectKind::DegenerateFace => "degenerate_face",
            DefectKind::Component => "component",
            DefectKind::Handle => "handle",
        }
    }
}

/// One defect.
#[derive(Clone, Debug, PartialEq)]
pub struct Defect {
    /// What it is.
    pub kind: DefectKind,
    /// The element ids it names (vertices, faces or vertex pairs: see [`DefectKind`]).
    pub elements: Vec<u32>,
    /// A point to show it at (a loop's or face's centre, the shared position, the crossing).
    pub position: Vec3,
    /// The component it lies on (index into [`Mesh::face_components`]).
    pub component: usize,
    /// For a component, its genus; `None` for other kinds.
    pub genus: Option<i64>,
}

/// Everything [`defects`] finds wrong with `mesh`, in this order: components (when there is
/// more than one, or one is open or has handles), boundaries, non-manifold vertices and edges
/// (touching at one position), degenerate faces, self-intersections, handle loops.
///
/// Cost: linear in the mesh, plus [`super::self_intersections`]'s O(n log n + k) and the
/// handle loops' O(n log n + g·n) (g handles, at most [`super::MAX_HANDLES`] loops).
///
/// # Errors
/// [`MeshError::Limit`] when the current cancellation token stops; a face that cannot be cut
/// into triangles ([`MeshError::Triangulation`]).
pub fn defects(mesh: &Mesh) -> Result<Vec<Defect>, MeshError> {
    let comps = mesh.face_components();
    let mut face_comp = vec![0u32; mesh.face_count()];
    for (c, faces) in comps.iter().enumerate() {
        for &f in faces {
            face_comp[f as usize] = c as u32;
        }
    }
    let comp_of_vertex = |v: u32| {
        let h = mesh.vertex_halfedge(v);
        if h == NONE {
            return 0;
        }
        let f = mesh.face(h);
        let f = if f == NONE { mesh.face(mesh.twin(h)) } else { f };
        face_comp[f as usize] as usize
    };
    let centre = |vs: &[u32]| vs.iter().map(|&v| mesh.position(v)).sum::<Vec3>() / vs.len().max(1) as f64;
    let mut out = Vec::new();

    let genus = component_genus(mesh, &comps, &face_comp);
    let loops = super::boundary_loops(mesh);
    let mut open = vec![false; comps.len()];
    for l in &loops {
        open[comp_of_vertex(l[0])] = true;
    }
    if comps.len() > 1 || open.iter().any(|&o| o) || genus.iter().any(|&g| g != 0) {
        for (c, faces) in comps.iter().enumerate() {
            let vs: Vec<u32> = faces.iter().flat_map(|&f| mesh.face_vertices(f)).collect();
            out.push(Defect {
                kind: DefectKind::Component,
                elements: faces.clone(),
                position: centre(&vs),
                component: c,
                genus: Some(genus[c]),
            });
        }
    }
    for l in loops {
        out.push(Defect {
            kind: DefectKind::Boundary,
            position: centre(&l),
            component: comp_of_vertex(l[0]),
            elements: l,
            genus: None,
        });
    }

    // Vertices and edges sharing a position.
    let key = |p: Vec3| [p.x, p.y, p.z].map(|c| if c == 0.0 { 0u64 } else { c.to_bits() });
    let mut at: IdMap<[u64; 3], Vec<u32>> = IdMap::default();
    for v in 0..mesh.vertex_count() as u32 {
        crate::limits::poll_at(v as usize)?;
        if mesh.vertex_halfedge(v) != NONE {
            at.entry(key(mesh.position(v))).or_default().push(v);
        }
    }
    let mut shared: Vec<Vec<u32>> = at.into_values().filter(|vs| vs.len() > 1).collect();
    shared.sort_unstable();
    let mut canon: IdMap<u32, u32> = IdMap::default();
    for vs in &shared {
        for &v in vs {
            canon.insert(v, vs[0]);
        }
        out.push(Defect {
            kind: DefectKind::NonManifoldVertex,
            position: mesh.position(vs[0]),
            component: comp_of_vertex(vs[0]),
            elements: vs.clone(),
            genus: None,
        });
    }
    if !shared.is_empty() {
        let c = |v: u32| canon.get(&v).copied().unwrap_or(v);
        let mut edges: IdMap<(u32, u32), Vec<u32>> = IdMap::default();
        for h in mesh.edges() {
            let (a, b) = (mesh.origin(h), mesh.target(h));
            if canon.contains_key(&a) && canon.contains_key(&b) {
                let (x, y) = (c(a), c(b));
                edges.entry((x.min(y), x.max(y))).or_default().extend([a, b]);
            }
        }
        let mut groups: Vec<Vec<u32>> = edges.into_values().filter(|e| e.len() > 2).collect();
        groups.sort_unstable();
        for e in groups {
            out.push(Defect {
                kind: DefectKind::NonManifoldEdge,
                position: (mesh.position(e[0]) + mesh.position(e[1])) * 0.5,
                component: comp_of_vertex(e[0]),
                elements: e,
                genus: None,
            });
        }
    }

    for f in 0..mesh.face_count() as u32 {
        crate::limits::poll_at(f as usize)?;
        let vs: Vec<u32> = mesh.face_vertices(f).collect();
        let p: Vec<Vec3> = vs.iter().map(|&v| mesh.position(v)).collect();
        let pinched = (0..p.len()).any(|i| p[i] == p[(i + 1) % p.len()]);
        let flat = (1..p.len() - 1).all(|i| is_degenerate([p[0], p[i], p[i + 1]]));
        if pinched || flat {
            out.push(Defect {
                kind: DefectKind::DegenerateFace,
                elements: vec![f],
                position: centre(&vs),
                component: face_comp[f as usize] as usize,
                genus: None,
            });
        }
    }

    for c in crossings(mesh)? {
        out.push(Defect {
            kind: DefectKind::SelfIntersection,
            elements: c.faces.to_vec(),
            position: c.at,
            component: face_comp[c.faces[0] as usize] as usize,
            genus: None,
        });
    }

    for l in handle_loops(mesh)? {
        out.push(Defect {
            kind: DefectKind::Handle,
            position: centre(&l.vertices),
            component: l.component,
            elements: l.vertices,
            genus: None,
        });
    }
    Ok(out)
}
