//! Named block models shared by the tests of several steps.

use crate::math::Vec3;

use super::{Block, BlockModel, Face};

/// The axis-aligned block from `min` to `max`.
pub(crate) fn boxed(min: [f64; 3], max: [f64; 3]) -> Block {
    Block::from_bounds(Vec3::from_array(min), Vec3::from_array(max)).unwrap()
}

/// A model of one all-sharp box from `min` to `max`, with each `(face, nu, nv)` grid.
pub(crate) fn sharp_box(min: [f64; 3], max: [f64; 3], grids: &[(Face, i64, i64)]) -> BlockModel {
    let mut b = boxed(min, max);
    b.sharp_all();
    for &(face, nu, nv) in grids {
        b.subdivide(face, nu, nv).unwrap();
    }
    let mut m = BlockModel::new();
    m.add(b);
    m
}

/// Whether the segment `a b` runs along an edge of the box `min`–`max`: both ends at the same
/// bound in two coordinates.
pub(crate) fn along_box_edge(a: Vec3, b: Vec3, min: [f64; 3], max: [f64; 3]) -> bool {
    let (a, b) = (a.to_array(), b.to_array());
    (0..3).filter(|&i| a[i] == b[i] && (a[i] == min[i] || a[i] == max[i])).count() == 2
}

/// The hand of seed 000 Fig. 5c: the palm's top face (+y) divided 4 × 1 for four fingers, its
/// side (-x) 3 × 1 with the thumb on the middle sub-face; each finger and the thumb has its own
/// group, allowed to connect to the palm's (0) but not to each other.
pub(crate) fn hand() -> BlockModel {
    let mut m = BlockModel::new();
    let mut palm = boxed([0.0; 3], [4.0, 3.0, 1.0]);
    palm.subdivide(Face::PosY, 4, 1).unwrap();
    palm.subdivide(Face::NegX, 3, 1).unwrap();
    m.add(palm);
    for i in 0..4 {
        let x = f64::from(i);
        let mut finger = boxed([x + 0.1, 3.0, 0.1], [x + 0.9, 5.0 - 0.3 * (x - 1.5).abs(), 0.9]);
        finger.set_group(i64::from(i) + 1);
        m.add(finger);
        m.allow(0, i64::from(i) + 1);
    }
    let mut thumb = boxed([-1.8, 1.1, 0.1], [0.0, 1.9, 0.9]);
    thumb.set_group(5);
    m.add(thumb);
    m.allow(0, 5);
    m
}
