//! Rigid and affine transforms. Each returns a new mesh with the same vertex and face ids;
//! transforms that reverse orientation (mirrors, odd negative scales) reverse the faces so they
//! keep facing outward.

use super::Mesh;
use crate::math::{direction, translation_between, Mat3, Quat, Vec3};

impl Mesh {
    /// This mesh moved by `offset`.
    #[must_use]
    pub fn translate(&self, offset: Vec3) -> Mesh {
        self.map_positions(|p| p + offset)
    }

    /// This mesh turned by `degrees` about `axis` through the origin (right-handed); the axis
    /// may have any non-zero length. A zero axis leaves the mesh as it is.
    #[must_use]
    pub fn rotate(&self, axis: Vec3, degrees: f64) -> Mesh {
        let Some(axis) = direction(axis) else { return self.clone() };
        let q = Quat::from_axis_angle(axis, degrees.to_radians());
        self.map_positions(|p| q * p)
    }

    /// This mesh scaled about the origin by `factors` per axis. A negative product of factors
    /// reverses the faces so that they keep facing outward.
    #[must_use]
    pub fn scale(&self, factors: Vec3) -> Mesh {
        let m = self.map_positions(|p| p * factors);
        if factors.x * factors.y * factors.z < 0.0 {
            m.reversed()
        } else {
            m
        }
    }

    /// This mesh reflected through the plane through the origin with normal `normal`, faces
    /// reversed so that they keep facing outward. A zero normal leaves the mesh as it is.
    #[must_use]
    pub fn mirror(&self, normal: Vec3) -> Mesh {
        let Some(n) = direction(normal) else { return self.clone() };
        let reflect = Mat3::IDENTITY - 2.0 * Mat3::from_cols(n * n.x, n * n.y, n * n.z);
        self.map_positions(|p| reflect * p).reversed()
    }

    /// The same surface with every face's orientation reversed. Vertex and face ids are kept;
    /// half-edge ids are not.
    #[must_use]
    pub fn reversed(&self) -> Mesh {
        let faces: Vec<Vec<u32>> = self
            .to_polygons()
            .into_iter()
            .map(|mut f| {
                f.reverse();
                f
            })
            .collect();
        let mut m =
            Mesh::from_polygons(self.positions.clone(), &faces).expect("reversing a manifold mesh keeps it manifold");
        m.copy_attributes_from(self);
        m
    }

    /// The vector that moves `other` onto this mesh, when this mesh is `other` translated: the
    /// same vertices, faces, half-edges and attributes (creases, corners, colours, face sources
    /// and parts), and every vertex moved by one vector within `tolerance` per coordinate (the
    /// vector taken from the first vertex). `None` otherwise, or for a mesh without vertices.
    /// Linear, and cheap when the two differ (the counts and arrays are compared first).
    #[must_use]
    pub fn translation_from(&self, other: &Mesh, tolerance: f64) -> Option<Vec3> {
        // Every field but the positions, named, so that a field added to `Mesh` is compared too.
        let Mesh {
            positions,
            vertex_out,
            he_origin,
            he_next,
            he_prev,
            he_twin,
            he_face,
            face_he,
            he_sharpness,
            vertex_sharpness,
            subdiv_options,
            vertex_colors,
            face_sources,
            face_parts,
            parts,
        } = other;
        let same = self.positions.len() == positions.len()
            && self.face_he == *face_he
            && self.he_origin == *he_origin
            && self.he_next == *he_next
            && self.he_twin == *he_twin
            && self.he_face == *he_face
            && self.he_prev == *he_prev
            && self.vertex_out == *vertex_out
            && self.he_sharpness == *he_sharpness
            && self.vertex_sharpness == *vertex_sharpness
            && self.subdiv_options == *subdiv_options
            && self.vertex_colors == *vertex_colors
            && self.face_sources == *face_sources
            && self.face_parts == *face_parts
            && self.parts == *parts;
        if same {
            translation_between(positions, &self.positions, tolerance)
        } else {
            None
        }
    }

    /// Copies crease sharpness (by vertex pair), corner sharpness and colours from `other`, a mesh with
    /// the same vertices, and its face sources and parts when it has as many faces (face ids kept).
    pub(crate) fn copy_attributes_from(&mut self, other: &Mesh) {
        for ([a, b], s) in other.crease_sharpnesses() {
            if let Some(h) = self.find_halfedge(a, b) {
                self.set_edge_sharpness_halfedge(h, s);
            }
        }
        self.vertex_sharpness.clone_from(&other.vertex_sharpness);
        self.subdiv_options = other.subdiv_options;
        self.vertex_colors.clone_from(&other.vertex_colors);
        if other.face_count() == self.face_count() {
            self.face_sources.clone_from(&other.face_sources);
            self.face_parts.clone_from(&other.face_parts);
            self.parts.clone_from(&other.parts);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotation_by_90_about_z_takes_x_to_y() {
        let m = Mesh::cube(2.0).translate(Vec3::X * 5.0).rotate(Vec3::Z, 90.0);
        let c = m.bounds().center();
        assert!((c - Vec3::new(0.0, 5.0, 0.0)).length() < 1e-12, "{c}");
    }

    #[test]
    fn axes_of_any_nonzero_length_turn_the_same_way() {
        let m = Mesh::cube(2.0).translate(Vec3::X * 5.0);
        let want = m.rotate(Vec3::Z, 90.0);
        for axis in [Vec3::Z * 1e300, Vec3::Z * 1e-200, Vec3::Z * f64::MAX, Vec3::Z * 5e-324] {
            assert_eq!(m.rotate(axis, 90.0), want, "{axis}");
            assert_eq!(m.mirror(axis), m.mirror(Vec3::Z), "{axis}");
        }
        assert_eq!(m.rotate(Vec3::ZERO, 90.0), m);
    }

    #[test]
    fn mirror_and_negative_scale_keep_volume_positive() {
        let m = Mesh::icosphere(1.0, 1).translate(Vec3::new(3.0, 0.0, 0.0));
        let v = m.volume();
        for t in [m.mirror(Vec3::X), m.scale(Vec3::new(-1.0, 1.0, 1.0)), m.scale(Vec3::new(-2.0, -1.0, 1.0))] {
            assert!(t.volume() > 0.0);
            assert_eq!(t.face_count(), m.face_count());
        }
        assert!((m.mirror(Vec3::X).bounds().center().x + 3.0).abs() < 1e-12);
        assert!((m.mirror(Vec3::X).volume() - v).abs() < 1e-12);
    }

    #[test]
    fn a_translate_is_found_and_nothing_else_is() {
        let mut m = Mesh::icosphere(1.0, 1);
        m.crease_all();
        let d = Vec3::new(3.0, -2.0, 0.5);
        let t = m.translate(d);
        let found = t.translation_from(&m, 1e-12).unwrap();
        assert!((found - d).length() < 1e-12);
        assert!(m.translation_from(&m, 0.0) == Some(Vec3::ZERO));
        // Turned, scaled, one vertex moved, another crease: not translates.
        assert!(m.rotate(Vec3::Z, 10.0).translation_from(&m, 1e-9).is_none());
        assert!(m.scale(Vec3::splat(2.0)).translation_from(&m, 1e-9).is_none());
        let mut bent = t.clone();
        bent.set_position(3, bent.position(3) + Vec3::new(0.0, 1e-6, 0.0)).unwrap();
        assert!(bent.translation_from(&m, 1e-9).is_none());
        assert!(bent.translation_from(&m, 1e-5).is_some(), "within the tolerance");
        let mut smooth = t.clone();
        smooth.set_edge_sharpness_halfedge(0, 0.0);
        assert!(smooth.translation_from(&m, 1e-9).is_none());
        assert!(Mesh::cube(1.0).translation_from(&m, 1e-9).is_none());
    }

    #[test]
    fn transforms_keep_creases() {
        let mut m = Mesh::cube(1.0);
        m.crease_all();
        assert_eq!(m.mirror(Vec3::Y).crease_count(), 12);
    }
}
