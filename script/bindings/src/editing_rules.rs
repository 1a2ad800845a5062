//! The editing rule: one per kind of value, stated once here and shown at the top of
//! `blocksmith doc` and on each type's page (`blocksmith doc Mesh`). The declarations of the
//! script API are checked against it (see the tests), so a new function cannot quietly break
//! the rule its type states, and the dropped-result lint ([`crate::lint`]) reports the calls
//! that lose a change under it.

/// How the methods of one kind of value treat the value they are called on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rule {
    /// A value never changes: every method returning one of its kind returns a new one. The
    /// only methods that touch the receiver return nothing (a Mesh's subdivision tags).
    Value,
    /// Edits change the value in place and return the value itself (the same value, not a copy),
    /// so a chain of edits on a variable edits that variable; queries leave it as it was. Any
    /// other copy (`let c = b;`, an argument, an array element) is a value of its own.
    EditAndSelf,
    /// Edits change the value in place and return nothing or what they made (an id, the new
    /// elements); queries and conversions leave it as it was.
    InPlace,
}

/// One kind of value: its script name, the Rust type its methods take, its rule and the rule
/// in words.
pub struct Kind {
    /// The script name (`Mesh`).
    pub name: &'static str,
    /// The Rust type of the receiver in the declarations (`SharedMesh`).
    pub rust: &'static str,
    /// Its rule.
    pub rule: Rule,
    /// The rule as `blocksmith doc` states it.
    pub text: &'static str,
}

/// The kinds of values scripts edit, and their rules.
pub const KINDS: &[Kind] = &[
    Kind {
        name: "Mesh",
        rust: "SharedMesh",
        rule: Rule::Value,
        text: "A Mesh is a value: methods that give a Mesh (translate, rotate, scale, mirror, \
               catmull_clark, triangulate, CSG...) return a new one and leave this one as it was, so keep \
               the result: `m = m.translate(v);`. Only the subdivision tags (crease, crease_all, corner, \
               subdiv_options) mark this mesh itself, and they return nothing.",
    },
    Kind {
        name: "Profile",
        rust: "Profile",
        rule: Rule::Value,
        text: "A Profile is a value: every operation (+, -, intersect, offset, fillet, chamfer, hull, \
               translate, rotate, scale, mirror, simplify) returns a new profile and leaves this one as it was, \
               so keep the result: `p = p.offset(1);`.",
    },
    Kind {
        name: "Vec3",
        rust: "Vec3",
        rule: Rule::Value,
        text: "A Vec3 is a value: arithmetic and functions return a new vector; `v.x = 1` sets a coordinate.",
    },
    Kind {
        name: "Block",
        rust: "Block",
        rule: Rule::EditAndSelf,
        text: "Block methods (subdivide, sharp, smooth, sharp_all, smooth_all, translate, rotate) change \
               this block and return the block itself, so a chain edits it: `b.subdivide(\"+z\", 2, 2).sharp_all();` \
               leaves b subdivided and sharp, and `m.add(block(lo, hi).sharp_all());` sets up a new block in \
               one expression. `let c = b;` makes a copy that changes on its own (as does a block passed to a \
               function or put in an array), while `let c = b.translate(v);` is b itself, moved. `m.add(b)` \
               adds a copy of b as it is then.",
    },
    Kind {
        name: "BlockModel",
        rust: "BlockModel",
        rule: Rule::InPlace,
        text: "A BlockModel is edited in place: add, allow, connect and `threshold =` change it (add returns \
               the new block's id); connections, control_mesh and stats leave it as it was, and mesh (also \
               named to_mesh) returns the surface, keeping only its counts for stats.",
    },
    Kind {
        name: "PolarMesh",
        rust: "PolarMesh",
        rule: Rule::InPlace,
        text: "A PolarMesh is edited in place: the polar operations and move_vertices, scale_vertices, \
               rotate_vertices change it and return nothing or the elements they made (the new loop, the \
               new pole); `pm.to_mesh()` gives a Mesh. The whole-mesh translate(offset), rotate(axis, deg), \
               scale(factor) and mirror(normal) return a moved copy, as a Mesh's do: `pm = pm.translate(v);`.",
    },
    Kind {
        name: "Voxels",
        rust: "Voxels",
        rule: Rule::InPlace,
        text: "Voxels are edited in place: fill_sphere, fill_box, fill_mesh, set and sculpt change the grid; \
               lod and to_mesh return a new value and leave it as it was.",
    },
    Kind {
        name: "Solver",
        rust: "Solver",
        rule: Rule::InPlace,
        text: "A Solver is edited in place: each constraint (rigid, circle, plane, closeness, laplacian, \
               anchor) is added to it and returns nothing; `s.solve(n)` returns the solved Mesh.",
    },
    Kind {
        name: "Rng",
        rust: "Rng",
        rule: Rule::InPlace,
        text: "An Rng is one random stream, shared by every copy: float, range, int, normal, choice, shuffle, \
               unit_vector and in_sphere each draw from it and advance it, so a helper function given the Rng \
               (`fn roll(r) { r.int(1, 6) }`) advances its caller's. `rng(seed)` makes a new stream.",
    },
    Kind {
        name: "Animation",
        rust: "Animation",
        rule: Rule::InPlace,
        text: "An Animation is edited in place: `anim.add(modifier)` adds to it and returns nothing; pose and \
               frames return meshes.",
    },
];

/// The rule of the type named `name` (a script name), if it has one.
#[must_use]
pub fn kind(name: &str) -> Option<&'static Kind> {
    KINDS.iter().find(|k| k.name == name)
}

/// The text `blocksmith doc` opens with: the rule of each kind of value, and what happens to
/// a call that loses a change.
#[must_use]
pub fn overview() -> String {
    let mut out = String::from("How values change (the editing rule of each kind of value):\n");
    for k in KINDS {
        out.push_str(&format!("  {}: {}\n", k.name, k.text));
    }
    out.push_str(
        "A call whose result is dropped while its receiver stays as it was is reported before the script \
         runs: a warning in `run` and the REPL, an error in `blocksmith test`. Warnings a running script \
         gives (blocks that touch without connecting, from `mesh`) go the same way; a test that expects one \
         takes it with `take_warnings()` and checks it.\n\n",
    );
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::api::registry::REGISTRY;

    #[test]
    fn every_method_keeps_the_rule_its_type_states() {
        for k in KINDS {
            let methods: Vec<_> = REGISTRY.iter().filter(|d| d.receiver == Some(k.rust)).collect();
            assert!(!methods.is_empty() || k.name == "Vec3", "{} has no methods", k.name);
            for d in methods {
                let edits = !d.pure && !d.context;
                match k.rule {
                    // A value: what returns one of its kind is pure; an edit returns nothing.
                    Rule::Value => {
                        assert!(
                            d.returns != k.rust || d.pure,
                            "{}.{} returns a {} but is not pure",
                            k.name,
                            d.name,
                            k.name
                        );
                        assert!(
                            !edits || d.returns == "()",
                            "{}.{} changes the {} and returns {}",
                            k.name,
                            d.name,
                            k.name,
                            d.returns
                        );
                    }
                    // Every edit returns the value itself.
                    Rule::EditAndSelf => {
                        assert!(
                            !edits || d.returns_receiver(),
                            "{}.{} changes the {} but returns {}",
                            k.name,
                            d.name,
                            k.name,
                            d.returns
                        );
                    }
                    // Nothing both changes the value and returns one of its kind.
                    Rule::InPlace => {
                        assert!(
                            d.returns != k.rust || d.pure,
                            "{}.{} returns a {} but is not pure",
                            k.name,
                            d.name,
                            k.name
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn the_rules_are_stated_at_the_top_of_the_reference_and_on_each_type_s_page() {
        let engine = crate::new_engine(crate::EngineOptions::default());
        let all = crate::doc::render(&engine, None).unwrap();
        assert!(all.starts_with("How values change"), "{}", &all[..200]);
        for k in KINDS {
            assert!(all.contains(&format!("  {}: {}", k.name, k.text)), "{}", k.name);
            if k.name != "Vec3" {
                let page = crate::doc::render(&engine, Some(k.name)).unwrap();
                assert!(page.contains(k.text), "doc {}: {page}", k.name);
            }
        }
    }

    #[test]
    fn a_block_chain_keeps_every_edit_and_a_mesh_transform_leaves_its_receiver() {
        // What the Block and Mesh rules promise, run: a chain on a fresh block and on a variable.
        let engine = crate::new_engine(crate::EngineOptions::default());
        let sharp: bool = engine
            .eval("let b = block([0, 0, 0], [1, 1, 1]).subdivide(\"+z\", 2, 2).sharp_all();\nb.is_sharp(\"+x+y\")")
            .unwrap();
        assert!(sharp);
        let r: rhai::Array = engine
            .eval("let b = block([0, 0, 0], [1, 1, 1]);\nb.subdivide(\"+z\", 2, 2).sharp_all();\n[b.is_sharp(\"+x+y\"), b.subface_count(\"+z\")]")
            .unwrap();
        assert_eq!((r[0].as_bool(), r[1].as_int()), (Ok(true), Ok(4)));
        let (moved, kept): (f64, f64) = {
            let r: rhai::Array = engine
                .eval("let c = cube(2);\nlet d = c.translate([5, 0, 0]);\n[d.bounds().min.x, c.bounds().min.x]")
                .unwrap();
            (r[0].as_float().unwrap(), r[1].as_float().unwrap())
        };
        assert_eq!((moved, kept), (4.0, -1.0));
        // A PolarMesh edit changes it and returns nothing.
        let (unit, z): (bool, f64) = {
            let r: rhai::Array = engine
                .eval("let pm = polar_octahedron();\nlet r = pm.move_vertices([5], [0, 0, 1]);\n[type_of(r) == \"()\", pm.position(5).z]")
                .unwrap();
            (r[0].as_bool().unwrap(), r[1].as_float().unwrap())
        };
        assert!(unit);
        assert_eq!(z, 2.0);
    }
}
