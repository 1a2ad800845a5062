//! A model of blocks: the blocks, which groups may connect, the distance threshold and manual
//! connections (seed 000 §2.2). Connections are computed on demand by
//! [`BlockModel::connections`] (see `connect.rs`).

use std::collections::BTreeSet;

use super::{Block, BlockError, Face};
use crate::mesh::BlockSubFace;

/// The default connection threshold: sub-faces connect when their distance is below
/// `0.05 × (perimeter(A) + perimeter(B))`.
pub const DEFAULT_THRESHOLD: f64 = 0.05;

/// One sub-face of one block of a model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SubFaceRef {
    /// The block id (its index in the model).
    pub block: u32,
    /// The face.
    pub face: Face,
    /// The sub-face index `i + nu * j`.
    pub sub: u32,
}

impl From<SubFaceRef> for BlockSubFace {
    /// The id a face's [`FaceSource::Block`](crate::mesh::FaceSource::Block) records.
    fn from(r: SubFaceRef) -> BlockSubFace {
        BlockSubFace { block: r.block, face: r.face.index() as u8, sub: r.sub }
    }
}

impl TryFrom<BlockSubFace> for SubFaceRef {
    type Error = BlockError;

    /// The sub-face a face's source names.
    ///
    /// # Errors
    /// [`BlockError::UnknownFace`] for a face index from 6 up.
    fn try_from(id: BlockSubFace) -> Result<SubFaceRef, BlockError> {
        let face = Face::from_index(usize::from(id.face))
            .ok_or_else(|| BlockError::UnknownFace { name: format!("of index {}", id.face) })?;
        Ok(SubFaceRef { block: id.block, face, sub: id.sub })
    }
}

/// A connection between two sub-faces of different blocks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Connection {
    /// The first sub-face (the lower block id for automatic connections).
    pub a: SubFaceRef,
    /// The second sub-face.
    pub b: SubFaceRef,
    /// The distance between them along the rays from their centres (for a manual connection,
    /// the distance between the centres).
    pub distance: f64,
    /// Whether it was given by [`BlockModel::connect`] rather than found.
    pub manual: bool,
}

/// Blocks, the group pairs allowed to connect, a scale-invariant threshold and manual
/// connections.
///
/// Nothing connects until a group pair is allowed: [`BlockModel::allow`]`(g, g)` lets blocks of
/// group `g` connect with each other (seed 000 Fig. 5a is a model with no allowed pair).
#[derive(Clone, Debug, PartialEq)]
pub struct BlockModel {
    blocks: Vec<Block>,
    allowed: BTreeSet<(i64, i64)>,
    threshold: f64,
    manual: Vec<Connection>,
}

impl Default for BlockModel {
    fn default() -> BlockModel {
        BlockModel::new()
    }
}

impl BlockModel {
    /// An empty model with the [`DEFAULT_THRESHOLD`].
    #[must_use]
    pub fn new() -> BlockModel {
        BlockModel { blocks: Vec::new(), allowed: BTreeSet::new(), threshold: DEFAULT_THRESHOLD, manual: Vec::new() }
    }

    /// Adds a block (a copy), returning its id.
    pub fn add(&mut self, block: Block) -> u32 {
        self.blocks.push(block);
        (self.blocks.len() - 1) as u32
    }

    /// Replaces block `id` with `block` (a copy): how a block is edited after it was added.
    /// Manual connections to the block stay when the sub-faces they name still exist.
    ///
    /// # Errors
    /// [`BlockError::NoSuchBlock`]; [`BlockError::SubFaceOutOfRange`] when a manual connection
    /// names a sub-face the new block does not have. The model is unchanged on error.
    pub fn set_block(&mut self, id: i64, block: Block) -> Result<(), BlockError> {
        let b = self.check_block(id)?;
        for c in &self.manual {
            for r in [c.a, c.b].into_iter().filter(|r| r.block == b) {
                block.check_subface(r.face, i64::from(r.sub))?;
            }
        }
        self.blocks[b as usize] = block;
        Ok(())
    }

    /// The blocks, indexed by id.
    #[must_use]
    pub fn blocks(&self) -> &[Block] {
        &self.blocks
    }

    /// Block `id`.
    ///
    /// # Errors
    /// [`BlockError::NoSuchBlock`] for an id not in the model.
    pub fn block(&self, id: i64) -> Result<&Block, BlockError> {
        self.check_block(id).map(|b| &self.blocks[b as usize])
    }

    fn check_block(&self, id: i64) -> Result<u32, BlockError> {
        if id < 0 || id as usize >= self.blocks.len() {
            return Err(BlockError::NoSuchBlock { id, count: self.blocks.len() });
        }
        Ok(id as u32)
    }

    /// Lets blocks of groups `g1` and `g2` connect (in either order).
    pub fn allow(&mut self, g1: i64, g2: i64) {
        self.allowed.insert((g1.min(g2), g1.max(g2)));
    }

    /// Whether groups `g1` and `g2` may connect.
    #[must_use]
    pub fn is_allowed(&self, g1: i64, g2: i64) -> bool {
        self.allowed.contains(&(g1.min(g2), g1.max(g2)))
    }

    /// The connection threshold.
    #[must_use]
    pub fn threshold(&self) -> f64 {
        self.threshold
    }

    /// Sets the connection threshold: sub-faces A and B may connect when their distance is below
    /// `threshold × (perimeter(A) + perimeter(B))` (seed 000 §2.2, scale invariant).
    ///
    /// # Errors
    /// [`BlockError::BadThreshold`] for a negative or non-finite value.
    pub fn set_threshold(&mut self, threshold: f64) -> Result<(), BlockError> {
        if !(threshold.is_finite() && threshold >= 0.0) {
            return Err(BlockError::BadThreshold { value: threshold });
        }
        self.threshold = threshold;
        Ok(())
    }

    /// A sub-face reference checked against the model.
    ///
    /// # Errors
    /// [`BlockError::NoSuchBlock`], [`BlockError::SubFaceOutOfRange`].
    pub fn subface(&self, block: i64, face: Face, sub: i64) -> Result<SubFaceRef, BlockError> {
        let b = self.check_block(block)?;
        let sub = self.blocks[b as usize].check_subface(face, sub)?;
        Ok(SubFaceRef { block: b, face, sub })
    }

    /// Adds a manual connection between sub-face `sub_a` of face `face_a` of block `a` and sub-face
    /// `sub_b` of `face_b` of block `b`, whatever their distance, groups or facing. It takes
    /// precedence over found connections: neither sub-face, nor the pair of blocks, gets another.
    ///
    /// # Errors
    /// [`BlockError::NoSuchBlock`], [`BlockError::SubFaceOutOfRange`], [`BlockError::SameBlock`],
    /// [`BlockError::AlreadyConnected`] when a sub-face is in a manual connection already. The model
    /// is unchanged on error.
    pub fn connect(
        &mut self,
        a: i64,
        face_a: Face,
        sub_a: i64,
        b: i64,
        face_b: Face,
        sub_b: i64,
    ) -> Result<(), BlockError> {
        let ra = self.subface(a, face_a, sub_a)?;
        let rb = self.subface(b, face_b, sub_b)?;
        if ra.block == rb.block {
            return Err(BlockError::SameBlock { block: ra.block });
        }
        for r in [ra, rb] {
            if self.manual.iter().any(|c| c.a == r || c.b == r) {
                return Err(BlockError::AlreadyConnected { block: r.block, face: r.face.name(), sub: r.sub });
            }
        }
        let centre = |r: SubFaceRef| {
            let q = self.blocks[r.block as usize].subface_corners(r.face, r.sub);
            (q[0] + q[1] + q[2] + q[3]) * 0.25
        };
        let distance = centre(ra).distance(centre(rb));
        self.manual.push(Connection { a: ra, b: rb, distance, manual: true });
        Ok(())
    }

    /// The manual connections, in the order given.
    #[must_use]
    pub fn manual_connections(&self) -> &[Connection] {
        &self.manual
    }
}
