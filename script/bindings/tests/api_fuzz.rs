//! Every function of the script API, called with hostile arguments — NaN, ±inf, 0, ±1e300,
//! ±i64::MAX, empty arrays and maps, strings, values of the wrong type, closures, `()` — on a
//! receiver of each type: each call returns a value or an error, never a panic or an abort.
//!
//! For each overload: the plausible call (each argument a value of its declared type, a method
//! also on a receiver of every other type); every parameter in turn taking every hostile value
//! while the others stay plausible; every pair of hostile values in the first two parameters;
//! all parameters the same hostile value. The calls are the same on every run (no randomness);
//! a failure names the call as script text.
//! `catch_unwind` only detects a panic, so that the report can name the call.

use std::collections::BTreeSet;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::Duration;

use blocksmith_kernel::limits;
use blocksmith_script::catalogue::{self, Overload};
use blocksmith_script::{new_engine, set_limits, EngineOptions, RunContext};
use rhai::{Dynamic, Engine, Scope};

/// A small value of each script API type, made fresh for every call.
const RECEIVERS: &[(&str, &str)] = &[
    ("Mesh", "cube(1)"),
    ("Vec3", "vec3(1, 2, 3)"),
    ("PolarMesh", "polar_sphere(1, 8, 4)"),
    ("Skeleton", "polar_sphere(1, 8, 4).skeleton()"),
    ("Voxels", "{ let v = voxels(8); v.fill_box([2, 2, 2], [6, 6, 6]); v }"),
    ("Block", "block([0, 0, 0], [1, 1, 1])"),
    ("BlockModel", "{ let b = blocks(); b.add(block([0, 0, 0], [1, 1, 1])); b }"),
    ("LSystem", "lsystem(#{ axiom: \"F\", rules: #{ F: \"F[+F]F\" } })"),
    ("Animation", "animation(polar_sphere(0.2, 8, 4))"),
    ("Modifier", "growth()"),
    ("Solver", "shape_up(cube(2))"),
    ("Blob", "blob(4, 1)"),
    ("Profile", "(rect([0, 0], [2, 1]) - circle(0.2, 8).translate([1, 0.5]))"),
    ("Rng", "rng(1)"),
];

/// The hostile values, as scope variables (`h0`, `h1`...) or script text.
fn hostile() -> Vec<(String, Option<Dynamic>)> {
    let v = |x: Dynamic| Some(x);
    vec![
        ("nan".into(), v(Dynamic::from(f64::NAN))),
        ("inf".into(), v(Dynamic::from(f64::INFINITY))),
        ("-inf".into(), v(Dynamic::from(f64::NEG_INFINITY))),
        ("0".into(), v(Dynamic::from(0_i64))),
        ("0.0".into(), v(Dynamic::from(0.0))),
        ("1e300".into(), v(Dynamic::from(1e300))),
        ("-1e300".into(), v(Dynamic::from(-1e300))),
        ("i64::MAX".into(), v(Dynamic::from(i64::MAX))),
        ("-i64::MAX".into(), v(Dynamic::from(-i64::MAX))),
        ("[]".into(), None),
        ("#{}".into(), None),
        ("\"\"".into(), None),
        ("[nan, inf, 1e300]".into(), v(Dynamic::from_array(vec![f64::NAN.into(), f64::INFINITY.into(), 1e300.into()]))),
        ("[i64::MAX, -1, 0]".into(), v(Dynamic::from_array(vec![i64::MAX.into(), (-1_i64).into(), 0_i64.into()]))),
        ("#{ a: nan }".into(), v(Dynamic::from_map([("a".into(), Dynamic::from(f64::NAN))].into_iter().collect()))),
        ("()".into(), None),
        ("cube(1)".into(), None),
        ("|x| x".into(), None),
        ("vec3(1e300, -1e300, 0)".into(), None),
    ]
}

/// A plausible value of a declared script type.
fn plausible(t: &str) -> String {
    match t {
        "int" => "2".into(),
        "float" => "0.5".into(),
        "bool" => "true".into(),
        "string" => "\"x\"".into(),
        "char" => "'x'".into(),
        "array" => "[1, 2, 3]".into(),
        "map" => "#{}".into(),
        "closure" => "|x| x".into(),
        "any" => "1.0".into(),
        "number" => "0.5".into(),
        "number|Vec3" => "2".into(),
        "[x, y]" => "[1, 2]".into(),
        "number|[x, y]" => "2".into(),
        // One of several types (`Mesh|BlockModel`): the first.
        t if t.contains('|') => plausible(t.split('|').next().unwrap_or(t)),
        t => RECEIVERS.iter().find(|(n, _)| *n == t).map_or_else(|| "()".into(), |(_, s)| s.to_string()),
    }
}

/// The calls of one overload: each argument list as script text, hostile values bound in
/// `scope` by name.
fn calls(o: &Overload, hostile: &[(String, Option<Dynamic>)]) -> Vec<String> {
    let recv = o.receiver().map(str::to_string);
    let params: Vec<&str> = o.params.iter().skip(usize::from(recv.is_some())).map(|(_, t)| t.as_str()).collect();
    let text = |i: usize| if hostile[i].1.is_some() { format!("h{i}") } else { hostile[i].0.clone() };
    // The plausible call, then each parameter hostile in turn, every pair of hostile values
    // in the first two parameters, and all parameters the same hostile value.
    let mut lists: Vec<Vec<String>> = vec![params.iter().map(|t| plausible(t)).collect()];
    if params.len() >= 2 {
        for h1 in 0..hostile.len() {
            for h2 in 0..hostile.len() {
                let mut args: Vec<String> = params.iter().map(|t| plausible(t)).collect();
                args[0] = text(h1);
                args[1] = text(h2);
                lists.push(args);
            }
        }
    }
    for p in 0..params.len() {
        for h in 0..hostile.len() {
            let mut args: Vec<String> = params.iter().map(|t| plausible(t)).collect();
            args[p] = text(h);
            lists.push(args);
        }
    }
    if params.len() > 1 {
        for h in 0..hostile.len() {
            lists.push(vec![text(h); params.len()]);
        }
    }
    // A method is also called on a receiver of every other type.
    let receivers: Vec<&str> = match &recv {
        Some(r) => std::iter::once(r.as_str()).chain(RECEIVERS.iter().map(|(n, _)| *n).filter(|n| n != r)).collect(),
        None => Vec::new(),
    };
    let mut out = Vec::new();
    for (i, args) in lists.into_iter().enumerate() {
        let args = args.join(", ");
        let on = if i == 0 { &receivers[..] } else { &receivers[..receivers.len().min(1)] };
        if recv.is_none() {
            out.push(format!("{}({args})", o.name));
        }
        for r in on {
            out.push(match o.property {
                Some("get") => format!("let r = {}; r.{}", plausible(r), o.name),
                Some(_) => format!("let r = {}; r.{} = {args}; r", plausible(r), o.name),
                None => format!("let r = {}; r.{}({args})", plausible(r), o.name),
            });
        }
    }
    out
}

fn engine(dir: &std::path::Path) -> (Engine, EngineOptions) {
    let context = RunContext {
        script_dir: Some(dir.to_path_buf()),
        output_dir: Some(dir.to_path_buf()),
        ..RunContext::default()
    };
    let options = EngineOptions {
        context,
        max_operations: Some(200_000),
        timeout: Some(Duration::from_secs(5)),
        ..EngineOptions::default()
    };
    let mut e = new_engine(options.clone());
    e.on_print(|_| {}).on_debug(|_, _, _| {});
    (e, options)
}

#[test]
fn no_registered_function_panics_on_hostile_arguments() {
    // Estimates refuse anything over 1 GiB: the fuzz must not exhaust the machine's memory.
    limits::set_memory_limit(1 << 30);
    let dir = tempfile::tempdir().unwrap();
    let (mut engine, options) = engine(dir.path());
    let hostile = hostile();
    let ours: Vec<Overload> = catalogue::overloads(&engine, false).into_iter().filter(|o| o.ours).collect();
    // Every receiver type has a sample, so that no method goes untried.
    let missing: BTreeSet<&str> = ours
        .iter()
        .filter_map(Overload::receiver)
        .flat_map(|t| t.split('|'))
        .filter(|t| !RECEIVERS.iter().any(|(n, _)| n == t))
        .collect();
    assert!(missing.is_empty(), "add a sample of {missing:?} to RECEIVERS");
    let mut panics = Vec::new();
    let (mut calls_made, mut errors) = (0usize, 0usize);
    let names: BTreeSet<&str> = ours.iter().map(|o| o.name.as_str()).collect();
    for o in &ours {
        for script in calls(o, &hostile) {
            let mut scope = Scope::new();
            for (i, (_, v)) in hostile.iter().enumerate() {
                if let Some(v) = v {
                    scope.push(format!("h{i}"), v.clone());
                }
            }
            set_limits(&mut engine, &options);
            calls_made += 1;
            match catch_unwind(AssertUnwindSafe(|| engine.eval_with_scope::<Dynamic>(&mut scope, &script))) {
                Ok(Ok(_)) => {}
                Ok(Err(_)) => errors += 1,
                Err(p) => {
                    let why = p
                        .downcast_ref::<String>()
                        .cloned()
                        .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                        .unwrap_or_default();
                    panics.push(format!("{script}  →  {why}"));
                }
            }
        }
    }
    eprintln!("{} functions, {} overloads, {calls_made} calls, {errors} errors", names.len(), ours.len());
    // The calls reach the functions: many succeed (a plausible argument list fails only where
    // one argument is hostile).
    assert!(names.len() > 100 && calls_made > 5000, "{} functions, {calls_made} calls", names.len());
    assert!(calls_made - errors > calls_made / 40, "only {} of {calls_made} calls succeeded", calls_made - errors);
    assert!(panics.is_empty(), "{} calls panicked:\n{}", panics.len(), panics.join("\n"));
}
