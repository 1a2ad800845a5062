//! Poses of the example animations (issue 35, seed 004 Part II): `run --time T` writes the still
//! at T of the Animation a recipe ends with, at every time of a growth and of a fall under
//! gravity, each a closed, manifold mesh read back from its `.glb` (written under
//! `target/test-output/poses/`, which CI hands to the Khronos validator); `--stats` says which
//! pose it measured; `render --time T` draws the pose at T; `--time` on a value that is no
//! animation is refused by name.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).ancestors().nth(2).unwrap().to_path_buf()
}

fn blocksmith(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_blocksmith")).args(args).current_dir(workspace()).output().unwrap()
}

fn ok(o: &Output) -> String {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

#[test]
fn every_pose_of_the_example_animations_is_written_as_a_valid_mesh() {
    let dir = workspace().join("target/test-output/poses");
    std::fs::create_dir_all(&dir).unwrap();
    // plant_growth's growth lasts 5.2 (12 segments × delay 0.4 + 1 / speed 1.5 ≈ 5.47): poses
    // from before the start to after the end; plant_gravity's fall over its 2 s.
    let cases: &[(&str, &[f64])] = &[
        ("plant_growth", &[-1.0, 0.0, 0.05, 0.4, 1.0, 1.7, 2.5, 3.3, 4.1, 4.9, 5.5, 9.0]),
        ("plant_gravity", &[0.0, 0.25, 0.5, 1.0, 1.5, 2.0]),
    ];
    for (recipe, times) in cases {
        for &t in *times {
            let out = dir.join(format!("{recipe}_t{t}.glb"));
            let recipe_path = format!("examples/{recipe}.rhai");
            let time = format!("--time={t}");
            let o = blocksmith(&["run", &recipe_path, &time, "-o", out.to_str().unwrap()]);
            let err = String::from_utf8_lossy(&o.stderr).into_owned();
            assert!(o.status.success(), "{recipe} at {t}: {err}");
            assert!(err.contains(&format!("posed at t = {t}")), "{err}");
            let m = blocksmith_kernel::io::load(&out).unwrap();
            let what = format!("{recipe} at t = {t}");
            assert!(m.is_closed() && m.is_manifold(), "{what}: not closed and manifold");
            assert!(m.volume() > 0.0, "{what}: volume {}", m.volume());
            assert!(m.vertex_colors().is_some(), "{what}: the feature colours");
        }
    }
}

#[test]
fn stats_name_the_pose_they_measured() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("g.glb");
    let out = out.to_str().unwrap();
    let rest: serde_json::Value =
        serde_json::from_str(&ok(&blocksmith(&["run", "examples/plant_growth.rhai", "-o", out, "--stats", "json"])))
            .unwrap();
    assert!(rest["pose"].as_str().unwrap().starts_with("rest: the mesh the animated file skins"), "{rest}");
    let at: serde_json::Value = serde_json::from_str(&ok(&blocksmith(&[
        "run",
        "examples/plant_growth.rhai",
        "--time",
        "0",
        "-o",
        out,
        "--stats",
        "json",
    ])))
    .unwrap();
    assert!(at["pose"].as_str().unwrap().starts_with("t = 0: "), "{at}");
    // At t = 0 the plant is a seed: its model a thousandth of its size.
    let (h0, h) = (at["bounds"]["max"][2].as_f64().unwrap(), rest["bounds"]["max"][2].as_f64().unwrap());
    assert!((h0 - 0.001 * h).abs() < 1e-6 * h, "{h0} vs {h}");
    let text = ok(&blocksmith(&["run", "examples/plant_growth.rhai", "--time", "2", "-o", out, "--stats"]));
    assert!(text.lines().nth(1).is_some_and(|l| l.starts_with("pose: t = 2")), "{text}");
    // A model that is no animation has no pose line.
    let cube = ok(&blocksmith(&["run", "examples/hello.rhai", "-o", out, "--stats", "json"]));
    assert!(!cube.contains("\"pose\""), "{cube}");
}

#[test]
fn render_draws_the_pose_at_the_time_asked_and_time_needs_an_animation() {
    let dir = tempfile::tempdir().unwrap();
    let png = |name: &str, extra: &[&str]| {
        let p = dir.path().join(name);
        let mut args = vec!["render", "examples/plant_growth.rhai", "--size", "160x120", "-o", p.to_str().unwrap()];
        args.extend_from_slice(extra);
        ok(&blocksmith(&args));
        std::fs::read(p).unwrap()
    };
    let end = png("end.png", &[]);
    assert_eq!(end, png("end_time.png", &["--time", "100"]), "the default is the last frame, the grown plant");
    assert_ne!(end, png("mid.png", &["--time", "2"]), "half grown is drawn otherwise");
    for args in [
        ["run", "examples/hello.rhai", "--time", "1", "-o", "/tmp/never.glb"],
        ["render", "examples/hello.rhai", "--time", "1", "-o", "/tmp/never.png"],
    ] {
        let o = blocksmith(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains("--time 1: the") && err.contains("not an Animation"), "{err}");
    }
}
