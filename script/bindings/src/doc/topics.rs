//! Where the reference lists each function: constructors and free functions by topic
//! (primitives, 2D, booleans, files, math, random...), operators together, then each type's
//! methods and properties. Placed by rule, so a function added anywhere lands without a list
//! kept by hand.
//!
//! # The rule (the first that applies)
//!
//! 1. Operators (`+`, `==`...) are listed under Operators.
//! 2. A line `Topic: KEY` alone in the function's doc comment files it under that topic as a free
//!    function; the line itself is not shown. For a free function whose first parameter is a
//!    script type (`dot(a, b)`, `box(min, max)`, `union(a, b)`, `noise(p, ...)`) or one that belongs
//!    elsewhere than its file's topic. `KEY` is one of [`TOPICS`]' keys (a test refuses others).
//! 3. A property, or a function whose first parameter is a script type (capitalised: `Mesh`,
//!    `Vec3`, `Block`...), is a method of that type: `m.color(c)` lands under Mesh wherever it is
//!    registered.
//! 4. Any other function goes under the topic of the api file that registers it
//!    (`src/api/FILE.rs`, by [`FILE_TOPICS`]); a file not in that table gets a topic of its own,
//!    titled after the file. A function no api file declares goes under "Other functions".
//!
//! Rhai's own functions that recipes use every day are listed apart ([`BUILTINS`]), from the
//! engine's metadata like the rest, with the units of their angles.

use crate::catalogue::Overload;

/// One topic of free functions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Topic {
    /// The key a `Topic:` line and [`FILE_TOPICS`] use.
    pub key: &'static str,
    /// The heading.
    pub title: &'static str,
    /// One line under the heading.
    pub intro: &'static str,
}

/// The topics in the order the reference lists them.
pub const TOPICS: &[Topic] = &[
    Topic {
        key: "primitives",
        title: "Primitives",
        intro: "Solids from a few numbers: `cube(2)`, `box(min, max)`, `cylinder(r, h, n)`. Each is a closed mesh, centred \
                on the origin unless it says otherwise; `m.translate(v)` moves it.",
    },
    Topic {
        key: "2d",
        title: "2D profiles and sweeps",
        intro: "Regions in the plane (x, y) and the solids made from them: `rect`, `circle`, `polygon`, `text`, then \
                `extrude`, `revolve`, `sweep`, `loft`. Angles in degrees.",
    },
    Topic {
        key: "booleans",
        title: "Booleans and hulls",
        intro: "Solids from solids: `union`, `subtract`, `intersect` (also `a + b`, `a - b`), hulls and Minkowski sums.",
    },
    Topic {
        key: "files",
        title: "Files",
        intro: "`load` and `save` by extension. Z is up; glTF is converted from and to its Y-up on the way.",
    },
    Topic {
        key: "math",
        title: "Math and vectors",
        intro: "Points and directions (`vec3`, or any `[x, y, z]` array) and the usual vector functions. blocksmith's \
                angles are in degrees; Rhai's `sin`, `cos`, `tan` and `atan` work in radians (see Rhai's built-in \
                functions below, and `to_radians` / `to_degrees`).",
    },
    Topic {
        key: "random",
        title: "Random numbers and noise",
        intro: "Seeded randomness: the same seed gives the same model, byte for byte.",
    },
    Topic { key: "colour", title: "Colour and appearance", intro: "Colours and named parts, kept through CSG and files." },
    Topic {
        key: "surface",
        title: "Surface finishing",
        intro: "Smoothing, remeshing and decimating a mesh's surface.",
    },
    Topic {
        key: "subdivision",
        title: "Subdivision",
        intro: "Catmull–Clark and Loop surfaces with semi-sharp creases (most are methods of Mesh).",
    },
    Topic {
        key: "blocks",
        title: "Blocks",
        intro: "Modeling with blocks (Leblanc et al.): cuboids with sub-face grids that connect by themselves, meshed \
                watertight. See Block and BlockModel for their methods.",
    },
    Topic {
        key: "polar",
        title: "Polar meshes",
        intro: "Brazzolotto's polar meshes: poles, loops and the seven operations that keep a mesh polar.",
    },
    Topic {
        key: "animation",
        title: "Animating polar meshes",
        intro: "Skeleton-driven animation of polar meshes: `animation(pm)` and its modifiers.",
    },
    Topic {
        key: "lsystems",
        title: "L-systems and plants",
        intro: "L-systems derived to strings and grown directly as polar meshes.",
    },
    Topic {
        key: "shape_up",
        title: "Shape-Up constraints",
        intro: "Tsoi & Hui's constraints on a mesh's vertices, and fits of circles and cylinders.",
    },
    Topic { key: "voxels", title: "Voxel sculpting", intro: "Voxel grids, sculpting with voxel tools, Haar levels of detail." },
    Topic {
        key: "repair",
        title: "Diagnosis and repair",
        intro: "Finding what is wrong with a mesh and mending what can be mended.",
    },
    Topic {
        key: "runtime",
        title: "Recipes: parameters, checks and output",
        intro: "A recipe's knobs (`param`), the relations between them (`param_check`), assertions for tests, and \
                `show` for a value beside the model.",
    },
    Topic {
        key: "text",
        title: "Strings, arrays and printing",
        intro: "blocksmith's versions of Rhai functions that grow or print data: checked against the memory budget \
                and the nesting limit.",
    },
    Topic { key: "other", title: "Other functions", intro: "Functions no api file declares." },
];

/// The topic of each api file's free functions (`src/api/FILE.rs`), including files other
/// engineers are expected to add (`rng`, `colour`...).
pub const FILE_TOPICS: &[(&str, &str)] = &[
    ("mesh", "primitives"),
    ("values", "math"),
    ("math", "math"),
    ("files", "files"),
    ("csg", "booleans"),
    ("profile", "2d"),
    ("blocks", "blocks"),
    ("block_handle", "blocks"),
    ("polar", "polar"),
    ("anim", "animation"),
    ("lsystem", "lsystems"),
    ("plants", "lsystems"),
    ("solve", "shape_up"),
    ("voxel", "voxels"),
    ("voxels", "voxels"),
    ("subdiv", "subdivision"),
    ("runtime", "runtime"),
    ("params", "runtime"),
    ("data", "text"),
    ("nesting", "text"),
    ("colour", "colour"),
    ("color", "colour"),
    ("appearance", "colour"),
    ("rng", "random"),
    ("random", "random"),
    ("noise", "random"),
    ("remesh", "surface"),
    ("surface", "surface"),
    ("finish", "surface"),
    ("smooth", "surface"),
    ("repair", "repair"),
    ("diagnose", "repair"),
    ("defects", "repair"),
];

/// Rhai's own functions a recipe uses every day, listed in the reference by group with what
/// the engine's metadata says of them and a note on units and traps.
pub struct BuiltinGroup {
    /// The heading.
    pub title: &'static str,
    /// What to know first (units, traps).
    pub note: &'static str,
    /// The functions, each with a note (`""` for none) shown under its metadata's text.
    pub names: &'static [(&'static str, &'static str)],
}

/// The groups of Rhai built-ins the reference lists ([`TOPICS`] cover blocksmith's own).
pub const BUILTINS: &[BuiltinGroup] = &[
    BuiltinGroup {
        title: "Angles and trigonometry (radians)",
        note: "Rhai's trigonometry works in **radians**: `sin`, `cos`, `tan` take radians and `asin`, `acos`, `atan` \
               return radians. blocksmith's own angles (`rotate`, `revolve`'s `angle`, `twist`, every `deg` \
               argument) are in **degrees**. Convert with `to_radians(deg)` and `to_degrees(rad)`: \
               `sin(to_radians(30)) == 0.5`. `PI()` is a function call.",
        names: &[
            ("sin", "x in radians: `sin(to_radians(90.0)) == 1.0`."),
            ("cos", "x in radians: `cos(PI()) == -1.0`."),
            ("tan", "x in radians."),
            ("asin", "Returns radians."),
            ("acos", "Returns radians."),
            (
                "atan",
                "Returns radians. With two arguments, `atan(y, x)` is the angle of the point (x, y) from the +x axis \
                 (C's `atan2(y, x)`; y comes first): `to_degrees(atan(1.0, 0.0)) == 90.0`.",
            ),
            ("to_radians", "Degrees to radians: `to_radians(180.0) == PI()`."),
            ("to_degrees", "Radians to degrees: `to_degrees(PI()) == 180.0`."),
            ("PI", "A function: write `PI()`."),
            ("E", "A function: write `E()`."),
            ("hypot", ""),
        ],
    },
    BuiltinGroup {
        title: "Numbers",
        note: "Integers and floats are different types. `7 / 2 == 3` (integer division truncates); write `7.0 / 2` \
               or `to_float(n) / 2` for 3.5. `floor`, `ceiling`, `round` and `int` return **floats**: index an \
               array with `x.floor().to_int()`. Mixed arithmetic (`1 + 0.5`) gives a float. `x ** y` is a power.",
        names: &[
            ("sqrt", ""),
            ("abs", ""),
            ("min", "Also mixes integers and floats: `min(1, 0.5) == 0.5`."),
            ("max", ""),
            ("floor", "Returns a float: `floor(2.7) == 2.0`; use `.to_int()` for an index."),
            ("ceiling", "Returns a float."),
            ("round", "Returns a float, halves away from zero: `round(2.5) == 3.0`."),
            ("int", "The integral part, as a float."),
            ("fraction", ""),
            ("to_int", "A float to an integer, truncating toward zero: `to_int(2.7) == 2`, `to_int(-2.7) == -2`."),
            ("to_float", "An integer to a float: `to_float(7) / 2 == 3.5`."),
            ("sign", ""),
            ("exp", ""),
            ("ln", ""),
            ("log", ""),
            ("is_nan", ""),
            ("is_finite", ""),
            ("parse_int", ""),
            ("parse_float", ""),
        ],
    },
    BuiltinGroup {
        title: "Strings",
        note: "Strings are written `\"...\"` or as templates `` `${x} mm` ``; `+` joins them.",
        names: &[
            ("len", ""),
            ("contains", ""),
            ("sub_string", ""),
            ("split", ""),
            ("trim", ""),
            ("to_upper", ""),
            ("to_lower", ""),
            ("index_of", ""),
            ("starts_with", ""),
            ("ends_with", ""),
            ("to_string", ""),
        ],
    },
    BuiltinGroup {
        title: "Arrays",
        note: "Arrays are values: passing one to a function passes a copy (see the traps page). `a.map(|x| ...)`, \
               `a.filter(...)`, `a.reduce(|sum, x| ..., 0)` return new arrays or values.",
        names: &[
            ("push", ""),
            ("pop", ""),
            ("insert", ""),
            ("remove", ""),
            ("map", ""),
            ("filter", ""),
            ("reduce", ""),
            ("sort", ""),
            ("reverse", ""),
            ("some", ""),
            ("all", ""),
            ("extract", ""),
            ("is_empty", ""),
        ],
    },
    BuiltinGroup {
        title: "Maps",
        note: "Object maps are written `#{ key: value }`; `m.key` reads a field, `m.key = v` sets one.",
        names: &[("keys", ""), ("values", ""), ("get", ""), ("set", "")],
    },
    BuiltinGroup {
        title: "Ranges",
        note: "`for i in 0..n` counts 0 to n-1, `0..=n` includes n, `range(0, n, 2)` steps. A range is not an array: \
               there is no `(0..n).collect()` or `(0..n).map(...)`; build the array with a loop \
               (`let a = []; for i in 0..n { a.push(i * 2); }`).",
        names: &[("range", ""), ("start", ""), ("end", ""), ("is_inclusive", "")],
    },
];

/// The doc text without its `Topic: KEY` line, and the key.
#[must_use]
pub fn split_tag(doc: &str) -> (String, Option<String>) {
    let mut topic = None;
    let mut lines = Vec::new();
    for line in doc.lines() {
        match line.trim().strip_prefix("Topic:") {
            Some(key) if topic.is_none() && !key.trim().is_empty() && !key.trim().contains(' ') => {
                topic = Some(key.trim().to_string());
            }
            _ => lines.push(line),
        }
    }
    // A tag between blank lines leaves two: keep one.
    let mut text = lines.join("\n");
    while text.contains("\n\n\n") {
        text = text.replace("\n\n\n", "\n\n");
    }
    (text.trim().to_string(), topic)
}

/// Where one function is listed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Place {
    /// Under a topic of free functions (the key).
    Topic(String),
    /// With the operators.
    Operators,
    /// With the methods and properties of a type.
    Type(String),
}

/// Where the reference lists `f` (the rule at the top of this file).
#[must_use]
pub fn place(f: &Overload) -> Place {
    if !f.name.starts_with(|c: char| c.is_alphabetic() || c == '_') {
        return Place::Operators;
    }
    if let Some(t) = &f.topic {
        return Place::Topic(t.clone());
    }
    if let Some(t) = f.receiver() {
        return Place::Type(t.to_string());
    }
    Place::Topic(file_topic(f).to_string())
}

/// The topic of `f`'s api file (by name and arity in the declarations table).
fn file_topic(f: &Overload) -> &'static str {
    let same = || crate::api::registry::REGISTRY.iter().filter(|d| d.name == f.name && d.arity == f.params.len());
    // The declaration whose parameters are the overload's (`to_string(a: array)`, not the
    // Animation's), else a free one (`mesh(points, faces)`, not `m.mesh(o)`), else any.
    let types_match = |d: &&crate::api::registry::Declared| {
        d.params.iter().zip(&f.params).all(|(rust, (_, script))| crate::catalogue::script_type(rust) == *script)
    };
    let Some(d) = same().find(types_match).or_else(|| same().find(|d| d.receiver.is_none())).or_else(|| same().next())
    else {
        return "other";
    };
    FILE_TOPICS.iter().find(|(file, _)| *file == d.module).map_or(d.module, |(_, key)| key)
}

/// The heading of topic `key`: one of [`TOPICS`]' titles, or one made from an api file's name
/// not in [`FILE_TOPICS`] (`rng` → "Rng").
#[must_use]
pub fn title(key: &str) -> String {
    match TOPICS.iter().find(|t| t.key == key) {
        Some(t) => t.title.to_string(),
        None => {
            let words = key.replace('_', " ");
            let mut chars = words.chars();
            chars.next().map(|c| c.to_uppercase().chain(chars).collect()).unwrap_or_default()
        }
    }
}

/// The line under topic `key`'s heading (empty for a topic made from a file's name).
#[must_use]
pub fn intro(key: &str) -> &'static str {
    TOPICS.iter().find(|t| t.key == key).map_or("", |t| t.intro)
}

/// The order of a topic: [`TOPICS`]' order, then the others.
#[must_use]
pub fn order(key: &str) -> usize {
    TOPICS.iter().position(|t| t.key == key).unwrap_or(TOPICS.len())
}

#[cfg(test)]
#[path = "tests_topics.rs"]
mod tests;
