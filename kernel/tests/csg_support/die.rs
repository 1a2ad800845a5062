//! The die's pip layout shared by the CSG engine evaluation and the CSG bench (included with
//! `#[path]`): as ../shared/peers/die_manifold.py lays it out for manifold3d.

/// The 21 pip centres of a die of side 2 centred at the origin, sunk 0.05 into the faces: 1 on
/// +z, 6 on −z, 2 on +x, 5 on −x, 3 on +y, 4 on −y (opposite faces add up to 7), offsets of 0.5.
pub fn die_pips() -> Vec<[f64; 3]> {
    let d = 0.5;
    let layouts: [&[(f64, f64)]; 6] = [
        &[(0.0, 0.0)],
        &[(-d, -d), (d, d)],
        &[(-d, -d), (0.0, 0.0), (d, d)],
        &[(-d, -d), (-d, d), (d, -d), (d, d)],
        &[(-d, -d), (-d, d), (0.0, 0.0), (d, -d), (d, d)],
        &[(-d, -d), (-d, 0.0), (-d, d), (d, -d), (d, 0.0), (d, d)],
    ];
    let faces = [(1, 2, 1.0), (6, 2, -1.0), (2, 0, 1.0), (5, 0, -1.0), (3, 1, 1.0), (4, 1, -1.0)];
    let mut out = Vec::new();
    for (val, axis, sign) in faces {
        let others: Vec<usize> = (0..3).filter(|&a| a != axis).collect();
        for &(u, v) in layouts[val - 1] {
            let mut p = [0.0; 3];
            p[axis] = sign * 0.95;
            p[others[0]] = u;
            p[others[1]] = v;
            out.push(p);
        }
    }
    out
}
