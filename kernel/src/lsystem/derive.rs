//! Derivation (seed 004, §10.1): every module of the string is rewritten at once by the first
//! rule that matches it — its symbol, its parameter count and, for context-sensitive rules, its
//! neighbours (ABOP §1.8 bracketed contexts) — choosing among stochastic successors with the
//! seeded generator (§10.2, §11).
//!
//! Context matching skips the `ignore` symbols; a left context skips whole sibling branches
//! (`[…]` before the module) and climbs out of the branch the module is in; a right context
//! skips child branches and stops at the end of the module's branch.

use std::fmt::Display;

use super::grammar::{Lsystem, Module, Prob, Rule};
use super::LsystemError;
use crate::math::SplitMix64;

/// A probability callback: `(choice id, step, predecessor parameters) → probability`.
pub type ProbabilityFn<'a, E> = dyn FnMut(u32, u32, &[f64]) -> Result<f64, E> + 'a;

/// The memory of one module of a derived string, with its symbol and parameters (an estimate).
const MODULE_BYTES: f64 = 96.0;
/// The memory budget and the cancellation token are checked every 2^16 modules.
const CHECK_SHIFT: u32 = 16;

impl Lsystem {
    /// The string after `steps` derivation steps, for a grammar whose probabilities are all
    /// fixed numbers.
    ///
    /// # Errors
    /// As [`Lsystem::derive_with`]; a callback probability is an [`LsystemError::Callback`].
    pub fn derive(&self, steps: u32) -> Result<Vec<Module>, LsystemError> {
        self.derive_with(steps, &mut |_, _, _| Err::<f64, &str>("no probability callback was given"))
    }

    /// The string after `steps` derivation steps. `probability(id, step, params)` evaluates a
    /// [`Probability::Callback`](super::Probability::Callback) choice with that id for derivation step `step` (0 for the first
    /// rewriting) and the predecessor's parameters. Deterministic rules draw no random number,
    /// each stochastic rewriting draws one, in string order, from SplitMix64 seeded with the
    /// L-system's seed: the same seed gives the same string.
    ///
    /// Linear time in the total length of the strings.
    ///
    /// # Errors
    /// [`LsystemError::Callback`], [`LsystemError::BadProbability`],
    /// [`LsystemError::ProbabilitySum`] (the callbacks' values at one use do not sum to 1),
    /// [`LsystemError::NonFiniteParameter`], [`LsystemError::TooManyModules`].
    pub fn derive_with<E: Display>(
        &self,
        steps: u32,
        probability: &mut ProbabilityFn<'_, E>,
    ) -> Result<Vec<Module>, LsystemError> {
        let mut rng = SplitMix64::new(self.seed);
        let mut cur = self.axiom.clone();
        let mut probs: Vec<f64> = Vec::new();
        let mut vars: Vec<f64> = Vec::new();
        for step in 0..steps {
            let (open_of, close_of) = brackets(&cur);
            let mut next = Vec::with_capacity(cur.len() * 2);
            let mut checked = 0;
            for (i, m) in cur.iter().enumerate() {
                let Some(rule) = self.matching_rule(&cur, i, &open_of, &close_of) else {
                    next.push(m.clone());
                    continue;
                };
                let k = if rule.choices.len() == 1 {
                    0
                } else {
                    let place = || format!("rules[\"{}\"] at step {step} for `{m}`", rule.key);
                    probs.clear();
                    for (c, (_, p)) in rule.choices.iter().enumerate() {
                        let p = match p {
                            Prob::Fixed(p) => *p,
                            Prob::Callback(id) => probability(*id, step, &m.params).map_err(|e| {
                                LsystemError::Callback { place: place(), choice: c, message: e.to_string() }
                            })?,
                            Prob::Expr(e) => {
                                vars.clear();
                                vars.extend_from_slice(&m.params);
                                vars.push(f64::from(step));
                                e.eval(&vars)
                            }
                        };
                        if !(0.0..=1.0).contains(&p) {
                            return Err(LsystemError::BadProbability { place: place(), choice: c, p });
                        }
                        probs.push(p);
                    }
                    let sum: f64 = probs.iter().sum();
                    if (sum - 1.0).abs() > 1e-9 {
                        return Err(LsystemError::ProbabilitySum { place: place(), sum });
                    }
                    let u = rng.next_f64() * sum;
                    let mut acc = 0.0;
                    let mut pick = probs.len() - 1;
                    for (c, &p) in probs.iter().enumerate() {
                        acc += p;
                        if u < acc {
                            pick = c;
                            break;
                        }
                    }
                    pick
                };
                for t in &rule.choices[k].0 {
                    let mut params = Vec::with_capacity(t.params.len());
                    for (j, e) in t.params.iter().enumerate() {
                        let v = e.eval(&m.params);
                        if !v.is_finite() {
                            return Err(LsystemError::NonFiniteParameter {
                                place: format!("rules[\"{}\"] at step {step} for `{m}`", rule.key),
                                symbol: t.symbol.clone(),
                                index: j,
                                value: v,
                            });
                        }
                        params.push(v);
                    }
                    next.push(Module { symbol: t.symbol.clone(), params });
                }
                if next.len() > self.max_modules {
                    return Err(LsystemError::TooManyModules { count: next.len(), step, cap: self.max_modules });
                }
                if next.len() >> CHECK_SHIFT != checked {
                    // Every 65,536 modules: the strings so far against the memory budget (a
                    // raised max_modules must not run the machine out of memory), and the
                    // cancellation token.
                    checked = next.len() >> CHECK_SHIFT;
                    let n = cur.len() + next.len();
                    crate::limits::check_memory(
                        || format!("the derived string ({n} modules at step {step})"),
                        n as f64 * MODULE_BYTES,
                    )?;
                    crate::limits::charge(1 << CHECK_SHIFT)?;
                }
            }
            cur = next;
        }
        Ok(cur)
    }

    fn matching_rule(&self, s: &[Module], i: usize, open_of: &[usize], close_of: &[usize]) -> Option<&Rule> {
        let m = &s[i];
        let ids = self.by_symbol.get(&m.symbol)?;
        ids.iter().map(|&r| &self.rules[r]).find(|r| {
            r.formals.as_ref().is_none_or(|f| f.len() == m.params.len())
                && self.left_matches(s, i, &r.left, open_of)
                && self.right_matches(s, i, &r.right, close_of)
        })
    }

    fn ignored(&self, m: &Module) -> bool {
        self.ignore.contains(&m.symbol)
    }

    fn left_matches(&self, s: &[Module], i: usize, pattern: &[String], open_of: &[usize]) -> bool {
        let mut j = i;
        for want in pattern.iter().rev() {
            loop {
                if j == 0 {
                    return false;
                }
                j -= 1;
                let m = &s[j];
                if m.closes() {
                    // Skip the sibling branch before: jump to its opening bracket.
                    j = open_of[j];
                } else if m.opens() || self.ignored(m) {
                    // Climb out of this branch to the parent, or skip an ignored symbol.
                } else {
                    break;
                }
            }
            if s[j].symbol != *want {
                return false;
            }
        }
        true
    }

    fn right_matches(&self, s: &[Module], i: usize, pattern: &[String], close_of: &[usize]) -> bool {
        let mut j = i;
        for want in pattern {
            loop {
                j += 1;
                let Some(m) = s.get(j) else { return false };
                if m.opens() {
                    j = close_of[j];
                } else if m.closes() {
                    return false;
                } else if !self.ignored(m) {
                    break;
                }
            }
            if s[j].symbol != *want {
                return false;
            }
        }
        true
    }
}

/// For each `]` the index of its opening bracket and for each opening bracket its `]` (other
/// entries unused). Unbalanced strings cannot be derived from balanced axioms and successors;
/// unmatched entries point at themselves.
fn brackets(s: &[Module]) -> (Vec<usize>, Vec<usize>) {
    let mut open_of: Vec<usize> = (0..s.len()).collect();
    let mut close_of: Vec<usize> = (0..s.len()).collect();
    let mut stack = Vec::new();
    for (i, m) in s.iter().enumerate() {
        if m.opens() {
            stack.push(i);
        } else if m.closes() {
            if let Some(o) = stack.pop() {
                open_of[i] = o;
                close_of[o] = i;
            }
        }
    }
    // An unclosed `[` skips to the end.
    for o in stack {
        close_of[o] = s.len();
    }
    (open_of, close_of)
}

#[cfg(test)]
mod tests {
    use super::super::grammar::{modules_to_string, ChoiceSpec, Probability, RuleSpec};
    use super::*;

    fn derive(axiom: &str, rules: &[(&str, &str)], steps: u32) -> String {
        let rules: Vec<RuleSpec> = rules.iter().map(|(k, v)| RuleSpec::deterministic(k, v)).collect();
        modules_to_string(&Lsystem::new(axiom, &rules, 0).unwrap().derive(steps).unwrap())
    }

    #[test]
    fn all_symbols_are_rewritten_at_once() {
        // §10.1's example: A → AB applied to ABBAAB gives ABBBABABB.
        assert_eq!(derive("ABBAAB", &[("A", "AB")], 1), "ABBBABABB");
        // Algae: lengths follow Fibonacci numbers 1, 2, 3, 5, 8, 13.
        let lens: Vec<usize> = (0..6).map(|n| derive("A", &[("A", "AB"), ("B", "A")], n).len()).collect();
        assert_eq!(lens, [1, 2, 3, 5, 8, 13]);
    }

    #[test]
    fn parameters_are_computed_from_the_predecessor() {
        // The thesis's steps: L0(s) → L(s) L0(s+1).
        assert_eq!(derive("L0(0)", &[("L0(s)", "L(s)L0(s+1)")], 3), "L(0)L(1)L(2)L0(3)");
        // A rule with formals applies only to modules of that arity.
        assert_eq!(derive("A A(1)", &[("A(x)", "B(x*2)")], 1), "AB(2)");
    }

    #[test]
    fn context_rules_see_through_ignored_symbols_and_branches() {
        // Signal propagation (ABOP Fig. 1.31 style): B moves right one symbol per step.
        let rules = [("B<A", "B"), ("B", "A")];
        assert_eq!(derive("BAAA", &rules, 1), "ABAA");
        assert_eq!(derive("BAAA", &rules, 2), "AABA");
        // Ignored symbols between; a sibling branch skipped on the left; the parent reached
        // from inside a branch.
        let ls = Lsystem::new("B+A", &[RuleSpec::deterministic("B<A", "C")], 0).unwrap().with_ignore("+").unwrap();
        assert_eq!(modules_to_string(&ls.derive(1).unwrap()), "B+C");
        assert_eq!(derive("B[X]A", &[("B<A", "C")], 1), "B[X]C");
        assert_eq!(derive("B[A]", &[("B<A", "C")], 1), "B[C]");
        // Right context skips child branches and stops at the branch end.
        assert_eq!(derive("A[X]B", &[("A>B", "C")], 1), "C[X]B");
        assert_eq!(derive("[A]B", &[("A>B", "C")], 1), "[A]B");
        // Context rules win over context-free ones.
        assert_eq!(derive("BA A", &[("A", "D"), ("B<A", "C")], 1), "BCD");
    }

    #[test]
    fn same_seed_same_string_and_seeds_differ() {
        let c = |to: &str| ChoiceSpec { to: to.into(), p: Probability::Fixed(0.5) };
        let rule = RuleSpec { key: "A".into(), choices: vec![c("A[A]"), c("AA")] };
        let ls = Lsystem::new("A", &[rule], 7).unwrap();
        let a = modules_to_string(&ls.derive(8).unwrap());
        assert_eq!(a, modules_to_string(&ls.derive(8).unwrap()));
        let strings: std::collections::HashSet<String> =
            (0..8).map(|s| modules_to_string(&ls.clone().with_seed(s).derive(8).unwrap())).collect();
        // 255 independent coin flips per derivation: two seeds agreeing on all is (almost) impossible.
        assert_eq!(strings.len(), 8);
    }

    #[test]
    fn callback_probabilities_are_checked_at_each_use() {
        let rule = RuleSpec {
            key: "A(s)".into(),
            choices: vec![
                ChoiceSpec { to: "A(s+1)".into(), p: Probability::Callback(0) },
                ChoiceSpec { to: "B".into(), p: Probability::Callback(1) },
            ],
        };
        let ls = Lsystem::new("A(0)", &[rule], 3).unwrap();
        // pr(step) = 1 while the parameter is below 2, then 0: exactly A(0) → A(1) → A(2) → B.
        let mut pr = |id: u32, _step: u32, p: &[f64]| -> Result<f64, String> {
            let keep = if p[0] < 2.0 { 1.0 } else { 0.0 };
            Ok(if id == 0 { keep } else { 1.0 - keep })
        };
        assert_eq!(modules_to_string(&ls.derive_with(4, &mut pr).unwrap()), "B");
        let mut bad = |_: u32, step: u32, _: &[f64]| -> Result<f64, String> { Ok(if step == 1 { 0.3 } else { 0.5 }) };
        let e = ls.derive_with(3, &mut bad).unwrap_err();
        assert!(
            e.to_string().contains("rules[\"A(s)\"] at step 1 for `A(1)`: the choices' probabilities sum to 0.6"),
            "{e}"
        );
        let e = ls.derive(1).unwrap_err();
        assert!(matches!(e, LsystemError::Callback { .. }), "{e}");
    }

    #[test]
    fn expression_probabilities_see_parameters_and_the_step() {
        // pr = 1 for s < 2 (then 0) written as an expression: A(0) → A(1) → A(2) → B.
        let rule = RuleSpec {
            key: "A(s)".into(),
            choices: vec![
                ChoiceSpec { to: "A(s+1)".into(), p: Probability::Expression("max(0, min(1, 2 - s))".into()) },
                ChoiceSpec { to: "B".into(), p: Probability::Expression("1 - max(0, min(1, 2 - s))".into()) },
            ],
        };
        let ls = Lsystem::new("A(0)", &[rule], 3).unwrap();
        assert_eq!(modules_to_string(&ls.derive(4).unwrap()), "B");
        // `step` is the derivation step: 0.5 + 0.5·step sums to 1 with its complement only.
        let rule = RuleSpec {
            key: "A".into(),
            choices: vec![
                ChoiceSpec { to: "A".into(), p: Probability::Expression("step".into()) },
                ChoiceSpec { to: "B".into(), p: Probability::Expression("0.5".into()) },
            ],
        };
        let e = Lsystem::new("A", &[rule], 0).unwrap().derive(1).unwrap_err();
        assert!(e.to_string().contains("at step 0 for `A`: the choices' probabilities sum to 0.5"), "{e}");
    }

    #[test]
    fn runaway_derivation_stops_at_the_cap() {
        let ls = Lsystem::new("A", &[RuleSpec::deterministic("A", "AA")], 0).unwrap().with_max_modules(1000);
        let e = ls.derive(20).unwrap_err();
        assert!(matches!(e, LsystemError::TooManyModules { step: 9, cap: 1000, .. }), "{e}");
    }
}
