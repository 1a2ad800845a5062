//! The guides say what blocksmith does: the picture's numbering is the numbering connections
//! report, and the table top's advice connects its legs.

use super::*;

fn eval(code: &str) -> rhai::Dynamic {
    let engine = crate::new_engine(crate::EngineOptions::default());
    engine.eval::<rhai::Dynamic>(code).unwrap_or_else(|e| panic!("{e}\n{code}"))
}

#[test]
fn the_picture_s_numbering_is_the_one_connections_report() {
    // A small block standing on each of the six sub-faces of the picture's "+z" face: the
    // connection names the sub-face the picture shows under it.
    for (sub, (x, y)) in
        [(0, (0.5, 0.5)), (1, (1.5, 0.5)), (2, (2.5, 0.5)), (3, (0.5, 1.5)), (4, (1.5, 1.5)), (5, (2.5, 1.5))]
    {
        let code = format!(
            "let m = blocks(); m.allow(0, 0);
             let base = block([0, 0, 0], [3, 2, 1]); base.subdivide(\"+z\", 3, 2); m.add(base);
             m.add(block([{} - 0.2, {} - 0.2, 1], [{} + 0.2, {} + 0.2, 2]));
             let c = m.connections(); assert_eq(c.len(), 1); c[0]",
            x, y, x, y
        );
        let c = eval(&code).cast::<rhai::Map>();
        let (face, s) = if c["a"].as_int().unwrap() == 0 { ("face_a", "sub_a") } else { ("face_b", "sub_b") };
        assert_eq!(c[face].to_string(), "+z");
        assert_eq!(c[s].as_int().unwrap(), sub, "over ({x}, {y})");
    }
    // The table of axes: "+y" runs u along x and v along z.
    let c = eval(
        "let m = blocks(); m.allow(0, 0);
         let base = block([0, 0, 0], [2, 1, 2]); base.subdivide(\"+y\", 2, 2); m.add(base);
         m.add(block([1.2, 1, 0.2], [1.8, 2, 0.8]));   // x high, z low: i = 1, j = 0
         m.connections()[0]",
    )
    .cast::<rhai::Map>();
    let s = if c["a"].as_int().unwrap() == 0 { "sub_a" } else { "sub_b" };
    assert_eq!(c[s].as_int().unwrap(), 1);
}

#[test]
fn the_table_top_s_advice_connects_every_leg() {
    // A 2 × 2 top with 0.2 legs at its corners (a tenth of its width): undivided, no leg
    // connects; its underside subdivided 6 × 6 as the guide says, all four do.
    let table = |division: &str| {
        format!(
            "let m = blocks(); m.allow(0, 0);
             let top = block([0, 0, 1], [2, 2, 1.2]); {division} m.add(top);
             for p in [[0, 0], [1.8, 0], [0, 1.8], [1.8, 1.8]] {{
                 m.add(block([p[0], p[1], 0], [p[0] + 0.2, p[1] + 0.2, 1]));
             }}
             m.connections().len()"
        )
    };
    assert_eq!(eval(&table("")).as_int().unwrap(), 0);
    assert_eq!(eval(&table("top.subdivide(\"-z\", 6, 6);")).as_int().unwrap(), 4);
    assert!(markdown().contains("top.subdivide(\"-z\", 6, 6)"));
}

#[test]
fn guides_are_found_by_a_prefix_of_their_heading() {
    assert!(text("block faces").unwrap().contains("i + nu * j"));
    assert!(text("L-system").unwrap().contains("lsystem"));
    assert!(text("bl").is_none() && text("nothing like it").is_none());
}

#[test]
fn the_lsystem_guide_is_the_kernels_symbol_table() {
    let guide = text("L-system symbols").unwrap();
    assert!(guide.contains(blocksmith_kernel::lsystem::symbols::markdown_table().trim_end()));
    assert!(markdown().contains("| `F` | the segment's length (absolute)"), "in the reference");
    assert!(guide.contains("`L(s)` a growth step"));
}
