//! L-system plants written to files: the same seed gives the same bytes (OBJ and GLB), different
//! seeds different files (Brazzolotto §11; API conventions: "the same script with the same seed
//! gives byte-identical output").

use blocksmith_script::{new_engine, EngineOptions};

/// Grows `grammar` with `seed` and writes it to `path`.
fn write(dir: &std::path::Path, grammar: &str, seed: i64, file: &str) -> Vec<u8> {
    let path = dir.join(file);
    let script =
        format!("{grammar}.with_seed({seed}).grow(6, #{{ valence: 10 }}).save({:?});", path.display().to_string());
    new_engine(EngineOptions::default()).run(&script).unwrap_or_else(|e| panic!("{e}\n{script}"));
    std::fs::read(&path).unwrap()
}

#[test]
fn same_seed_same_bytes_and_different_seeds_differ() {
    let dir = tempfile::tempdir().unwrap();
    // The thesis's plant (branches nested on branches) and a stochastic plant whose branches all
    // leave the trunk, each over several seeds, to both formats.
    let thesis = "thesis_plant(#{ seed: 0 })";
    let trunk = r#"lsystem(#{ axiom: "F X(0)", rules: #{ "X(s)": [
        #{ to: "[+F] F X(s+1)", p: 0.4 }, #{ to: "[-F] F X(s+1)", p: 0.4 }, #{ to: "F X(s+1)", p: 0.2 }] } })"#;
    for (grammar, ext) in [(thesis, "obj"), (thesis, "glb"), (trunk, "obj"), (trunk, "glb")] {
        for seed in [1, 3, 5] {
            let a = write(dir.path(), grammar, seed, &format!("a.{ext}"));
            let b = write(dir.path(), grammar, seed, &format!("b.{ext}"));
            assert!(a.len() > 1000, "{ext}: only {} bytes", a.len());
            assert!(a == b, "{grammar} seed {seed}: the two .{ext} files differ");
            let c = write(dir.path(), grammar, seed + 1, &format!("c.{ext}"));
            assert!(a != c, "{grammar}: seeds {seed} and {} wrote the same .{ext}", seed + 1);
        }
    }
}
