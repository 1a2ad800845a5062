//! The reference's page "Rhai for OpenSCAD, Python and JavaScript users": each trap a newcomer
//! meets, the code that falls in, the error it gives (as blocksmith prints it) and the fix.
//! The tests run every trap and every fix, so the page cannot drift from what blocksmith says.

/// One trap.
#[derive(Debug, Clone, Copy)]
pub struct Trap {
    /// A short heading.
    pub title: &'static str,
    /// Who expects otherwise, and why it bites.
    pub why: &'static str,
    /// Code that falls in.
    pub wrong: &'static str,
    /// A part of the error blocksmith gives for `wrong`; empty when it runs without an error
    /// and gives the wrong value (the code's comment says which).
    pub error: &'static str,
    /// The same done right: runs without an error.
    pub fix: &'static str,
}

/// The page's heading.
pub const TITLE: &str = "Rhai for OpenSCAD, Python and JavaScript users";

/// The traps, in the order people meet them.
pub const TRAPS: &[Trap] = &[
    Trap {
        title: "Arguments are passed by value",
        why: "In Python and JavaScript a function that pushes onto an array it was given changes the caller's \
              array. In Rhai every argument is a copy: the caller's array stays as it was, and no error says so.",
        wrong: "fn add_tooth(teeth) { teeth.push(1); }\nlet teeth = [];\nadd_tooth(teeth);\nassert_eq(teeth.len(), 0);   // still empty",
        error: "",
        fix: "// Return the new value and assign it...\nfn with_tooth(teeth) { teeth.push(1); teeth }\nlet teeth = [];\nteeth = with_tooth(teeth);\n// ...or write a method: `this` is the caller's value itself.\nfn add_tooth() { this.push(1); }\nteeth.add_tooth();\nassert_eq(teeth.len(), 2);",
    },
    Trap {
        title: "Functions do not see the recipe's variables",
        why: "A `fn` sees only its parameters (unlike a Python or JavaScript closure, or OpenSCAD's top-level \
              variables). Pass what it needs, or make it a constant and read it as `global::NAME`. Closures \
              (`|x| x * k`) do capture variables.",
        wrong: "let k = 2;\nfn f(x) { x * k }\nf(3)",
        error: "Variable not found: k",
        fix: "fn f(x, k) { x * k }\nassert_eq(f(3, 2), 6);\nconst K = 2;\nfn g(x) { x * global::K }\nassert_eq(g(3), 6);\nlet k = 2;\nlet h = |x| x * k;   // a closure captures k\nassert_eq(h.call(3), 6);",
    },
    Trap {
        title: "Some words are reserved",
        why: "Rhai reserves words it may use one day — `module`, `match`, `new`, `use`, `with`, `default`, \
              `static`, `package`, `var`, `case`, `public`... — and the names of its own functions `call`, \
              `curry`, `eval`, `print`, `type_of` and `this`. A gear maker's `module` is one of them; add a word \
              (`gear_module`) or a trailing underscore (`module_`).",
        wrong: "let module = 2;",
        error: "'module' is a reserved keyword",
        fix: "let gear_module = 2;\nlet module_ = 2;\nlet call_ = 1;",
    },
    Trap {
        title: "Ranges are not arrays",
        why: "`0..n` is a range for `for` loops. Python's `list(range(n))`, JavaScript's `Array.from` and \
              `(0..n).collect()` have no equivalent: there is no `collect`, and array methods (`map`, \
              `filter`) do not take a range. Build the array in a loop.",
        wrong: "let angles = (0..4).map(|i| i * 90);",
        error: "argument 1 `array` must be an array, got a range",
        fix: "let angles = [];\nfor i in 0..4 { angles.push(i * 90); }\nassert_eq(angles, [0, 90, 180, 270]);\n// or keep the range and map afterwards\nlet a = [];\nfor i in 0..4 { a.push(i); }\nassert_eq(a.map(|i| i * 90), angles);",
    },
    Trap {
        title: "Integer division truncates",
        why: "As in C (and unlike Python 3's `/` or JavaScript), two integers divide to an integer. Write one \
              side as a float.",
        wrong: "let half = 7 / 2;\nassert_eq(half, 3);   // not 3.5",
        error: "",
        fix: "assert_eq(7.0 / 2, 3.5);\nlet n = 7;\nassert_eq(to_float(n) / 2, 3.5);",
    },
    Trap {
        title: "Math functions take floats, in radians",
        why: "Rhai's `sqrt`, `sin`, `cos`... take floats only (`sqrt(2)` is an error: write `2.0`), and angles in \
              radians, while blocksmith's `rotate` and every other angle it takes are in degrees (as in OpenSCAD, \
              whose `sin` takes degrees too).",
        wrong: "let y = sin(30);",
        error: "argument 1 `x` must be a float, got an integer",
        fix: "let y = sin(to_radians(30.0));\nassert_near(y, 0.5, 1e-12);\nassert_near(sqrt(2.0), 1.4142135623730951, 1e-15);\nlet m = cube(1).rotate([0, 0, 1], 30);   // degrees",
    },
    Trap {
        title: "floor and round return floats",
        why: "`floor`, `ceiling`, `round` and `int` return floats, and an array index must be an integer. \
              Convert with `to_int`.",
        wrong: "let a = [10, 20, 30];\nlet x = 1.7;\na[x.floor()]",
        error: "expecting i64",
        fix: "let a = [10, 20, 30];\nlet x = 1.7;\nassert_eq(a[x.floor().to_int()], 20);",
    },
    Trap {
        title: "No ++, and single quotes are characters",
        why: "There is no `i++` (write `i += 1`), no C-style `for (i = 0; i < n; i++)` (write `for i in 0..n`), and \
              `'a'` is one character: strings take double quotes or backticks.",
        wrong: "let i = 0;\ni++;",
        error: "Unknown operator: '++'",
        fix: "let i = 0;\ni += 1;\nlet name = \"gear\";\nlet label = `${name} ${i}`;\nassert_eq(label, \"gear 1\");",
    },
    Trap {
        title: "OpenSCAD's modifiers are methods, and values are meshes",
        why: "OpenSCAD writes `translate([1, 0, 0]) cube(2);` and combines shapes implicitly. Here a shape is a \
              value: transforms are methods returning a new mesh, booleans are `+`, `-` and `intersect`, and the \
              recipe's last value is the model. `$fn` is an argument (`cylinder(r, h, 64)`).",
        wrong: "translate([1, 0, 0]) cube(2);",
        error: "error",
        fix: "let part = cube(2).translate([1, 0, 0]) - cylinder(0.5, 3, 32).translate([1, 0, 0]);\nassert(part.is_closed(), \"a closed solid\");\npart",
    },
    Trap {
        title: "A closure must not use the variable its call chain starts from",
        why: "While `pm.outgoing(v).map(...)` runs, Rhai holds `pm` (the chain's start); a closure that reads `pm` \
              inside that chain finds it held. Store the chain's value in a variable first.",
        wrong: "let pm = polar_octahedron();\nlet v = pm.poles()[0];\nlet ends = pm.outgoing(v).map(|h| pm.ends(h)[1]);",
        error: "map: the closure passed to `map` uses `pm`, the variable this call chain starts from",
        fix: "let pm = polar_octahedron();\nlet v = pm.poles()[0];\nlet hs = pm.outgoing(v);\nlet ends = hs.map(|h| pm.ends(h)[1]);\nassert_eq(ends.len(), 4);\n// The same when the closure uses the array it maps over:\nlet xs = [1, 2];\nlet copy = xs;\nassert_eq(copy.map(|x| xs.len() + x), [3, 4]);",
    },
];

/// The page as Markdown (a section of the whole reference).
#[must_use]
pub fn markdown() -> String {
    let mut out = format!(
        "## {TITLE}\n\nRhai reads like JavaScript and Rust, but a few of its rules surprise people who come from \
         OpenSCAD, Python or JavaScript. Each trap below shows the code that falls in, what blocksmith says, and \
         the fix.\n\n"
    );
    for t in TRAPS {
        out.push_str(&format!("### {}\n\n{}\n\n```rhai\n{}\n```\n\n", t.title, t.why, t.wrong));
        if t.error.is_empty() {
            out.push_str("No error: the value is silently not what was meant (see the comment).\n\n");
        } else {
            out.push_str(&format!("blocksmith says: `{}`\n\n", t.error));
        }
        out.push_str(&format!("The fix:\n\n```rhai\n{}\n```\n\n", t.fix));
    }
    out
}

#[cfg(test)]
#[path = "tests_traps.rs"]
mod tests;
