//! Shape-Up constraints (Bouaziz et al., summarised by Tsoi & Hui, seed 002 §4–5): a local/global
//! solver whose constraints project their vertices onto a shape (rigid, circle, plane, anchors)
//! and whose global step solves one prefactored sparse normal system; and the cylinder fit of
//! §5 that measures circular features.
//!
//! - [`ShapeUp`]: constraints and energies, [`ShapeUp::factor`] once, [`Factored::solve`] many
//!   times (libigl's `_precompute` / `_solve` split);
//! - `projections`: the local step of each constraint (Eqs. 5–9 and Shape-Up's circle and plane);
//! - `svd3`: the 3×3 singular value decomposition the projections use;
//! - [`fit_circle`]: the least-squares circle of a ring (centre, normal, radius, deviation);
//! - [`fit_cylinder`]: Eqs. 13–14;
//! - [`retain_circular_features`]: the whole pipeline of Fig. 1.

mod error;
mod fit_circle;
mod fit_cylinder;
mod projections;
mod retain;
mod shape_up;
mod svd3;

pub use error::SolveError;
pub use fit_circle::{fit_circle, Circle};
pub use fit_cylinder::{fit_cylinder, Cylinder, RadiusRule};
pub use retain::{retain_circular_features, FeatureReport, RetainOptions};
pub use shape_up::{CircleSize, Factored, ShapeUp, Solution};
