//! How close marching cubes comes to the shape that was voxelized, raw and smoothed (issue 35):
//! the angle between each vertex normal (area-weighted, as a viewer shades) and the analytic one,
//! and each vertex's distance to the analytic surface, on a voxelized sphere and on the faces of
//! a box tool cut into a block with a composed rotation.
//!
//! The 64³ cases run in every test pass; `surface_error_table` (release only, ignored) prints the
//! 64³/128³/256³ table of the issue-35 note:
//! `cargo test -p blocksmith-kernel --release --lib voxel::tests_smooth -- --ignored --nocapture`.

use super::{SculptMode, SculptOptions, Surface, Voxels, DEFAULT_ISO};
use crate::math::{Quat, Vec3};
use crate::mesh::Mesh;

/// Max and 95th percentile of the normal error (degrees), max distance (voxels), and the
/// number of vertices measured.
#[derive(Debug, Clone, Copy)]
pub(super) struct SurfaceError {
    pub max_deg: f64,
    pub p95_deg: f64,
    pub max_dist: f64,
    pub count: usize,
}

/// Measures the vertices `select` keeps (it returns the analytic unit normal and the distance
/// to the analytic surface there, or `None` to skip the vertex).
fn measure(mesh: &Mesh, select: impl Fn(Vec3) -> Option<(Vec3, f64)>) -> SurfaceError {
    let normals = mesh.vertex_normals();
    let mut angles = Vec::new();
    let mut max_dist = 0.0f64;
    for (v, n) in normals.iter().enumerate() {
        if let Some((exact, dist)) = select(mesh.position(v as u32)) {
            angles.push(n.dot(exact).clamp(-1.0, 1.0).acos().to_degrees());
            max_dist = max_dist.max(dist.abs());
        }
    }
    angles.sort_by(f64::total_cmp);
    let p95 = angles[((angles.len() as f64 * 0.95) as usize).min(angles.len() - 1)];
    SurfaceError { max_deg: *angles.last().unwrap(), p95_deg: p95, max_dist, count: angles.len() }
}

/// A ball of radius 0.39 n off the grid's centre by a fraction of a voxel.
fn sphere_case(n: usize, surface: Surface) -> (Mesh, SurfaceError) {
    let c = Vec3::new(n as f64 / 2.0 + 0.3, n as f64 / 2.0 - 0.17, n as f64 / 2.0 + 0.11);
    let r = 0.39 * n as f64;
    let mut v = Voxels::new(n).unwrap();
    v.fill_sphere(c, r).unwrap();
    let mesh = v.to_mesh_with(0, DEFAULT_ISO, surface).unwrap();
    let e = measure(&mesh, |p| {
        let d = p - c;
        Some((d / d.length(), d.length() - r))
    });
    (mesh, e)
}

/// The turn of the box tool: 30° about z, then 20° about x (composed turns).
fn box_turn() -> Quat {
    Quat::from_axis_angle(Vec3::X, 20f64.to_radians()) * Quat::from_axis_angle(Vec3::Z, 30f64.to_radians())
}

/// A block filling [n/8, 7n/8)³ with a box of side n/4 (a centred tool) cut into its top face
/// by a composed rotation; measured on the box's faces, at least 4 voxels from the box's edges
/// (beyond the filter's reach) and from the block's faces. Returns the mesh, the errors, and
/// the largest deviation of a face's vertices from their own best-fit plane.
fn box_cut_case(n: usize, surface: Surface) -> (Mesh, SurfaceError, f64) {
    let nf = n as f64;
    let mut v = Voxels::new(n).unwrap();
    v.fill_box(Vec3::splat(nf / 8.0), Vec3::splat(7.0 * nf / 8.0)).unwrap();
    let side = nf / 4.0;
    let tool = Voxels::centred_box(Vec3::splat(side)).unwrap();
    let at = Vec3::new(nf / 2.0 + 0.37, nf / 2.0 - 0.21, 7.0 * nf / 8.0 - 0.1 * nf);
    let q = box_turn();
    v.sculpt(&tool, &SculptOptions::at(at).with_quat(q).with_mode(SculptMode::Subtract)).unwrap();
    let mesh = v.to_mesh_with(0, DEFAULT_ISO, surface).unwrap();
    let (h, margin) = (side / 2.0, 4.0);
    let inv = q.inverse();
    let face_of = |p: Vec3| -> Option<(usize, Vec3, f64)> {
        if (0..3).any(|a| p[a] < nf / 8.0 + margin || p[a] > 7.0 * nf / 8.0 - margin) {
            return None;
        }
        let u = inv * (p - at);
        let a = (0..3).max_by(|&i, &j| u[i].abs().total_cmp(&u[j].abs())).unwrap();
        if (u[a].abs() - h).abs() > 1.5 || (0..3).any(|b| b != a && u[b].abs() > h - margin) {
            return None;
        }
        let mut e = Vec3::ZERO;
        e[a] = u[a].signum();
        // The cut's surface faces into the removed box: its outward normal points to the centre.
        Some((a * 2 + usize::from(u[a] > 0.0), -(q * e), u[a].abs() - h))
    };
    let e = measure(&mesh, |p| face_of(p).map(|(_, n, d)| (n, d)));
    // Flatness: each face's vertices against their own least-squares plane.
    let mut groups: Vec<Vec<Vec3>> = vec![Vec::new(); 6];
    for i in 0..mesh.vertex_count() as u32 {
        let p = mesh.position(i);
        if let Some((f, _, _)) = face_of(p) {
            groups[f].push(p);
        }
    }
    let mut flat = 0.0f64;
    for g in groups.iter().filter(|g| g.len() >= 3) {
        let c = g.iter().copied().sum::<Vec3>() / g.len() as f64;
        let mut cov = crate::math::Mat3::ZERO;
        for p in g {
            let d = *p - c;
            cov += crate::math::Mat3::from_cols(d * d.x, d * d.y, d * d.z);
        }
        // The plane's normal: the covariance's direction of least spread.
        let a = faer::Mat::<f64>::from_fn(3, 3, |i, j| cov.col(j)[i]);
        let u = a.svd().expect("a finite covariance").U().to_owned();
        let normal = Vec3::new(u[(0, 2)], u[(1, 2)], u[(2, 2)]);
        flat = flat.max(g.iter().map(|p| (*p - c).dot(normal).abs()).fold(0.0, f64::max));
    }
    (mesh, e, flat)
}

fn check_solid(mesh: &Mesh, genus: i64, what: &str) {
    assert!(mesh.is_closed() && mesh.is_manifold(), "{what}: closed and manifold");
    assert_eq!((mesh.genus(), mesh.component_count()), (genus, 1), "{what}: genus, components");
    assert!(mesh.volume() > 0.0, "{what}: faces outward");
}

#[test]
fn smooth_sphere_at_64_has_normals_within_3_degrees() {
    let (raw_mesh, raw) = sphere_case(64, Surface::Raw);
    let (mesh, smooth) = sphere_case(64, Surface::Smooth);
    check_solid(&raw_mesh, 0, "raw sphere");
    check_solid(&mesh, 0, "smooth sphere");
    // Raw: 7.5° at the 95th percentile, 14° at worst; smooth: 2.4° and 3.9° (issue-35 note).
    assert!(raw.p95_deg > 6.0, "{raw:?}");
    assert!(smooth.p95_deg < 3.0 && smooth.max_deg < 5.0, "{smooth:?}");
    assert!(smooth.max_dist < 0.15, "{smooth:?}");
    // At r = 25 voxels the smooth surface sits 0.02 voxel inside on average (0.45/r, see
    // `smooth_ball_sits_inside_by_the_documented_offset`): the volume stays within 0.5 %.
    let r = 0.39 * 64.0;
    let exact = 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
    assert!((mesh.volume() - exact).abs() / exact < 5e-3, "volume {} vs {exact}", mesh.volume());
}

/// smooth_field's documented shrink: the separable filter cancels its second moment on grid
/// planes only, so oblique parts of a sphere of radius r move inward by about 0.8/r voxel and
/// the whole surface on average by 0.45/r (raw: 0.11/r), and the ball loses about 1.8/r² of its
/// volume (raw: 0.8/r²). Measured at r = 8, 12, 16: offset × r −0.449, −0.447, −0.446, volume
/// lost × r² 1.76 (raw −0.115 and 0.82). Off-centre balls of three radii check both laws (a shrink that is first order in
/// 1/r, not a fixed offset), so a change of filter that moves them is seen here and in the docs.
#[test]
fn smooth_ball_sits_inside_by_the_documented_offset() {
    for r in [8.0, 12.0, 16.0] {
        let c = Vec3::new(20.3, 19.83, 20.11);
        let mut v = Voxels::new(64).unwrap();
        v.fill_sphere(c, r).unwrap();
        let exact = 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
        for (surface, offset, loss) in [(Surface::Smooth, 0.45, 1.76), (Surface::Raw, 0.115, 0.82)] {
            let mesh = v.to_mesh_with(0, DEFAULT_ISO, surface).unwrap();
            check_solid(&mesh, 0, "ball");
            let p = mesh.positions();
            let mean = p.iter().map(|q| (*q - c).length() - r).sum::<f64>() / p.len() as f64;
            let lost = 1.0 - mesh.volume() / exact;
            eprintln!("{surface:?} r {r}: mean offset × r {:.3}, volume lost × r² {:.3}", mean * r, lost * r * r);
            assert!((mean * r + offset).abs() < 0.03, "{surface:?} r {r}: mean offset {mean} × r vs -{offset}");
            assert!((lost * r * r - loss).abs() < 0.1, "{surface:?} r {r}: lost {lost} × r² vs {loss}");
        }
    }
}

#[test]
fn smooth_rotated_box_cut_at_64_has_flat_faces() {
    let (raw_mesh, raw, raw_flat) = box_cut_case(64, Surface::Raw);
    let (mesh, smooth, flat) = box_cut_case(64, Surface::Smooth);
    check_solid(&raw_mesh, 0, "raw cut");
    check_solid(&mesh, 0, "smooth cut");
    eprintln!("raw {raw:?} flat {raw_flat}\nsmooth {smooth:?} flat {flat}");
    assert!(smooth.count > 100, "{smooth:?}");
    assert!(flat < 0.1 && smooth.max_dist < 0.1, "{smooth:?}, flat to {flat}");
    assert!(smooth.p95_deg < 3.0, "{smooth:?}");
    assert!(raw_flat > flat && raw.p95_deg > smooth.p95_deg, "raw {raw:?} flat to {raw_flat}");
}

#[test]
#[ignore = "release only: prints the issue-35 table at 64³, 128³ and 256³"]
fn surface_error_table() {
    println!("| shape | n | surface | vertices | normal max (°) | normal p95 (°) | max distance (voxels) | flatness (voxels) |");
    println!("|---|---|---|---|---|---|---|---|");
    for n in [64, 128, 256] {
        for surface in [Surface::Raw, Surface::Smooth] {
            let (m, e) = sphere_case(n, surface);
            check_solid(&m, 0, "sphere");
            println!(
                "| sphere r = 0.39 n | {n}³ | {surface:?} | {} | {:.2} | {:.2} | {:.3} | – |",
                e.count, e.max_deg, e.p95_deg, e.max_dist
            );
        }
        for surface in [Surface::Raw, Surface::Smooth] {
            let (m, e, flat) = box_cut_case(n, surface);
            check_solid(&m, 0, "box cut");
            println!(
                "| rotated box cut, faces | {n}³ | {surface:?} | {} | {:.2} | {:.2} | {:.3} | {flat:.3} |",
                e.count, e.max_deg, e.p95_deg, e.max_dist
            );
        }
    }
}
