//! `LSystem`: L-systems derived to strings and grown directly as polar meshes (Brazzolotto
//! part III, seed 004; kernel `lsystem`). Probability and size closures are evaluated here, at
//! the binding edge: the kernel calls back with `(step, params)`.

use std::rc::Rc;

use blocksmith_kernel::lsystem::{
    grow_with, modules_to_string, ChoiceSpec, GrowOptions, Grown, Lsystem as KernelLsystem, Module, Probability,
    RuleSpec, Size,
};
use blocksmith_kernel::math::fmt_num;
use rhai::plugin::*;
use rhai::{exported_module, Array, Engine, FnPtr, Map, Scope, AST, INT};

use super::polar::PolarMesh;
use crate::convert::{error, fail, kernel, type_name, Options, ScriptResult};
use crate::resolver::Resolver;

/// An L-system as scripts hold it (script type `LSystem`): the grammar and the closures its
/// stochastic choices use. Immutable: `derive` and `grow` never change it.
#[derive(Clone, Debug)]
pub struct LSystem(pub Rc<Inner>);

/// The grammar and its probability closures (indexed by the kernel's callback ids).
#[derive(Debug)]
pub struct Inner {
    /// The kernel grammar.
    pub grammar: KernelLsystem,
    /// `Probability::Callback(i)` is `closures[i]`.
    pub closures: Vec<FnPtr>,
    /// The script the closures were defined in, when it is not the caller's (the standard
    /// library's `thesis_plant`): they are called in it.
    pub ast: Option<Rc<AST>>,
}

/// Registers the `LSystem` type and the L-system functions on `engine`.
pub fn register(engine: &mut Engine) {
    engine.register_type_with_name::<LSystem>("LSystem");
    engine.register_global_module(exported_module!(lsystem_api).into());
}

fn to_number(v: &Dynamic) -> Option<f64> {
    v.as_float().ok().or_else(|| v.as_int().ok().map(|i| i as f64))
}

fn build(options: Map) -> ScriptResult<LSystem> {
    const F: &str = "lsystem";
    let opts = Options::new(F, options, &["axiom", "rules", "seed", "ignore", "max_modules"])?;
    if !opts.has("axiom") {
        return fail(F, "option `axiom` (the starting string) is required");
    }
    let axiom = opts.string("axiom", "")?;
    let seed = opts.int("seed", 0)?;
    let mut closures = Vec::new();
    let mut specs = Vec::new();
    if let Some(rules) = opts.raw("rules") {
        let Some(rules) = rules.clone().try_cast::<Map>() else {
            return fail(
                F,
                format!("option `rules` must be an object map from symbols to successors, got {}", type_name(rules)),
            );
        };
        for (key, value) in rules {
            let arg = format!("rules[\"{key}\"]");
            if let Ok(to) = value.clone().into_string() {
                specs.push(RuleSpec::deterministic(&key, &to));
                continue;
            }
            let Some(choices) = value.clone().try_cast::<Array>() else {
                return fail(
                    F,
                    format!(
                        "argument `{arg}` must be a successor string or an array of #{{to, p}} choices, got {}",
                        type_name(&value)
                    ),
                );
            };
            let mut cs = Vec::with_capacity(choices.len());
            for (i, c) in choices.into_iter().enumerate() {
                let Some(c) = c.clone().try_cast::<Map>() else {
                    return fail(F, format!("argument `{arg}[{i}]` must be a map #{{to, p}}, got {}", type_name(&c)));
                };
                if let Some(bad) = c.keys().find(|k| k.as_str() != "to" && k.as_str() != "p") {
                    return fail(F, format!("argument `{arg}[{i}]`: unknown key `{bad}`; valid keys are: p, to"));
                }
                let to = match c.get("to").map(|t| t.clone().into_string()) {
                    Some(Ok(t)) => t,
                    _ => return fail(F, format!("argument `{arg}[{i}].to` must be a successor string")),
                };
                let p = match c.get("p") {
                    None => return fail(F, format!("argument `{arg}[{i}].p` (the choice's probability) is missing")),
                    Some(p) => {
                        if let Some(x) = to_number(p) {
                            Probability::Fixed(x)
                        } else if let Ok(e) = p.clone().into_string() {
                            Probability::Expression(e)
                        } else if let Some(f) = p.clone().try_cast::<FnPtr>() {
                            closures.push(f);
                            Probability::Callback((closures.len() - 1) as u32)
                        } else {
                            return fail(
                                F,
                                format!(
                                    "argument `{arg}[{i}].p` must be a number, an expression string or a closure |step, params|, got {}",
                                    type_name(p)
                                ),
                            );
                        }
                    }
                };
                cs.push(ChoiceSpec { to, p });
            }
            specs.push(RuleSpec { key: key.to_string(), choices: cs });
        }
    }
    let mut grammar = kernel(F, KernelLsystem::new(&axiom, &specs, seed as u64))?;
    if opts.has("ignore") {
        grammar = kernel(F, grammar.with_ignore(&opts.string("ignore", "")?))?;
    }
    if opts.has("max_modules") {
        let cap = opts.int("max_modules", 0)?;
        if cap < 1 {
            return fail(F, format!("option `max_modules` must be at least 1, got {cap}"));
        }
        grammar = grammar.with_max_modules(cap as usize);
    }
    Ok(LSystem(Rc::new(Inner { grammar, closures, ast: None })))
}

fn steps_of(func: &str, steps: INT) -> ScriptResult<u32> {
    if !(0..=1000).contains(&steps) {
        return fail(func, format!("argument `steps` must be between 0 and 1000, got {steps}"));
    }
    Ok(steps as u32)
}

fn derive_modules(ctx: &NativeCallContext, func: &str, ls: &LSystem, steps: INT) -> ScriptResult<Vec<Module>> {
    let steps = steps_of(func, steps)?;
    let inner = &ls.0;
    let mut call = |id: u32, step: u32, params: &[f64]| -> Result<f64, String> {
        let f = &inner.closures[id as usize];
        let args: Array = params.iter().map(|&p| Dynamic::from(p)).collect();
        let r: Dynamic = match &inner.ast {
            Some(ast) => f.call(ctx.engine(), ast, (INT::from(step), args)),
            None => f.call_within_context(ctx, (INT::from(step), args)),
        }
        .map_err(|e| crate::convert::closure_error("the closure `p`", &e))?;
        to_number(&r).ok_or_else(|| format!("the closure `p` returned {}, not a number", type_name(&r)))
    };
    kernel(func, inner.grammar.derive_with(steps, &mut call))
}

/// A size option: a number (scaled by the sigmoid unless `sigmoid: false`) or a closure of the
/// step.
enum SizeOpt {
    Number(f64),
    Closure(FnPtr),
}

fn size_opt(opts: &Options, key: &str, default: f64) -> ScriptResult<SizeOpt> {
    match opts.raw(key) {
        None => Ok(SizeOpt::Number(default)),
        Some(v) => {
            if let Some(f) = v.clone().try_cast::<FnPtr>() {
                Ok(SizeOpt::Closure(f))
            } else {
                Ok(SizeOpt::Number(opts.number(key, default)?))
            }
        }
    }
}

fn grow_all(ctx: &NativeCallContext, ls: &LSystem, steps: INT, options: Map) -> ScriptResult<Grown> {
    const F: &str = "grow";
    let opts = Options::new(
        F,
        options,
        &[
            "radius",
            "length",
            "valence",
            "angle",
            "divergence",
            "sigmoid",
            "wide_gaps",
            "base",
            "max_vertices",
            "max_features",
        ],
    )?;
    let d = GrowOptions::DEFAULT;
    let radius = size_opt(&opts, "radius", d.radius)?;
    let length = size_opt(&opts, "length", d.length)?;
    let valence = opts.int("valence", INT::from(d.valence))?;
    if !(6..=100_000).contains(&valence) {
        return fail(F, format!("option `valence` must be between 6 and 100000, got {valence}"));
    }
    let caps = |key: &str, default: usize| -> ScriptResult<usize> {
        let v = opts.int(key, default as INT)?;
        if v < 1 {
            return fail(F, format!("option `{key}` must be at least 1, got {v}"));
        }
        Ok(v as usize)
    };
    let sigmoid = opts.bool("sigmoid", d.sigmoid)?;
    let mut o = d
        .with_valence(valence as u32)
        .with_angle(opts.number("angle", d.angle)?)
        .with_divergence(opts.number("divergence", d.divergence)?)
        .with_sigmoid(sigmoid)
        .with_wide_gaps(opts.bool("wide_gaps", d.wide_gaps)?)
        .with_flat_base(opts.choice("base", "point", &["point", "flat"])? == "flat")
        .with_caps(caps("max_vertices", d.max_vertices)?, caps("max_features", d.max_features)?);
    for (key, s) in [("radius", &radius), ("length", &length)] {
        if let SizeOpt::Number(x) = s {
            if *x <= 0.0 {
                return fail(F, format!("option `{key}` must be positive, got {}", fmt_num(*x)));
            }
        }
    }
    if let SizeOpt::Number(r) = radius {
        o = o.with_radius(r);
    }
    if let SizeOpt::Number(l) = length {
        o = o.with_length(l);
    }
    let modules = derive_modules(ctx, F, ls, steps)?;
    let mut size = |what: Size, step: f64| -> Result<f64, String> {
        let (s, key) = match what {
            Size::Length => (&length, "length"),
            Size::Radius => (&radius, "radius"),
        };
        match s {
            SizeOpt::Number(x) => Ok(if sigmoid { x * blocksmith_kernel::lsystem::sigmoid(step) } else { *x }),
            SizeOpt::Closure(f) => {
                let r: Dynamic = f
                    .call_within_context(ctx, (step,))
                    .map_err(|e| crate::convert::closure_error(&format!("the closure `{key}`"), &e))?;
                to_number(&r).ok_or_else(|| format!("the closure `{key}` returned {}, not a number", type_name(&r)))
            }
        }
    };
    let _bar = crate::progress::bar(F);
    kernel(F, grow_with(&modules, &o, &mut size))
}

#[export_module]
pub mod lsystem_api {
    use super::*;

    /// An L-system (§10.1–10.2, §11) from an option map: `axiom` (the starting string, required),
    /// `rules` (a map from a symbol to its successor string, or to an array of stochastic choices
    /// `#{to, p}` whose probabilities sum to 1 — `p` a number, a closure `|step, params|` of the
    /// derivation step and the predecessor's parameters, or an expression string of the rule's
    /// parameters and `step` such as `"1 - 1/(1 + exp(5.2 - s))"`, as pr(step) of Eq. 11.1), `seed`
    /// (default 0; every random choice), `ignore` (symbols context rules skip, e.g. `"+-"`) and
    /// `max_modules` (cap on the derived string, default 5,000,000).
    ///
    /// Symbols are a letter with optional digits (`F`, `L0`), the turtle symbols
    /// `+ - & ^ \ / | !`, the brackets `[` `]` and the thesis's `[L` `[R`; parameters follow in
    /// parentheses, `L(3)`. A key `"L0(s)"` names formal parameters that successor expressions
    /// use (`"L(s+1)"`, with `+ - * / ^`); a key `"A<B>C"` is context-sensitive (left and right
    /// context; branches are skipped as in L-Py). Bad input is an error naming the rule.
    ///
    /// ```rhai
    /// let algae = lsystem(#{ axiom: "A", rules: #{ A: "AB", B: "A" } });
    /// assert_eq(algae.derive(4), "ABAABABA");
    /// let coin = lsystem(#{ axiom: "A", seed: 7,
    ///     rules: #{ A: [#{ to: "AB", p: 0.5 }, #{ to: "BA", p: |step, params| 0.5 }] } });
    /// assert_eq(coin.derive(3).len(), 4);
    /// let stop = lsystem(#{ axiom: "A(0)",
    ///     rules: #{ "A(s)": [#{ to: "FA(s+1)", p: "max(0, min(1, 3 - s))" },
    ///                        #{ to: "F", p: "1 - max(0, min(1, 3 - s))" }] } });
    /// assert_eq(stop.derive(10), "FFFF");
    /// ```
    #[rhai_fn(return_raw)]
    pub fn lsystem(options: Map) -> ScriptResult<LSystem> {
        build(options)
    }

    /// The string after `steps` derivation steps (every module rewritten at once per step). The
    /// same seed gives the same string.
    ///
    /// ```rhai
    /// let ls = lsystem(#{ axiom: "L0(0)", rules: #{ "L0(s)": "L(s)L0(s+1)" } });
    /// assert_eq(ls.derive(2), "L(0)L(1)L0(2)");
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn derive(ctx: NativeCallContext, ls: &mut LSystem, steps: INT) -> ScriptResult<String> {
        Ok(modules_to_string(&derive_modules(&ctx, "derive", ls, steps)?))
    }

    /// Grows the string of `steps` derivation steps directly as a polar mesh (§11.1) with the
    /// default options; see `grow(steps, options)`.
    ///
    /// ```rhai
    /// let pm = lsystem(#{ axiom: "F[+F][-F]F" }).grow(0);
    /// pm.check();
    /// assert_eq(pm.poles().len(), 4);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn grow(ctx: NativeCallContext, ls: &mut LSystem, steps: INT) -> ScriptResult<PolarMesh> {
        grow_with_options(ctx, ls, steps, Map::new())
    }

    /// Grows the string of `steps` derivation steps directly as a polar mesh (§11.1), each
    /// module one polar operation: loops by add_refinement, branches nested by add_feature
    /// where the turtle points, poles ending them. What every symbol does and what its
    /// parameter means (`F(x)` a length, `L(s)` a growth step) is the table "L-system symbols"
    /// of the reference (`blocksmith doc "L-system symbols"`). Options: `radius` (0.25) and `length` (1) — a
    /// number scaled by the sigmoid of Eq. 11.2 of the step (a thesis symbol's first parameter,
    /// else the branch depth) unless `sigmoid: false`, or a closure `|step|` giving the value —,
    /// `valence` (8, vertices per trunk loop), `angle` (30°), `divergence` (137.5°, the parent's
    /// roll at each `[L` / `[R`), `wide_gaps` (false; true grows every branch at its parent's
    /// valence on half its loop, as the thesis does — bigger plants, more crossings at branch
    /// bases), `base` (`"point"`: the trunk starts at its root pole, a cone's tip; `"flat"`:
    /// the root pole at the centre of a loop of the trunk's first radius where the turtle starts,
    /// so the plant stands on a flat disk — one more skeleton node, at the root), `max_vertices`
    /// (4,000,000) and `max_features` (200,000), the caps that stop runaway growth with an
    /// error.
    ///
    /// ```rhai
    /// let ls = lsystem(#{ axiom: "L(0) [L(0) L(1) P(1)] P(0)" });
    /// let pm = ls.grow(0, #{ valence: 12, radius: 0.3 });
    /// pm.check();
    /// assert_eq(pm.skeleton().node_count, 1 + 5);
    /// let flat = ls.grow(0, #{ valence: 12, radius: 0.3, base: "flat" });
    /// assert_eq(flat.skeleton().node_count, 2 + 5);   // the base loop
    /// assert_eq(flat.to_mesh().bounds().min.z, 0.0);  // standing on z = 0
    /// ```
    #[rhai_fn(name = "grow", pure, return_raw)]
    pub fn grow_with_options(
        ctx: NativeCallContext,
        ls: &mut LSystem,
        steps: INT,
        options: Map,
    ) -> ScriptResult<PolarMesh> {
        Ok(PolarMesh(Rc::new(grow_all(&ctx, ls, steps, options)?.mesh)))
    }

    /// Grows like `grow(steps, options)` and reports the counts behind the mesh's skeleton:
    /// `#{mesh, root, segments, branches, open_ends, features}` — the skeleton rooted at `root`
    /// has `1 + segments + open_ends` nodes (one per drawn module, plus the root and the tips of
    /// branches not ended by `P`) and `branches` leaves.
    ///
    /// ```rhai
    /// let g = lsystem(#{ axiom: "F[+F]F" }).grow_report(0, #{});
    /// assert_eq(g.segments, 3);
    /// assert_eq(g.mesh.skeleton(#{ root: g.root }).node_count, 1 + g.segments + g.open_ends);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn grow_report(ctx: NativeCallContext, ls: &mut LSystem, steps: INT, options: Map) -> ScriptResult<Map> {
        let g = grow_all(&ctx, ls, steps, options)?;
        let mut m = Map::new();
        m.insert("root".into(), Dynamic::from(INT::from(g.root)));
        m.insert("segments".into(), Dynamic::from(g.segments as INT));
        m.insert("branches".into(), Dynamic::from(g.branches as INT));
        m.insert("open_ends".into(), Dynamic::from(g.open_ends as INT));
        m.insert("features".into(), Dynamic::from(g.features as INT));
        m.insert("mesh".into(), Dynamic::from(PolarMesh(Rc::new(g.mesh))));
        Ok(m)
    }

    /// The axiom as a string.
    ///
    /// ```rhai
    /// assert_eq(lsystem(#{ axiom: "F [ L]" }).axiom, "F[ L]");
    /// ```
    #[rhai_fn(get = "axiom", pure)]
    pub fn axiom(ls: &mut LSystem) -> String {
        modules_to_string(ls.0.grammar.axiom())
    }

    /// The seed.
    ///
    /// ```rhai
    /// assert_eq(lsystem(#{ axiom: "F", seed: 9 }).seed, 9);
    /// ```
    #[rhai_fn(get = "seed", pure)]
    pub fn seed(ls: &mut LSystem) -> INT {
        ls.0.grammar.seed() as INT
    }

    /// The same grammar with another seed.
    ///
    /// ```rhai
    /// let ls = lsystem(#{ axiom: "A", rules: #{ A: [#{ to: "AB", p: 0.5 }, #{ to: "BA", p: 0.5 }] } });
    /// assert_eq(ls.with_seed(3).seed, 3);
    /// ```
    #[rhai_fn(pure)]
    pub fn with_seed(ls: &mut LSystem, seed: INT) -> LSystem {
        LSystem(Rc::new(Inner {
            grammar: ls.0.grammar.clone().with_seed(seed as u64),
            closures: ls.0.closures.clone(),
            ast: ls.0.ast.clone(),
        }))
    }

    /// The sigmoid of Eq. 11.2, `1 − 1 / (1 + e^(2 − step))`, the default profile of lengths and
    /// radii.
    ///
    /// ```rhai
    /// assert_near(lsystem_sigmoid(2), 0.5, 1e-12);
    /// ```
    pub fn lsystem_sigmoid(step: f64) -> f64 {
        blocksmith_kernel::lsystem::sigmoid(step)
    }

    /// `lsystem_sigmoid` for an integer step.
    ///
    /// ```rhai
    /// assert(lsystem_sigmoid(0) > lsystem_sigmoid(5), "the sigmoid falls with the step");
    /// ```
    #[rhai_fn(name = "lsystem_sigmoid")]
    pub fn lsystem_sigmoid_int(step: INT) -> f64 {
        blocksmith_kernel::lsystem::sigmoid(step as f64)
    }

    /// The thesis's plant (§11): the stochastic parametric grammar `L0(s) → [L L0 L P]`,
    /// `[R L0 L P]`, both, or `L`, with probabilities pr(s) − pr(s)², pr(s) − pr(s)², pr(s)² and
    /// (1 − pr(s))², pr of Eq. 11.1. Written in Rhai in the standard library (`stdlib/plants.rhai`,
    /// also `import "plants" as plants; plants::thesis_plant(...)`). Option: `seed`.
    ///
    /// ```rhai
    /// let pm = thesis_plant(#{ seed: 1 }).grow(6);
    /// pm.check();
    /// ```
    #[rhai_fn(return_raw)]
    pub fn thesis_plant(ctx: NativeCallContext, options: Map) -> ScriptResult<LSystem> {
        const F: &str = "thesis_plant";
        let src =
            Resolver::stdlib_source("plants").ok_or_else(|| error(F, "the standard library has no `plants` module"))?;
        let engine = ctx.engine();
        let ast = engine.compile(src).map_err(|e| error(F, format!("stdlib/plants.rhai does not compile: {e}")))?;
        let r: Dynamic = engine.call_fn(&mut Scope::new(), &ast, "thesis_plant", (options,))?;
        let ls = r
            .clone()
            .try_cast::<LSystem>()
            .ok_or_else(|| error(F, format!("stdlib returned {}, not an LSystem", type_name(&r))))?;
        // Its closures live in the standard library's script: call them there.
        let Inner { grammar, closures, .. } = Rc::try_unwrap(ls.0).unwrap_or_else(|rc| Inner {
            grammar: rc.grammar.clone(),
            closures: rc.closures.clone(),
            ast: None,
        });
        Ok(LSystem(Rc::new(Inner { grammar, closures, ast: Some(Rc::new(ast)) })))
    }

    /// A one-line summary.
    ///
    /// ```rhai
    /// assert_eq(`${lsystem(#{ axiom: "F", rules: #{ F: "FF" } })}`, "LSystem(axiom \"F\", 1 rules, seed 0)");
    /// ```
    #[rhai_fn(name = "to_string", name = "to_debug", pure)]
    pub fn to_string(ls: &mut LSystem) -> String {
        format!(
            "LSystem(axiom \"{}\", {} rules, seed {})",
            modules_to_string(ls.0.grammar.axiom()),
            ls.0.grammar.rule_count(),
            ls.0.grammar.seed()
        )
    }
}
