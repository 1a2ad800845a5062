//! Subdivision options, as OpenSubdiv's `Sdc::Options` names them.

/// How boundary vertices are interpolated (OpenSubdiv's `VtxBoundaryInterpolation`).
///
/// Boundary edges are infinitely sharp in every mode (OpenSubdiv sharpens them whatever the
/// option, `Sdc::Crease::SharpenBoundaryEdge`); the modes differ at boundary vertices.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum BoundaryInterpolation {
    /// OpenSubdiv's `VTX_BOUNDARY_NONE`: refinement as [`BoundaryInterpolation::EdgeOnly`]; in
    /// OpenSubdiv the faces at the boundary are left out of the limit surface (patches), which the
    /// refined meshes here keep.
    None,
    /// `VTX_BOUNDARY_EDGE_ONLY`: boundary vertices follow the crease rule along the boundary, also
    /// the corner of an open grid (Blender's default).
    #[default]
    EdgeOnly,
    /// `VTX_BOUNDARY_EDGE_AND_CORNER`: as edge only, and a boundary vertex with one face (two
    /// edges) is an infinitely sharp corner that stays put.
    EdgeAndCorner,
}

/// How semi-sharp crease sharpness decays from one level to the next (`Sdc::Options::CreasingMethod`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum CreaseMethod {
    /// `CREASE_UNIFORM`: every child edge has its parent's sharpness less 1 (DeRose et al. 1998 §3).
    #[default]
    Uniform,
    /// `CREASE_CHAIKIN`: a child edge has ¾ of its parent's sharpness plus ¼ of the mean of the
    /// other semi-sharp edges at its end vertex, less 1 (the sharpness varies smoothly along a
    /// crease of varying sharpness).
    Chaikin,
}

/// How Catmull–Clark weights edge points next to triangles (`Sdc::Options::TriangleSubdivision`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TriangleSubdivision {
    /// `TRI_SUB_CATMARK`: the ordinary Catmull–Clark rules.
    #[default]
    CatmullClark,
    /// `TRI_SUB_SMOOTH`: a smooth edge point next to a triangle weighs the triangle's face point
    /// 0.47 instead of ¼ (and each end vertex the rest), which rounds triangles out more evenly
    /// (OpenSubdiv's `CATMARK_SMOOTH_TRI_EDGE_WEIGHT`).
    Smooth,
}

/// The options of a subdivision; [`SubdivOptions::default`] is edge-only boundaries, uniform
/// creasing and the ordinary Catmull–Clark rules on triangles.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct SubdivOptions {
    /// Boundary vertex interpolation.
    pub boundary: BoundaryInterpolation,
    /// Decay of semi-sharp creases.
    pub crease: CreaseMethod,
    /// Catmull–Clark weights next to triangles (ignored by Loop).
    pub triangles: TriangleSubdivision,
}
