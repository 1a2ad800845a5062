//! A procedural building of blocks, the kind of model seed 000 §3 meshes in Figs. 18–20 (its
//! four-storey office building: 1,694 blocks, 105,264 triangles): storeys of rooms on a grid,
//! for benchmarks and tests at any size.
//!
//! # Layout
//! Each storey is a grid of `rooms_x × rooms_y` rooms. In plan, the building is divided into
//! `(2 rooms_x + 1) × (2 rooms_y + 1)` cells: even-even cells are columns, even-odd and odd-even
//! cells walls, odd-odd cells rooms. Each storey is a floor layer — one slab block on every cell —
//! and a wall layer — a block on every column and wall cell, except one door per room (in the
//! wall on its low-x side) — and a roof layer of slabs closes the top. Neighbouring blocks share
//! whole faces, so every connection is exact. Everything is sharp except the columns, which are
//! smooth (rounded pillars where doors expose them). The faces of rooms are tiled: floors and
//! ceilings 4 × 4 sub-faces, walls 4 × 3.

use crate::math::Vec3;

use super::{Block, BlockModel, Face};

/// The dimensions of a [`building`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BuildingPlan {
    /// Storeys (each a floor layer and a wall layer); a roof layer closes the top.
    pub storeys: u32,
    /// Rooms along x.
    pub rooms_x: u32,
    /// Rooms along y.
    pub rooms_y: u32,
}

impl BuildingPlan {
    /// Width of a room cell.
    const ROOM: f64 = 4.0;
    /// Thickness of walls and columns.
    const WALL: f64 = 0.25;
    /// Thickness of slabs.
    const SLAB: f64 = 0.3;
    /// Height of walls.
    const HEIGHT: f64 = 2.7;

    /// The number of blocks [`building`] makes for this plan.
    #[must_use]
    pub fn block_count(&self) -> usize {
        let (s, nx, ny) = (self.storeys as usize, self.rooms_x as usize, self.rooms_y as usize);
        let slabs = (2 * nx + 1) * (2 * ny + 1);
        let walls = (nx + 1) * (ny + 1) + nx * (ny + 1) + ny * (nx + 1) - nx * ny;
        (s + 1) * slabs + s * walls
    }

    /// The low and high coordinate of cell `i` along one axis.
    fn cell(i: u32) -> (f64, f64) {
        let rooms = f64::from(i / 2);
        let lo = rooms * (BuildingPlan::ROOM + BuildingPlan::WALL) + if i % 2 == 1 { BuildingPlan::WALL } else { 0.0 };
        let width = if i % 2 == 1 { BuildingPlan::ROOM } else { BuildingPlan::WALL };
        (lo, lo + width)
    }
}

/// The building of `plan` (see the [module documentation](self)): all blocks in group 0, which
/// is allowed to connect with itself.
///
/// # Panics
/// Never for plans whose block count fits in memory: every block is a valid box.
#[must_use]
pub fn building(plan: &BuildingPlan) -> BlockModel {
    let mut m = BlockModel::new();
    m.allow(0, 0);
    let (cx, cy) = (2 * plan.rooms_x + 1, 2 * plan.rooms_y + 1);
    let storey = BuildingPlan::SLAB + BuildingPlan::HEIGHT;
    let boxed = |i: u32, j: u32, z0: f64, z1: f64| {
        let ((x0, x1), (y0, y1)) = (BuildingPlan::cell(i), BuildingPlan::cell(j));
        Block::from_bounds(Vec3::new(x0, y0, z0), Vec3::new(x1, y1, z1)).expect("cells are boxes")
    };
    for s in 0..=plan.storeys {
        let z = f64::from(s) * storey;
        for j in 0..cy {
            for i in 0..cx {
                let mut b = boxed(i, j, z, z + BuildingPlan::SLAB);
                b.sharp_all();
                if i % 2 == 1 && j % 2 == 1 {
                    b.subdivide(Face::NegZ, 4, 4).expect("4 × 4 is a valid grid");
                    if s < plan.storeys {
                        b.subdivide(Face::PosZ, 4, 4).expect("4 × 4 is a valid grid");
                    }
                }
                m.add(b);
            }
        }
        if s == plan.storeys {
            break;
        }
        let (z0, z1) = (z + BuildingPlan::SLAB, z + storey);
        for j in 0..cy {
            for i in 0..cx {
                let (wall_x, wall_y) = (i % 2 == 0 && j % 2 == 1, i % 2 == 1 && j % 2 == 0);
                let column = i % 2 == 0 && j % 2 == 0;
                // A door in the low-x wall of every room: every room opens onto its neighbour.
                let door = wall_x && i + 1 < cx;
                if !(column || wall_x || wall_y) || door {
                    continue;
                }
                let mut b = boxed(i, j, z0, z1);
                if !column {
                    b.sharp_all();
                    let faces = if wall_x { [Face::NegX, Face::PosX] } else { [Face::NegY, Face::PosY] };
                    for f in faces {
                        b.subdivide(f, 4, 3).expect("4 × 3 is a valid grid");
                    }
                }
                m.add(b);
            }
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::blocks::MeshOptions;

    #[test]
    fn a_small_building_is_one_closed_solid() {
        let plan = BuildingPlan { storeys: 2, rooms_x: 2, rooms_y: 2 };
        let m = building(&plan);
        assert_eq!(m.blocks().len(), plan.block_count());
        let t = m.tessellate(&MeshOptions::DEFAULT.with_tolerance(0.01).with_max_depth(4), None).unwrap();
        assert!(t.mesh.is_closed() && t.mesh.is_manifold());
        // Blocks share faces and never overlap: the solid's volume is theirs, less anything the
        // smooth columns round off.
        let solid: f64 = m.blocks().iter().map(Block::volume).sum();
        let v = t.mesh.volume();
        assert!(v <= solid + 1e-9 && v > 0.99 * solid, "volume {v} of {solid}");
    }
}
