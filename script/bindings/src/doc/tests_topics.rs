//! The reference's layout: every free function under its topic, types' methods under their
//! type, every `Topic:` key known, and Rhai's math functions present with their units.

use super::*;
use crate::doc::reference::{markdown, Reference, Section};

fn reference() -> Reference {
    Reference::of(&crate::new_engine(crate::EngineOptions::default()))
}

/// The `## ` section of `md` holding `### name`.
fn section_of<'a>(md: &'a str, name: &str) -> &'a str {
    let at = md.find(&format!("\n### {name}\n")).unwrap_or_else(|| panic!("no ### {name}"));
    let start = md[..at].rfind("\n## ").unwrap();
    md[start + 4..].lines().next().unwrap()
}

#[test]
fn free_functions_are_listed_by_topic_not_under_their_first_argument_s_type() {
    let md = markdown(&reference(), true);
    for (name, topic) in [
        ("cube", "Primitives"),
        ("box", "Primitives"),
        ("cylinder", "Primitives"),
        ("vec3", "Math and vectors"),
        ("dot", "Math and vectors"),
        ("cross", "Math and vectors"),
        ("length", "Math and vectors"),
        ("lerp", "Math and vectors"),
        ("normalize", "Math and vectors"),
        ("distance", "Math and vectors"),
        ("union", "Booleans and hulls"),
        ("subtract", "Booleans and hulls"),
        ("hull", "Booleans and hulls"),
        ("load", "Files"),
        ("save", "Files"),
        ("rect", "2D profiles and sweeps"),
        ("extrude", "2D profiles and sweeps"),
        ("block", "Blocks"),
        ("blocks", "Blocks"),
        ("lsystem", "L-systems and plants"),
        ("param", "Recipes: parameters, checks and output"),
        ("voxels", "Voxel sculpting"),
        ("shape_up", "Shape-Up constraints"),
        ("polar_from", "Polar meshes"),
        ("animation", "Animating polar meshes"),
    ] {
        assert_eq!(section_of(&md, name), topic, "{name}");
    }
    // Methods stay with their type.
    assert_eq!(section_of(&md, "translate"), "Block");
    assert!(md.contains("\n## Mesh\n") && md.contains("\n## Vec3\n"));
    // No section is named after a union of types.
    assert!(!md.contains("\n## Mesh|BlockModel\n"));
    // A type points to the free functions taking it first.
    let vec3 = &md[md.find("\n## Vec3\n").unwrap()..];
    assert!(vec3[..400].contains("[dot](#dot)"), "{}", &vec3[..400]);
}

#[test]
fn every_free_function_is_under_a_topic_and_every_tag_is_known() {
    let r = reference();
    for f in &r.functions {
        if let Some(t) = &f.topic {
            assert!(
                TOPICS.iter().any(|k| k.key == t),
                "`{}` says `Topic: {t}`; the topics are {:?}",
                f.name,
                TOPICS.iter().map(|k| k.key).collect::<Vec<_>>()
            );
        }
        let s = Section::of(f);
        match (&s, f.receiver()) {
            (Section::Type(t), Some(r)) => assert_eq!(t, r),
            (Section::Topic(..) | Section::Operators, _) => {}
            other => panic!("{}: {other:?}", f.signature()),
        }
        // Free functions never land in "Other functions": every api file has its topic.
        if f.receiver().is_none() && matches!(s, Section::Topic(..)) {
            assert_ne!(s, Section::Topic(order("other"), "other".into()), "{} has no topic", f.signature());
        }
    }
}

#[test]
fn the_tag_line_is_hidden_and_read() {
    let (text, tag) = split_tag("Dot product.\n\nTopic: math\n\n```rhai\ndot(a, b)\n```");
    assert_eq!(tag.as_deref(), Some("math"));
    assert_eq!(text, "Dot product.\n\n```rhai\ndot(a, b)\n```");
    assert_eq!(split_tag("Topic: of the day is boxes").1, None, "a sentence is not a tag");
    assert_eq!(title("rng"), "Rng");
    assert_eq!(title("2d"), "2D profiles and sweeps");
}

#[test]
fn rhai_math_is_listed_with_its_units() {
    let md = markdown(&reference(), true);
    let builtins = &md[md.find("\n## Rhai's built-in functions\n").expect("a built-ins section")..];
    for name in
        ["sin", "cos", "tan", "atan", "sqrt", "abs", "min", "max", "floor", "round", "to_int", "PI", "to_radians"]
    {
        assert!(builtins.contains(&format!("\n#### {name}\n")), "no {name}");
    }
    let sin = &builtins[builtins.find("\n#### sin\n").unwrap()..];
    assert!(sin[..400].contains("radians"), "{}", &sin[..400]);
    let atan = &builtins[builtins.find("\n#### atan\n").unwrap()..];
    assert!(atan[..800].contains("atan(y, x)"), "{}", &atan[..800]);
    assert!(builtins.contains("**degrees**") && builtins.contains("floor(2.7) == 2.0"));
    // `doc sin` finds it.
    let engine = crate::new_engine(crate::EngineOptions::default());
    let one = crate::doc::render_as(&engine, Some("sin"), crate::doc::Format::Markdown).unwrap();
    assert!(one.contains("sin(x: float) -> float"), "{one}");
}
