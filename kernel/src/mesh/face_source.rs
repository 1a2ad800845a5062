//! Face provenance: where each face of a boolean result came from ([`FaceSource`]), in ids the
//! mesh can hold without knowing the modules that made them (`blocks::SubFaceRef` converts to and
//! from [`BlockSubFace`]).

/// One sub-face of one block of a block model, as a face's source records it: the mesh-level form
/// of `blocks::SubFaceRef` (which converts to and from it), ordered the same way.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct BlockSubFace {
    /// The block id (its index in the model).
    pub block: u32,
    /// The index of the block's face, `0..6` in the order `-x +x -y +y -z +z` (`blocks::Face::index`).
    pub face: u8,
    /// The sub-face index `i + nu * j` on that face.
    pub sub: u32,
}

/// Where a face of a boolean result came from (seed 000 §2.4.2: the surviving patches keep
/// their tags). `leaf` numbers the inputs of the CSG tree, left to right.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum FaceSource {
    /// A triangle of a tessellated block model: the block sub-face it lies on.
    Block {
        /// The input (leaf) of the CSG tree.
        leaf: u32,
        /// The block, face and sub-face.
        sub_face: BlockSubFace,
    },
    /// A face of an input mesh.
    Mesh {
        /// The input (leaf) of the CSG tree.
        leaf: u32,
        /// The face id in that input mesh.
        face: u32,
    },
    /// A face whose source is not known (a part without sources in [`Mesh::combine`](super::Mesh::combine)).
    Unknown,
}

impl FaceSource {
    /// The leaf (input) this face came from; `None` for [`FaceSource::Unknown`].
    #[must_use]
    pub fn leaf(&self) -> Option<u32> {
        match self {
            FaceSource::Block { leaf, .. } | FaceSource::Mesh { leaf, .. } => Some(*leaf),
            FaceSource::Unknown => None,
        }
    }

    /// The same source with its leaf id moved up by `offset`.
    #[must_use]
    pub fn shifted(self, offset: u32) -> FaceSource {
        match self {
            FaceSource::Block { leaf, sub_face } => FaceSource::Block { leaf: leaf + offset, sub_face },
            FaceSource::Mesh { leaf, face } => FaceSource::Mesh { leaf: leaf + offset, face },
            FaceSource::Unknown => FaceSource::Unknown,
        }
    }
}
