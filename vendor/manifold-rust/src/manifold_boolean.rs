// Copyright 2026 Lars Brubaker
//
// Licensed under the Apache License, Version 2.0 (the "License");
// you may not use this file except in compliance with the License.
// You may obtain a copy of the License at
//
//      http://www.apache.org/licenses/LICENSE-2.0
//
// Unless required by applicable law or agreed to in writing, software
// distributed under the License is distributed on an "AS IS" BASIS,
// WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
// See the License for the specific language governing permissions and
// limitations under the License.

// manifold_boolean.rs — Manifold's boolean operations: the two-operand
// booleans with their engine / winding-rule / cancellation / progress
// variants, the pairwise batch fold, plane splits and trims built on a
// half-space cutter, and the `+` / `-` / `^` operator overloads (C++
// `operator+`, `operator-`, `operator^`). A child module of manifold.rs so
// it can reach the private `imp` field; the kernels are in boolean3.rs and,
// for the robust engine, src/robust.

use super::Manifold;
use crate::boolean3;
use crate::linalg::{normalize, Vec3};
use crate::math;
use crate::types::{Error, OpType};

impl Manifold {
    /// Split this manifold into two using a cutter manifold.
    /// Returns (intersection, difference).
    pub fn split(&self, cutter: &Self) -> (Self, Self) {
        let intersection = self.intersection(cutter);
        let difference = self.difference(cutter);
        (intersection, difference)
    }

    /// Split this manifold by a plane defined by a normal and offset from origin.
    /// Returns (in direction of normal, opposite direction).
    pub fn split_by_plane(&self, normal: Vec3, origin_offset: f64) -> (Self, Self) {
        // Per C++ #1659: errored manifolds are empty, so the is_empty()
        // early-return below would silently drop their status — guard first.
        if self.imp.status != Error::NoError {
            return (self.clone(), self.clone());
        }
        if self.is_empty() {
            return (Self::empty(), Self::empty());
        }
        let halfspace = Self::halfspace(&self.imp.bbox, normal, origin_offset);
        self.split(&halfspace)
    }

    /// Trim this manifold by a half-space, keeping only the part in the direction
    /// of the normal vector.
    pub fn trim_by_plane(&self, normal: Vec3, origin_offset: f64) -> Self {
        if self.is_empty() {
            return Self::empty();
        }
        let halfspace = Self::halfspace(&self.imp.bbox, normal, origin_offset);
        self.intersection(&halfspace)
    }

    /// Apply batch boolean operations on a list of manifolds.
    pub fn batch_boolean(manifolds: &[Self], op: OpType) -> Self {
        if manifolds.is_empty() {
            return Self::empty();
        }
        let mut result = manifolds[0].clone();
        for m in &manifolds[1..] {
            result = result.boolean(m, op);
        }
        result
    }

    /// Internal helper: create a halfspace (large cube) for plane splitting.
    fn halfspace(bbox: &crate::types::Box, normal: Vec3, origin_offset: f64) -> Self {
        let n = normalize(normal);
        let cutter = Self::cube(Vec3::splat(2.0), true).translate(Vec3::new(1.0, 0.0, 0.0));
        let center = bbox.center();
        let size_len = (bbox.size().x * bbox.size().x
            + bbox.size().y * bbox.size().y
            + bbox.size().z * bbox.size().z)
            .sqrt();
        let dist = ((center.x - n.x * origin_offset).powi(2)
            + (center.y - n.y * origin_offset).powi(2)
            + (center.z - n.z * origin_offset).powi(2))
        .sqrt()
            + 0.5 * size_len;
        let cutter = cutter
            .scale(Vec3::splat(dist))
            .translate(Vec3::new(origin_offset, 0.0, 0.0));
        let y_deg = -math::asin(n.z).to_degrees();
        let z_deg = math::atan2(n.y, n.x).to_degrees();
        cutter.rotate(0.0, y_deg, z_deg)
    }

    pub fn boolean(&self, other: &Self, op: OpType) -> Self {
        self.boolean_with_engine(other, op, crate::types::BooleanConfig::default_engine())
    }

    /// [`Manifold::boolean`] with an explicit engine choice, overriding the
    /// process-global default set via
    /// [`crate::types::BooleanConfig::set_default_engine`].
    pub fn boolean_with_engine(
        &self,
        other: &Self,
        op: OpType,
        engine: crate::types::BooleanEngine,
    ) -> Self {
        Self::from_impl(boolean3::boolean_dispatch(
            &self.imp, &other.imp, op, engine, None,
        ))
    }

    /// [`Manifold::boolean_with_engine`] with cooperative cancellation.
    pub fn boolean_with_engine_and_token(
        &self,
        other: &Self,
        op: OpType,
        engine: crate::types::BooleanEngine,
        token: Option<&crate::cancel::CancelToken>,
    ) -> Self {
        Self::from_impl(boolean3::boolean_dispatch(
            &self.imp, &other.imp, op, engine, token,
        ))
    }

    /// The exact boolean `self op other` for export only: its result is not
    /// sorted and has neither a collider nor vertex normals, so it must not be
    /// an operand of a later boolean (see `boolean3::boolean_for_export_with_token`).
    /// blocksmith patches (PATCHES.md, 17, 23).
    pub fn boolean_for_export_with_token(
        &self,
        other: &Self,
        op: OpType,
        token: Option<&crate::cancel::CancelToken>,
    ) -> Self {
        Self::from_impl(boolean3::boolean_for_export_with_token(
            &self.imp, &other.imp, op, token,
        ))
    }

    /// The exact boolean `self op other` on operands it takes: each is freed
    /// once the result no longer reads it, before the result's triangulation,
    /// simplification and sort, so its peak memory does not hold both operands
    /// and their colliders beside the result (see
    /// `boolean3::boolean_owned_with_token`). The same result as
    /// [`Manifold::boolean_with_engine_and_token`] with the exact engine; when
    /// not `sorted`, as [`Manifold::boolean_for_export_with_token`] (for export
    /// only). blocksmith patch (PATCHES.md, 18).
    pub fn into_boolean_with_token(
        self,
        other: Self,
        op: OpType,
        token: Option<&crate::cancel::CancelToken>,
        sorted: bool,
    ) -> Self {
        Self::from_impl(boolean3::boolean_owned_with_token(
            self.imp, other.imp, op, token, sorted,
        ))
    }

    /// [`Manifold::boolean_with_engine_and_token`] that also reports coarse
    /// pipeline progress.
    ///
    /// Cancellation and progress travel together because callers that want one
    /// almost always want the other (a UI showing a progress bar next to a
    /// cancel button); pass `None` for either independently. `None` progress is
    /// byte-for-byte the un-instrumented path — see [`crate::progress`] for the
    /// phases reported and the throttling contract.
    pub fn boolean_with_engine_and_progress(
        &self,
        other: &Self,
        op: OpType,
        engine: crate::types::BooleanEngine,
        token: Option<&crate::cancel::CancelToken>,
        progress: Option<&crate::progress::ProgressReporter>,
    ) -> Self {
        Self::from_impl(boolean3::boolean_dispatch_with_progress(
            &self.imp, &other.imp, op, engine, token, progress,
        ))
    }

    /// [`Manifold::boolean_with_engine`] with an explicit winding rule.
    ///
    /// [`crate::types::WindingRule::Nonzero`] treats inside-out geometry as
    /// solid (`w != 0` rather than `w >= 1`), which keeps the inverted regions
    /// of inconsistently wound scans instead of dropping them. The rule is a
    /// robust-engine semantic: the exact engine ignores it, and `Auto` routes
    /// to the robust engine whenever the rule is `Nonzero` (see
    /// [`crate::boolean3::boolean_dispatch_full`]).
    pub fn boolean_with_engine_and_rule(
        &self,
        other: &Self,
        op: OpType,
        engine: crate::types::BooleanEngine,
        rule: crate::types::WindingRule,
    ) -> Self {
        self.boolean_with_engine_rule_and_progress(other, op, engine, rule, None, None)
    }

    /// The full per-call boolean path: engine, winding rule, cancellation, and
    /// progress. Every other boolean entry point on `Manifold` is this one with
    /// defaults filled in.
    pub fn boolean_with_engine_rule_and_progress(
        &self,
        other: &Self,
        op: OpType,
        engine: crate::types::BooleanEngine,
        rule: crate::types::WindingRule,
        token: Option<&crate::cancel::CancelToken>,
        progress: Option<&crate::progress::ProgressReporter>,
    ) -> Self {
        Self::from_impl(boolean3::boolean_dispatch_full(
            &self.imp, &other.imp, op, engine, rule, token, progress,
        ))
    }

    /// [`Manifold::batch_boolean`] with an explicit engine choice (pairwise
    /// left fold, like `batch_boolean`).
    pub fn batch_boolean_with_engine(
        manifolds: &[Self],
        op: OpType,
        engine: crate::types::BooleanEngine,
    ) -> Self {
        if manifolds.is_empty() {
            return Self::empty();
        }
        let mut result = manifolds[0].clone();
        for m in &manifolds[1..] {
            result = result.boolean_with_engine(m, op, engine);
        }
        result
    }

    pub fn union_with_engine(&self, other: &Self, engine: crate::types::BooleanEngine) -> Self {
        self.boolean_with_engine(other, OpType::Add, engine)
    }

    pub fn difference_with_engine(
        &self,
        other: &Self,
        engine: crate::types::BooleanEngine,
    ) -> Self {
        self.boolean_with_engine(other, OpType::Subtract, engine)
    }

    pub fn intersection_with_engine(
        &self,
        other: &Self,
        engine: crate::types::BooleanEngine,
    ) -> Self {
        self.boolean_with_engine(other, OpType::Intersect, engine)
    }

    /// [`Manifold::boolean`] with cooperative cancellation.
    ///
    /// Pass `None` for the uncancellable behaviour of [`Manifold::boolean`] —
    /// that path is unchanged and touches no atomics. With `Some(token)`, a
    /// cancel requested from any thread (before or during the call) makes this
    /// return an empty manifold whose [`Manifold::status`] is
    /// [`Error::Cancelled`], mirroring the C++ `ExecutionContext` contract.
    pub fn boolean_with_token(
        &self,
        other: &Self,
        op: OpType,
        token: Option<&crate::cancel::CancelToken>,
    ) -> Self {
        Self::from_impl(boolean3::boolean_with_token(
            &self.imp, &other.imp, op, token,
        ))
    }

    pub fn union(&self, other: &Self) -> Self {
        self.boolean(other, OpType::Add)
    }

    pub fn difference(&self, other: &Self) -> Self {
        self.boolean(other, OpType::Subtract)
    }

    pub fn intersection(&self, other: &Self) -> Self {
        self.boolean(other, OpType::Intersect)
    }
}

// Operator overloads: + for union, - for difference, ^ for intersection
// Matches C++ operator+(Manifold), operator-(Manifold), operator^(Manifold)

impl std::ops::Add for Manifold {
    type Output = Self;
    fn add(self, rhs: Self) -> Self {
        self.union(&rhs)
    }
}

impl std::ops::Add<&Manifold> for Manifold {
    type Output = Self;
    fn add(self, rhs: &Self) -> Self {
        self.union(rhs)
    }
}

impl std::ops::Add<&Manifold> for &Manifold {
    type Output = Manifold;
    fn add(self, rhs: &Manifold) -> Manifold {
        self.union(rhs)
    }
}

impl std::ops::AddAssign for Manifold {
    fn add_assign(&mut self, rhs: Self) {
        *self = self.union(&rhs);
    }
}

impl std::ops::AddAssign<&Manifold> for Manifold {
    fn add_assign(&mut self, rhs: &Self) {
        *self = self.union(rhs);
    }
}

impl std::ops::Sub for Manifold {
    type Output = Self;
    fn sub(self, rhs: Self) -> Self {
        self.difference(&rhs)
    }
}

impl std::ops::Sub<&Manifold> for Manifold {
    type Output = Self;
    fn sub(self, rhs: &Self) -> Self {
        self.difference(rhs)
    }
}

impl std::ops::Sub<&Manifold> for &Manifold {
    type Output = Manifold;
    fn sub(self, rhs: &Manifold) -> Manifold {
        self.difference(rhs)
    }
}

impl std::ops::SubAssign for Manifold {
    fn sub_assign(&mut self, rhs: Self) {
        *self = self.difference(&rhs);
    }
}

impl std::ops::SubAssign<&Manifold> for Manifold {
    fn sub_assign(&mut self, rhs: &Self) {
        *self = self.difference(rhs);
    }
}

impl std::ops::BitXor for Manifold {
    type Output = Self;
    fn bitxor(self, rhs: Self) -> Self {
        self.intersection(&rhs)
    }
}

impl std::ops::BitXor<&Manifold> for Manifold {
    type Output = Self;
    fn bitxor(self, rhs: &Self) -> Self {
        self.intersection(rhs)
    }
}

impl std::ops::BitXor<&Manifold> for &Manifold {
    type Output = Manifold;
    fn bitxor(self, rhs: &Manifold) -> Manifold {
        self.intersection(rhs)
    }
}

impl std::ops::BitXorAssign for Manifold {
    fn bitxor_assign(&mut self, rhs: Self) {
        *self = self.intersection(&rhs);
    }
}

impl std::ops::BitXorAssign<&Manifold> for Manifold {
    fn bitxor_assign(&mut self, rhs: &Self) {
        *self = self.intersection(rhs);
    }
}

/// blocksmith patch (PATCHES.md, 17): the boolean for export.
#[cfg(test)]
mod for_export_tests {
    use super::*;

    /// Each triangle as its face ID and its corners' coordinates (bits), from the smallest
    /// corner on, sorted: the triangles whatever their order.
    fn triangles(m: &Manifold) -> Vec<(u64, [[u64; 3]; 3])> {
        let g = m.get_mesh_gl64(-1);
        let np = g.num_prop as usize;
        let corner = |v: u64| {
            let p = &g.vert_properties[np * v as usize..np * v as usize + 3];
            [p[0].to_bits(), p[1].to_bits(), p[2].to_bits()]
        };
        let mut out: Vec<(u64, [[u64; 3]; 3])> = g
            .tri_verts
            .chunks_exact(3)
            .enumerate()
            .map(|(t, c)| {
                let mut corners = [corner(c[0]), corner(c[1]), corner(c[2])];
                let first = (0..3).min_by_key(|&i| corners[i]).unwrap_or(0);
                corners.rotate_left(first);
                (g.face_id[t], corners)
            })
            .collect();
        out.sort_unstable();
        out
    }

    #[test]
    fn a_boolean_for_export_is_the_boolean_in_another_order() {
        let a = Manifold::cube(Vec3::new(2.0, 2.0, 2.0), true);
        let b = Manifold::sphere(1.3, 48).translate(Vec3::new(0.3, 0.2, 0.1));
        for op in [OpType::Add, OpType::Subtract, OpType::Intersect] {
            let sorted = a.boolean(&b, op);
            let unsorted = a.boolean_for_export_with_token(&b, op, None);
            assert_eq!(unsorted.status(), Error::NoError);
            assert!(unsorted.as_impl().is_manifold(), "{op:?}");
            assert_eq!(unsorted.num_tri(), sorted.num_tri(), "{op:?}");
            assert_eq!(unsorted.num_vert(), sorted.num_vert(), "{op:?}");
            assert_eq!(unsorted.genus(), sorted.genus(), "{op:?}");
            assert_eq!(triangles(&unsorted), triangles(&sorted), "{op:?}");
            // Patch 23: the vertex normals only an operand needs are left out.
            assert!(unsorted.as_impl().vert_normal.is_empty(), "{op:?}");
            assert_eq!(sorted.as_impl().vert_normal.len(), sorted.num_vert(), "{op:?}");
            // No vertex flagged for removal is left, and every face is paired.
            assert!(unsorted.as_impl().vert_pos.iter().all(|p| p.x.is_finite()));
            assert!(unsorted
                .as_impl()
                .halfedge
                .iter()
                .all(|h| h.paired_halfedge >= 0));
        }
    }
}

/// blocksmith patch (PATCHES.md, 18): the boolean that takes its operands.
#[cfg(test)]
mod owned_tests {
    use super::*;

    /// Everything an export reads: positions and properties (bits), triangles, face and
    /// run IDs.
    fn exported(m: &Manifold) -> (Vec<u64>, Vec<u64>, Vec<u64>, Vec<u32>) {
        let g = m.get_mesh_gl64(-1);
        let bits = g.vert_properties.iter().map(|p| p.to_bits()).collect();
        let ids = g.run_original_id.clone();
        (bits, g.tri_verts.clone(), g.face_id.clone(), ids)
    }

    #[test]
    fn a_boolean_on_operands_it_takes_is_the_borrowing_boolean() {
        let cube = Manifold::cube(Vec3::new(2.0, 2.0, 2.0), true);
        let sphere = Manifold::sphere(1.3, 48).translate(Vec3::new(0.3, 0.2, 0.1));
        // Operands with properties: those are read after the edges' assembly, so the
        // operands are freed later on that path.
        let with_props = |m: &Manifold| {
            m.set_properties(4, |out, p, _| {
                out.copy_from_slice(&[p.x, p.y, p.z, p.x * p.y])
            })
        };
        let cases = [
            (cube.clone(), sphere.clone()),
            (with_props(&cube), with_props(&sphere)),
            (cube.clone(), with_props(&sphere)),
            // Apart, and one empty: the fast paths, which move an operand rather than copy it.
            (cube.clone(), sphere.translate(Vec3::new(5.0, 0.0, 0.0))),
            (Manifold::empty(), sphere.clone()),
            (cube.clone(), Manifold::empty()),
        ];
        for (k, (a, b)) in cases.iter().enumerate() {
            for op in [OpType::Add, OpType::Subtract, OpType::Intersect] {
                let sorted = a.boolean_with_engine_and_token(
                    b,
                    op,
                    crate::types::BooleanEngine::Exact,
                    None,
                );
                let owned = a.clone().into_boolean_with_token(b.clone(), op, None, true);
                assert_eq!(owned.status(), Error::NoError, "case {k} {op:?}");
                assert_eq!(owned.num_prop(), sorted.num_prop(), "case {k} {op:?}");
                assert_eq!(exported(&owned), exported(&sorted), "case {k} {op:?}");
                let export = a.boolean_for_export_with_token(b, op, None);
                let owned = a
                    .clone()
                    .into_boolean_with_token(b.clone(), op, None, false);
                assert_eq!(
                    exported(&owned),
                    exported(&export),
                    "case {k} {op:?}, for export"
                );
            }
        }
        // Cancelled before it starts: the cancelled result, as the borrowing boolean's.
        let token = crate::cancel::CancelToken::new();
        token.cancel();
        let owned = cube.clone().into_boolean_with_token(
            sphere.clone(),
            OpType::Subtract,
            Some(&token),
            true,
        );
        assert_eq!(owned.status(), Error::Cancelled);
        assert!(owned.is_empty());
    }
}
