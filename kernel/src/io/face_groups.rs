//! How writers group a mesh's faces by their parts ([`crate::mesh::FacePart`]): into objects by
//! part name (3MF objects, glTF nodes, OBJ `o` groups) and into materials by colour (3MF base
//! materials, glTF materials, OBJ `usemtl`), in the order parts are first met.

use std::sync::Arc;

use crate::mesh::{to_hex_color, Mesh, Rgba};

/// Whether `mesh` has parts a writer shows: some face with a colour or a name.
pub(crate) fn has_parts(mesh: &Mesh) -> bool {
    mesh.face_part_ids().is_some() && mesh.parts().iter().any(|p| p.color.is_some() || p.name.is_some())
}

/// A mesh's faces grouped into objects and materials.
pub(crate) struct FaceGroups {
    /// The colour of each material (`None`: faces without a colour).
    pub colors: Vec<Option<Rgba>>,
    /// The name of each object (`None`: faces of unnamed parts).
    pub objects: Vec<Option<Arc<str>>>,
    /// The faces of each object, in face order.
    pub object_faces: Vec<Vec<u32>>,
    /// The material of each face.
    face_material: Vec<u32>,
}

impl FaceGroups {
    /// The groups of `mesh`'s faces (one object and one material for a mesh without parts).
    pub(crate) fn of(mesh: &Mesh) -> FaceGroups {
        let parts = mesh.parts();
        let mut colors: Vec<Option<Rgba>> = Vec::new();
        let mut objects: Vec<Option<Arc<str>>> = Vec::new();
        let mut part_material = Vec::with_capacity(parts.len());
        let mut part_object = Vec::with_capacity(parts.len());
        for p in parts {
            part_material.push(index_of(&mut colors, p.color) as u32);
            part_object.push(index_of(&mut objects, p.name.clone()));
        }
        let mut object_faces = vec![Vec::new(); objects.len().max(1)];
        let mut face_material = Vec::with_capacity(mesh.face_count());
        match mesh.face_part_ids() {
            Some(ids) => {
                for (f, &id) in ids.iter().enumerate() {
                    object_faces[part_object[id as usize]].push(f as u32);
                    face_material.push(part_material[id as usize]);
                }
            }
            None => {
                object_faces[0] = (0..mesh.face_count() as u32).collect();
                face_material = vec![0; mesh.face_count()];
            }
        }
        if colors.is_empty() {
            colors.push(None);
        }
        if objects.is_empty() {
            objects.push(None);
        }
        // Objects left without faces (a part table holding unused parts) are dropped.
        let kept: Vec<usize> = (0..objects.len()).filter(|&k| !object_faces[k].is_empty()).collect();
        let objects = kept.iter().map(|&k| objects[k].clone()).collect();
        let object_faces = kept.iter().map(|&k| std::mem::take(&mut object_faces[k])).collect();
        FaceGroups { colors, objects, object_faces, face_material }
    }

    /// The material of face `f`.
    pub(crate) fn material_of_face(&self, f: u32) -> u32 {
        self.face_material[f as usize]
    }

    /// A material's name: its colour as `#rrggbb[aa]`, `default` for faces without one.
    pub(crate) fn material_name(&self, k: usize) -> String {
        self.colors[k].map_or_else(|| "default".to_string(), to_hex_color)
    }
}

/// The index of `x` in `list`, pushed at the end when it is new.
fn index_of<T: PartialEq>(list: &mut Vec<T>, x: T) -> usize {
    match list.iter().position(|y| *y == x) {
        Some(i) => i,
        None => {
            list.push(x);
            list.len() - 1
        }
    }
}
