//! One block: a generalised cuboid of 8 free corners and 6 bilinear faces, each divided into its
//! own grid of sub-faces, with sharp or smooth edges and a group id (seed 000 §2.1).
//!
//! # Notation
//! - **Corners** `0..8`: bit `i` of the index says whether the corner is on the high side of axis
//!   `i` (x, y, z): corner `k` of an axis-aligned block is
//!   `(k&1 ? max.x : min.x, k&2 ? max.y : min.y, k&4 ? max.z : min.z)`.
//! - **Faces** `-x +x -y +y -z +z` ([`Face`]). On a face of axis `a`, the parameter `u` runs along
//!   the first of the two other axes in x, y, z order and `v` along the second (on `+y`, u along x
//!   and v along z), from the low corner to the high one. A face is the bilinear patch of its four
//!   corners over (u, v) ∈ [0, 1]²; it need not be planar.
//! - **Sub-faces**: a face divided `nu × nv` has sub-faces `i + nu * j` (0 ≤ i < nu, 0 ≤ j < nv)
//!   spanning u ∈ [i/nu, (i+1)/nu], v ∈ [j/nv, (j+1)/nv].
//! - **Edges** ([`Edge`]): the 12 block edges, named by their two faces, lower axis first
//!   (`"+x+y"`, `"-x-z"`, `"+y-z"`); either order is accepted when parsing.

use crate::math::{is_finite, lerp, Quat, Vec3};
use crate::mesh::Rgba;

use super::BlockError;

/// The largest coordinate magnitude a corner may have: distances, areas and volumes of larger
/// blocks overflow.
pub const MAX_COORDINATE: f64 = 1e100;

/// The most sub-faces along one direction of a face.
pub const MAX_SUBDIVISIONS: u32 = 256;

/// One of the six faces of a block.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Face {
    /// The low-x face.
    NegX = 0,
    /// The high-x face.
    PosX = 1,
    /// The low-y face.
    NegY = 2,
    /// The high-y face.
    PosY = 3,
    /// The low-z face.
    NegZ = 4,
    /// The high-z face.
    PosZ = 5,
}

impl Face {
    /// The six faces in index order.
    pub const ALL: [Face; 6] = [Face::NegX, Face::PosX, Face::NegY, Face::PosY, Face::NegZ, Face::PosZ];

    /// The face of `axis` (0, 1, 2) on its high (`true`) or low side.
    #[must_use]
    pub fn from_axis(axis: usize, high: bool) -> Face {
        Face::ALL[axis * 2 + usize::from(high)]
    }

    /// The face's index `0..6` (`-x +x -y +y -z +z`).
    #[must_use]
    pub fn index(self) -> usize {
        self as usize
    }

    /// The face of index `i` (see [`Face::index`]), `None` from 6 up.
    #[must_use]
    pub fn from_index(i: usize) -> Option<Face> {
        Face::ALL.get(i).copied()
    }

    /// The axis the face is normal to: 0, 1 or 2.
    #[must_use]
    pub fn axis(self) -> usize {
        self as usize / 2
    }

    /// Whether the face is on the high side of its axis.
    #[must_use]
    pub fn is_high(self) -> bool {
        self as usize % 2 == 1
    }

    /// The face's name, `"-x"` … `"+z"`.
    #[must_use]
    pub fn name(self) -> &'static str {
        ["-x", "+x", "-y", "+y", "-z", "+z"][self as usize]
    }

    /// The face named `name`.
    ///
    /// # Errors
    /// [`BlockError::UnknownFace`] for anything but `-x +x -y +y -z +z`.
    pub fn parse(name: &str) -> Result<Face, BlockError> {
        Face::ALL.into_iter().find(|f| f.name() == name).ok_or_else(|| BlockError::UnknownFace { name: name.into() })
    }

    /// The axes u and v run along: the two other axes in x, y, z order.
    #[must_use]
    pub fn uv_axes(self) -> (usize, usize) {
        match self.axis() {
            0 => (1, 2),
            1 => (0, 2),
            _ => (0, 1),
        }
    }

    /// Whether ∂/∂u × ∂/∂v points out of the block (it does on `+x`, `-y` and `+z`).
    #[must_use]
    pub fn uv_is_outward(self) -> bool {
        self.is_high() != (self.axis() == 1)
    }

    /// The corner at (u, v) = (`s`, `t`) of this face, `s`, `t` ∈ {0, 1}.
    #[must_use]
    pub fn corner(self, s: usize, t: usize) -> usize {
        let (p, q) = self.uv_axes();
        (usize::from(self.is_high()) << self.axis()) | (s << p) | (t << q)
    }
}

/// One of the twelve edges of a block: `axis * 4 + bit(a) + 2 * bit(b)` where the edge runs along
/// `axis` and `a < b` are the two other axes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Edge(u8);

impl Edge {
    /// The edge's index `0..12`.
    #[must_use]
    pub fn index(self) -> usize {
        self.0 as usize
    }

    /// The edge of index `i` (`i < 12`).
    #[must_use]
    pub fn from_index(i: usize) -> Edge {
        Edge((i % 12) as u8)
    }

    /// All twelve edges.
    pub fn all() -> impl Iterator<Item = Edge> {
        (0..12u8).map(Edge)
    }

    /// The axis the edge runs along.
    #[must_use]
    pub fn axis(self) -> usize {
        self.0 as usize / 4
    }

    fn other_axes(axis: usize) -> (usize, usize) {
        match axis {
            0 => (1, 2),
            1 => (0, 2),
            _ => (0, 1),
        }
    }

    /// The edge along `axis` through corner `corner` (the corner's bit on `axis` is ignored).
    #[must_use]
    pub fn along(axis: usize, corner: usize) -> Edge {
        let (a, b) = Edge::other_axes(axis);
        Edge((axis * 4 + ((corner >> a) & 1) + 2 * ((corner >> b) & 1)) as u8)
    }

    /// The edge where faces `f` and `g` meet, `None` when they are the same or opposite.
    #[must_use]
    pub fn between(f: Face, g: Face) -> Option<Edge> {
        if f.axis() == g.axis() {
            return None;
        }
        let axis = 3 - f.axis() - g.axis();
        let corner = (usize::from(f.is_high()) << f.axis()) | (usize::from(g.is_high()) << g.axis());
        Some(Edge::along(axis, corner))
    }

    /// The two faces that meet at this edge, lower axis first.
    #[must_use]
    pub fn faces(self) -> (Face, Face) {
        let (a, b) = Edge::other_axes(self.axis());
        let i = self.0 as usize % 4;
        (Face::from_axis(a, i & 1 == 1), Face::from_axis(b, i & 2 == 2))
    }

    /// The edge's name, e.g. `"+x+y"` (lower axis first).
    #[must_use]
    pub fn name(self) -> String {
        let (f, g) = self.faces();
        format!("{}{}", f.name(), g.name())
    }

    /// The edge named by two faces in either order, e.g. `"+x+y"` or `"+y+x"`.
    ///
    /// # Errors
    /// [`BlockError::UnknownEdge`] for anything else (opposite faces included).
    pub fn parse(name: &str) -> Result<Edge, BlockError> {
        let bad = || BlockError::UnknownEdge { name: name.into() };
        if name.len() != 4 || !name.is_char_boundary(2) {
            return Err(bad());
        }
        let f = Face::parse(&name[..2]).map_err(|_| bad())?;
        let g = Face::parse(&name[2..]).map_err(|_| bad())?;
        Edge::between(f, g).ok_or_else(bad)
    }

    /// The edge's two corners: the low end and the high end along its axis.
    #[must_use]
    pub fn corners(self) -> (usize, usize) {
        let (a, b) = Edge::other_axes(self.axis());
        let i = self.0 as usize % 4;
        let low = ((i & 1) << a) | (((i >> 1) & 1) << b);
        (low, low | (1 << self.axis()))
    }
}

/// A block: 8 corners, per-face sub-face grids, per-edge sharpness, a group id and a colour.
///
/// An edge's sharpness is 0 (smooth), `f64::INFINITY` (sharp: a crease at every level) or between
/// (semi-sharp: DeRose, Kass & Truong 1998 §3 as OpenSubdiv applies it, the crease rules for that
/// many levels, then smooth — a bevelled edge on a smooth block, rounder as the value falls).
///
/// Made by [`Block::from_bounds`] or [`Block::from_corners`], which validate the corners. Every
/// face starts undivided (1 × 1), every edge smooth, the group 0. Changes are all or nothing: an
/// operation that fails leaves the block as it was.
#[derive(Clone, Debug, PartialEq)]
pub struct Block {
    corners: [Vec3; 8],
    divisions: [[u32; 2]; 6],
    sharp: [f64; 12],
    group: i64,
    color: Option<Rgba>,
}

impl Block {
    /// The axis-aligned block from `min` to `max`.
    ///
    /// # Errors
    /// As [`Block::from_corners`]: a zero extent is [`BlockError::CoincidentCorners`], `min > max`
    /// on an axis [`BlockError::Inverted`].
    pub fn from_bounds(min: Vec3, max: Vec3) -> Result<Block, BlockError> {
        let c = |k: usize| {
            Vec3::new(
                if k & 1 != 0 { max.x } else { min.x },
                if k & 2 != 0 { max.y } else { min.y },
                if k & 4 != 0 { max.z } else { min.z },
            )
        };
        Block::from_corners([c(0), c(1), c(2), c(3), c(4), c(5), c(6), c(7)])
    }

    /// The block with these 8 corners, in the order of the [module documentation](self).
    ///
    /// # Errors
    /// - [`BlockError::NonFinite`] for a NaN or infinite coordinate;
    /// - [`BlockError::TooFar`] for a coordinate beyond ±[`MAX_COORDINATE`];
    /// - [`BlockError::CoincidentCorners`] for two corners closer than 1e-12 of the block's size;
    /// - [`BlockError::FoldedFace`] when a face's corners cross;
    /// - [`BlockError::Inverted`] when the corner frame (the three edges leaving a corner toward
    ///   higher x, y, z) is left-handed or flat at some corner.
    pub fn from_corners(corners: [Vec3; 8]) -> Result<Block, BlockError> {
        validate(&corners)?;
        Ok(Block { corners, divisions: [[1, 1]; 6], sharp: [0.0; 12], group: 0, color: None })
    }

    /// The 8 corners.
    #[must_use]
    pub fn corners(&self) -> &[Vec3; 8] {
        &self.corners
    }

    /// The sub-face grid of `face`: `(nu, nv)`.
    #[must_use]
    pub fn divisions(&self, face: Face) -> (u32, u32) {
        let [nu, nv] = self.divisions[face.index()];
        (nu, nv)
    }

    /// Number of sub-faces of `face`.
    #[must_use]
    pub fn subface_count(&self, face: Face) -> u32 {
        let (nu, nv) = self.divisions(face);
        nu * nv
    }

    /// Divides `face` into `nu × nv` sub-faces.
    ///
    /// # Errors
    /// [`BlockError::ZeroSubdivisions`] for `nu` or `nv` below 1,
    /// [`BlockError::TooManySubdivisions`] above [`MAX_SUBDIVISIONS`].
    pub fn subdivide(&mut self, face: Face, nu: i64, nv: i64) -> Result<(), BlockError> {
        if nu < 1 || nv < 1 {
            return Err(BlockError::ZeroSubdivisions { face: face.name(), nu, nv });
        }
        let max = i64::from(MAX_SUBDIVISIONS);
        if nu > max || nv > max {
            return Err(BlockError::TooManySubdivisions { face: face.name(), nu, nv, max: MAX_SUBDIVISIONS });
        }
        self.divisions[face.index()] = [nu as u32, nv as u32];
        Ok(())
    }

    /// Whether `edge` is sharp or semi-sharp (sharpness above 0).
    #[must_use]
    pub fn is_sharp(&self, edge: Edge) -> bool {
        self.sharp[edge.index()] > 0.0
    }

    /// The sharpness of `edge`: 0 smooth, `f64::INFINITY` sharp, between semi-sharp.
    #[must_use]
    pub fn sharpness(&self, edge: Edge) -> f64 {
        self.sharp[edge.index()]
    }

    /// Tags `edge` sharp (`true`, infinitely) or smooth.
    pub fn set_sharp(&mut self, edge: Edge, sharp: bool) {
        self.sharp[edge.index()] = if sharp { f64::INFINITY } else { 0.0 };
    }

    /// Sets the sharpness of `edge` (0 smooth, `f64::INFINITY` or 10 and more sharp).
    ///
    /// # Errors
    /// [`BlockError::BadSharpness`] for NaN or a negative value; the block is unchanged.
    pub fn set_sharpness(&mut self, edge: Edge, sharpness: f64) -> Result<(), BlockError> {
        if sharpness.is_nan() || sharpness < 0.0 {
            return Err(BlockError::BadSharpness { edge: edge.name(), sharpness });
        }
        self.sharp[edge.index()] = sharpness;
        Ok(())
    }

    /// Tags every edge sharp.
    pub fn sharp_all(&mut self) {
        self.sharp = [f64::INFINITY; 12];
    }

    /// Gives every edge the crease `sharpness` (0 smooth, 10 and more sharp, between
    /// semi-sharp).
    ///
    /// # Errors
    /// [`BlockError::BadSharpness`] for NaN or a negative value; the block is unchanged.
    pub fn set_sharpness_all(&mut self, sharpness: f64) -> Result<(), BlockError> {
        if sharpness.is_nan() || sharpness < 0.0 {
            return Err(BlockError::BadSharpness { edge: "every edge".into(), sharpness });
        }
        self.sharp = [sharpness; 12];
        Ok(())
    }

    /// Tags every edge smooth.
    pub fn smooth_all(&mut self) {
        self.sharp = [0.0; 12];
    }

    /// The group id.
    #[must_use]
    pub fn group(&self) -> i64 {
        self.group
    }

    /// Sets the group id.
    pub fn set_group(&mut self, group: i64) {
        self.group = group;
    }

    /// The colour of the block's surface, if set: the faces the meshing makes from its sub-faces
    /// carry it (and keep it through booleans, as a mesh's colours do).
    #[must_use]
    pub fn color(&self) -> Option<Rgba> {
        self.color
    }

    /// Sets (`Some`) or clears (`None`) the block's colour.
    ///
    /// # Errors
    /// [`BlockError::BadColor`] for a component outside `0..=1` (NaN included); the block is
    /// unchanged.
    pub fn set_color(&mut self, color: Option<Rgba>) -> Result<(), BlockError> {
        if let Some(c) = color {
            if let Some(component) = c.iter().position(|x| !(0.0..=1.0).contains(x)) {
                return Err(BlockError::BadColor { component, value: f64::from(c[component]) });
            }
        }
        self.color = color;
        Ok(())
    }

    /// Moves the block by `offset`.
    ///
    /// # Errors
    /// [`BlockError::NonFinite`] or [`BlockError::TooFar`] when the offset takes a coordinate out
    /// of range; the block is unchanged.
    pub fn translate(&mut self, offset: Vec3) -> Result<(), BlockError> {
        let mut c = self.corners;
        c.iter_mut().for_each(|p| *p += offset);
        self.set_corners(c)
    }

    /// Turns the block by `degrees` about `axis` through the origin (right-handed); a zero axis
    /// leaves it as it is.
    ///
    /// # Errors
    /// [`BlockError::NonFinite`] for a non-finite angle; the block is unchanged.
    pub fn rotate(&mut self, axis: Vec3, degrees: f64) -> Result<(), BlockError> {
        let Some(axis) = axis.try_normalize() else { return Ok(()) };
        let q = Quat::from_axis_angle(axis, degrees.to_radians());
        let mut c = self.corners;
        c.iter_mut().for_each(|p| *p = q * *p);
        self.set_corners(c)
    }

    /// Replaces the corners, keeping grids, tags and group.
    ///
    /// # Errors
    /// As [`Block::from_corners`]; the block is unchanged on error.
    pub fn set_corners(&mut self, corners: [Vec3; 8]) -> Result<(), BlockError> {
        validate(&corners)?;
        self.corners = corners;
        Ok(())
    }

    /// The point at (u, v) of `face` (bilinear in its four corners).
    #[must_use]
    pub fn face_point(&self, face: Face, u: f64, v: f64) -> Vec3 {
        let c = |s, t| self.corners[face.corner(s, t)];
        let bottom = lerp(c(0, 0), c(1, 0), u);
        let top = lerp(c(0, 1), c(1, 1), u);
        lerp(bottom, top, v)
    }

    /// Checks that `sub` names a sub-face of `face`.
    ///
    /// # Errors
    /// [`BlockError::SubFaceOutOfRange`] otherwise.
    pub fn check_subface(&self, face: Face, sub: i64) -> Result<u32, BlockError> {
        let count = self.subface_count(face);
        if sub < 0 || sub >= i64::from(count) {
            return Err(BlockError::SubFaceOutOfRange { face: face.name(), sub, count });
        }
        Ok(sub as u32)
    }

    /// The (u, v) of the four corners of sub-face `sub` of `face`, counter-clockwise seen from
    /// outside the block, starting at its low-u low-v corner.
    #[must_use]
    pub fn subface_uv(&self, face: Face, sub: u32) -> [[f64; 2]; 4] {
        let (nu, nv) = self.divisions(face);
        let (i, j) = (sub % nu, sub / nu);
        let (u0, u1) = (f64::from(i) / f64::from(nu), f64::from(i + 1) / f64::from(nu));
        let (v0, v1) = (f64::from(j) / f64::from(nv), f64::from(j + 1) / f64::from(nv));
        if face.uv_is_outward() {
            [[u0, v0], [u1, v0], [u1, v1], [u0, v1]]
        } else {
            [[u0, v0], [u0, v1], [u1, v1], [u1, v0]]
        }
    }

    /// The four corners of sub-face `sub` of `face`, in the order of [`Block::subface_uv`].
    #[must_use]
    pub fn subface_corners(&self, face: Face, sub: u32) -> [Vec3; 4] {
        self.subface_uv(face, sub).map(|[u, v]| self.face_point(face, u, v))
    }

    /// The block's volume: the hexahedron with each face split into four triangles about its
    /// centre (exact for planar faces).
    #[must_use]
    pub fn volume(&self) -> f64 {
        let mut six_v = 0.0;
        for face in Face::ALL {
            let q = self.subface_corners_full(face);
            let c = (q[0] + q[1] + q[2] + q[3]) * 0.25;
            for k in 0..4 {
                six_v += c.dot(q[k].cross(q[(k + 1) % 4]));
            }
        }
        six_v / 6.0
    }

    /// The four corners of a whole face, counter-clockwise seen from outside.
    fn subface_corners_full(&self, face: Face) -> [Vec3; 4] {
        let c = |s, t| self.corners[face.corner(s, t)];
        if face.uv_is_outward() {
            [c(0, 0), c(1, 0), c(1, 1), c(0, 1)]
        } else {
            [c(0, 0), c(0, 1), c(1, 1), c(1, 0)]
        }
    }
}

/// The validity checks of [`Block::from_corners`].
fn validate(c: &[Vec3; 8]) -> Result<(), BlockError> {
    if let Some(k) = c.iter().position(|p| !is_finite(*p)) {
        return Err(BlockError::NonFinite { corner: k, x: c[k].x, y: c[k].y, z: c[k].z });
    }
    if let Some(k) = c.iter().position(|p| p.abs().max_element() > MAX_COORDINATE) {
        return Err(BlockError::TooFar { corner: k, value: c[k].abs().max_element() });
    }
    let (lo, hi) = c.iter().fold((c[0], c[0]), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
    let size = (hi - lo).length();
    for a in 0..8 {
        for b in a + 1..8 {
            if c[a].distance(c[b]) <= 1e-12 * size {
                return Err(BlockError::CoincidentCorners { a, b });
            }
        }
    }
    let probe = Block { corners: *c, divisions: [[1, 1]; 6], sharp: [0.0; 12], group: 0, color: None };
    for face in Face::ALL {
        let q = probe.subface_corners_full(face);
        let n = (q[2] - q[0]).cross(q[3] - q[1]);
        for k in 0..4 {
            let t = (q[(k + 1) % 4] - q[k]).cross(q[(k + 3) % 4] - q[k]);
            if t.dot(n) <= 0.0 {
                return Err(BlockError::FoldedFace { face: face.name() });
            }
        }
    }
    for k in 0..8 {
        let e = |axis: usize| c[k | (1 << axis)] - c[k & !(1 << axis)];
        if e(0).dot(e(1).cross(e(2))) <= 0.0 {
            return Err(BlockError::Inverted { corner: k });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit() -> Block {
        Block::from_bounds(Vec3::ZERO, Vec3::ONE).unwrap()
    }

    #[test]
    fn corner_order_follows_the_bits_of_the_index() {
        let b = Block::from_bounds(Vec3::new(-1.0, -2.0, -3.0), Vec3::new(1.0, 2.0, 3.0)).unwrap();
        // Corner 6 = bits y and z: (min.x, max.y, max.z).
        assert_eq!(b.corners()[6], Vec3::new(-1.0, 2.0, 3.0));
        assert_eq!(b.corners()[1], Vec3::new(1.0, -2.0, -3.0));
        // 2 × 4 × 6.
        assert!((b.volume() - 48.0).abs() < 1e-12, "{}", b.volume());
    }

    #[test]
    fn face_parameters_run_along_the_other_axes_in_order() {
        let b = unit();
        // On +y, u runs along x and v along z.
        assert_eq!(b.face_point(Face::PosY, 0.25, 0.75), Vec3::new(0.25, 1.0, 0.75));
        assert_eq!(b.face_point(Face::NegX, 0.25, 0.75), Vec3::new(0.0, 0.25, 0.75));
        assert_eq!(b.face_point(Face::PosZ, 0.25, 0.75), Vec3::new(0.25, 0.75, 1.0));
    }

    #[test]
    fn subface_corners_wind_counter_clockwise_from_outside() {
        let mut b = unit();
        for face in Face::ALL {
            b.subdivide(face, 3, 2).unwrap();
            let outward = {
                let mut n = Vec3::ZERO;
                n[face.axis()] = if face.is_high() { 1.0 } else { -1.0 };
                n
            };
            for s in 0..6 {
                let q = b.subface_corners(face, s);
                let n = (q[2] - q[0]).cross(q[3] - q[1]);
                assert!(n.dot(outward) > 0.0, "face {} sub {s}: {n}", face.name());
            }
            // Sub-face i + nu * j: sub 4 = (1, 1) spans u ∈ [1/3, 2/3], v ∈ [1/2, 1].
            let uv = b.subface_uv(face, 4);
            assert!(uv.contains(&[1.0 / 3.0, 0.5]) && uv.contains(&[2.0 / 3.0, 1.0]));
        }
    }

    #[test]
    fn edges_are_named_by_their_faces_in_either_order() {
        let e = Edge::parse("+x+y").unwrap();
        assert_eq!(Edge::parse("+y+x").unwrap(), e);
        assert_eq!(e.name(), "+x+y");
        assert_eq!(e.axis(), 2);
        // The edge x = max, y = max runs from corner 3 to corner 7.
        assert_eq!(e.corners(), (3, 7));
        for edge in Edge::all() {
            assert_eq!(Edge::parse(&edge.name()).unwrap(), edge);
            let (f, g) = edge.faces();
            assert_eq!(Edge::between(g, f), Some(edge));
        }
        assert!(matches!(Edge::parse("+x-x"), Err(BlockError::UnknownEdge { .. })));
        assert!(matches!(Edge::parse("+x"), Err(BlockError::UnknownEdge { .. })));
        assert!(matches!(Face::parse("x"), Err(BlockError::UnknownFace { .. })));
    }

    #[test]
    fn bad_corners_are_typed_errors() {
        let one = Vec3::ONE;
        assert_eq!(
            Block::from_bounds(Vec3::ZERO, Vec3::new(1.0, 0.0, 1.0)),
            Err(BlockError::CoincidentCorners { a: 0, b: 2 })
        );
        assert!(matches!(Block::from_bounds(one, Vec3::ZERO), Err(BlockError::Inverted { .. })));
        assert!(matches!(
            Block::from_bounds(Vec3::ZERO, Vec3::new(f64::NAN, 1.0, 1.0)),
            Err(BlockError::NonFinite { .. })
        ));
        // Swapping two corners of the +z face folds it.
        let mut c = *unit().corners();
        c.swap(4, 5);
        assert!(matches!(Block::from_corners(c), Err(BlockError::FoldedFace { .. })));
        // A mirrored block is inside out.
        let m = unit().corners().map(|p| Vec3::new(-p.x, p.y, p.z));
        assert!(matches!(Block::from_corners(m), Err(BlockError::Inverted { .. })));
        // Huge coordinates would overflow distances (1e300² = inf) and be called coincident.
        let far = Block::from_bounds(Vec3::ZERO, Vec3::splat(1e300));
        assert!(matches!(far, Err(BlockError::TooFar { corner: 1, .. })), "{far:?}");
        assert!(Block::from_bounds(Vec3::ZERO, Vec3::splat(1e99)).is_ok());
    }

    #[test]
    fn failed_operations_leave_the_block_unchanged() {
        let mut b = unit();
        let before = b.clone();
        assert!(matches!(b.subdivide(Face::PosX, 0, 2), Err(BlockError::ZeroSubdivisions { .. })));
        assert!(matches!(b.subdivide(Face::PosX, 2, 100_000), Err(BlockError::TooManySubdivisions { .. })));
        assert!(b.translate(Vec3::new(f64::INFINITY, 0.0, 0.0)).is_err());
        assert!(matches!(b.translate(Vec3::new(0.0, 2e100, 0.0)), Err(BlockError::TooFar { .. })));
        assert!(b.rotate(Vec3::Z, f64::NAN).is_err());
        assert_eq!(b, before);
        assert!(matches!(b.check_subface(Face::PosX, 1), Err(BlockError::SubFaceOutOfRange { count: 1, .. })));
    }

    #[test]
    fn rigid_transforms_keep_the_volume() {
        let mut b = unit();
        b.rotate(Vec3::new(1.0, 2.0, 3.0), 37.0).unwrap();
        b.translate(Vec3::new(5.0, 0.0, 0.0)).unwrap();
        assert!((b.volume() - 1.0).abs() < 1e-12);
        // A skewed (non-planar) block is still valid.
        let mut c = *unit().corners();
        c[7] += Vec3::new(0.3, 0.2, 0.4);
        assert!(Block::from_corners(c).is_ok());
    }
}
