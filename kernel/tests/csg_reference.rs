//! blocksmith's CSG against manifold3d (the C++ Manifold 3.5.4) on the same input meshes: volume
//! and surface area to 1e-6 relative, Euler characteristic exact, for differences, unions and intersections of
//! cubes, a sphere, a tilted cylinder, a torus, and the die (a cube minus 21 pips).
//!
//! The inputs (OBJ) and manifold3d's numbers (reference.json) were written by
//! tests/data/csg_reference/make_reference.py (run with the peers' venv python).

use std::collections::HashMap;
use std::path::PathBuf;

use blocksmith_kernel::csg::Csg;
use blocksmith_kernel::io::load;
use blocksmith_kernel::Mesh;

fn data() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../tests/data/csg_reference")
}

fn input(cache: &mut HashMap<String, Mesh>, name: &str) -> Csg {
    let m = cache.entry(name.to_string()).or_insert_with(|| load(data().join(format!("{name}.obj"))).unwrap());
    Csg::mesh(m.clone())
}

#[test]
fn booleans_agree_with_manifold3d() {
    let text = std::fs::read_to_string(data().join("reference.json")).unwrap();
    let reference: serde_json::Value = serde_json::from_str(&text).unwrap();
    let mut cache = HashMap::new();
    let cases = reference.as_object().unwrap();
    assert_eq!(cases.len(), 7);
    for (name, c) in cases {
        let a = input(&mut cache, c["a"].as_str().unwrap());
        let b = match &c["b"] {
            serde_json::Value::Array(names) => {
                Csg::union_all(names.iter().map(|n| input(&mut cache, n.as_str().unwrap())).collect()).unwrap()
            }
            n => input(&mut cache, n.as_str().unwrap()),
        };
        let tree = match c["op"].as_str().unwrap() {
            "+" => a.union(b),
            "-" => a.difference(b),
            _ => a.intersection(b),
        };
        let m = tree.evaluate().unwrap();
        assert!(m.is_closed() && m.is_manifold(), "{name}");
        let (v, area) = (c["volume"].as_f64().unwrap(), c["area"].as_f64().unwrap());
        assert!((m.volume() - v).abs() <= 1e-6 * v, "{name}: volume {} vs manifold3d {v}", m.volume());
        assert!((m.area() - area).abs() <= 1e-6 * area, "{name}: area {} vs manifold3d {area}", m.area());
        // Manifold's genus is 1 − χ/2 over the whole mesh (ours sums over components): compare χ.
        assert_eq!(m.euler(), 2 - 2 * c["genus"].as_i64().unwrap(), "{name}: Euler characteristic");
    }
}
