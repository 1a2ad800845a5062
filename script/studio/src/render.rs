//! `blocksmith render`: a picture of meshes on the CPU — no GPU, no browser — the same bytes
//! on every run, for documentation, CI artefacts and the gallery.
//!
//! A z-buffered rasteriser of triangles under an orthographic camera (the views of
//! [`View`]), supersampled 3×3 per pixel: the model is lit by one light fixed to the camera
//! (Lambert, both sides, plus an ambient term) in linear colour, then stored with gamma 2.
//! Colours are the page's: a mesh's own face colours (its materials) times its vertex colours
//! (feature colours come in that way), else [`PLAIN`], on [`BACKGROUND`]. Provenance (which
//! boolean operand a face came from) is a debugging view, not drawn here.
//!
//! Why our own rasteriser rather than a crate: the job is one fixed pipeline (flat triangles,
//! interpolated vertex colours, one light) in about two hundred lines, and the promise is the
//! same bytes for the same input. The general software renderers on crates.io (`euc`) bring a
//! generic shader pipeline and threading whose order we would have to pin down, and 2D
//! rasterisers (`tiny-skia`) have no depth buffer. Here every step is sequential IEEE
//! arithmetic with no transcendental functions (normalisation and gamma use `sqrt`, which IEEE
//! rounds exactly), so the bytes do not depend on a platform's maths library. PNG encoding is
//! the `image` crate's.

use std::str::FromStr;

use blocksmith_kernel::{Mesh, Vec3};

/// The background, linear RGB.
pub const BACKGROUND: [f64; 3] = [0.86, 0.87, 0.89];
/// The colour of a mesh without vertex colours, linear RGB (the page's plain material).
pub const PLAIN: [f64; 3] = [0.55, 0.6, 0.68];
/// Samples per pixel along each axis.
const SUPERSAMPLE: usize = 3;
/// The share of the picture left free around the model, on each side.
const MARGIN: f64 = 0.06;

/// Where the camera looks from; the kernel's +Z is up in every side view.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    /// From the front, right and above (+X, −Y, +Z).
    Iso,
    /// From −Y.
    Front,
    /// From +Y.
    Back,
    /// From −X.
    Left,
    /// From +X.
    Right,
    /// From +Z, +Y up the picture.
    Top,
    /// From −Z, −Y up the picture.
    Bottom,
}

impl View {
    /// Every view, by name.
    pub const ALL: [(&'static str, View); 7] = [
        ("iso", View::Iso),
        ("front", View::Front),
        ("back", View::Back),
        ("left", View::Left),
        ("right", View::Right),
        ("top", View::Top),
        ("bottom", View::Bottom),
    ];

    /// The direction towards the camera and the direction up the picture (not unit).
    fn axes(self) -> (Vec3, Vec3) {
        match self {
            View::Iso => (Vec3::new(1.0, -1.0, 1.0), Vec3::Z),
            View::Front => (Vec3::NEG_Y, Vec3::Z),
            View::Back => (Vec3::Y, Vec3::Z),
            View::Left => (Vec3::NEG_X, Vec3::Z),
            View::Right => (Vec3::X, Vec3::Z),
            View::Top => (Vec3::Z, Vec3::Y),
            View::Bottom => (Vec3::NEG_Z, Vec3::NEG_Y),
        }
    }
}

impl FromStr for View {
    type Err = String;

    fn from_str(s: &str) -> Result<View, String> {
        View::ALL.iter().find(|(name, _)| *name == s).map(|&(_, v)| v).ok_or_else(|| {
            let names: Vec<&str> = View::ALL.iter().map(|(n, _)| *n).collect();
            format!("unknown view `{s}`; the views are: {}", names.join(", "))
        })
    }
}

/// An RGB picture, 8 bits a channel, rows top to bottom.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Picture {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
}

impl Picture {
    /// The PNG file of the picture.
    ///
    /// # Panics
    /// Never for a picture made by [`render`] (its buffer matches its size).
    #[must_use]
    pub fn png(&self) -> Vec<u8> {
        let mut out = Vec::new();
        image::ImageEncoder::write_image(
            image::codecs::png::PngEncoder::new(&mut out),
            &self.rgb,
            self.width,
            self.height,
            image::ExtendedColorType::Rgb8,
        )
        .expect("an RGB buffer of the picture's size encodes");
        out
    }

    /// How many pixels differ from the background colour.
    #[must_use]
    pub fn covered_pixels(&self) -> usize {
        let bg = encode(BACKGROUND);
        self.rgb.chunks_exact(3).filter(|p| *p != bg).count()
    }
}

/// Gamma 2 (rather than sRGB's curve): `sqrt` is exact in IEEE arithmetic, so the bytes are.
fn encode(c: [f64; 3]) -> [u8; 3] {
    c.map(|x| (x.clamp(0.0, 1.0).sqrt() * 255.0 + 0.5) as u8)
}

/// Renders `meshes` together at `width`×`height` from `view`, fitted to the picture.
/// Polygons are split into triangles as a fan from their first corner (the picture needs no
/// more for the convex and near-convex faces of a model's surface).
#[must_use]
pub fn render(meshes: &[&Mesh], width: u32, height: u32, view: View) -> Picture {
    let (w, h) = (width as usize * SUPERSAMPLE, height as usize * SUPERSAMPLE);
    let (toward, up) = view.axes();
    let toward = toward.normalize();
    let right = up.cross(toward).normalize();
    let up = toward.cross(right);
    let light = (right * -0.35 + up * 0.55 + toward * 0.75).normalize();

    // Fit the projected points into the picture, less the margin.
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in meshes.iter().flat_map(|m| m.positions()) {
        let s = [p.dot(right), p.dot(up)];
        for k in 0..2 {
            lo[k] = lo[k].min(s[k]);
            hi[k] = hi[k].max(s[k]);
        }
    }
    let span = [(hi[0] - lo[0]).max(1e-12), (hi[1] - lo[1]).max(1e-12)];
    let scale = ((w as f64) * (1.0 - 2.0 * MARGIN) / span[0]).min((h as f64) * (1.0 - 2.0 * MARGIN) / span[1]);
    let centre = [(lo[0] + hi[0]) * 0.5, (lo[1] + hi[1]) * 0.5];
    let to_screen = |p: Vec3| -> [f64; 3] {
        [
            w as f64 * 0.5 + (p.dot(right) - centre[0]) * scale,
            h as f64 * 0.5 - (p.dot(up) - centre[1]) * scale,
            p.dot(toward),
        ]
    };

    let mut depth = vec![f64::NEG_INFINITY; w * h];
    let mut colour = vec![BACKGROUND; w * h];
    for mesh in meshes {
        let screen: Vec<[f64; 3]> = mesh.positions().iter().map(|&p| to_screen(p)).collect();
        let colours = mesh.vertex_colors();
        // As glTF viewers draw a material over vertex colours: the face's colour times the
        // vertex's, either alone, or the plain colour when there is neither.
        let tint = |v: u32, face: Option<[f32; 4]>| -> [f64; 3] {
            let vertex = colours.map(|c| c[v as usize]);
            match (face, vertex) {
                (None, None) => PLAIN,
                (f, v) => {
                    let (f, v) = (f.unwrap_or([1.0; 4]), v.unwrap_or([1.0; 4]));
                    [0, 1, 2].map(|k| f64::from(f[k]) * f64::from(v[k]))
                }
            }
        };
        for f in 0..mesh.face_count() as u32 {
            let face = mesh.face_color(f);
            let ids: Vec<u32> = mesh.face_vertices(f).collect();
            for k in 1..ids.len().saturating_sub(1) {
                let t = [ids[0], ids[k], ids[k + 1]];
                let [a, b, c] = t.map(|v| mesh.position(v));
                let n = (b - a).cross(c - a).normalize_or_zero();
                let shade = 0.3 + 0.7 * n.dot(light).abs();
                let tri = Triangle { p: t.map(|v| screen[v as usize]), c: t.map(|v| tint(v, face).map(|x| x * shade)) };
                tri.draw(w, h, &mut depth, &mut colour);
            }
        }
    }

    // Average each pixel's samples (in linear colour), then encode.
    let n = (SUPERSAMPLE * SUPERSAMPLE) as f64;
    let mut rgb = Vec::with_capacity(width as usize * height as usize * 3);
    for py in 0..height as usize {
        for px in 0..width as usize {
            let mut sum = [0.0; 3];
            for sy in 0..SUPERSAMPLE {
                for sx in 0..SUPERSAMPLE {
                    let s = colour[(py * SUPERSAMPLE + sy) * w + px * SUPERSAMPLE + sx];
                    for k in 0..3 {
                        sum[k] += s[k];
                    }
                }
            }
            rgb.extend(encode(sum.map(|x| x / n)));
        }
    }
    Picture { width, height, rgb }
}

/// One triangle in sample coordinates (x right, y down, z towards the camera) with the shaded
/// colour of each corner.
struct Triangle {
    p: [[f64; 3]; 3],
    c: [[f64; 3]; 3],
}

impl Triangle {
    /// Writes the samples whose centres the triangle covers and where it is nearest so far
    /// (ties keep the earlier triangle, so the order of faces decides, deterministically).
    fn draw(&self, w: usize, h: usize, depth: &mut [f64], colour: &mut [[f64; 3]]) {
        let [p0, p1, p2] = self.p;
        let edge = |a: [f64; 3], b: [f64; 3], x: f64, y: f64| (b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0]);
        let area = edge(p0, p1, p2[0], p2[1]);
        if area == 0.0 || !area.is_finite() {
            return;
        }
        let x0 = p0[0].min(p1[0]).min(p2[0]).floor().max(0.0) as usize;
        let x1 = (p0[0].max(p1[0]).max(p2[0]).ceil().max(0.0) as usize).min(w);
        let y0 = p0[1].min(p1[1]).min(p2[1]).floor().max(0.0) as usize;
        let y1 = (p0[1].max(p1[1]).max(p2[1]).ceil().max(0.0) as usize).min(h);
        for y in y0..y1 {
            let sy = y as f64 + 0.5;
            for x in x0..x1 {
                let sx = x as f64 + 0.5;
                let b = [edge(p1, p2, sx, sy) / area, edge(p2, p0, sx, sy) / area, edge(p0, p1, sx, sy) / area];
                if b.iter().any(|&v| v < 0.0) {
                    continue;
                }
                let z = b[0] * p0[2] + b[1] * p1[2] + b[2] * p2[2];
                let i = y * w + x;
                if z > depth[i] {
                    depth[i] = z;
                    colour[i] = [0, 1, 2].map(|k| b[0] * self.c[0][k] + b[1] * self.c[1][k] + b[2] * self.c[2][k]);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube() -> Mesh {
        Mesh::cuboid(Vec3::ZERO, Vec3::ONE)
    }

    #[test]
    fn a_cube_fills_the_middle_and_leaves_the_corners_to_the_background() {
        let pic = render(&[&cube()], 64, 48, View::Front);
        let px = |x: usize, y: usize| &pic.rgb[(y * 64 + x) * 3..(y * 64 + x) * 3 + 3];
        let bg = encode(BACKGROUND);
        assert_eq!(px(0, 0), bg);
        assert_eq!(px(63, 47), bg);
        assert_ne!(px(32, 24), bg);
        // Seen from the front a unit cube is a square: 88 % of the height, as wide.
        let side = (48.0 * (1.0 - 2.0 * MARGIN)) as usize;
        let covered = pic.covered_pixels();
        assert!(covered.abs_diff(side * side) <= 2 * side + 4, "{covered} vs {}", side * side);
    }

    #[test]
    fn the_same_meshes_give_the_same_bytes_and_each_view_its_own() {
        let m = Mesh::cuboid(Vec3::ZERO, Vec3::new(2.0, 1.0, 0.5));
        let a = render(&[&m], 80, 60, View::Iso).png();
        assert_eq!(a, render(&[&m], 80, 60, View::Iso).png());
        assert_eq!(&a[..8], b"\x89PNG\r\n\x1a\n");
        let front = render(&[&m], 80, 60, View::Front);
        let top = render(&[&m], 80, 60, View::Top);
        assert_ne!(front, top);
        // From the front the box is 2 wide and 0.5 high; from above, 2 by 1.
        assert!(top.covered_pixels() > front.covered_pixels() * 3 / 2);
    }

    #[test]
    fn vertex_colours_are_drawn_and_a_plain_mesh_is_plain() {
        let mut m = cube();
        m.set_vertex_colors(Some(vec![[1.0, 0.0, 0.0, 1.0]; m.vertex_count()])).unwrap();
        let red = render(&[&m], 32, 32, View::Front);
        let mid = &red.rgb[(16 * 32 + 16) * 3..(16 * 32 + 16) * 3 + 3];
        assert!(mid[0] > 100 && mid[1] == 0 && mid[2] == 0, "{mid:?}");
        let plain = render(&[&cube()], 32, 32, View::Front);
        let mid = &plain.rgb[(16 * 32 + 16) * 3..(16 * 32 + 16) * 3 + 3];
        assert!(mid[2] > mid[0], "the plain colour is bluish grey: {mid:?}");
    }

    #[test]
    fn face_colours_are_drawn_and_tint_vertex_colours() {
        // The front face (−Y) green, the rest blue: from the front, green.
        let mut m = cube();
        m.set_color([0.0, 0.0, 1.0, 1.0]).unwrap();
        let front = (0..m.face_count() as u32).find(|&f| m.face_normal(f).y < -0.9).unwrap();
        let mut ids = m.face_part_ids().unwrap().to_vec();
        let mut parts = m.parts().to_vec();
        parts.push(blocksmith_kernel::mesh::FacePart::with_color([0.0, 1.0, 0.0, 1.0]));
        ids[front as usize] = (parts.len() - 1) as u32;
        m.set_face_parts(ids, parts).unwrap();
        let pic = render(&[&m], 32, 32, View::Front);
        let mid = &pic.rgb[(16 * 32 + 16) * 3..(16 * 32 + 16) * 3 + 3];
        assert!(mid[1] > 100 && mid[0] == 0 && mid[2] == 0, "{mid:?}");
        // A half-grey vertex colour darkens the face's colour.
        m.set_vertex_colors(Some(vec![[0.5, 0.5, 0.5, 1.0]; m.vertex_count()])).unwrap();
        let dim = render(&[&m], 32, 32, View::Front);
        let d = &dim.rgb[(16 * 32 + 16) * 3..(16 * 32 + 16) * 3 + 3];
        assert!(d[1] < mid[1] && d[1] > 0 && d[0] == 0, "{d:?} vs {mid:?}");
    }

    #[test]
    fn a_view_is_named_and_a_wrong_name_lists_the_views() {
        assert_eq!("top".parse::<View>(), Ok(View::Top));
        let e = "diagonal".parse::<View>().unwrap_err();
        assert!(e.contains("diagonal") && e.contains("iso, front"), "{e}");
    }
}
