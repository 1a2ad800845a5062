//! The reference's short guides to what a signature cannot say: how a block's faces are
//! divided into sub-faces (with a picture), and the L-system symbols' parameters (the kernel's
//! table). Their claims are checked by the tests beside this file.

/// The guides' headings, in order.
pub const TITLES: &[&str] = &[BLOCK_FACES, LSYSTEM_SYMBOLS];

/// The heading of the block faces guide.
pub const BLOCK_FACES: &str = "Block faces and sub-face grids";
/// The heading of the L-system symbols guide.
pub const LSYSTEM_SYMBOLS: &str = "L-system symbols";

/// The picture and the rules of sub-face grids.
const BLOCK_FACES_TEXT: &str = r#"A block has six faces named by their outward axis: `"-x" "+x" "-y" "+y" "-z" "+z"`, and twelve
edges named by their two faces (`"+x+y"`, either order). `b.subdivide(face, nu, nv)` cuts a face into
`nu × nv` sub-faces. On a face of axis a, **u** runs along the first of the other two axes in x, y, z
order and **v** along the second, each toward + whichever side the face is on; sub-face `i + nu * j` is
the `i`-th along u and the `j`-th along v, from 0.

| face | u along | v along |
|---|---|---|
| `-x`, `+x` | y | z |
| `-y`, `+y` | x | z |
| `-z`, `+z` | x | y |

`b.subdivide("+z", 3, 2)` on a block from `[0, 0, 0]` to `[3, 2, 1]`, seen from above (and `"-z"`, the
underside, is numbered the same way, seen through the block from above):

```text
   y
   ^
 2 +---------+---------+---------+
   |         |         |         |
   |    3    |    4    |    5    |   j = 1
   |         |         |         |
 1 +---------+---------+---------+
   |         |         |         |
   |    0    |    1    |    2    |   j = 0
   |         |         |         |
 0 +---------+---------+---------+--> x
   0  i = 0  1  i = 1  2  i = 2  3
```

Two blocks connect where a ray from the centre of a sub-face of one hits a sub-face of the other and
the ray back from that one's centre hits the first (seed 000 §2.2). A leg under the corner of a table
top therefore touches the top's undivided underside without connecting: the underside's one centre
is in the middle, over no leg. Subdivide the underside so that a sub-face centre lies over each leg
(`top.subdivide("-z", 6, 6)` for legs a tenth of the top wide at its corners) — the warning for
such blocks names the subdivision that does it. `m.connections()` lists what connected, with
`face_a`, `sub_a`, `face_b` and `sub_b` in this numbering.

Edges: `b.sharp(edges)` keeps a crease there; `b.sharp(edges, s)` gives a semi-sharp crease of
sharpness `s` (0 is smooth — the same as `b.smooth(edges)` — and 10 or more is sharp);
`b.sharp_all()` and `b.sharp_all(s)` do every edge."#;

/// What the symbols' table says first.
const LSYSTEM_INTRO: &str =
    "What each symbol of a string does when [lsystem](#lsystem)'s `grow` grows it, and what its first \
     parameter means — `F(x)` a length, `L(s)` a growth step fed to the sigmoid of Eq. 11.2, a turn \
     an angle in degrees (`F(0)` is a segment of length 0, `L(0)` the first, largest step). Options \
     named in backticks are `grow`'s. The table is made from the kernel's own symbol definitions \
     (`kernel/src/lsystem/symbols.rs`), which the growth reads its symbols by.";

/// The L-system symbols guide: the introduction and the kernel's table.
fn lsystem_text() -> String {
    format!("{LSYSTEM_INTRO}\n\n{}", blocksmith_kernel::lsystem::symbols::markdown_table().trim_end())
}

/// The guides as Markdown (sections of the whole reference).
#[must_use]
pub fn markdown() -> String {
    format!("## {BLOCK_FACES}\n\n{BLOCK_FACES_TEXT}\n\n## {LSYSTEM_SYMBOLS}\n\n{}\n\n", lsystem_text())
}

/// The text of the guide `title` (`blocksmith doc "Block faces"`), by a case-insensitive
/// prefix of its heading.
#[must_use]
pub fn text(title: &str) -> Option<String> {
    let t = title.to_lowercase();
    if t.len() < 4 {
        return None;
    }
    if BLOCK_FACES.to_lowercase().starts_with(&t) {
        Some(format!("{BLOCK_FACES}\n\n{BLOCK_FACES_TEXT}\n"))
    } else if LSYSTEM_SYMBOLS.to_lowercase().starts_with(&t) {
        Some(format!("{LSYSTEM_SYMBOLS}\n\n{}\n", lsystem_text()))
    } else {
        None
    }
}

#[cfg(test)]
#[path = "tests_guides.rs"]
mod tests;
