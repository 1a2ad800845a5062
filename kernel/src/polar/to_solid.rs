//! A polar mesh as a valid solid: a closed, manifold mesh without self-intersections that
//! bounds the same shape — for grown plants, whose faces cross at branch bases (a branch's
//! first quads pass through its parent's wall, lsystem/tests_grow.rs counts them), so that the
//! polar mesh is closed but no solid: booleans, volumes, slicers and 3D printing misread it.
//!
//! # Method: tubes capped inside their parents, united by the boolean engine
//! The surface is cut along its loops into *tubes*, each closed by cones to the centre of the
//! loop it ends at, and the tubes are united by the kernel's boolean engine (`csg`, Manifold's
//! exact predicates):
//!
//! 1. The skeleton (§7.1) gives the regions (annular rings of quads, pole fans: one skeleton
//!    segment each) and the loop complexes (a loop with the far sides of the gaps nested on it:
//!    one node each).
//! 2. Regions are joined across every loop node that only two regions meet (a simple loop in
//!    the middle of a branch): a *tube* runs from branching to branching (or to a tip pole).
//!    Where a feature is nested, the nesting loop's node meets three or more regions — the
//!    parent below it, the parent beyond it and each branch — and there tubes end.
//! 3. Each tube's boundary loops are closed by a cone (a fan of triangles) from every boundary
//!    edge to the node's centre, the mean of the node's vertices (the skeleton node's
//!    position). A branch's boundary is its gap on the parent's wall, so its cone reaches into
//!    the parent, to the parent's axis: the branch is *capped inside its parent*, and the parent's
//!    own tubes, closed by cones to the same centre, hold that volume too.
//! 4. The tubes are united ([`Csg::union_all`], evaluated as Manifold's batch union).
//!
//! Why this is the same solid: at every node the cones of the tubes that meet there share the
//! node's centre and, edge for edge, the node's loop edges, each loop edge in exactly two
//! tubes with opposite orientations (a closed polar mesh has two faces at every loop edge), so
//! the cones cancel in pairs and the union's surface is the polar mesh's surface wherever no
//! other tube covers it. Where a branch's first quads pass through its parent's wall, the part
//! inside the parent is covered by the parent's tube, and the engine cuts it away: the crossing
//! is resolved instead of hidden. The volume is that of the union of the tubes (but for the
//! stand-ins, below), which is the set of points where the polar mesh's winding number is
//! positive (each tube is positively oriented, and the tubes' winding numbers add up to the
//! polar mesh's because the cones cancel) — the tests measure both sides of that statement by
//! integrating along lines.
//!
//! Why not the alternatives: the polar mesh as one operand cannot go into the engine (Manifold,
//! like every exact boolean, takes inputs that do not cross themselves), and a local
//! re-stitching at each branch base would have to find and re-triangulate every crossing,
//! the job the engine already does robustly; each branch's tube on its own does not cross
//! itself (the growth keeps every quad unfolded, tested over many seeds), which is all the
//! engine asks.
//!
//! Everted tubes: two sibling branches turned the same way at one node (`F[-F][-F]`, which
//! `F[+F]F[-F]` makes after two steps) take two gaps of the parent's loop, and the second
//! faces away from where its branch grows, so the branch runs back through its parent and its
//! loops wind the other way round its axis: its tube bounds negative volume. Each piece is
//! turned to face outwards before the union (the set is the same; the cones no longer cancel
//! there, and the union covers them).
//!
//! # Stand-ins
//! A tube whose own faces cross cannot go into the engine: its regions go one by one, and a
//! region whose own faces cross stands in as its convex hull (its apexes included, so that the
//! cones its neighbours share are covered). Such regions are where a branch's loops fold over
//! themselves: a branch's first loop takes the shape of its gap, a crescent round part of its
//! parent, and seen along the branch that crescent crosses itself (measured on thesis plant 7
//! with wide gaps: its four largest stand-ins, loops of 8 vertices zigzagging across the
//! branch's axis, hold 28-62 % of their hulls); the loops after it round off over a few segments
//! (lsystem/grow.rs). Where a loop crosses itself the points of positive winding number are a
//! thin folded set, and the hull fills the fold. So the solid holds all of the union of the
//! tubes and exceeds it only inside the stand-ins (tests_to_solid integrates where, along
//! lines), and where an everted tube's cones (below) or a cone's reach past a loop that is not
//! convex about its centre stand out (under 3e-5 of the volume of the seeded plants, 1.5e-4
//! of planar plants whose branches cross each other). Measured over the release
//! sweep (64 seeds, `cargo test --release -p blocksmith-kernel --lib to_solid -- --ignored`),
//! the stand-ins' excess as a fraction of the solid's volume, median and worst: the thesis's
//! grammar 2.90 % and 3.77 % with the default gaps, 3.85 % and 5.39 % with wide gaps; the
//! growing tree 1.88 % and 2.49 %, 3.15 % and 4.12 %; the recipes' turtle plant 0.07 %. Tighter
//! stand-ins were tried and not kept (kernel/benches/lsystem.rs): thin convex slices per face
//! cost 1.7 to 9 times the time and took plant 7 only from 5.8 % to 5.3 %, as each slice holds
//! the branch's axis, which a folded loop does not surround.
//!
//! Limits: loops must cut the solid across (the cones of a loop that runs round a hole, not
//! across a limb, would fill the hole): fewer handles than the polar mesh, or more parts, is
//! [`PolarError::NotTubes`]. Where branches cross each other as well as their parent (narrow
//! branching angles, thick branches, plants in one plane), the tubes enclose tunnels between
//! them: the union has more handles than the polar mesh (genus 2–20 measured on `F[+F][-F]F`
//! at 3 steps), which is the shape of the plant, kept when the union is closed, manifold and
//! crosses itself nowhere (the exact test), else refused naming that cause. Two vertices at one
//! point (a zero-length segment) are refused by the engine's import as a surface touching
//! itself.

use std::collections::HashMap;

use super::select_feature::Dsu;
use super::{PolarError, PolarMesh, Skeleton};
use crate::csg::Csg;
use crate::math::Vec3;
use crate::mesh::Mesh;

/// How far a piece's cone reaches past the centre of the loop it ends at, as a fraction of
/// the loop's mean radius: each piece pokes into its neighbours, so that pieces overlap in
/// volume instead of touching along their caps (solids that only touch can stay apart in the
/// engine's union), well short of a segment's tip cap (half a radius at least).
const REACH: f64 = 0.25;

/// The id standing for the apex of node `n` in [`Tubes`].
const fn apex(n: u32) -> u32 {
    u32::MAX - n
}

impl PolarMesh {
    /// The same shape as a valid solid: a closed, manifold triangle mesh without
    /// self-intersections, the union of the mesh's tubes (regions joined from branching to
    /// branching, each capped by cones to the centres of the loops it ends at, which for a
    /// branch lie inside its parent), united by the boolean engine. The polar mesh is not
    /// changed. See the module doc of `to_solid` for why this is the same solid; for a grown
    /// plant it is the plant with the crossings at its branch bases cut away. A region whose
    /// own faces cross (a branch's loops folded over themselves) stands in as its convex hull:
    /// the solid exceeds the union of the tubes there only (median 2-4 % of a plant's volume,
    /// at most 5.4 % over 256 seeded plants; module doc, "Stand-ins").
    ///
    /// Time: the skeleton and the tubes in linear time, then the engine's union (near-linear
    /// in the triangles, tubes far apart composed without a boolean); when branches enclose
    /// tunnels, the exact crossing test of the union (O(n log n) in its triangles). Tells a
    /// listener ([`crate::limits::listen`]) the tubes built, then the union as many units again.
    ///
    /// # Errors
    /// [`PolarError::NotTubes`] when the loops do not cut the mesh into tubes (a loop round a
    /// hole, a region meeting one loop twice: fewer handles or more parts than the mesh), or
    /// branches crossing each other leave a union that touches itself;
    /// [`PolarError::Solid`] for two vertices at one point (as a zero-length segment makes) or
    /// when the engine refuses a tube; [`PolarError::Limit`] over the budget or when stopped.
    pub fn to_solid(&self) -> Result<Mesh, PolarError> {
        let m = self.mesh();
        for (i, h) in m.edges().enumerate() {
            crate::limits::poll_at(i)?;
            let (a, b) = (m.origin(h), m.target(h));
            if self.position(a) == self.position(b) {
                return Err(PolarError::Solid(format!(
                    "vertices {} and {} lie at one point {:?}: a segment of zero length bounds no solid (grow it with a positive length)",
                    a.min(b),
                    a.max(b),
                    self.position(a).to_array()
                )));
            }
        }
        // Progress: each tube, then their union as much again.
        let mut work: Option<(crate::limits::Work, u64)> = None;
        let pieces = self.solid_pieces(&mut |t, tubes| {
            let (work, _) = work.get_or_insert_with(|| (crate::limits::Work::start(2 * tubes as u64), tubes as u64));
            work.set(t as u64);
        })?;
        let (work, tubes) = work.unwrap_or_else(|| (crate::limits::Work::start(0), 0));
        work.set(tubes);
        let parts: Vec<Csg> = pieces.into_iter().map(|p| Csg::mesh(p.mesh)).collect();
        let Some(tree) = Csg::union_all(parts) else {
            return Err(PolarError::Internal("a polar mesh without faces".into()));
        };
        let solid = tree.evaluate().map_err(|e| match e {
            crate::csg::CsgError::Limit(l) => PolarError::Limit(l),
            e => PolarError::Solid(format!("the boolean engine refused the tubes: {e}")),
        })?;
        work.finish();
        let solid = without_cavities(solid)?;
        // A loop round a hole (not across a limb) fills the hole: fewer handles than the mesh,
        // or a piece left apart. More handles come from branches that cross or touch each other
        // as well as their parent (thick branches at narrow angles, sibling branches turned the
        // same way): the tubes enclose tunnels between them, which belong to their union — kept
        // when the union is a valid solid, closed and manifold with no two triangles crossing.
        let (want, got) = (self.mesh().genus(), solid.genus());
        let (parts, mesh_parts) = (solid.component_count(), self.mesh().component_count());
        let not_tubes = |why: &str| PolarError::NotTubes {
            reason: format!(
                "the union of its tubes has genus {got} in {parts} part(s), \
                 the mesh genus {want} in {mesh_parts}: {why}"
            ),
        };
        if got < want || parts != mesh_parts {
            return Err(not_tubes("a loop runs round a hole instead of across a limb"));
        }
        if got > want {
            let valid = solid.is_closed()
                && solid.is_manifold()
                && crate::diagnose::self_intersections(&solid)
                    .map_err(|e| PolarError::Solid(e.to_string()))?
                    .is_empty();
            if !valid {
                return Err(not_tubes(
                    "branches cross each other as well as their parent and their union touches itself (grow with a wider angle or thinner branches)",
                ));
            }
        }
        Ok(solid)
    }

    /// The pieces whose union is [`PolarMesh::to_solid`]: each tube, facing outwards, or where
    /// a tube's own faces cross, its regions one by one, each standing in as its convex hull
    /// where its own faces cross (see the module doc of `to_solid`, "Stand-ins"). Tells
    /// `at_tube(t, tubes)` as it starts on each tube.
    pub(crate) fn solid_pieces(&self, at_tube: &mut dyn FnMut(usize, usize)) -> Result<Vec<SolidPiece>, PolarError> {
        let sk = self.skeleton(None)?;
        let apexes: Vec<Vec3> = (0..sk.node_count() as u32).map(|n| self.apex_of(&sk, n)).collect();
        let tube_of_segment = self.tube_of_segment(&sk);
        let tubes = self.capped(&sk, &tube_of_segment)?;
        // Regions as pieces of their own, built only if some tube crosses itself.
        let mut regions: Option<Vec<Vec<Vec<u32>>>> = None;
        let mut pieces = Vec::with_capacity(tubes.len());
        for (t, polys) in tubes.iter().enumerate() {
            crate::limits::poll_at(t)?;
            at_tube(t, tubes.len());
            let tube = piece_mesh(self, &sk, &apexes, polys)?;
            if !crosses_itself(&tube)? {
                pieces.push(SolidPiece::new(tube, false)?);
                continue;
            }
            if regions.is_none() {
                let own: Vec<usize> = (0..sk.segment_count()).collect();
                regions = Some(self.capped(&sk, &own)?);
            }
            let regions = regions.as_ref().map_or(&[][..], Vec::as_slice);
            for s in (0..sk.segment_count()).filter(|&s| tube_of_segment[s] == t) {
                let region = piece_mesh(self, &sk, &apexes, &regions[s])?;
                let crosses = crosses_itself(&region)?;
                pieces.push(SolidPiece::new(region, crosses)?);
            }
        }
        Ok(pieces)
    }

    /// The tube of each skeleton segment: regions joined across loop nodes that exactly two
    /// regions meet.
    pub(crate) fn tube_of_segment(&self, sk: &Skeleton) -> Vec<usize> {
        let ns = sk.segment_count();
        let mut dsu = Dsu::new(ns);
        for n in 0..sk.node_count() as u32 {
            let adj = sk.neighbors(n);
            if !sk.is_pole(n) && adj.len() == 2 && adj[0].0 != adj[1].0 {
                dsu.union(adj[0].0, adj[1].0);
            }
        }
        let mut tube_of_root: HashMap<u32, usize> = HashMap::new();
        (0..ns as u32)
            .map(|s| {
                let r = dsu.find(s);
                let next = tube_of_root.len();
                *tube_of_root.entry(r).or_insert(next)
            })
            .collect()
    }

    /// Pieces of the surface, `piece_of_segment[s]` the piece of region `s` (numbered from 0
    /// without gaps): each piece's faces as polygons of polar vertex ids, then a cone triangle
    /// on each of its boundary edges whose third corner `u32::MAX - node` stands for the apex of
    /// the edge's loop node.
    pub(crate) fn capped(&self, sk: &Skeleton, piece_of_segment: &[usize]) -> Result<Vec<Vec<Vec<u32>>>, PolarError> {
        let m = self.mesh();
        let count = piece_of_segment.iter().max().map_or(0, |&x| x + 1);
        let mut polygons: Vec<Vec<Vec<u32>>> = vec![Vec::new(); count];
        let piece_of_face = |f: u32| piece_of_segment[sk.segment_of_face(f) as usize];
        for f in 0..m.face_count() as u32 {
            crate::limits::poll_at(f as usize)?;
            let t = piece_of_face(f);
            polygons[t].push(m.face_vertices(f).collect());
            for h in m.face_halfedges(f) {
                if piece_of_face(m.face(m.twin(h))) == t {
                    continue;
                }
                let (u, v) = (m.origin(h), m.target(h));
                let n = sk.node_of(u);
                if sk.node_of(v) != n || sk.is_pole(n) {
                    return Err(PolarError::Internal(format!(
                        "the boundary edge {u}–{v} of a tube is no edge of one loop complex"
                    )));
                }
                polygons[t].push(vec![v, u, apex(n)]);
            }
        }
        Ok(polygons)
    }

    /// Where the cones at loop node `n` meet: the mean of the vertices of the loop by which the
    /// tree reaches `n` from the root (its parent region's boundary at `n`: for a nesting loop,
    /// the whole loop below the gaps, so the tube below is capped flat in the loop's own plane
    /// and the branches' cones reach down to the parent's axis), or the node's position at a
    /// root. Not the mean of the whole loop complex: the gaps' far sides stand a quarter
    /// segment ahead, and on the short segments of a plant's last steps cones to that point
    /// crossed the tube's other end.
    fn apex_of(&self, sk: &Skeleton, n: u32) -> Vec3 {
        let m = self.mesh();
        let Some(s) = sk.parent_segment(n) else { return sk.position(n) };
        let mut sum = Vec3::ZERO;
        let mut count = 0usize;
        for &f in sk.segment_faces(s) {
            for h in m.face_halfedges(f) {
                let (u, v) = (m.origin(h), m.target(h));
                if self.is_loop(h) && sk.node_of(u) == n && sk.node_of(v) == n {
                    sum += self.position(u);
                    count += 1;
                }
            }
        }
        if count == 0 {
            sk.position(n)
        } else {
            sum / count as f64
        }
    }
}

/// One operand of the union [`PolarMesh::to_solid`] makes.
pub(crate) struct SolidPiece {
    /// A closed, manifold triangle mesh of positive volume.
    pub mesh: Mesh,
    /// Whether it is the convex hull standing in for a region whose own faces cross.
    /// (Read by the tests, which measure where the solid exceeds the union of the tubes.)
    #[cfg_attr(not(test), allow(dead_code))]
    pub stand_in: bool,
    /// Whether it is a tube or region turned outwards (an everted branch,
    /// `SolidPiece::new`).
    #[cfg_attr(not(test), allow(dead_code))]
    pub everted: bool,
}

/// One piece as a closed triangle mesh: its polygons (from [`PolarMesh::capped`]) on their own
/// vertices, each apex at `apexes[node]`, triangulated here so that the self-intersection check
/// and the engine see the same triangles. A piece meeting one node along two separate loops (a
/// region that runs round a cycle of the skeleton) would pinch at the apex: refused.
fn piece_mesh(pm: &PolarMesh, sk: &Skeleton, apexes: &[Vec3], polys: &[Vec<u32>]) -> Result<Mesh, PolarError> {
    let nv = pm.vertex_count();
    // Per apex node: the piece's vertices off that node (their mean sets the way out) and the
    // boundary vertices on it (their distance from the centre sets the reach).
    let mut off: HashMap<u32, (Vec3, usize)> = HashMap::new();
    let mut rim: HashMap<u32, (f64, usize)> = HashMap::new();
    for p in polys {
        if let [a, b, x] = p[..] {
            if x as usize >= nv {
                let n = u32::MAX - x;
                for v in [a, b] {
                    let e = rim.entry(n).or_insert((0.0, 0));
                    e.0 += pm.position(v).distance(apexes[n as usize]);
                    e.1 += 1;
                }
            }
        }
    }
    let mut all = (Vec3::ZERO, 0usize);
    for p in polys {
        for &v in p.iter().filter(|&&v| (v as usize) < nv) {
            all.0 += pm.position(v);
            all.1 += 1;
            for &n in rim.keys() {
                if sk.node_of(v) != n {
                    let o = off.entry(n).or_insert((Vec3::ZERO, 0));
                    o.0 += pm.position(v);
                    o.1 += 1;
                }
            }
        }
    }
    let apex_at = |n: u32| {
        let c = apexes[n as usize];
        let (r, k) = rim.get(&n).copied().unwrap_or((0.0, 1));
        let reach = REACH * r / k.max(1) as f64;
        let (sum, count) = off.get(&n).copied().filter(|o| o.1 > 0).unwrap_or(all);
        let inside = if count > 0 { sum / count as f64 } else { c };
        c + (c - inside).normalize_or_zero() * reach
    };
    let mut local: HashMap<u32, u32> = HashMap::new();
    let mut positions: Vec<Vec3> = Vec::new();
    let faces: Vec<Vec<u32>> = polys
        .iter()
        .map(|p| {
            p.iter()
                .map(|&v| {
                    *local.entry(v).or_insert_with(|| {
                        positions.push(if v as usize >= nv { apex_at(u32::MAX - v) } else { pm.position(v) });
                        (positions.len() - 1) as u32
                    })
                })
                .collect()
        })
        .collect();
    let not_tubes = |e: String| PolarError::NotTubes {
        reason: format!(
            "a tube does not close into a manifold ({e}): a region meets one loop along two separate cycles"
        ),
    };
    let mut piece = Mesh::from_polygons(positions, &faces).map_err(|e| not_tubes(e.to_string()))?;
    if let Some(parents) = parent_faces(pm, polys) {
        piece.inherit_parts(pm.mesh(), &parents).map_err(|e| PolarError::Internal(e.to_string()))?;
    }
    if !piece.is_closed() || !piece.is_manifold() {
        return Err(not_tubes("open or not manifold".into()));
    }
    piece.triangulate().map_err(|e| PolarError::Solid(e.to_string()))
}

/// For each of a piece's polygons, the polar face whose colour and origin it takes: itself, or
/// for a cap triangle `[a, b, apex]` the face across its rim edge (the one holding `b → a`).
/// `None` when the polar mesh has no parts to carry.
fn parent_faces(pm: &PolarMesh, polys: &[Vec<u32>]) -> Option<Vec<u32>> {
    let m = pm.mesh();
    m.face_part_ids()?;
    let nv = pm.vertex_count();
    let face_of = |a: u32, b: u32| m.find_halfedge(a, b).map(|h| m.face(h));
    Some(
        polys
            .iter()
            .map(|p| match p[..] {
                [a, b, x] if x as usize >= nv => face_of(b, a),
                _ => face_of(p[0], p[1]),
            })
            .map(|f| f.unwrap_or(0))
            .collect(),
    )
}

impl SolidPiece {
    /// `piece` bounding positive volume — reversed when its faces face inwards — or with
    /// `stand_in`, its convex hull. A branch grown from a gap on the far side of its direction
    /// (two sibling branches turned the same way at one node take two gaps of the parent's loop,
    /// and the second faces away from where it grows) runs through its parent and comes out
    /// everted: its loops wind the other way round its axis.
    fn new(piece: Mesh, stand_in: bool) -> Result<SolidPiece, PolarError> {
        let everted = piece.volume() < 0.0;
        let piece = if everted { piece.reversed() } else { piece };
        let mesh = if stand_in { hull_of(&piece)? } else { piece };
        Ok(SolidPiece { mesh, stand_in, everted })
    }
}

/// Whether a piece's triangles cross or touch each other away from what they share (exact,
/// [`crate::diagnose::self_intersections`]).
fn crosses_itself(piece: &Mesh) -> Result<bool, PolarError> {
    Ok(!crate::diagnose::self_intersections(piece).map_err(|e| PolarError::Solid(e.to_string()))?.is_empty())
}

/// The convex hull of a piece's vertices (its apexes included, so the cones' volume that its
/// neighbours' cones meet is covered): the stand-in for a region whose own faces cross.
/// It takes the colour and origin of the piece's first face.
fn hull_of(piece: &Mesh) -> Result<Mesh, PolarError> {
    let mut hull = crate::profile::hull_points(piece.positions())
        .map_err(|e| PolarError::Solid(format!("the hull of a region: {e}")))?;
    let parents = vec![0; hull.face_count()];
    hull.inherit_parts(piece, &parents).map_err(|e| PolarError::Internal(e.to_string()))?;
    Ok(hull)
}

/// `solid` without its cavities: the shells of negative volume. The polar mesh is one closed
/// surface per part and bounds no cavity; where the caps of several pieces meet at a branching
/// (each poking past the loop's centre its own way) a sliver between them can stay uncovered
/// (measured: one of 3.6e-6 in a plant of volume 0.49), which the union keeps as an inner shell.
/// Filling it is what the union of the tubes means.
fn without_cavities(solid: Mesh) -> Result<Mesh, PolarError> {
    let parts = solid.face_components();
    if parts.len() < 2 {
        return Ok(solid);
    }
    let volume = |faces: &[u32]| -> f64 {
        faces
            .iter()
            .map(|&f| {
                let p: Vec<Vec3> = solid.face_vertices(f).map(|v| solid.position(v)).collect();
                (1..p.len() - 1).map(|k| p[0].dot(p[k].cross(p[k + 1]))).sum::<f64>() / 6.0
            })
            .sum()
    };
    let kept: Vec<&Vec<u32>> = parts.iter().filter(|c| volume(c) > 0.0).collect();
    if kept.len() == parts.len() {
        return Ok(solid);
    }
    let mut local: HashMap<u32, u32> = HashMap::new();
    let mut positions = Vec::new();
    let parents: Vec<u32> = kept.iter().flat_map(|c| c.iter().copied()).collect();
    let faces: Vec<Vec<u32>> = parents
        .iter()
        .map(|&f| {
            solid
                .face_vertices(f)
                .map(|v| {
                    *local.entry(v).or_insert_with(|| {
                        positions.push(solid.position(v));
                        (positions.len() - 1) as u32
                    })
                })
                .collect()
        })
        .collect();
    let mut out = Mesh::from_polygons(positions, &faces).map_err(|e| PolarError::Solid(e.to_string()))?;
    out.inherit_parts(&solid, &parents).map_err(|e| PolarError::Internal(e.to_string()))?;
    Ok(out)
}
