//! Relaxation: vertices moved towards the mean of their neighbours. Laplacian smoothing shrinks
//! a closed surface; Taubin's λ|μ smoothing ("A signal processing approach to fair surface
//! design", SIGGRAPH 1995, §4: λ = 0.5, μ = −0.53, alternating steps) removes noise without
//! shrinking. Crease-tagged edges' vertices stay put, so features and part borders hold. Only
//! positions change: every id, colour and part is kept. O(iterations × edges).

use crate::limits;
use crate::math::Vec3;
use crate::mesh::Mesh;

use super::FinishError;

/// The smoothing rule of [`relax`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RelaxMethod {
    /// Taubin's λ|μ steps: smooth without shrinking (the default).
    Taubin,
    /// Plain Laplacian steps of weight ½: smoother, but the volume shrinks.
    Laplacian,
}

/// What [`relax`] is asked for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RelaxOptions {
    /// Rounds (1 to 10 000); a Taubin round is one λ and one μ step.
    pub iterations: u32,
    /// The rule.
    pub method: RelaxMethod,
}

impl Default for RelaxOptions {
    fn default() -> RelaxOptions {
        RelaxOptions { iterations: 10, method: RelaxMethod::Taubin }
    }
}

/// Taubin's weights (§4: pass band k_PB = 1/λ + 1/μ ≈ 0.1).
const LAMBDA: f64 = 0.5;
const MU: f64 = -0.53;

/// A copy of `mesh` relaxed by `options` (see the module notes). Vertices on crease edges or
/// the boundary do not move. Tells a listener ([`limits::listen`]) its smoothing steps (two an
/// iteration for Taubin's).
///
/// # Errors
/// [`FinishError::BadOption`] for iterations outside 1–10 000; a stop of the cancellation token.
pub fn relax(mesh: &Mesh, options: RelaxOptions) -> Result<Mesh, FinishError> {
    if !(1..=10_000).contains(&options.iterations) {
        return Err(FinishError::bad("iterations", f64::from(options.iterations), "between 1 and 10000"));
    }
    let n = mesh.vertex_count();
    let fixed: Vec<bool> =
        (0..n as u32).map(|v| mesh.is_boundary_vertex(v) || mesh.outgoing(v).any(|h| mesh.is_crease(h))).collect();
    // Neighbours in a flat table (CSR).
    let mut start = Vec::with_capacity(n + 1);
    let mut nbr = Vec::with_capacity(2 * mesh.edge_count());
    for v in 0..n as u32 {
        start.push(nbr.len());
        nbr.extend(mesh.vertex_neighbors(v));
    }
    start.push(nbr.len());
    let mut p: Vec<Vec3> = mesh.positions().to_vec();
    let mut next = p.clone();
    let steps: Vec<f64> = match options.method {
        RelaxMethod::Taubin => (0..options.iterations).flat_map(|_| [LAMBDA, MU]).collect(),
        RelaxMethod::Laplacian => vec![0.5; options.iterations as usize],
    };
    let work = limits::Work::start(steps.len() as u64);
    for (i, &w) in steps.iter().enumerate() {
        limits::poll_at(i * n)?;
        work.set(i as u64);
        for v in 0..n {
            let ring = &nbr[start[v]..start[v + 1]];
            if fixed[v] || ring.is_empty() {
                next[v] = p[v];
                continue;
            }
            let mean = ring.iter().map(|&u| p[u as usize]).sum::<Vec3>() / ring.len() as f64;
            next[v] = p[v] + (mean - p[v]) * w;
        }
        std::mem::swap(&mut p, &mut next);
    }
    work.finish();
    let mut out = mesh.clone();
    out.set_positions(p)?;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::SplitMix64;

    fn noisy_sphere() -> (Mesh, Mesh) {
        let ball = Mesh::icosphere(1.0, 3);
        let mut r = SplitMix64::new(4);
        let moved = ball.positions().iter().map(|&p| p * (1.0 + 0.03 * (2.0 * r.next_f64() - 1.0))).collect();
        let mut noisy = ball.clone();
        noisy.set_positions(moved).unwrap();
        (ball, noisy)
    }

    fn roughness(m: &Mesh) -> f64 {
        m.positions().iter().map(|p| (p.length() - 1.0).abs()).fold(0.0, f64::max)
    }

    #[test]
    fn taubin_removes_noise_without_shrinking_and_laplacian_shrinks() {
        let (ball, noisy) = noisy_sphere();
        let t = relax(&noisy, RelaxOptions { iterations: 10, method: RelaxMethod::Taubin }).unwrap();
        let l = relax(&noisy, RelaxOptions { iterations: 10, method: RelaxMethod::Laplacian }).unwrap();
        assert!(t.is_closed() && t.is_manifold() && t.genus() == 0);
        let (v0, vt, vl) = (ball.volume(), t.volume(), l.volume());
        assert!((vt - v0).abs() / v0 < 0.02, "Taubin volume {vt} vs {v0}");
        assert!(vl < 0.95 * v0, "Laplacian volume {vl} vs {v0}");
        // Smoother: the spread of radii drops.
        let spread = |m: &Mesh| {
            let r: Vec<f64> = m.positions().iter().map(|p| p.length()).collect();
            let mean = r.iter().sum::<f64>() / r.len() as f64;
            (r.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / r.len() as f64).sqrt()
        };
        assert!(spread(&t) < 0.5 * spread(&noisy), "{} vs {}", spread(&t), spread(&noisy));
        assert!(roughness(&noisy) > 0.02);
    }

    #[test]
    fn creased_vertices_stay_and_bad_iterations_are_refused() {
        let mut c = Mesh::cube(2.0).triangulate().unwrap();
        c.crease_all();
        let r = relax(&c, RelaxOptions::default()).unwrap();
        assert_eq!(r.positions(), c.positions());
        assert!(relax(&c, RelaxOptions { iterations: 0, ..RelaxOptions::default() })
            .unwrap_err()
            .to_string()
            .contains("`iterations`"));
    }
}
