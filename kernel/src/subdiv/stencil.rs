//! Stencil tables: sparse linear maps from one set of points to another, in CSR form.
//!
//! Row `i` says: output point `i` = Σ `weights[k]` · source point `indices[k]` for `k` in
//! `offsets[i]..offsets[i + 1]`. Subdivision levels, their compositions and limit positions are
//! all stencil tables over the control vertices, so a caller that moves the control points (an
//! animation, a solver) recomputes the refined or limit points from the stored weights without
//! touching the topology again (OpenSubdiv's `Far::StencilTable`).

use crate::math::Vec3;

/// A sparse linear map from `source_count` points to `rows()` points (CSR).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StencilTable {
    offsets: Vec<u32>,
    indices: Vec<u32>,
    weights: Vec<f64>,
    source_count: usize,
}

/// Accumulates one row at a time, merging repeated sources with a stamp array (no hashing).
pub(crate) struct RowBuilder {
    table: StencilTable,
    slot: Vec<u32>,
    row_start: usize,
}

impl RowBuilder {
    pub(crate) fn new(source_count: usize, rows_hint: usize, entries_hint: usize) -> RowBuilder {
        let mut offsets = Vec::with_capacity(rows_hint + 1);
        offsets.push(0);
        RowBuilder {
            table: StencilTable {
                offsets,
                indices: Vec::with_capacity(entries_hint),
                weights: Vec::with_capacity(entries_hint),
                source_count,
            },
            slot: vec![u32::MAX; source_count],
            row_start: 0,
        }
    }

    /// Adds `w` · source `i` to the current row.
    #[inline]
    pub(crate) fn add(&mut self, i: u32, w: f64) {
        let s = self.slot[i as usize];
        if s != u32::MAX && (s as usize) >= self.row_start && self.table.indices[s as usize] == i {
            self.table.weights[s as usize] += w;
        } else {
            self.slot[i as usize] = self.table.indices.len() as u32;
            self.table.indices.push(i);
            self.table.weights.push(w);
        }
    }

    /// Closes the current row.
    #[inline]
    pub(crate) fn end_row(&mut self) {
        self.row_start = self.table.indices.len();
        self.table.offsets.push(self.row_start as u32);
    }

    pub(crate) fn finish(self) -> StencilTable {
        self.table
    }
}

impl StencilTable {
    /// The identity map on `n` points.
    #[must_use]
    pub fn identity(n: usize) -> StencilTable {
        StencilTable {
            offsets: (0..=n as u32).collect(),
            indices: (0..n as u32).collect(),
            weights: vec![1.0; n],
            source_count: n,
        }
    }

    /// Number of output points.
    #[must_use]
    pub fn rows(&self) -> usize {
        self.offsets.len() - 1
    }

    /// Number of source points the table reads.
    #[must_use]
    pub fn source_count(&self) -> usize {
        self.source_count
    }

    /// Number of stored (index, weight) pairs.
    #[must_use]
    pub fn entry_count(&self) -> usize {
        self.indices.len()
    }

    /// Row `i` as parallel slices of source indices and weights.
    #[must_use]
    pub fn row(&self, i: usize) -> (&[u32], &[f64]) {
        let r = self.offsets[i] as usize..self.offsets[i + 1] as usize;
        (&self.indices[r.clone()], &self.weights[r])
    }

    /// Applies the map: one output point per row. Rows are taken as affine (weights summing to
    /// 1, as every subdivision and limit stencil's do) and summed relative to their first source.
    ///
    /// # Panics
    /// When `src.len()` differs from [`StencilTable::source_count`] (a caller bug).
    #[must_use]
    pub fn apply(&self, src: &[Vec3]) -> Vec<Vec3> {
        assert_eq!(src.len(), self.source_count, "stencil table applied to the wrong number of points");
        (0..self.rows())
            .map(|i| {
                let (idx, w) = self.row(i);
                // Relative to the row's first source (rows are affine: weights sum to 1), so
                // coordinates all its sources share come out exactly.
                let Some(&first) = idx.first() else { return Vec3::ZERO };
                let o = src[first as usize];
                o + idx.iter().zip(w).fold(Vec3::ZERO, |acc, (&j, &w)| acc + (src[j as usize] - o) * w)
            })
            .collect()
    }

    /// The composition `next ∘ self`: a table from this table's sources straight to `next`'s
    /// outputs (OpenSubdiv's factorised intermediate levels).
    ///
    /// # Panics
    /// When `next.source_count()` differs from `self.rows()` (a caller bug).
    #[must_use]
    pub fn then(&self, next: &StencilTable) -> StencilTable {
        assert_eq!(next.source_count, self.rows(), "stencil tables do not chain");
        let mut b = RowBuilder::new(self.source_count, next.rows(), next.entry_count() * 4);
        for i in 0..next.rows() {
            let (idx, w) = next.row(i);
            for (&j, &wj) in idx.iter().zip(w) {
                let (idx2, w2) = self.row(j as usize);
                for (&k, &wk) in idx2.iter().zip(w2) {
                    b.add(k, wj * wk);
                }
            }
            b.end_row();
        }
        b.finish()
    }

    /// The sum of each row's weights (1 for every row of an affine map such as subdivision).
    #[must_use]
    pub fn row_sums(&self) -> Vec<f64> {
        (0..self.rows()).map(|i| self.row(i).1.iter().sum()).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn repeated_sources_merge_within_a_row_only() {
        let mut b = RowBuilder::new(3, 2, 8);
        b.add(1, 0.25);
        b.add(2, 0.5);
        b.add(1, 0.25);
        b.end_row();
        b.add(1, 1.0);
        b.end_row();
        let t = b.finish();
        assert_eq!(t.row(0), (&[1u32, 2][..], &[0.5, 0.5][..]));
        assert_eq!(t.row(1), (&[1u32][..], &[1.0][..]));
    }

    #[test]
    fn composition_equals_applying_twice() {
        // A: midpoints of a segment chain; B: midpoints again. (B∘A) p must equal B(A p).
        let mut a = RowBuilder::new(3, 2, 4);
        for i in 0..2u32 {
            a.add(i, 0.5);
            a.add(i + 1, 0.5);
            a.end_row();
        }
        let a = a.finish();
        let mut b = RowBuilder::new(2, 1, 2);
        b.add(0, 0.5);
        b.add(1, 0.5);
        b.end_row();
        let b = b.finish();
        let p = [Vec3::ZERO, Vec3::X, Vec3::new(3.0, 0.0, 0.0)];
        let ab = a.then(&b);
        assert_eq!(ab.apply(&p), b.apply(&a.apply(&p)));
        // (p0 + 2 p1 + p2) / 4 = (0 + 2 + 3) / 4.
        assert_eq!(ab.apply(&p)[0], Vec3::new(1.25, 0.0, 0.0));
        assert_eq!(ab.row_sums(), vec![1.0]);
    }
}
