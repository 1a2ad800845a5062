//! What every symbol of a grown string does and what its parameter means (seed 004, §10.3 and
//! §11): the definitions [`grow`](super::grow) reads its symbols by, and the table the reference
//! prints ([`markdown_table`]), so the two cannot drift apart. A thesis symbol's parameter is a
//! growth *step* fed to the sigmoid of Eq. 11.2, a turtle symbol's a length or an angle: `F(0)`
//! is a segment of length 0, `L(0)` the first, largest step.

/// Symbols whose first parameter is a growth step `s` (Eq. 11.2: lengths and radii are the
/// `length` and `radius` options × sigmoid(s) unless `sigmoid: false`).
pub const STEP_SYMBOLS: &[&str] = &["L", "L0", "P", "[L", "[R"];

/// Symbols whose first parameter is a length (absolute, not scaled).
pub const LENGTH_SYMBOLS: &[&str] = &["F", "f"];

/// The factor `!` without a parameter multiplies the radius by.
pub const SHRINK: f64 = 0.7;

/// One row of the symbol table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SymbolDoc {
    /// The symbols of the row, as written in a string.
    pub symbols: &'static [&'static str],
    /// What the first parameter means.
    pub parameter: &'static str,
    /// What the symbol does without a parameter.
    pub without: &'static str,
    /// What the symbol does when grown.
    pub does: &'static str,
}

/// Every symbol `grow` reads, in the order of the table.
pub const SYMBOLS: &[SymbolDoc] = &[
    SymbolDoc {
        symbols: &["F"],
        parameter: "the segment's length (absolute)",
        without: "`length` × sigmoid(branch depth)",
        does: "moves forward and draws a loop (add_refinement on the tip pole's spoke, §4.1)",
    },
    SymbolDoc {
        symbols: &["f"],
        parameter: "the distance (absolute)",
        without: "as `F`",
        does: "moves forward without drawing",
    },
    SymbolDoc {
        symbols: &["L", "L0"],
        parameter: "the growth step s: length `length`·sigmoid(s), radius `radius`·sigmoid(s)",
        without: "s = the branch depth",
        does: "moves forward and draws a loop, as `F`",
    },
    SymbolDoc {
        symbols: &["P"],
        parameter: "the growth step s, as `L`",
        without: "s = the branch depth",
        does: "moves forward and puts the tip pole there: the branch ends",
    },
    SymbolDoc {
        symbols: &["[L", "[R"],
        parameter: "the growth step s of the loop drawn, as `L`",
        without: "s = the branch depth",
        does: "draws a loop, rolls the parent by `divergence`, pushes, and turns left (`+`) or right (`-`) by `angle` for a branch nested on that loop",
    },
    SymbolDoc {
        symbols: &["["],
        parameter: "none",
        without: "—",
        does: "pushes the turtle: the branch is nested (add_feature, §4.3) on the current loop where the turtle points, when it first draws",
    },
    SymbolDoc { symbols: &["]"], parameter: "none", without: "—", does: "pops: back to the parent's turtle and loop" },
    SymbolDoc {
        symbols: &["+", "-"],
        parameter: "an angle in degrees",
        without: "`angle`",
        does: "turns about the turtle's up: `+` towards its left, `-` towards its right",
    },
    SymbolDoc {
        symbols: &["&", "^"],
        parameter: "an angle in degrees",
        without: "`angle`",
        does: "pitches: `&` down (away from up), `^` up",
    },
    SymbolDoc {
        symbols: &["\\", "/"],
        parameter: "an angle in degrees",
        without: "`angle`",
        does: "rolls about the heading: `\\` left towards up, `/` the other way",
    },
    SymbolDoc { symbols: &["|"], parameter: "none", without: "—", does: "turns round (180° about up)" },
    SymbolDoc {
        symbols: &["!"],
        parameter: "the radius from here on (absolute)",
        without: "the radius × 0.7",
        does: "sets the radius of the loops drawn next on this branch",
    },
    SymbolDoc {
        symbols: &["any other letter (`A`, `X`, `B2`...)"],
        parameter: "free: for the rules' own use",
        without: "—",
        does: "draws nothing (a placeholder the rules rewrite)",
    },
];

/// The table as Markdown: symbol, parameter, without a parameter, what it does.
#[must_use]
pub fn markdown_table() -> String {
    let code = |s: &str| if s.contains(' ') { s.to_string() } else { format!("`{}`", s.replace('|', "\\|")) };
    let mut out = String::from("| symbol | parameter | without one | grown as |\n|---|---|---|---|\n");
    for row in SYMBOLS {
        let names: Vec<String> = row.symbols.iter().map(|s| code(s)).collect();
        let cell = |s: &str| s.replace('|', "\\|");
        out.push_str(&format!(
            "| {} | {} | {} | {} |\n",
            names.join(" "),
            cell(row.parameter),
            cell(row.without),
            cell(row.does)
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::{grow, parse_modules, sigmoid, GrowOptions, Turtle};
    use super::*;

    /// The turtle symbols of the table are the ones the turtle turns by, and no other.
    #[test]
    fn the_table_names_every_turning_symbol_and_only_those() {
        let listed: Vec<&str> = SYMBOLS.iter().flat_map(|r| r.symbols.iter().copied()).collect();
        for s in ["+", "-", "&", "^", "\\", "/", "|"] {
            assert!(Turtle::default().apply(s, 30.0), "{s} turns");
            assert!(listed.contains(&s), "{s} is in the table");
        }
        for s in ["F", "f", "L", "L0", "P", "[L", "[R", "[", "]", "!"] {
            assert!(!Turtle::default().apply(s, 30.0), "{s} does not turn");
            assert!(listed.contains(&s), "{s} is in the table");
        }
    }

    /// What the table says of the parameters is what `grow` does: `F(x)` and `f(x)` lengths,
    /// `L(s)` a sigmoid step, `!(r)` a radius and `!` a shrink by [`SHRINK`].
    #[test]
    fn the_parameters_mean_what_the_table_says() {
        let opts = GrowOptions::DEFAULT;
        let top = |s: &str| {
            let g = grow(&parse_modules("t", s).unwrap(), &opts).unwrap();
            g.mesh.mesh().positions().iter().map(|p| p.z).fold(f64::MIN, f64::max)
        };
        // `F(2) P(0)`: the pole at 2 + the length of step 0.
        assert!((top("F(2) P(0)") - (2.0 + sigmoid(0.0))).abs() < 1e-12);
        // `f(3)` moves 3 without drawing.
        assert!((top("f(3) F(1) P(0)") - (4.0 + sigmoid(0.0))).abs() < 1e-12);
        // `L(4)` is a step, not a length.
        assert!((top("L(4) P(4)") - 2.0 * sigmoid(4.0)).abs() < 1e-12);
        // `!(0.5)` sets the radius, `!` shrinks it.
        let widest = |s: &str| {
            let g = grow(&parse_modules("t", s).unwrap(), &opts).unwrap();
            g.mesh.mesh().positions().iter().map(|p| p.x.hypot(p.y)).fold(0.0, f64::max)
        };
        assert!((widest("!(0.5) F(1) P(0)") - 0.5).abs() < 1e-12);
        assert!((widest("!(0.5) ! F(1) P(0)") - 0.5 * SHRINK).abs() < 1e-12);
    }

    #[test]
    fn the_markdown_table_has_a_row_per_definition() {
        let t = markdown_table();
        assert_eq!(t.lines().count(), 2 + SYMBOLS.len());
        assert!(t.contains("| `F` | the segment's length (absolute)"), "{t}");
        assert!(t.contains("`\\|`"), "the bar is escaped: {t}");
        assert!(t.contains(&format!("the radius × {SHRINK}")), "{t}");
    }
}
