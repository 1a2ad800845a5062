//! Rhai's terse lookup failures explained from the catalogue of what exists:
//! "Function not found: cylinder (i64, i64, f64)" becomes which argument did not fit and why,
//! with the signatures that exist; an unknown name gets a did-you-mean by edit distance; a
//! method called on the wrong type says which type has it; an unknown property lists near ones.

use rhai::Engine;

use crate::api::csg::solid_hint;
use crate::catalogue::{a, conversions, is_api_type, script_type, Overload};
use crate::spelling::{did_you_mean, edit_distance};

/// `text` with every lookup failure Rhai reports in it explained (the rest unchanged) from
/// the functions of `engine`, the engine that gave the error. A multi-line explanation keeps
/// its first line in place and its other lines at the end.
#[must_use]
pub fn explain(engine: &Engine, text: &str) -> String {
    // The catalogue is the engine's functions, read from its metadata on first use (a tenth of
    // a second): only a message that names a function or property to explain needs it, so a
    // stop (Ctrl-C, --timeout) or any other error is reported at once.
    if ![NOT_FOUND, GETTER, SETTER].iter().any(|marker| text.contains(marker)) {
        return text.to_string();
    }
    explain_with(&crate::catalogue::of(engine), text)
}

const NOT_FOUND: &str = "Function not found: ";
const GETTER: &str = "Unknown property '";
const SETTER: &str = "No writable property '";

fn explain_with(all: &[Overload], text: &str) -> String {
    if let Some(i) = text.find(NOT_FOUND) {
        let rest = &text[i + NOT_FOUND.len()..];
        if let Some(close) = rest.find(')') {
            let explained = function_not_found(all, &rest[..=close]);
            return format!("{}{}{}", &text[..i], explained, &rest[close + 1..]);
        }
    }
    for (marker, setter) in [(GETTER, false), (SETTER, true)] {
        if let Some(i) = text.find(marker) {
            let rest = &text[i + marker.len()..];
            let Some(end_name) = rest.find('\'') else { continue };
            let name = &rest[..end_name];
            let Some(t) = rest.find("for type '").map(|j| &rest[j + "for type '".len()..]) else { continue };
            let Some(end_type) = t.find('\'') else { continue };
            let ty = script_type(&t[..end_type]);
            // The rest of Rhai's sentence (`to handle 'i64'`) is dropped with it.
            let tail_start = t[end_type + 1..].find(" (line ").map_or(t.len(), |k| end_type + 1 + k);
            let explained = unknown_property(all, name, &ty, setter);
            return format!("{}{}{}", &text[..i], explained, &t[tail_start..]);
        }
    }
    text.to_string()
}

/// Explains `sig` as Rhai writes it: `name (type, type, ...)`.
fn function_not_found(all: &[Overload], sig: &str) -> String {
    let (name, args) = sig.split_once(" (").unwrap_or((sig, ")"));
    let args = args.trim_end_matches(')');
    let given: Vec<String> =
        if args.trim().is_empty() { Vec::new() } else { args.split(", ").map(script_type).collect() };
    let shown = format!("{name}({})", given.join(", "));
    let receiver = given.first().filter(|t| is_api_type(t)).cloned();
    let same: Vec<&Overload> = all.iter().filter(|o| o.name == name && o.property.is_none()).collect();
    if same.is_empty() {
        return unknown_function(all, name, receiver.as_deref(), &shown);
    }
    if let Some(msg) = not_a_solid(name, &given) {
        return msg;
    }
    // The name exists: on another type, or with other arguments.
    if let Some(t) = &receiver {
        let on_type =
            same.iter().any(|o| o.receiver() == Some(t.as_str()) || o.params.first().is_some_and(|p| fits(&p.1, t)));
        let owners: Vec<&str> = unique(same.iter().filter_map(|o| o.receiver()));
        if !on_type && !owners.is_empty() {
            return wrong_type(all, name, t, &owners, &same);
        }
    }
    // Of a name with many overloads (`+` has forty), those for the script API's types given.
    let for_given: Vec<&Overload> = same
        .iter()
        .copied()
        .filter(|o| o.params.iter().zip(&given).any(|((_, p), g)| is_api_type(g) && p == g))
        .collect();
    let same = if for_given.is_empty() { same } else { for_given };
    let mut msg = format!("{shown} matches no signature of `{name}`");
    let fitting: Vec<&&Overload> = same.iter().filter(|o| o.params.len() == given.len()).collect();
    if fitting.is_empty() {
        let counts: Vec<String> = unique(same.iter().map(|o| o.params.len())).iter().map(ToString::to_string).collect();
        msg.push_str(&format!(": it takes {} argument(s), not {}", counts.join(" or "), given.len()));
    } else if let Some(why) = fitting.iter().find_map(|o| first_misfit(o, &given)) {
        msg.push_str(&format!(": {why}"));
    }
    msg.push_str(&signatures(&same));
    msg
}

/// `pm + m` or `m - vx`: CSG's operators on a value that is not a solid, and how to get one.
fn not_a_solid(name: &str, given: &[String]) -> Option<String> {
    if !matches!(name, "+" | "-") || given.len() != 2 {
        return None;
    }
    let solid = |t: &str| t == "Mesh" || t == "BlockModel";
    if !given.iter().any(|t| solid(t)) {
        return None;
    }
    let other = given.iter().find(|t| !solid(t))?;
    // A way to a solid, for the script API's types (a Profile extrudes); a number has none.
    let hint = if is_api_type(other) { solid_hint(other) } else { String::new() };
    Some(format!("`{name}` (CSG) takes a Mesh or a BlockModel on each side, not {}{hint}", a(other)))
}

/// Why `given` does not fit `o`: the first argument whose type differs.
fn first_misfit(o: &Overload, given: &[String]) -> Option<String> {
    for (i, ((pname, ptype), g)) in o.params.iter().zip(given).enumerate() {
        if fits(ptype, g) {
            continue;
        }
        let hint = match (ptype.as_str(), g.as_str()) {
            ("int", "float") => " (a count is a whole number: write it without a decimal point)",
            ("float", "int") => " (write it with a decimal point, e.g. 2.0)",
            ("array", t) if is_api_type(t) => " (give the ids in an array, e.g. [0, 1])",
            _ => "",
        };
        return Some(format!("argument {} `{pname}` must be {}, got {}{hint}", i + 1, a(ptype), a(g)));
    }
    None
}

/// Whether a value of script type `given` fits a parameter of script type `param` (a `number`
/// takes an int or a float; a `Vec3`, a point `[x, y]` and a colour `[r, g, b, a]` an array too).
/// The language server judges calls with it before a run.
#[must_use]
pub fn fits(param: &str, given: &str) -> bool {
    param == "any"
        || param == given
        || param.split('|').any(|p| {
            p == given
                || (p == "number" && matches!(given, "int" | "float"))
                || ((p == "Vec3" || p.starts_with('[')) && given == "array")
        })
}

fn unknown_function(all: &[Overload], name: &str, receiver: Option<&str>, shown: &str) -> String {
    if let Some(t) = receiver {
        // A property called like a method (`pm.face_count()`): it is read without brackets.
        if all.iter().any(|o| o.receiver() == Some(t) && o.name == name && o.property == Some("get")) {
            return format!("`{name}` is a property of {t}: read it without brackets, as `.{name}`");
        }
        let methods: Vec<&str> = unique(all.iter().filter(|o| o.receiver() == Some(t)).map(|o| o.name.as_str()));
        if let Some(near) = did_you_mean(name, methods.iter().copied()) {
            return format!("{t} has no method `{name}` (did you mean `{near}`?)");
        }
    }
    let names: Vec<&str> = unique(all.iter().filter(|o| o.property.is_none()).map(|o| o.name.as_str()));
    let near = did_you_mean(name, names.iter().copied());
    match (receiver, near) {
        (None, Some(near)) => format!("unknown function `{name}` (did you mean `{near}`?)"),
        (None, None) => format!("unknown function {shown} (see `blocksmith doc` for every function)"),
        (Some(t), Some(near)) => {
            let owners: Vec<&str> = unique(all.iter().filter(|o| o.name == near).filter_map(|o| o.receiver()));
            if owners.is_empty() {
                format!("{t} has no method `{name}` (did you mean the function `{near}`?)")
            } else {
                format!("{t} has no method `{name}` (`{near}` is a method of {})", owners.join(" and "))
            }
        }
        (Some(t), None) => format!("{t} has no method `{name}` (see `blocksmith doc {t}`)"),
    }
}

/// `name` called on a `t` while only `owners` have it.
fn wrong_type(all: &[Overload], name: &str, t: &str, owners: &[&str], same: &[&Overload]) -> String {
    let owners_text = owners.join(" or ");
    let mut msg = format!("`{name}` is a method of {owners_text}, not of {t}");
    // A way from this type to the owner's: a method of `t` without arguments returning it.
    if let Some((owner, convert)) = owners.iter().map(|o| (o, conversions(all, t, o))).find(|(_, c)| !c.is_empty()) {
        msg.push_str(&format!(": get {} with {}", a(owner), convert.join(" or ")));
    }
    // This type's methods of a similar name (`subdivide` → `loop_subdivide`).
    let near: Vec<&str> = unique(
        all.iter()
            .filter(|o| o.receiver() == Some(t) && o.ours)
            .map(|o| o.name.as_str())
            .filter(|m| m.contains(name) || name.contains(*m) || edit_distance(m, name) <= 2),
    );
    if !near.is_empty() {
        msg.push_str(&format!(
            "; for a {t} see {}",
            near.iter().map(|m| format!("`{m}`")).collect::<Vec<_>>().join(", ")
        ));
    }
    msg.push_str(&signatures(same));
    msg
}

/// The explanation of a property `name` of a `t` (a script type) that is not there: read, or
/// written when `setter` ("Mesh has no property `volum` (did you mean the method `.volume()`?)").
#[must_use]
pub fn property_not_found(engine: &Engine, name: &str, t: &str, setter: bool) -> String {
    unknown_property(&crate::catalogue::of(engine), name, t, setter)
}

fn unknown_property(all: &[Overload], name: &str, t: &str, setter: bool) -> String {
    let props: Vec<&Overload> = all.iter().filter(|o| o.receiver() == Some(t) && o.property.is_some()).collect();
    if setter && props.iter().any(|o| o.name == name && o.property == Some("get")) {
        return format!("the property `{name}` of a {t} is read-only");
    }
    let prop_names: Vec<&str> = unique(props.iter().map(|o| o.name.as_str()));
    let methods: Vec<&str> =
        unique(all.iter().filter(|o| o.receiver() == Some(t) && o.property.is_none()).map(|o| o.name.as_str()));
    let mut msg = format!("{t} has no property `{name}`");
    if let Some(p) = did_you_mean(name, prop_names.iter().copied()) {
        msg.push_str(&format!(" (did you mean `.{p}`?)"));
    } else if let Some(m) =
        did_you_mean(name, methods.iter().copied()).or_else(|| methods.contains(&name).then_some(name))
    {
        msg.push_str(&format!(" (did you mean the method `.{m}()`?)"));
    } else if !prop_names.is_empty() {
        msg.push_str(&format!("; its properties: {}", prop_names.join(", ")));
    }
    msg
}

fn signatures(same: &[&Overload]) -> String {
    let mut sigs: Vec<String> = same.iter().map(|o| o.signature()).collect();
    sigs.dedup();
    format!(
        "\nsignatures of `{}`:\n{}",
        same[0].name,
        sigs.iter().map(|s| format!("  {s}")).collect::<Vec<_>>().join("\n")
    )
}

fn unique<T: PartialEq + Clone>(items: impl IntoIterator<Item = T>) -> Vec<T> {
    let mut out: Vec<T> = Vec::new();
    for i in items {
        if !out.contains(&i) {
            out.push(i);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The explanation of what `script` fails with.
    fn explained(script: &str) -> String {
        let engine = crate::new_engine(crate::EngineOptions::default());
        let err = engine.eval::<rhai::Dynamic>(script).expect_err(script);
        explain(&engine, &crate::diagnostics::message(&err))
    }

    #[test]
    fn a_float_where_a_count_is_needed_names_the_argument_and_the_signatures() {
        let e = explained("cylinder(1, 2, 16.5)");
        assert!(
            e.starts_with("cylinder(int, int, float) matches no signature of `cylinder`: argument 3 `segments` must be an integer, got a float (a count is a whole number"),
            "{e}"
        );
        assert!(
            e.contains(
                "signatures of `cylinder`:\n  cylinder(radius: number, height: number, segments: int) -> Mesh\n"
            ),
            "{e}"
        );
        let e = explained("cylinder(1, 2)");
        assert!(e.contains("it takes 3 or 4 argument(s), not 2"), "{e}");
    }

    #[test]
    fn unknown_names_get_the_nearest_existing_one() {
        assert_eq!(explained("cilinder(1, 2, 3)"), "unknown function `cilinder` (did you mean `cylinder`?)");
        assert_eq!(explained("tours(1, 2, 3, 4)"), "unknown function `tours` (did you mean `torus`?)");
        assert_eq!(explained("cube(1).volum()"), "Mesh has no method `volum` (did you mean `volume`?)");
        assert_eq!(
            explained("polar_sphere(1, 8, 4).face_count()"),
            "`face_count` is a property of PolarMesh: read it without brackets, as `.face_count`"
        );
        assert_eq!(explained("cube(1).volum"), "Mesh has no property `volum` (did you mean the method `.volume()`?)");
        assert_eq!(
            explained("cube(1).vertex_cont"),
            "Mesh has no property `vertex_cont` (did you mean `.vertex_count`?)"
        );
        assert_eq!(
            explained("let m = cube(1); m.vertex_count = 3;"),
            "the property `vertex_count` of a Mesh is read-only"
        );
    }

    #[test]
    fn csg_of_a_value_that_is_not_a_solid_says_how_to_get_one() {
        assert_eq!(
            explained("polar_octahedron() + cube(1)"),
            "`+` (CSG) takes a Mesh or a BlockModel on each side, not a PolarMesh: get a Mesh with `.to_mesh()`"
        );
        assert_eq!(
            explained("cube(1) - voxels(8)"),
            "`-` (CSG) takes a Mesh or a BlockModel on each side, not a Voxels: get a Mesh with `.to_mesh()`"
        );
        assert!(
            explained("cube(1) + block([0, 0, 0], [1, 1, 1])")
                .ends_with("not a Block: put it in a model, `let model = blocks(); model.add(…);`, and use the model"),
            "{}",
            explained("cube(1) + block([0, 0, 0], [1, 1, 1])")
        );
    }

    #[test]
    fn a_method_on_the_wrong_type_says_where_it_lives() {
        let e = explained("cube(1).subdivide(\"+z\", 2, 2)");
        assert!(e.starts_with("`subdivide` is a method of Block, not of Mesh; for a Mesh see `loop_subdivide`"), "{e}");
        assert!(e.contains("subdivide(b: Block, face_name: string, nu: int, nv: int) -> Block"), "{e}");
        let e = explained("polar_octahedron().loop_subdivide(1)");
        assert!(
            e.starts_with("`loop_subdivide` is a method of Mesh, not of PolarMesh: get a Mesh with `.to_mesh()`"),
            "{e}"
        );
    }
}
