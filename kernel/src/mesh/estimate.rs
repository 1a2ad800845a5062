//! The memory a mesh of a given size needs, estimated before it is built, so that a request
//! too large for the memory budget is refused instead of aborting the process.

use crate::limits::{check_memory, LimitError};

/// Bytes per vertex: the position, the outgoing half-edge, and the building's temporaries.
const VERTEX_BYTES: f64 = 48.0;
/// Bytes per half-edge: origin, next, previous, twin, face and crease tag, plus the edge map
/// the building uses to pair twins.
const HALFEDGE_BYTES: f64 = 48.0;
/// Bytes per face: the first half-edge and the input polygon's entry.
const FACE_BYTES: f64 = 16.0;

/// The estimated peak memory, in bytes, of building a mesh of `vertices` vertices, `corners`
/// face corners (one half-edge each: the sum of the face arities) and `faces` faces.
///
/// Computed in `f64` so that absurd counts cannot overflow.
#[must_use]
pub fn mesh_bytes(vertices: f64, corners: f64, faces: f64) -> f64 {
    vertices * VERTEX_BYTES + corners * HALFEDGE_BYTES + faces * FACE_BYTES
}

/// Refuses a mesh of the given size when its estimate ([`mesh_bytes`]) is over the memory
/// budget; `what` describes the request for the message (e.g. `"a 100000 × 100000 UV sphere"`).
///
/// # Errors
/// [`LimitError::OverBudget`] naming `what`, the estimate and the budget.
pub fn check_mesh_size(
    what: impl FnOnce() -> String,
    vertices: f64,
    corners: f64,
    faces: f64,
) -> Result<(), LimitError> {
    check_memory(what, mesh_bytes(vertices, corners, faces))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_quad_mesh_costs_about_256_bytes_a_face() {
        // A closed quad mesh has about as many vertices as faces and four half-edges per face.
        let f = 1e6;
        let b = mesh_bytes(f, 4.0 * f, f);
        assert!((2.5e8..2.7e8).contains(&b), "{b}");
        assert!(check_mesh_size(|| "small".into(), 8.0, 24.0, 6.0).is_ok());
        let e = check_mesh_size(|| "a 1e10-face mesh".into(), 1e10, 4e10, 1e10).unwrap_err();
        assert!(e.to_string().starts_with("a 1e10-face mesh needs an estimated 2.3"), "{e}");
    }
}
