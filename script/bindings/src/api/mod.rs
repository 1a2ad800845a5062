//! The script API, one module per kernel area (mirroring `kernel/src`). [`register_all`] is the
//! only place that knows them all.

pub mod anim;
pub mod block_handle;
pub mod blocks;
pub mod color;
pub mod csg;
pub mod data;
pub mod diagnose;
pub mod files;
pub mod finish;
pub mod lsystem;
pub mod mesh;
pub mod nesting;
pub mod noise;
pub mod paths;
pub mod polar;
pub mod profile;
pub mod registry;
pub mod rng;
pub mod runtime;
pub mod solve;
pub mod subdiv;
pub mod values;
pub mod voxel;

use blocksmith_kernel::Vec3;
use rhai::{exported_module, Engine};

/// Registers every type and function of the script API on `engine`.
pub fn register_all(engine: &mut Engine) {
    engine.register_type_with_name::<Vec3>("Vec3");
    engine.register_type_with_name::<mesh::SharedMesh>("Mesh");
    engine.register_global_module(exported_module!(values::vec3_api).into());
    engine.register_global_module(exported_module!(mesh::mesh_api).into());
    engine.register_global_module(exported_module!(color::color_api).into());
    engine.register_global_module(exported_module!(files::files_api).into());
    voxel::register(engine);
    subdiv::register(engine);
    polar::register(engine);
    lsystem::register(engine);
    anim::register(engine);
    solve::register(engine);
    blocks::register(engine);
    csg::register(engine);
    profile::register(engine);
    rng::register(engine);
    noise::register(engine);
    finish::register(engine);
    diagnose::register(engine);
    engine.register_global_module(exported_module!(runtime::runtime_api).into());
    engine.register_global_module(exported_module!(data::data_api).into());
    engine.register_global_module(exported_module!(nesting::nesting_api).into());
}
