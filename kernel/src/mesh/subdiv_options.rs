//! Subdivision options, as OpenSubdiv's `Sdc::Options` names them, and the names files and
//! scripts write them with. A mesh carries its options (as a USD mesh carries them as attributes),
//! so they are defined here, beside the crease and corner tags; `subdiv` re-exports them.

/// The sharpness from which a crease or corner is infinitely sharp (OpenSubdiv's
/// `Sdc::Crease::SHARPNESS_INFINITE`): subdivision treats every value from 10 up, and
/// `f64::INFINITY`, alike. Scripts see infinitely sharp creases as this value, since the
/// scripting language's comparisons of infinity are false.
pub const SHARPNESS_INFINITE: f64 = 10.0;

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

impl BoundaryInterpolation {
    /// The name scripts and glTF extras use: `"none"`, `"edge_only"`, `"edge_and_corner"`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            BoundaryInterpolation::None => "none",
            BoundaryInterpolation::EdgeOnly => "edge_only",
            BoundaryInterpolation::EdgeAndCorner => "edge_and_corner",
        }
    }

    /// The mode of a [`BoundaryInterpolation::name`].
    #[must_use]
    pub fn from_name(name: &str) -> Option<BoundaryInterpolation> {
        [BoundaryInterpolation::None, BoundaryInterpolation::EdgeOnly, BoundaryInterpolation::EdgeAndCorner]
            .into_iter()
            .find(|m| m.name() == name)
    }
}

impl CreaseMethod {
    /// The name scripts and glTF extras use: `"uniform"`, `"chaikin"`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            CreaseMethod::Uniform => "uniform",
            CreaseMethod::Chaikin => "chaikin",
        }
    }

    /// The method of a [`CreaseMethod::name`].
    #[must_use]
    pub fn from_name(name: &str) -> Option<CreaseMethod> {
        [CreaseMethod::Uniform, CreaseMethod::Chaikin].into_iter().find(|m| m.name() == name)
    }
}

impl TriangleSubdivision {
    /// The name scripts and glTF extras use: `"catmull_clark"`, `"smooth"`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            TriangleSubdivision::CatmullClark => "catmull_clark",
            TriangleSubdivision::Smooth => "smooth",
        }
    }

    /// The rule of a [`TriangleSubdivision::name`].
    #[must_use]
    pub fn from_name(name: &str) -> Option<TriangleSubdivision> {
        [TriangleSubdivision::CatmullClark, TriangleSubdivision::Smooth].into_iter().find(|m| m.name() == name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_read_back_and_unknown_names_are_none() {
        for b in [BoundaryInterpolation::None, BoundaryInterpolation::EdgeOnly, BoundaryInterpolation::EdgeAndCorner] {
            assert_eq!(BoundaryInterpolation::from_name(b.name()), Some(b));
        }
        for c in [CreaseMethod::Uniform, CreaseMethod::Chaikin] {
            assert_eq!(CreaseMethod::from_name(c.name()), Some(c));
        }
        for t in [TriangleSubdivision::CatmullClark, TriangleSubdivision::Smooth] {
            assert_eq!(TriangleSubdivision::from_name(t.name()), Some(t));
        }
        assert_eq!(BoundaryInterpolation::from_name("edge"), None);
        assert_eq!(CreaseMethod::from_name("normal"), None);
        assert_eq!(TriangleSubdivision::from_name("loop"), None);
    }
}
