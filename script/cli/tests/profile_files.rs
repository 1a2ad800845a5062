//! 2D profiles written for other tools: an SVG `save` is drawn by a real browser (Debian's
//! chromium, headless) with the region's area, and a DXF reads back with the same contours.

mod support;
use support::chromium;

use std::path::{Path, PathBuf};
use std::process::Command;

fn run(dir: &Path, name: &str, text: &str) -> std::process::Output {
    let recipe = dir.join(name);
    std::fs::write(&recipe, text).unwrap();
    Command::new(env!("CARGO_BIN_EXE_blocksmith")).arg("run").arg(&recipe).current_dir(dir).output().unwrap()
}

/// The region a browser fills: a 40 × 20 plate (one unit a millimetre) less a hole of radius 5
/// (a 32-gon). SVG lengths are in millimetres, 96 px to the inch, so the filled pixels are the
/// region's area × (96 / 25.4)², to the anti-aliased edge.
#[test]
fn an_svg_save_is_drawn_by_a_browser_with_the_region_s_area() {
    let Some(browser) = chromium() else { return };
    let dir = tempfile::tempdir().unwrap();
    let o = run(
        dir.path(),
        "plate.rhai",
        "let p = rect([0, 0], [40, 20]) - circle(5, 32).translate([12, 10]);\np.save(\"plate.svg\");\np.area()",
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let svg: PathBuf = dir.path().join("plate.svg");
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("fill-rule=\"evenodd\""), "{text}");
    let shot = dir.path().join("shot.png");
    let profile = tempfile::tempdir().unwrap();
    let out = Command::new(browser)
        .args(["--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--hide-scrollbars"])
        .args(["--disable-background-networking", "--disable-component-update", "--disable-sync"])
        .args(["--window-size=400,300", "--force-device-scale-factor=1"])
        .arg(format!("--user-data-dir={}", profile.path().display()))
        .arg(format!("--screenshot={}", shot.display()))
        .arg(format!("file://{}", svg.display()))
        .output()
        .unwrap();
    assert!(shot.exists(), "no screenshot: {}", String::from_utf8_lossy(&out.stderr));
    let picture = image::open(&shot).unwrap().to_rgb8();
    // Pixels clearly darker than the white page, weighted by how dark (so edges count by half).
    let background = picture.get_pixel(picture.width() - 1, picture.height() - 1).0;
    let ink: f64 = picture
        .pixels()
        .map(|p| {
            let d = (0..3).map(|i| f64::from(background[i]) - f64::from(p.0[i])).fold(0.0, f64::max);
            d / (f64::from(background[2]) - 0x4a as f64).max(1.0)
        })
        .map(|x| x.clamp(0.0, 1.0))
        .sum();
    let area = 40.0 * 20.0 - 16.0 * (2.0 * std::f64::consts::PI / 32.0).sin() * 25.0;
    let expected = area * (96.0 / 25.4_f64).powi(2);
    eprintln!("browser ink {ink:.0} px, region {expected:.0} px");
    assert!((ink - expected).abs() < 0.03 * expected, "the browser filled {ink:.0} px, the region is {expected:.0} px");
}

/// A DXF written by `save` reads back to the same region: contours, holes and area.
#[test]
fn a_dxf_save_reads_back_with_the_same_contours_and_area() {
    let dir = tempfile::tempdir().unwrap();
    let text = "let p = rect([0, 0], [40, 20]) - circle(5, 32).translate([12, 10]) + rect([50, 0], [60, 10]);\n\
                p.save(\"part.dxf\");\nlet q = load(\"part.dxf\");\n\
                assert_eq(q.contours().len(), 3);\nassert_near(q.area(), p.area(), 1e-6);\n\
                assert_eq(q.bounds().max, [60.0, 20.0]);";
    let o = run(dir.path(), "part.rhai", text);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}
