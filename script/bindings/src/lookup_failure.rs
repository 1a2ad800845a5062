//! A call that finds no function fails with its explanation, wherever it is made.
//!
//! Rhai reports a call that matches no function as `ErrorFunctionNotFound("name (types)")`,
//! and a `try … catch (e)` around it binds `e` to an object map of that raw text. The printer
//! explains it ([`crate::explain`]), but a recipe that catches it — at top level, inside its
//! own functions, around an operator (`cube(1) + 5`) or in an imported module — would read
//! Rhai's text. So the engine raises the explanation itself: [`install`] hooks the failed native
//! call (Rhai's `on_missing_function`, called after every native call that fails) and, when no
//! native function of that name takes arguments of those types, fails the call with the text a
//! run prints ("catmull_clark(Mesh, float) matches no signature of `catmull_clark`: argument 2
//! `levels` must be an integer, got a float …") as a runtime error, which `catch (e)` binds as
//! that string and the printer shows unchanged.
//!
//! A property that is not found (`m.volum`, `m.volum = 1`) goes another way: Rhai looks for a
//! getter or setter without the hook, then falls back to an indexer taking the property's
//! name. Each of the script API's types gets that indexer ([`install`]), which fails with the
//! explanation ("Mesh has no property `volum` (did you mean the method `.volume()`?)"); so
//! does `m["volum"]`, since the API's types have no indexing of their own.
//!
//! Left to Rhai: a call that found its function and failed in it (the script API's own errors,
//! arithmetic overflow), operators between Rhai's own types (its built-in operators are no
//! registered functions), indexing of Rhai's own types, and Rhai's keyword functions.

use std::any::TypeId;
use std::collections::HashMap;
use std::sync::{Arc, OnceLock};

use rhai::{
    Array, Blob, Dynamic, Engine, EvalAltResult, FnPtr, ImmutableString, Map, NativeCallContext, Position, FLOAT, INT,
};

/// The native functions of an engine: for each name, the parameter types of each overload.
type Overloads = HashMap<String, Vec<Vec<TypeId>>>;

/// Makes every call on `engine` that finds no function fail with its explanation (see the
/// module's doc). Call it once the engine has all its functions.
#[allow(deprecated)] // `on_missing_function` is marked volatile, not deprecated.
pub fn install(engine: &mut Engine) {
    register_property_fallbacks(engine);
    let overloads: Arc<OnceLock<Overloads>> = Arc::default();
    engine.on_missing_function(move |name, args, _is_method, ctx| {
        if !explains(name, args) {
            return Ok(None);
        }
        let engine = ctx.engine();
        // Read on the first failure, when the engine has every function it will have.
        let overloads = overloads.get_or_init(|| native_overloads(engine));
        let types: Vec<TypeId> = args.iter().map(|a| a.type_id()).collect();
        if has_overload(overloads, name, &types) {
            return Ok(None);
        }
        let text = crate::explain::explain(engine, &not_found(engine, name, args));
        Err(EvalAltResult::ErrorRuntime(text.into(), Position::NONE).into())
    });
}

/// Registers, for each of the script API's types, the indexers Rhai falls back to when a
/// property is not found, failing with the explanation a run prints.
fn register_property_fallbacks(engine: &mut Engine) {
    use crate::api::{
        anim::Animation, block_handle::Block, blocks::BlockModel, lsystem::LSystem, mesh::SharedMesh, polar::PolarMesh,
        polar::Skeleton, profile::Profile, rng::Rng, solve::Solver, voxel::Voxels,
    };
    fn fallback<T: rhai::Variant + Clone>(engine: &mut Engine) {
        let unknown = |ctx: &NativeCallContext, name: &str, setter: bool| -> Box<EvalAltResult> {
            let engine = ctx.engine();
            let t = crate::catalogue::script_type(engine.map_type_name(std::any::type_name::<T>()));
            let text = crate::explain::property_not_found(engine, name, &t, setter);
            EvalAltResult::ErrorRuntime(text.into(), Position::NONE).into()
        };
        engine.register_fn(
            INDEX_GET,
            move |ctx: NativeCallContext, _: &mut T, name: ImmutableString| -> Result<Dynamic, Box<EvalAltResult>> {
                Err(unknown(&ctx, &name, false))
            },
        );
        engine.register_fn(
            INDEX_SET,
            move |ctx: NativeCallContext,
                  _: &mut T,
                  name: ImmutableString,
                  _: Dynamic|
                  -> Result<(), Box<EvalAltResult>> { Err(unknown(&ctx, &name, true)) },
        );
    }
    fallback::<SharedMesh>(engine);
    fallback::<blocksmith_kernel::Vec3>(engine);
    fallback::<Block>(engine);
    fallback::<BlockModel>(engine);
    fallback::<PolarMesh>(engine);
    fallback::<Skeleton>(engine);
    fallback::<Profile>(engine);
    fallback::<Voxels>(engine);
    fallback::<Animation>(engine);
    fallback::<LSystem>(engine);
    fallback::<Rng>(engine);
    fallback::<Solver>(engine);
}

/// Rhai's names of the indexer functions.
pub const INDEX_GET: &str = "index$get$";
/// See [`INDEX_GET`].
pub const INDEX_SET: &str = "index$set$";

/// Whether a call of `name` with arguments of types `args` finds a native function of
/// `engine` (a `Dynamic` parameter takes anything): whether a failure of that call is the
/// function's own, not a failed lookup.
#[must_use]
pub fn finds_native(engine: &Engine, name: &str, args: &[TypeId]) -> bool {
    has_overload(&native_overloads(engine), name, args)
}

/// Whether a failed call of `name` with `args` is one this module words: not a property or
/// index access, not a keyword, not an operator between Rhai's own types.
fn explains(name: &str, args: &[&mut Dynamic]) -> bool {
    if name.contains('$') || crate::origins::KEYWORDS.contains(&name) {
        return false;
    }
    let operator = !name.starts_with(|c: char| c.is_alphabetic() || c == '_');
    !(operator && args.iter().all(|a| is_rhai_type(a)))
}

/// Whether `value` is one of Rhai's own types, which its built-in operators take.
fn is_rhai_type(value: &Dynamic) -> bool {
    let t = value.type_id();
    [
        TypeId::of::<INT>(),
        TypeId::of::<FLOAT>(),
        TypeId::of::<bool>(),
        TypeId::of::<char>(),
        TypeId::of::<ImmutableString>(),
        TypeId::of::<()>(),
        TypeId::of::<Array>(),
        TypeId::of::<Map>(),
        TypeId::of::<Blob>(),
        TypeId::of::<FnPtr>(),
    ]
    .contains(&t)
}

/// Every native function `engine` can call (its own, its packages' and Rhai's standard ones),
/// by name.
fn native_overloads(engine: &Engine) -> Overloads {
    let mut all = Overloads::new();
    let listed = engine.collect_fn_metadata(
        None,
        |info| info.script.is_none().then(|| (info.metadata.name.to_string(), info.metadata.param_types.to_vec())),
        true,
    );
    for (name, params) in listed {
        all.entry(name).or_default().push(params);
    }
    all
}

/// Whether a native overload of `name` may have been called with arguments of types `args`
/// (a `Dynamic` parameter takes anything). The hook sees the arguments after the call: a
/// function that was found took its arguments by value and left `()` in their place, so a `()`
/// argument fits any parameter — a call given `()` is explained only when no overload takes its
/// other arguments.
fn has_overload(all: &Overloads, name: &str, args: &[TypeId]) -> bool {
    let (any, taken) = (TypeId::of::<Dynamic>(), TypeId::of::<()>());
    all.get(name).is_some_and(|overloads| {
        overloads.iter().any(|params| {
            params.len() == args.len() && params.iter().zip(args).all(|(p, a)| *p == any || *a == taken || p == a)
        })
    })
}

/// Rhai's own message for the failed lookup, `Function not found: name (type, type)`, which
/// [`crate::explain`] reads.
fn not_found(engine: &Engine, name: &str, args: &[&mut Dynamic]) -> String {
    let types: Vec<&str> = args
        .iter()
        .map(|a| if a.is_string() { "&str | ImmutableString | String" } else { engine.map_type_name(a.type_name()) })
        .collect();
    format!("Function not found: {name} ({})", types.join(", "))
}

#[cfg(test)]
mod tests {
    use crate::engine::{new_engine, EngineOptions};

    /// What `catch (e)` binds for each of `calls` (one expression each), run inside a script
    /// function's body, at top level, and inside a closure.
    fn caught(calls: &[&str]) -> Vec<[String; 3]> {
        let engine = new_engine(EngineOptions::default());
        calls
            .iter()
            .map(|call| {
                let attempt = format!("let r = \"no error\"; try {{ {call}; }} catch (e) {{ r = e; }}");
                let script = format!(
                    "fn inside() {{ {attempt} r }}\n\
                     let top = {{ {attempt} r }};\n\
                     let f = || {{ {attempt} r }};\n\
                     [inside(), top, f.call()]"
                );
                let ast = engine.compile(&script).unwrap();
                let got: rhai::Array = engine.eval_ast(&ast).unwrap_or_else(|e| panic!("{call}: {e}"));
                let text: Vec<String> = got.iter().map(ToString::to_string).collect();
                [text[0].clone(), text[1].clone(), text[2].clone()]
            })
            .collect()
    }

    #[test]
    fn a_call_that_finds_no_function_is_caught_explained_in_a_function_body_at_top_level_and_in_a_closure() {
        let cases = caught(&[
            "cube(1).catmull_clark(1.5)",
            "cube(1).volum()",
            "cube(1) + 5",
            "cylinder(1, 2, 3, 4, 5, 6, 7)",
            "no_such_function(1)",
        ]);
        for (i, case) in cases.iter().enumerate() {
            assert!(case.iter().all(|c| c == &case[0]), "case {i}: the three places differ: {case:?}");
        }
        assert!(
            cases[0][0].starts_with("catmull_clark(Mesh, float) matches no signature of `catmull_clark`"),
            "{cases:?}"
        );
        assert!(cases[0][0].contains("argument 2 `levels` must be an integer, got a float"), "{cases:?}");
        assert_eq!(cases[1][0], "Mesh has no method `volum` (did you mean `volume`?)");
        assert_eq!(cases[2][0], "`+` (CSG) takes a Mesh or a BlockModel on each side, not an integer");
        assert!(
            cases[3][0].starts_with("cylinder(int, int, int, int, int, int, int) matches no signature"),
            "{cases:?}"
        );
        assert!(cases[4][0].contains("unknown function no_such_function(int)"), "{cases:?}");
        for case in &cases {
            assert!(!case[0].contains("Function not found") && !case[0].starts_with("#{"), "raw Rhai text: {case:?}");
        }
    }

    #[test]
    fn an_unknown_property_is_caught_explained_in_a_function_body_at_top_level_and_in_a_closure() {
        let cases =
            caught(&["cube(1).volum", "let m = cube(1); m.volum = 2", "vec3(1, 2, 3).w", "cube(1)[\"volume\"]"]);
        for (i, case) in cases.iter().enumerate() {
            assert!(case.iter().all(|c| c == &case[0]), "case {i}: the three places differ: {case:?}");
        }
        assert!(cases[0][0].starts_with("Mesh has no property `volum`"), "{cases:?}");
        assert!(cases[1][0].contains("volum") && !cases[1][0].starts_with("#{"), "{cases:?}");
        assert!(cases[2][0].starts_with("Vec3 has no property `w`"), "{cases:?}");
        assert!(
            cases[3][0].contains("Mesh has no property `volume`") && cases[3][0].contains(".volume()"),
            "{cases:?}"
        );
    }

    #[test]
    fn a_call_that_found_its_function_keeps_its_own_error_and_rhai_s_own_operators_keep_theirs() {
        let cases = caught(&["cube(-1)", "9223372036854775807 + 1", "[1, 2][5]", "throw \"mine\"", "cube(1).volume()"]);
        assert!(cases[0][0].starts_with("cube: "), "{cases:?}");
        // Rhai's arithmetic and index errors are caught as its object maps, as before.
        assert!(cases[1][0].contains("Arithmetic") || cases[1][0].contains("overflow"), "{cases:?}");
        assert!(cases[2][0].contains("out of bounds"), "{cases:?}");
        assert_eq!(cases[3][0], "mine");
        assert_eq!(cases[4][0], "no error");
    }

    #[test]
    fn an_uncaught_failed_lookup_is_printed_explained_at_its_line_inside_a_function_and_at_top_level() {
        let engine = new_engine(EngineOptions::default());
        let source = "fn smooth(m) {\n    m.catmull_clark(1.5)\n}\nlet a = cube(1);\nsmooth(a)\n";
        let err = engine.eval::<rhai::Dynamic>(source).unwrap_err();
        let text = crate::diagnostics::format_error(&engine, "t.rhai", source, &err);
        assert!(text.starts_with("t.rhai:2:7: error: catmull_clark(Mesh, float) matches no signature"), "{text}");
        assert!(text.contains("2 |     m.catmull_clark(1.5)"), "{text}");
        assert!(text.contains("\nt.rhai:5:1: note: in the call of `smooth` here\n    5 | smooth(a)"), "{text}");
        let source = "let a = cube(1);\nlet b = a + 5;\n";
        let err = engine.eval::<rhai::Dynamic>(source).unwrap_err();
        let text = crate::diagnostics::format_error(&engine, "t.rhai", source, &err);
        assert!(text.starts_with("t.rhai:2:11: error: `+` (CSG) takes a Mesh or a BlockModel"), "{text}");
    }

    #[test]
    fn a_call_finds_a_native_function_only_when_one_takes_its_argument_types() {
        use std::any::TypeId;
        let engine = new_engine(EngineOptions::default());
        let (mesh, text, int) = (
            TypeId::of::<crate::api::mesh::SharedMesh>(),
            TypeId::of::<rhai::ImmutableString>(),
            TypeId::of::<rhai::INT>(),
        );
        assert!(super::finds_native(&engine, "save", &[mesh, text]));
        assert!(!super::finds_native(&engine, "save", &[int, text]));
        assert!(!super::finds_native(&engine, "save", &[mesh]));
        assert!(!super::finds_native(&engine, "sav", &[mesh, text]));
        // Rhai's standard functions count: `len` of a string.
        assert!(super::finds_native(&engine, "len", &[text]));
    }
}
