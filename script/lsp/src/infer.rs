//! Script types of values known without running the recipe, from the catalogue's declared
//! return types: a literal's, a variable's (followed through `let` and assignments in order),
//! or what the function, method or property at the end of a chain returns when all of that
//! name's overloads that fit agree. The REPL completes after `m.` the same way, from the
//! session's values.

use std::collections::HashMap;

use blocksmith_script::catalogue::Overload;
use rhai::{Expr, Stmt};

use crate::text::{blank_strings_and_comments, is_ident};

/// The type `name` returns when called with `arity` arguments (a property when `property`)
/// on a receiver of type `receiver` (if known), when every overload that fits agrees.
#[must_use]
pub fn returns(
    catalogue: &[Overload],
    name: &str,
    arity: Option<usize>,
    receiver: Option<&str>,
    property: bool,
) -> Option<String> {
    let mut fits = catalogue.iter().filter(|o| {
        o.name == name
            && (o.property == Some("get")) == property
            && (property || o.property.is_none())
            && arity.is_none_or(|n| o.params.len() == n)
            && receiver.is_none_or(|t| o.params.first().is_some_and(|(_, pt)| pt == t))
    });
    let first = fits.next()?.returns.clone();
    (fits.all(|o| o.returns == first) && first != "any" && first != "nothing").then_some(first)
}

/// The method and property names callable on a value of script type `t`, blocksmith's and
/// Rhai's own, sorted.
#[must_use]
pub fn members<'a>(catalogue: &'a [Overload], t: &str) -> Vec<&'a Overload> {
    let mut out: Vec<&Overload> = catalogue
        .iter()
        .filter(|o| o.params.first().is_some_and(|(_, pt)| pt == t))
        .filter(|o| o.name.starts_with(|c: char| c.is_alphabetic()) && o.property != Some("set"))
        .collect();
    out.sort_by(|a, b| a.name.cmp(&b.name));
    out
}

/// Variables' types as the text before a point assigns them: `let x = EXPR;` and `x = EXPR;`
/// statements in order, each `EXPR` typed by [`type_of_text`] (the text need not parse).
#[must_use]
pub fn variables_in_text(catalogue: &[Overload], text: &str) -> HashMap<String, String> {
    let code = blank_strings_and_comments(text);
    let mut vars: HashMap<String, String> = HashMap::new();
    let bytes = code.as_bytes();
    let mut i = 0;
    while i < code.len() {
        let rest = &code[i..];
        let at_word_start = i == 0 || !is_ident(code[..i].chars().next_back().unwrap_or(' '));
        let after_let = rest.strip_prefix("let ").or_else(|| rest.strip_prefix("const "));
        if at_word_start {
            if let Some(after) = after_let {
                let skip = rest.len() - after.len();
                let name_len = after.trim_start().len();
                let pad = after.len() - name_len;
                let name_end = crate::text::word_len(after.trim_start());
                let name = &after.trim_start()[..name_end];
                let tail = after.trim_start()[name_end..].trim_start();
                if let Some(expr) = tail.strip_prefix('=').filter(|t| !t.starts_with('=')) {
                    let end = statement_end(expr);
                    match type_of_text(&|v| vars.get(v).cloned(), catalogue, expr[..end].trim()) {
                        Some(t) => vars.insert(name.to_string(), t),
                        None => vars.remove(name),
                    };
                }
                i += skip + pad + name_end.max(1);
                continue;
            }
        }
        i += rest.chars().next().map_or(1, char::len_utf8);
        let _ = bytes;
    }
    vars
}

/// Where the statement starting `text` ends: the first `;` outside brackets, or the end.
fn statement_end(text: &str) -> usize {
    let mut depth = 0i64;
    for (i, c) in text.char_indices() {
        match c {
            '(' | '[' | '{' => depth += 1,
            ')' | ']' | '}' if depth == 0 => return i,
            ')' | ']' | '}' => depth -= 1,
            ';' if depth == 0 => return i,
            _ => {}
        }
    }
    text.len()
}

/// The script type of the expression at the end of `expr` (the text before a `.`), when it
/// can be told without running it.
#[must_use]
pub fn type_of_text(vars: &dyn Fn(&str) -> Option<String>, catalogue: &[Overload], expr: &str) -> Option<String> {
    let expr = receiver_text(expr);
    if expr.is_empty() {
        return None;
    }
    if let Some(t) = literal_text_type(expr) {
        return Some(t.to_string());
    }
    if expr.chars().all(is_ident) {
        return vars(expr);
    }
    let (callee, called) = match expr.strip_suffix(')') {
        Some(inner) => (&expr[..matching_open(inner)?], true),
        None => (expr, false),
    };
    let name_start = crate::text::ident_start(callee);
    let name = &callee[name_start..];
    let receiver = callee[..name_start].strip_suffix('.');
    if !called && receiver.is_none() {
        return None;
    }
    let receiver_type = match receiver {
        Some(r) => Some(type_of_text(vars, catalogue, r)?),
        None => None,
    };
    returns(catalogue, name, None, receiver_type.as_deref(), !called)
}

fn literal_text_type(expr: &str) -> Option<&'static str> {
    let first = expr.chars().next()?;
    if expr.starts_with("#{") {
        return Some("map");
    }
    match first {
        '[' => Some("array"),
        '"' | '`' => Some("string"),
        '0'..='9' if expr.chars().all(|c| c.is_ascii_digit() || c == '_') => Some("int"),
        '0'..='9' if expr.parse::<f64>().is_ok() => Some("float"),
        _ if expr == "true" || expr == "false" => Some("bool"),
        _ => None,
    }
}

/// The receiver expression at the end of `text`: identifiers, `.`, `::` and bracketed groups
/// back to the first character that cannot be part of one (`let x = cube(1).` → `cube(1)`).
#[must_use]
pub fn receiver_text(text: &str) -> &str {
    let text = text.trim_end();
    let bytes = text.as_bytes();
    let mut i = text.len();
    while i > 0 {
        let c = bytes[i - 1];
        if c == b')' || c == b']' || c == b'}' {
            match matching_open(&text[..i - 1]) {
                Some(open) => {
                    i = open;
                    if text[..i].ends_with('#') {
                        i -= 1;
                    }
                }
                None => break,
            }
        } else if c.is_ascii_alphanumeric() || c == b'_' || c == b'.' || c == b':' || c >= 0x80 || c == b'"' {
            if c == b'"' {
                match text[..i - 1].rfind('"') {
                    Some(j) => i = j,
                    None => break,
                }
            } else {
                i -= 1;
            }
        } else {
            break;
        }
    }
    text[i..].trim_start_matches('.')
}

/// Where the bracket opens that closes just after `inner` (the text before a `)`, `]` or `}`).
#[must_use]
pub fn matching_open(inner: &str) -> Option<usize> {
    let mut depth = 0i64;
    for (i, c) in inner.char_indices().rev() {
        match c {
            ')' | ']' | '}' => depth += 1,
            '(' | '[' | '{' if depth == 0 => return Some(i),
            '(' | '[' | '{' => depth -= 1,
            _ => {}
        }
    }
    None
}

/// Variables' types followed through a compiled script, statement by statement.
#[derive(Debug, Default, Clone)]
pub struct Scope {
    /// Each variable's script type, when known.
    pub vars: HashMap<String, String>,
}

impl Scope {
    /// The script type of `e`'s value when literals and declared return types settle it.
    #[must_use]
    pub fn type_of(&self, catalogue: &[Overload], e: &Expr) -> Option<String> {
        let t = match e {
            Expr::IntegerConstant(..) => "int",
            Expr::FloatConstant(..) => "float",
            Expr::BoolConstant(..) => "bool",
            Expr::StringConstant(..) | Expr::InterpolatedString(..) => "string",
            Expr::CharConstant(..) => "char",
            Expr::Array(..) => "array",
            Expr::Map(..) => "map",
            Expr::DynamicConstant(d, _) => return Some(blocksmith_script::catalogue::script_type(d.type_name())),
            Expr::Variable(v, ..) => return self.vars.get(v.1.as_str()).cloned(),
            Expr::FnCall(call, _) if call.namespace.is_empty() && !call.is_operator_call() => {
                let receiver = call.args.first().and_then(|a| self.type_of(catalogue, a));
                let r = returns(catalogue, call.name.as_str(), Some(call.args.len()), receiver.as_deref(), false);
                return r.or_else(|| returns(catalogue, call.name.as_str(), Some(call.args.len()), None, false));
            }
            Expr::Dot(bin, ..) => {
                let mut t = self.type_of(catalogue, &bin.lhs)?;
                let mut links = Vec::new();
                flatten(&bin.rhs, &mut links);
                for l in links {
                    t = match l {
                        Link::Method(name, arity) => returns(catalogue, name, Some(arity), Some(&t), false)?,
                        Link::Property("") => return None,
                        Link::Property(name) => returns(catalogue, name, None, Some(&t), true)?,
                    };
                }
                return Some(t);
            }
            _ => return None,
        };
        Some(t.to_string())
    }

    /// Follows a statement's assignments: `let x = e` and `x = e` set `x`'s type (or forget it).
    pub fn assign(&mut self, catalogue: &[Overload], s: &Stmt) {
        let (name, value) = match s {
            Stmt::Var(x, ..) => (x.0.name.as_str(), &x.1),
            Stmt::Assignment(x) => match &x.1.lhs {
                Expr::Variable(v, ..) if !x.0.is_op_assignment() => (v.1.as_str(), &x.1.rhs),
                Expr::Variable(v, ..) => {
                    self.vars.remove(v.1.as_str());
                    return;
                }
                _ => return,
            },
            _ => return,
        };
        match self.type_of(catalogue, value) {
            Some(t) => self.vars.insert(name.to_string(), t),
            None => self.vars.remove(name),
        };
    }
}

/// One link of a method chain.
pub enum Link<'a> {
    /// `name(…)` with this many arguments, the receiver included.
    Method(&'a str, usize),
    /// `.name`.
    Property(&'a str),
}

/// The links of the right side of a `.` chain, in order.
pub fn flatten<'a>(e: &'a Expr, out: &mut Vec<Link<'a>>) {
    match e {
        Expr::MethodCall(call, _) => out.push(Link::Method(call.name.as_str(), call.args.len() + 1)),
        Expr::Property(p, _) => out.push(Link::Property(p.2.as_str())),
        Expr::Dot(bin, ..) => {
            flatten(&bin.lhs, out);
            flatten(&bin.rhs, out);
        }
        // What an index gives is not known: an empty property ends the chain's type.
        Expr::Index(bin, ..) => {
            flatten(&bin.lhs, out);
            out.push(Link::Property(""));
        }
        _ => {}
    }
}
