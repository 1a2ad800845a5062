//! glTF is Y-up (glTF 2.0 §3.4): a box taller in the kernel's z than it is wide, saved as
//! `.glb`, must stand upright in an ordinary glTF viewer. The viewer here is the vendored
//! three.js (its defaults: Y up, the camera looking down −Z) with its GLTFLoader, in a headless
//! chromium; the screenshot's box must be taller than wide. Skipped where chromium is missing,
//! except under CI=true, where it must be there.

use std::io::{BufRead, BufReader, Write};
use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::process::Command;

use blocksmith_kernel::{io, Mesh, Vec3};

/// A page that loads `box.glb` with three.js's defaults and draws it black on white, seen
/// from +Z by an orthographic camera (no perspective to stretch it).
const PAGE: &str = r#"<!doctype html>
<html><head><meta charset="utf-8"><title>loading</title>
<script type="importmap">
{ "imports": { "three": "/three/three.module.js", "three/addons/": "/three/jsm/" } }
</script>
<style>html, body { margin: 0; background: #fff; }</style></head>
<body><script type="module">
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
const renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
renderer.setSize(400, 400);
document.body.appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0xffffff);
const camera = new THREE.OrthographicCamera(-4, 4, 4, -4, 0.1, 100);
camera.position.set(0, 0, 20);
camera.lookAt(0, 0, 0);
new GLTFLoader().load('/box.glb', (gltf) => {
  const root = gltf.scene;
  root.traverse((o) => { if (o.isMesh) o.material = new THREE.MeshBasicMaterial({ color: 0x000000 }); });
  const centre = new THREE.Box3().setFromObject(root).getCenter(new THREE.Vector3());
  root.position.sub(centre);
  scene.add(root);
  renderer.render(scene, camera);
  document.title = 'drawn';
}, undefined, (e) => { document.title = 'failed: ' + e; });
</script></body></html>
"#;

/// Serves `page` at `/`, the file `glb` at `/box.glb` and the vendored three.js under
/// `/three/`, on 127.0.0.1; returns the address.
fn serve(glb: PathBuf) -> String {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = listener.local_addr().unwrap().to_string();
    let three = Path::new(env!("CARGO_MANIFEST_DIR")).join("../studio/web/vendor/three");
    std::thread::spawn(move || {
        for stream in listener.incoming() {
            let Ok(mut stream) = stream else { continue };
            // The request line, then the headers up to the blank line (read, so that closing
            // the connection does not reset it under the unread request).
            let mut reader = BufReader::new(&stream);
            let mut line = String::new();
            if reader.read_line(&mut line).is_err() {
                continue;
            }
            let mut header = String::new();
            while reader.read_line(&mut header).is_ok_and(|n| n > 2) {
                header.clear();
            }
            let path = line.split_whitespace().nth(1).unwrap_or("/").to_string();
            let (body, kind) = match path.as_str() {
                "/" => (Some(PAGE.as_bytes().to_vec()), "text/html"),
                "/box.glb" => (std::fs::read(&glb).ok(), "model/gltf-binary"),
                p => match p.strip_prefix("/three/") {
                    Some(rest) if !rest.contains("..") => (std::fs::read(three.join(rest)).ok(), "text/javascript"),
                    _ => (None, "text/plain"),
                },
            };
            let head = match &body {
                Some(b) => format!(
                    "HTTP/1.1 200 OK\r\nContent-Type: {kind}\r\nContent-Length: {}\r\nConnection: close\r\n\r\n",
                    b.len()
                ),
                None => "HTTP/1.1 404 Not Found\r\nContent-Length: 0\r\nConnection: close\r\n\r\n".to_string(),
            };
            let _ = stream.write_all(head.as_bytes());
            let _ = stream.write_all(&body.unwrap_or_default());
        }
    });
    addr
}

#[test]
fn a_box_tall_in_z_stands_upright_in_three_js() {
    let found = Command::new("chromium").arg("--version").output().is_ok_and(|o| o.status.success());
    if !found {
        assert!(std::env::var("CI").as_deref() != Ok("true"), "CI must install chromium for the browser tests");
        eprintln!("chromium not found: browser test skipped");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    // 1 wide, 2 deep, 5 tall in the kernel's z.
    let tall = Mesh::cuboid(Vec3::ZERO, Vec3::new(1.0, 2.0, 5.0));
    let glb = dir.path().join("box.glb");
    io::save(&tall, &glb).unwrap();
    assert_eq!(io::load(&glb).unwrap().positions(), tall.positions(), "the round trip keeps the z-up positions");
    let addr = serve(glb);
    let shot = dir.path().join("shot.png");
    let o = Command::new("chromium")
        .args(["--headless", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader"])
        .args(["--window-size=400,400", "--hide-scrollbars", "--virtual-time-budget=10000", "--dump-dom"])
        .arg(format!("--user-data-dir={}", dir.path().join("profile").display()))
        .arg(format!("--screenshot={}", shot.display()))
        .arg(format!("http://{addr}/"))
        .output()
        .unwrap();
    let dom = String::from_utf8_lossy(&o.stdout);
    assert!(dom.contains("<title>drawn</title>"), "the page did not draw the model: {dom}");
    // The extent of the dark pixels: the box seen from +Z with Y up is its kernel x (1) across
    // and its kernel z (5) up; lying on its side it would be 5 across, or 1 × 2 end on.
    let img = image::open(&shot).unwrap().to_rgb8();
    let (mut x0, mut x1, mut y0, mut y1) = (u32::MAX, 0, u32::MAX, 0);
    for (x, y, p) in img.enumerate_pixels() {
        if p.0.iter().all(|&c| c < 100) {
            (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
        }
    }
    assert!(x0 <= x1, "no model pixels in the screenshot");
    let (w, h) = (f64::from(x1 - x0 + 1), f64::from(y1 - y0 + 1));
    // 8 units over 400 pixels: 50 pixels a unit.
    assert!((w - 50.0).abs() <= 3.0 && (h - 250.0).abs() <= 3.0, "on screen {w} × {h} pixels, expected 50 × 250");
}
