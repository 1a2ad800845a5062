//! Feature colour coding (seed 004, appendix B.1.3): feature ids mapped to a small set of evenly
//! spaced hues, neighbouring features in different hues, written as vertex colours so that any
//! glTF viewer shows the structure.

use super::PolarMesh;
use crate::math::hsv_rgba;
use crate::mesh::Mesh;

/// The fewest hues used: few enough to tell apart, enough that neighbours rarely need more.
const MIN_HUES: usize = 6;

/// The colour of hue `h` (turns) at saturation 0.65 and value 0.95.
fn hue_rgb(h: f64) -> [f32; 4] {
    hsv_rgba(h, 0.65, 0.95)
}

impl PolarMesh {
    /// The colour index of every feature (by feature id of [`PolarMesh::feature_ids`]) and the
    /// number of hues. There are `max(6, 1 + most neighbours of one feature)` hues; feature `i`
    /// takes hue `i mod hues` unless a neighbour already has it, then the next free one, so
    /// features that share an edge always differ and separate features still vary.
    #[must_use]
    pub fn feature_palette(&self) -> (Vec<u32>, usize) {
        let m = &self.mesh;
        let (ids, count) = self.feature_ids();
        let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); count];
        for h in m.edges() {
            let (a, b) = (ids[m.face(h) as usize], ids[m.face(m.twin(h)) as usize]);
            if a != b {
                neighbours[a as usize].push(b);
                neighbours[b as usize].push(a);
            }
        }
        for n in &mut neighbours {
            n.sort_unstable();
            n.dedup();
        }
        let hues = neighbours.iter().map(|n| n.len() + 1).max().unwrap_or(1).max(MIN_HUES);
        let mut colour = vec![u32::MAX; count];
        for i in 0..count {
            let taken = |c: u32| neighbours[i].iter().any(|&n| colour[n as usize] == c);
            let start = (i % hues) as u32;
            colour[i] = (0..hues as u32).map(|k| (start + k) % hues as u32).find(|&c| !taken(c)).unwrap_or(start);
        }
        (colour, hues)
    }

    /// One RGBA colour per vertex showing the features (appendix B.1.3): each feature gets one
    /// of evenly spaced hues, neighbouring features different ones. A vertex on a boundary
    /// between features takes the colour of its smallest feature (fewest faces; lowest id on
    /// ties), so a small branch shows in full against its parent.
    #[must_use]
    pub fn feature_colors(&self) -> Vec<[f32; 4]> {
        let m = &self.mesh;
        let (ids, count) = self.feature_ids();
        let (colour, hues) = self.feature_palette();
        let mut size = vec![0usize; count];
        for &i in &ids {
            size[i as usize] += 1;
        }
        (0..m.vertex_count() as u32)
            .map(|v| {
                let best = m.vertex_faces(v).map(|f| ids[f as usize]).min_by_key(|&i| (size[i as usize], i));
                best.map_or([1.0; 4], |i| hue_rgb(f64::from(colour[i as usize]) / hues as f64))
            })
            .collect()
    }

    /// A copy of the mesh with [`PolarMesh::feature_colors`] as its vertex colours, ready to save
    /// as glTF; a polar mesh whose faces were coloured ([`PolarMesh::set_color`]) keeps its own
    /// colours instead.
    #[must_use]
    pub fn to_colored_mesh(&self) -> Mesh {
        let mut m = self.mesh.clone();
        if m.has_face_colors() {
            return m;
        }
        m.set_vertex_colors(Some(self.feature_colors())).expect("one colour per vertex");
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn neighbouring_features_get_different_hues() {
        let mut pm = PolarMesh::uv_sphere(1.0, 8, 4);
        let p = pm.add_feature(&[9, 10, 11]).unwrap();
        let (colour, hues) = pm.feature_palette();
        assert_eq!(colour.len(), 3);
        // Each feature has 2 neighbours: the minimum of 6 hues.
        assert_eq!(hues, 6);
        // The three features all touch each other at the nesting loop: three distinct colours.
        let mut c = colour.clone();
        c.sort_unstable();
        c.dedup();
        assert_eq!(c.len(), 3);
        let cols = pm.feature_colors();
        assert_eq!(cols.len(), pm.vertex_count());
        // The branch's pole and the south pole lie in different features: different colours.
        assert_ne!(cols[p as usize], cols[0]);
        let m = pm.to_colored_mesh();
        assert_eq!(m.vertex_colors().map(<[_]>::len), Some(pm.vertex_count()));
    }

    #[test]
    fn hues_are_evenly_spaced_and_valid() {
        for i in 0..6 {
            let c = hue_rgb(f64::from(i) / 6.0);
            assert!(c.iter().all(|x| (0.0..=1.0).contains(x)));
        }
        assert_eq!(hue_rgb(0.0)[0], 0.95);
        assert_ne!(hue_rgb(0.0), hue_rgb(0.5));
    }
}
