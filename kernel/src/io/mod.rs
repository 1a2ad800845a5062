//! Mesh files: OBJ (read and write), binary STL (write), glTF 2.0 (`.glb` and `.gltf`, read and
//! write).
