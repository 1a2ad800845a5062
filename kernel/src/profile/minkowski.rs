//! The Minkowski sum of two solids.
//!
//! Manifold's method: convex operands are summed as the hull of the pairwise vertex sums; a
//! non-convex operand is split into its triangles' convex pieces, each summed with the other
//! operand, and the pieces unioned.

use super::convert::{engine_error, mesh_from_solid, solid_from_mesh};
use super::ProfileError;
use crate::csg::engine::watching;
use crate::mesh::Mesh;

/// `a ⊕ b = { x + y : x ∈ a, y ∈ b }`, a closed manifold triangle mesh. Stops when the current
/// cancellation token does.
///
/// # Errors
/// [`ProfileError::NotSolid`] naming the operand (`"the first operand"`, `"the second
/// operand"`) that has no faces, a boundary or that the engine refuses;
/// [`ProfileError::NonFinite`] for a NaN or infinite coordinate; [`ProfileError::Limit`] when
/// stopped.
pub fn minkowski(a: &Mesh, b: &Mesh) -> Result<Mesh, ProfileError> {
    let sa = solid_from_mesh(a, "the first operand")?;
    let sb = solid_from_mesh(b, "the second operand")?;
    let token = crate::limits::current();
    let solid = watching(&token, |stop| sa.minkowski_until(&sb, stop)).map_err(engine_error)?;
    mesh_from_solid(&solid)
}
