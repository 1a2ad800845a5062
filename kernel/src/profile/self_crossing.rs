//! Refusing a solid built from profiles that passes through itself: a sweep whose path comes
//! back through its own tube, a loft whose placed profiles cross. The mesh is closed and
//! manifold either way, so nothing else would notice; booleans, volume and slicers misread it.

use super::ProfileError;
use crate::diagnose::crossings;
use crate::math::Vec3;
use crate::mesh::{Mesh, MeshError};

/// Refuses `mesh` (named `what`) when two of its faces cross or touch away from what they
/// share, by exact predicates ([`crossings`]: a bounding-volume hierarchy, O(n log n) in the
/// faces); `near` names the place of a crossing (the path point or profile nearest it).
///
/// # Errors
/// [`ProfileError::SelfCrossing`] with the first crossing's place and position;
/// [`ProfileError::Limit`] when stopped.
pub(super) fn refuse_self_crossing(
    mesh: &Mesh,
    what: &'static str,
    near: impl Fn(Vec3) -> String,
) -> Result<(), ProfileError> {
    let found = crossings(mesh).map_err(|e| match e {
        MeshError::Limit(l) => ProfileError::Limit(l),
        e => ProfileError::Engine { reason: e.to_string() },
    })?;
    match found.first() {
        Some(c) => Err(ProfileError::SelfCrossing { what, near: near(c.at), at: c.at }),
        None => Ok(()),
    }
}

/// The index of the point of `points` nearest `at` (0 when there are none).
pub(super) fn nearest(points: impl IntoIterator<Item = Vec3>, at: Vec3) -> usize {
    points
        .into_iter()
        .enumerate()
        .min_by(|(_, a), (_, b)| a.distance_squared(at).total_cmp(&b.distance_squared(at)))
        .map_or(0, |(i, _)| i)
}
