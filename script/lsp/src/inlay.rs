//! Inlay hints: after each `param(…)` call, the parameter's type and range as `blocksmith
//! params` lists them (the declaration checked and listed by the bindings' own code).

use lsp_types::{InlayHint, InlayHintKind, InlayHintLabel};

use crate::navigate::params;
use crate::text::Lines;
use crate::Analyzer;

/// The hints of `text` whose calls end inside `range` (every one for `None`).
#[must_use]
pub fn hints(a: &Analyzer, text: &str, range: Option<lsp_types::Range>) -> Vec<InlayHint> {
    let lines = Lines::new(text);
    let mut out = Vec::new();
    for (_, span) in params(text) {
        let end = lines.position(span.end);
        if range.is_some_and(|r| end < r.start || end > r.end) {
            continue;
        }
        let Some(label) = label(a, &text[span.clone()]) else { continue };
        out.push(InlayHint {
            position: end,
            label: InlayHintLabel::String(label),
            kind: Some(InlayHintKind::TYPE),
            text_edits: None,
            tooltip: None,
            padding_left: Some(true),
            padding_right: None,
            data: None,
        });
    }
    out
}

/// `: int, 1 to 12, step 1` for a `param(…)` call's text whose arguments are literals.
fn label(a: &Analyzer, call: &str) -> Option<String> {
    let ast = a.engine.compile_expression(call).ok()?;
    let call = match ast.statements().first()? {
        rhai::Stmt::FnCall(call, _) => call,
        rhai::Stmt::Expr(e) => match &**e {
            rhai::Expr::FnCall(call, _) => call,
            _ => return None,
        },
        _ => return None,
    };
    let (Some(rhai::Expr::StringConstant(name, _)), Some(default)) = (call.args.first(), call.args.get(1)) else {
        return None;
    };
    let default = default.get_literal_value(None)?;
    let options = match call.args.get(2) {
        None => rhai::Map::new(),
        Some(e) => e.get_literal_value(None)?.try_cast::<rhai::Map>()?,
    };
    let (_, spec) = blocksmith_script::params::Declared::new(name, default, options).ok()?.resolve(None).ok()?;
    // The listing's row: name, type, default, range, doc.
    let table = blocksmith_script::params::listing::to_text(&[spec]);
    let row = table.lines().nth(1)?;
    let header = table.lines().next()?;
    let column = |title: &str| header.find(title);
    let (t, d, r, doc) = (column("type")?, column("default")?, column("range")?, column("doc")?);
    let kind = row.get(t..d)?.trim();
    let range = row.get(r..doc.min(row.len())).map(str::trim).unwrap_or_default();
    Some(if range.is_empty() { format!(": {kind}") } else { format!(": {kind}, {range}") })
}
