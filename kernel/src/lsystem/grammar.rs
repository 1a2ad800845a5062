//! Grammars (seed 004, §10.1–10.2 and §11): modules (symbols with parameters), parameter
//! expressions, and rules — deterministic, stochastic (§11, choices whose probabilities may depend
//! on the step and the parameters), parametric and context-sensitive (`"A<B>C"`, §10.2).
//!
//! Notation. A *module* is a symbol with parameters, `L0(3)`. Symbols are a letter with optional
//! digits (`F`, `L0`, `A12`), the turtle symbols `+ - & ^ \ / | !`, the brackets `[` `]`, and the
//! thesis's branch symbols `[L` `[R` (a `[` directly followed by `L` or `R` that is not followed by
//! a letter or digit; write `[ L` for a push followed by `L`). `[L` and `[R` open a branch like
//! `[`, and `]` closes either.

use std::collections::HashMap;
use std::fmt;

use super::LsystemError;

/// A symbol with its parameters, e.g. `L0(3)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Module {
    /// The symbol: `"F"`, `"L0"`, `"["`, `"[L"`, …
    pub symbol: String,
    /// The actual parameters.
    pub params: Vec<f64>,
}

impl Module {
    /// Whether the symbol opens a branch (`[`, `[L`, `[R`).
    #[must_use]
    pub fn opens(&self) -> bool {
        is_open(&self.symbol)
    }

    /// Whether the symbol closes a branch (`]`).
    #[must_use]
    pub fn closes(&self) -> bool {
        self.symbol == "]"
    }
}

pub(crate) fn is_open(s: &str) -> bool {
    matches!(s, "[" | "[L" | "[R")
}

impl fmt::Display for Module {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.symbol)?;
        if !self.params.is_empty() {
            f.write_str("(")?;
            for (i, p) in self.params.iter().enumerate() {
                if i > 0 {
                    f.write_str(",")?;
                }
                if p.fract() == 0.0 && p.abs() < 1e15 {
                    write!(f, "{}", *p as i64)?;
                } else if p.abs() >= 1e15 {
                    // Huge values in exponent form (`F(1e200)`, not 201 digits); it parses back.
                    write!(f, "{p:e}")?;
                } else {
                    write!(f, "{p}")?;
                }
            }
            f.write_str(")")?;
        }
        Ok(())
    }
}

/// The modules as a string: each module's text, separated by nothing except a space between a
/// symbol ending in a letter or digit and one starting with a digit-free letter that would merge
/// with it (`L0` then `L` stays `L0 L`).
#[must_use]
pub fn modules_to_string(ms: &[Module]) -> String {
    let mut s = String::with_capacity(ms.len() * 2);
    let mut prev: Option<&Module> = None;
    for m in ms {
        if let Some(p) = prev {
            // Concatenation reads back the same except for `[` then `L` or `R`, which would
            // read as the thesis symbol `[L` / `[R`.
            if p.symbol == "[" && (m.symbol == "L" || m.symbol == "R") {
                s.push(' ');
            }
        }
        s.push_str(&m.to_string());
        prev = Some(m);
    }
    s
}

/// A binary operator of a parameter expression.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Op {
    Add,
    Sub,
    Mul,
    Div,
    Pow,
}

/// A parameter expression of a successor: numbers, the rule's formal parameters, `+ - * / ^` and
/// parentheses.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Expr {
    Num(f64),
    Var(usize),
    Neg(Box<Expr>),
    Bin(Op, Box<Expr>, Box<Expr>),
    Call(Func, Vec<Expr>),
}

/// A function of parameter expressions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Func {
    Exp,
    Ln,
    Sqrt,
    Abs,
    Min,
    Max,
}

impl Func {
    fn named(name: &str) -> Option<(Func, usize)> {
        Some(match name {
            "exp" => (Func::Exp, 1),
            "ln" => (Func::Ln, 1),
            "sqrt" => (Func::Sqrt, 1),
            "abs" => (Func::Abs, 1),
            "min" => (Func::Min, 2),
            "max" => (Func::Max, 2),
            _ => return None,
        })
    }
}

impl Expr {
    pub fn eval(&self, vars: &[f64]) -> f64 {
        match self {
            Expr::Num(x) => *x,
            Expr::Var(i) => vars.get(*i).copied().unwrap_or(f64::NAN),
            Expr::Neg(e) => -e.eval(vars),
            Expr::Bin(op, a, b) => {
                let (a, b) = (a.eval(vars), b.eval(vars));
                match op {
                    Op::Add => a + b,
                    Op::Sub => a - b,
                    Op::Mul => a * b,
                    Op::Div => a / b,
                    Op::Pow => a.powf(b),
                }
            }
            Expr::Call(f, args) => {
                let a = args.first().map_or(f64::NAN, |e| e.eval(vars));
                let b = args.get(1).map_or(f64::NAN, |e| e.eval(vars));
                match f {
                    Func::Exp => a.exp(),
                    Func::Ln => a.ln(),
                    Func::Sqrt => a.sqrt(),
                    Func::Abs => a.abs(),
                    Func::Min => a.min(b),
                    Func::Max => a.max(b),
                }
            }
        }
    }
}

/// A module of a successor: a symbol and parameter expressions.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Template {
    pub symbol: String,
    pub params: Vec<Expr>,
}

/// How likely a choice is.
#[derive(Clone, Debug, PartialEq)]
pub enum Probability {
    /// A fixed probability in [0, 1].
    Fixed(f64),
    /// Computed at each use by the derivation's callback with this id, from the step and the
    /// predecessor's parameters (as `pr(step)` in Eq. 11.1).
    Callback(u32),
    /// An expression of the rule's formal parameters and `step` (the derivation step), e.g.
    /// `"1 - 1/(1 + exp(5.2 - s))"`, with `+ - * / ^`, `exp ln sqrt abs min max`.
    Expression(String),
}

/// A parsed probability.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Prob {
    Fixed(f64),
    Callback(u32),
    Expr(Expr),
}

/// One choice of a rule as given: a successor string and its probability.
#[derive(Clone, Debug, PartialEq)]
pub struct ChoiceSpec {
    /// The successor, e.g. `"[L L0(s+1) L(s+1) P(s+1)]"`.
    pub to: String,
    /// Its probability.
    pub p: Probability,
}

/// A rule as given: its key (`"L0(s)"`, `"A<B>C"`) and its choices (one for a deterministic
/// rule).
#[derive(Clone, Debug, PartialEq)]
pub struct RuleSpec {
    /// `[left <] symbol[(formals)] [> right]`.
    pub key: String,
    /// The successors with their probabilities.
    pub choices: Vec<ChoiceSpec>,
}

impl RuleSpec {
    /// A deterministic rule `key → to`.
    #[must_use]
    pub fn deterministic(key: &str, to: &str) -> RuleSpec {
        RuleSpec { key: key.into(), choices: vec![ChoiceSpec { to: to.into(), p: Probability::Fixed(1.0) }] }
    }
}

/// A parsed rule.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Rule {
    pub key: String,
    pub left: Vec<String>,
    pub symbol: String,
    pub formals: Option<Vec<String>>,
    pub right: Vec<String>,
    pub choices: Vec<(Vec<Template>, Prob)>,
}

/// An L-system ⟨V, w, P⟩ (§10.1): an axiom, rules, a seed for every random choice, the symbols
/// that context matching skips, and a cap on the derived string.
#[derive(Clone, Debug, PartialEq)]
pub struct Lsystem {
    pub(crate) axiom: Vec<Module>,
    pub(crate) rules: Vec<Rule>,
    pub(crate) by_symbol: HashMap<String, Vec<usize>>,
    pub(crate) seed: u64,
    pub(crate) ignore: Vec<String>,
    pub(crate) max_modules: usize,
}

/// Default cap on the number of modules of a derived string.
pub const DEFAULT_MAX_MODULES: usize = 5_000_000;

impl Lsystem {
    /// Builds an L-system from an axiom and rules.
    ///
    /// Rules are tried per module in this order: context-sensitive rules first (longer contexts
    /// first), then context-free ones; a rule with formal parameters applies only to modules with
    /// as many parameters. Fixed probabilities must lie in [0, 1] and sum to 1 (within 1e-9);
    /// callback probabilities are checked at each use.
    ///
    /// # Errors
    /// [`LsystemError::EmptyAxiom`], [`LsystemError::UnknownSymbol`], [`LsystemError::Syntax`],
    /// [`LsystemError::UnbalancedBrackets`] (axiom or any successor),
    /// [`LsystemError::UnknownParameter`], [`LsystemError::NoChoices`],
    /// [`LsystemError::BadProbability`], [`LsystemError::ProbabilitySum`].
    pub fn new(axiom: &str, rules: &[RuleSpec], seed: u64) -> Result<Lsystem, LsystemError> {
        let axiom = parse_modules("axiom", axiom)?;
        if axiom.is_empty() {
            return Err(LsystemError::EmptyAxiom);
        }
        check_balance("axiom", axiom.iter().map(|m| m.symbol.as_str()))?;
        let mut parsed = Vec::with_capacity(rules.len());
        for spec in rules {
            parsed.push(parse_rule(spec)?);
        }
        let mut order: Vec<usize> = (0..parsed.len()).collect();
        order.sort_by_key(|&i| {
            let r: &Rule = &parsed[i];
            (std::cmp::Reverse(r.left.len() + r.right.len()), r.formals.is_none(), r.key.clone())
        });
        let mut by_symbol: HashMap<String, Vec<usize>> = HashMap::new();
        for i in order {
            by_symbol.entry(parsed[i].symbol.clone()).or_default().push(i);
        }
        Ok(Lsystem { axiom, rules: parsed, by_symbol, seed, ignore: Vec::new(), max_modules: DEFAULT_MAX_MODULES })
    }

    /// With the symbols context matching skips (e.g. `"+-&^"`), given as a string of symbols.
    ///
    /// # Errors
    /// [`LsystemError::UnknownSymbol`], [`LsystemError::Syntax`].
    pub fn with_ignore(mut self, symbols: &str) -> Result<Lsystem, LsystemError> {
        self.ignore = lex("ignore", symbols, None)?.into_iter().map(|t| t.symbol).collect();
        Ok(self)
    }

    /// With a cap on the number of modules of a derived string. Default value:
    /// [`DEFAULT_MAX_MODULES`].
    #[must_use]
    pub fn with_max_modules(mut self, cap: usize) -> Lsystem {
        self.max_modules = cap;
        self
    }

    /// With another seed.
    #[must_use]
    pub fn with_seed(mut self, seed: u64) -> Lsystem {
        self.seed = seed;
        self
    }

    /// The axiom.
    #[must_use]
    pub fn axiom(&self) -> &[Module] {
        &self.axiom
    }

    /// The seed.
    #[must_use]
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// Number of rules.
    #[must_use]
    pub fn rule_count(&self) -> usize {
        self.rules.len()
    }
}

/// Checks that every `]` closes an earlier `[` / `[L` / `[R` and every one of those is closed.
pub(crate) fn check_balance<'a>(place: &str, symbols: impl Iterator<Item = &'a str>) -> Result<(), LsystemError> {
    let mut depth = 0usize;
    for (i, s) in symbols.enumerate() {
        if is_open(s) {
            depth += 1;
        } else if s == "]" {
            if depth == 0 {
                return Err(LsystemError::UnbalancedBrackets {
                    place: place.into(),
                    reason: format!("the `]` of module {i} closes no `[`"),
                });
            }
            depth -= 1;
        }
    }
    if depth > 0 {
        return Err(LsystemError::UnbalancedBrackets {
            place: place.into(),
            reason: format!("{depth} `[` never closed"),
        });
    }
    Ok(())
}

/// Parses a string of modules whose parameters are constant expressions (an axiom).
///
/// # Errors
/// [`LsystemError::UnknownSymbol`], [`LsystemError::Syntax`], [`LsystemError::UnknownParameter`].
pub fn parse_modules(place: &str, s: &str) -> Result<Vec<Module>, LsystemError> {
    let ts = lex(place, s, Some(&[]))?;
    Ok(ts
        .into_iter()
        .map(|t| Module { params: t.params.iter().map(|e| e.eval(&[])).collect(), symbol: t.symbol })
        .collect())
}

fn parse_rule(spec: &RuleSpec) -> Result<Rule, LsystemError> {
    let place = format!("rules[\"{}\"]", spec.key);
    let key: Vec<char> = spec.key.chars().collect();
    let lt = key.iter().position(|&c| c == '<');
    let gt = key.iter().position(|&c| c == '>');
    if key.iter().filter(|&&c| c == '<').count() > 1 || key.iter().filter(|&&c| c == '>').count() > 1 {
        return Err(LsystemError::Syntax { place, reason: "a key has at most one `<` and one `>`".into(), at: 1 });
    }
    let (start, end) = (lt.map_or(0, |i| i + 1), gt.unwrap_or(key.len()));
    if start > end {
        return Err(LsystemError::Syntax { place, reason: "`>` before `<` in a context rule".into(), at: end + 1 });
    }
    let context = |a: usize, b: usize| -> Result<Vec<String>, LsystemError> {
        let text: String = key[a..b].iter().collect();
        if let Some(k) = text.find('(') {
            return Err(LsystemError::Syntax {
                place: place.clone(),
                reason: "context symbols take no parameters".into(),
                at: a + text[..k].chars().count() + 1,
            });
        }
        let ts = lex(&place, &text, None)?;
        if let Some(t) = ts.iter().find(|t| !t.params.is_empty() || is_open(&t.symbol) || t.symbol == "]") {
            return Err(LsystemError::Syntax {
                place: place.clone(),
                reason: format!("context symbol `{}` may carry neither parameters nor brackets", t.symbol),
                at: a + 1,
            });
        }
        Ok(ts.into_iter().map(|t| t.symbol).collect())
    };
    let left = if let Some(i) = lt { context(0, i)? } else { Vec::new() };
    let right = if let Some(i) = gt { context(i + 1, key.len())? } else { Vec::new() };
    // The predecessor: one symbol with optional formal parameter names.
    let pred: String = key[start..end].iter().collect();
    let (symbol, formals) = parse_predecessor(&place, &pred, start)?;
    if spec.choices.is_empty() {
        return Err(LsystemError::NoChoices { place });
    }
    let names: Vec<String> = formals.clone().unwrap_or_default();
    let mut choices = Vec::with_capacity(spec.choices.len());
    let mut sum = 0.0;
    let mut all_fixed = true;
    for (i, c) in spec.choices.iter().enumerate() {
        let cplace = if spec.choices.len() == 1 { place.clone() } else { format!("{place}[{i}].to") };
        let ts = lex(&cplace, &c.to, Some(&names))?;
        check_balance(&cplace, ts.iter().map(|t| t.symbol.as_str()))?;
        let p = match &c.p {
            Probability::Fixed(p) => {
                if !(0.0..=1.0).contains(p) {
                    return Err(LsystemError::BadProbability { place: place.clone(), choice: i, p: *p });
                }
                sum += p;
                Prob::Fixed(*p)
            }
            Probability::Callback(id) => {
                all_fixed = false;
                Prob::Callback(*id)
            }
            Probability::Expression(text) => {
                all_fixed = false;
                let pplace = format!("{place}[{i}].p");
                let chars: Vec<char> = text.chars().collect();
                let mut vars = names.clone();
                vars.push("step".into());
                Prob::Expr(ExprParser { place: &pplace, chars: &chars, pos: 0, names: &vars, parts: 0 }.parse()?)
            }
        };
        choices.push((ts, p));
    }
    if all_fixed && (sum - 1.0).abs() > 1e-9 {
        return Err(LsystemError::ProbabilitySum { place, sum });
    }
    Ok(Rule { key: spec.key.clone(), left, symbol, formals, right, choices })
}

fn parse_predecessor(place: &str, pred: &str, offset: usize) -> Result<(String, Option<Vec<String>>), LsystemError> {
    let chars: Vec<char> = pred.chars().collect();
    let syntax = |reason: &str, at: usize| LsystemError::Syntax {
        place: place.into(),
        reason: reason.into(),
        at: offset + at + 1,
    };
    let mut i = 0;
    while i < chars.len() && chars[i].is_whitespace() {
        i += 1;
    }
    let (symbol, len) = match symbol_at(&chars, i) {
        Some(x) => x,
        None if i >= chars.len() => return Err(syntax("the key names no symbol", i)),
        None => return Err(LsystemError::UnknownSymbol { place: place.into(), found: chars[i], at: offset + i + 1 }),
    };
    if symbol == "]" || is_open(&symbol) {
        return Err(syntax("brackets are not rewritten", i));
    }
    i += len;
    let mut formals = None;
    if i < chars.len() && chars[i] == '(' {
        let close =
            chars[i..].iter().position(|&c| c == ')').map(|p| p + i).ok_or_else(|| syntax("`(` never closed", i))?;
        let inner: String = chars[i + 1..close].iter().collect();
        let mut names = Vec::new();
        for n in inner.split(',') {
            let n = n.trim();
            let ok = n.chars().next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
                && n.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
            if !ok {
                return Err(syntax(&format!("formal parameter `{n}` is not a name"), i + 1));
            }
            names.push(n.to_string());
        }
        formals = Some(names);
        i = close + 1;
    }
    while i < chars.len() && chars[i].is_whitespace() {
        i += 1;
    }
    if i < chars.len() {
        return Err(syntax("a rule rewrites one symbol: put other symbols in a context (`A<B>C`)", i));
    }
    Ok((symbol, formals))
}

/// The symbol starting at `i` and its length in characters.
fn symbol_at(chars: &[char], i: usize) -> Option<(String, usize)> {
    let c = *chars.get(i)?;
    if c == '[' {
        if let Some(&d) = chars.get(i + 1) {
            if (d == 'L' || d == 'R') && !chars.get(i + 2).is_some_and(|e| e.is_ascii_alphanumeric() || *e == '_') {
                return Some((format!("[{d}"), 2));
            }
        }
        return Some(("[".into(), 1));
    }
    if "]+-&^\\/|!".contains(c) {
        return Some((c.to_string(), 1));
    }
    if c.is_ascii_alphabetic() {
        let mut n = 1;
        while chars.get(i + n).is_some_and(|d| d.is_ascii_digit()) {
            n += 1;
        }
        return Some((chars[i..i + n].iter().collect(), n));
    }
    None
}

/// Splits `s` into templates. `formals`: `Some(names)` allows parameter expressions over those
/// names; `None` forbids parameters... (contexts take them but reject later).
fn lex(place: &str, s: &str, formals: Option<&[String]>) -> Result<Vec<Template>, LsystemError> {
    let chars: Vec<char> = s.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        if chars[i].is_whitespace() {
            i += 1;
            continue;
        }
        let Some((symbol, len)) = symbol_at(&chars, i) else {
            return Err(LsystemError::UnknownSymbol { place: place.into(), found: chars[i], at: i + 1 });
        };
        i += len;
        let mut params = Vec::new();
        if chars.get(i) == Some(&'(') {
            if symbol == "[" || symbol == "]" {
                return Err(LsystemError::Syntax {
                    place: place.into(),
                    reason: format!("`{symbol}` takes no parameters"),
                    at: i + 1,
                });
            }
            let mut depth = 0;
            let mut close = None;
            for (j, &c) in chars.iter().enumerate().skip(i) {
                if c == '(' {
                    depth += 1;
                } else if c == ')' {
                    depth -= 1;
                    if depth == 0 {
                        close = Some(j);
                        break;
                    }
                }
            }
            let close = close.ok_or_else(|| LsystemError::Syntax {
                place: place.into(),
                reason: "`(` never closed".into(),
                at: i + 1,
            })?;
            let names = formals.unwrap_or(&[]);
            // Split at top-level commas.
            let mut start = i + 1;
            let mut d = 0;
            for j in i + 1..=close {
                let c = chars[j];
                if c == '(' {
                    d += 1;
                } else if c == ')' && d > 0 {
                    d -= 1;
                } else if (c == ',' && d == 0) || j == close {
                    let mut p = ExprParser { place, chars: &chars[..j], pos: start, names, parts: 0 };
                    let e = p.parse()?;
                    params.push(e);
                    start = j + 1;
                }
            }
            i = close + 1;
        }
        out.push(Template { symbol, params });
    }
    Ok(out)
}

/// The most operands (numbers, names, calls, parenthesised or negated terms) a parameter
/// expression may have. Parsing and evaluating recurse once per level of the expression's
/// tree, which is never deeper than this: 10,000 nested parentheses are refused instead of
/// overflowing the stack.
pub const MAX_EXPRESSION_PARTS: usize = 256;

struct ExprParser<'a> {
    place: &'a str,
    chars: &'a [char],
    pos: usize,
    names: &'a [String],
    /// Operands parsed so far, against [`MAX_EXPRESSION_PARTS`].
    parts: usize,
}

impl ExprParser<'_> {
    fn err(&self, reason: &str) -> LsystemError {
        LsystemError::Syntax { place: self.place.into(), reason: reason.into(), at: self.pos + 1 }
    }

    fn skip(&mut self) {
        while self.pos < self.chars.len() && self.chars[self.pos].is_whitespace() {
            self.pos += 1;
        }
    }

    fn peek(&mut self) -> Option<char> {
        self.skip();
        self.chars.get(self.pos).copied()
    }

    fn parse(&mut self) -> Result<Expr, LsystemError> {
        if self.peek().is_none() {
            return Err(self.err("empty parameter"));
        }
        let e = self.sum()?;
        if self.peek().is_some() {
            return Err(self.err("unexpected text in a parameter expression"));
        }
        Ok(e)
    }

    fn sum(&mut self) -> Result<Expr, LsystemError> {
        let mut a = self.product()?;
        while let Some(c @ ('+' | '-')) = self.peek() {
            self.pos += 1;
            let b = self.product()?;
            a = Expr::Bin(if c == '+' { Op::Add } else { Op::Sub }, Box::new(a), Box::new(b));
        }
        Ok(a)
    }

    fn product(&mut self) -> Result<Expr, LsystemError> {
        let mut a = self.unary()?;
        while let Some(c @ ('*' | '/')) = self.peek() {
            self.pos += 1;
            let b = self.unary()?;
            a = Expr::Bin(if c == '*' { Op::Mul } else { Op::Div }, Box::new(a), Box::new(b));
        }
        Ok(a)
    }

    fn unary(&mut self) -> Result<Expr, LsystemError> {
        self.parts += 1;
        if self.parts > MAX_EXPRESSION_PARTS {
            return Err(self.err(&format!(
                "the expression is too large: more than {MAX_EXPRESSION_PARTS} operands, nested terms included"
            )));
        }
        if self.peek() == Some('-') {
            self.pos += 1;
            return Ok(Expr::Neg(Box::new(self.unary()?)));
        }
        let base = self.atom()?;
        if self.peek() == Some('^') {
            self.pos += 1;
            let exp = self.unary()?;
            return Ok(Expr::Bin(Op::Pow, Box::new(base), Box::new(exp)));
        }
        Ok(base)
    }

    fn atom(&mut self) -> Result<Expr, LsystemError> {
        match self.peek() {
            Some('(') => {
                self.pos += 1;
                let e = self.sum()?;
                if self.peek() != Some(')') {
                    return Err(self.err("`)` expected"));
                }
                self.pos += 1;
                Ok(e)
            }
            Some(c) if c.is_ascii_digit() || c == '.' => {
                let start = self.pos;
                while self.pos < self.chars.len() {
                    let c = self.chars[self.pos];
                    let exp_sign = (c == '+' || c == '-') && matches!(self.chars[self.pos - 1], 'e' | 'E');
                    if c.is_ascii_digit() || c == '.' || c == 'e' || c == 'E' || exp_sign {
                        self.pos += 1;
                    } else {
                        break;
                    }
                }
                let text: String = self.chars[start..self.pos].iter().collect();
                text.parse::<f64>().map(Expr::Num).map_err(|_| LsystemError::Syntax {
                    place: self.place.into(),
                    reason: format!("`{text}` is not a number"),
                    at: start + 1,
                })
            }
            Some(c) if c.is_ascii_alphabetic() || c == '_' => {
                let start = self.pos;
                while self.pos < self.chars.len()
                    && (self.chars[self.pos].is_ascii_alphanumeric() || self.chars[self.pos] == '_')
                {
                    self.pos += 1;
                }
                let name: String = self.chars[start..self.pos].iter().collect();
                if self.peek() == Some('(') {
                    let Some((f, arity)) = Func::named(&name) else {
                        return Err(LsystemError::Syntax {
                            place: self.place.into(),
                            reason: format!("unknown function `{name}` (functions: exp, ln, sqrt, abs, min, max)"),
                            at: start + 1,
                        });
                    };
                    self.pos += 1;
                    let mut args = vec![self.sum()?];
                    while self.peek() == Some(',') {
                        self.pos += 1;
                        args.push(self.sum()?);
                    }
                    if self.peek() != Some(')') {
                        return Err(self.err("`)` expected"));
                    }
                    self.pos += 1;
                    if args.len() != arity {
                        return Err(LsystemError::Syntax {
                            place: self.place.into(),
                            reason: format!("`{name}` takes {arity} argument(s), got {}", args.len()),
                            at: start + 1,
                        });
                    }
                    return Ok(Expr::Call(f, args));
                }
                match self.names.iter().position(|n| *n == name) {
                    Some(k) => Ok(Expr::Var(k)),
                    None => Err(LsystemError::UnknownParameter {
                        place: self.place.into(),
                        name,
                        formals: if self.names.is_empty() { "none".into() } else { self.names.join(", ") },
                    }),
                }
            }
            _ => Err(self.err("a number, a parameter name or `(` expected")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn symbols_are_letters_with_digits_turtle_signs_and_thesis_brackets() {
        let ms = parse_modules("axiom", "FF+[L L0(2) L(1.5)P]-[ L]A12").unwrap();
        let syms: Vec<&str> = ms.iter().map(|m| m.symbol.as_str()).collect();
        assert_eq!(syms, ["F", "F", "+", "[L", "L0", "L", "P", "]", "-", "[", "L", "]", "A12"]);
        assert_eq!(ms[4].params, [2.0]);
        assert_eq!(ms[5].params, [1.5]);
        // `[L0` is a push followed by L0: the L is followed by a digit.
        let ms = parse_modules("axiom", "[L0]").unwrap();
        assert_eq!(ms[0].symbol, "[");
        assert_eq!(modules_to_string(&ms), "[L0]");
        let ms = parse_modules("axiom", "[ L]").unwrap();
        assert_eq!(modules_to_string(&ms), "[ L]");
    }

    #[test]
    fn unknown_characters_are_named_with_their_position() {
        let e = parse_modules("axiom", "F@F").unwrap_err();
        assert_eq!(e, LsystemError::UnknownSymbol { place: "axiom".into(), found: '@', at: 2 });
        assert!(e.to_string().contains("unknown symbol `@` at character 2"), "{e}");
    }

    #[test]
    fn deeply_nested_or_huge_expressions_are_refused_not_overflowing_the_stack() {
        let nested = format!("F({}1{})", "(".repeat(10_000), ")".repeat(10_000));
        let e = Lsystem::new(&nested, &[], 1).unwrap_err();
        assert!(e.to_string().contains("the expression is too large: more than 256 operands"), "{e}");
        let long = format!("F({})", vec!["1"; 300].join("+"));
        assert!(Lsystem::new(&long, &[], 1).is_err());
        let rule = RuleSpec::deterministic("A(x)", &format!("F({}x{})", "-(".repeat(5000), ")".repeat(5000)));
        let e = Lsystem::new("A(1)", &[rule], 1).unwrap_err();
        assert!(e.to_string().contains("more than 256 operands"), "{e}");
        // Within the limit, nesting works as written.
        let ok = format!("F({}2{})", "(".repeat(100), ")".repeat(100));
        assert!(Lsystem::new(&ok, &[], 1).is_ok());
    }

    #[test]
    fn parameter_expressions_follow_precedence() {
        let r = parse_rule(&RuleSpec::deterministic("A(x, y)", "B(x + y * 2, -(x - 1) ^ 2, 2 ^ 3 ^ 2 / 64, 1e-1)"))
            .unwrap();
        let (ts, _) = &r.choices[0];
        let vals: Vec<f64> = ts[0].params.iter().map(|e| e.eval(&[3.0, 4.0])).collect();
        // 3 + 8; −(2²); 2^(3^2)/64 = 512/64; 0.1.
        assert_eq!(vals, [11.0, -4.0, 8.0, 0.1]);
        let r =
            parse_rule(&RuleSpec::deterministic("A(x)", "B(max(x, 5) + exp(0) + sqrt(abs(-16)) + ln(1) + min(x, 1))"))
                .unwrap();
        assert_eq!(r.choices[0].0[0].params[0].eval(&[3.0]), 5.0 + 1.0 + 4.0 + 0.0 + 1.0);
        assert!(matches!(parse_rule(&RuleSpec::deterministic("A(x)", "B(cos(x))")), Err(LsystemError::Syntax { .. })));
        let e = parse_rule(&RuleSpec::deterministic("A(x)", "B(z)")).unwrap_err();
        assert!(matches!(e, LsystemError::UnknownParameter { ref name, .. } if name == "z"), "{e}");
    }

    #[test]
    fn context_keys_split_into_left_symbol_and_right() {
        let r = parse_rule(&RuleSpec::deterministic("A B < C(t) > D", "E")).unwrap();
        assert_eq!(
            (r.left.clone(), r.symbol.clone(), r.right.clone()),
            (vec!["A".into(), "B".into()], "C".into(), vec!["D".into()])
        );
        assert_eq!(r.formals, Some(vec!["t".to_string()]));
        assert!(matches!(parse_rule(&RuleSpec::deterministic("AB", "E")), Err(LsystemError::Syntax { .. })));
        assert!(matches!(parse_rule(&RuleSpec::deterministic("A(x)<B", "E")), Err(LsystemError::Syntax { .. })));
    }

    #[test]
    fn probabilities_must_be_consistent() {
        let c = |to: &str, p: f64| ChoiceSpec { to: to.into(), p: Probability::Fixed(p) };
        let bad = RuleSpec { key: "A".into(), choices: vec![c("B", 0.5), c("C", 0.4)] };
        let e = Lsystem::new("A", &[bad], 1).unwrap_err();
        assert!(matches!(e, LsystemError::ProbabilitySum { .. }), "{e}");
        assert!(e.to_string().contains("rules[\"A\"]: the choices' probabilities sum to 0.9"), "{e}");
        let neg = RuleSpec { key: "A".into(), choices: vec![c("B", 1.5), c("C", -0.5)] };
        assert!(matches!(Lsystem::new("A", &[neg], 1), Err(LsystemError::BadProbability { choice: 0, .. })));
        let ok = RuleSpec { key: "A".into(), choices: vec![c("B", 0.25), c("C", 0.75)] };
        assert!(Lsystem::new("A", &[ok], 1).is_ok());
    }

    #[test]
    fn brackets_must_balance_in_the_axiom_and_every_successor() {
        let e = Lsystem::new("F[F", &[], 1).unwrap_err();
        assert!(e.to_string().contains("axiom: unbalanced brackets: 1 `[` never closed"), "{e}");
        let e = Lsystem::new("F", &[RuleSpec::deterministic("F", "F]F[")], 1).unwrap_err();
        assert!(e.to_string().contains("rules[\"F\"]: unbalanced brackets: the `]` of module 1 closes no `[`"), "{e}");
        assert!(matches!(Lsystem::new("  ", &[], 1), Err(LsystemError::EmptyAxiom)));
    }
}
