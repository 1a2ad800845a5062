//! Hover and signature help. Hover over a function, method, type or standard-library function
//! shows exactly what `blocksmith doc NAME` prints; over the recipe's own function or a local
//! module's, its signature and `///` comment; over a variable, its type when known. Signature
//! help lists the overloads of the call being typed (a method's without its receiver when the
//! receiver's type is known) with the argument under the cursor.

use std::path::Path;

use blocksmith_script::doc::{render_as, Format};
use lsp_types::{
    Documentation, Hover, HoverContents, MarkupContent, MarkupKind, ParameterInformation, ParameterLabel,
    SignatureHelp, SignatureInformation,
};

use crate::infer::{type_of_text, variables_in_text};
use crate::navigate::{functions, imports, module_file};
use crate::text::{enclosing_call, word_at, Lines};
use crate::Analyzer;

fn plain(text: String) -> Hover {
    Hover { contents: HoverContents::Markup(MarkupContent { kind: MarkupKind::PlainText, value: text }), range: None }
}

/// What `blocksmith doc NAME` prints for `name`, if it knows it.
#[must_use]
pub fn doc_text(a: &Analyzer, name: &str) -> Option<String> {
    render_as(&a.engine, Some(name), Format::Text).ok()
}

/// The hover at byte `offset` of `text`.
#[must_use]
pub fn hover(a: &Analyzer, text: &str, offset: usize, dir: Option<&Path>) -> Option<Hover> {
    let (start, word) = word_at(text, offset)?;
    let lines = Lines::new(text);
    let range = lsp_types::Range::new(lines.position(start), lines.position(start + word.len()));
    let mut found = hover_text(a, text, start, word, dir)?;
    found.range = Some(range);
    Some(found)
}

fn hover_text(a: &Analyzer, text: &str, start: usize, word: &str, dir: Option<&Path>) -> Option<Hover> {
    if let Some((alias, name)) = word.split_once("::") {
        let imp = imports(text).into_iter().find(|i| i.alias == alias)?;
        if let Some(Err(module)) = crate::diagnose::resolve_import(&imp.name, dir) {
            return doc_text(a, &format!("{module}::{name}")).map(plain);
        }
        let source = std::fs::read_to_string(module_file(&imp.name, dir)?).ok()?;
        let f = functions(&source).into_iter().find(|f| f.name == name)?;
        return Some(plain(format!("{}\n    {}\n", f.signature(Some(alias)), f.doc.replace('\n', "\n    "))));
    }
    if let Some(f) = functions(text).into_iter().find(|f| f.name == word) {
        return Some(plain(format!("{}\n    {}\n", f.signature(None), f.doc.replace('\n', "\n    "))));
    }
    let is_call = text[start + word.len()..].trim_start().starts_with('(');
    let is_member = text[..start].ends_with('.');
    if !is_call && !is_member {
        let vars = variables_in_text(&a.catalogue, &text[..start]);
        if let Some(t) = vars.get(word) {
            return Some(plain(format!("{word}: {t}")));
        }
    }
    doc_text(a, word).map(plain)
}

/// The signature help at byte `offset` of `text`.
#[must_use]
pub fn signature_help(a: &Analyzer, text: &str, offset: usize, dir: Option<&Path>) -> Option<SignatureHelp> {
    let (name, open, active) = enclosing_call(text, offset)?;
    let callee_start = open - name.len() - (text[..open].len() - text[..open].trim_end().len());
    let head = &text[..callee_start];
    let mut sigs: Vec<SignatureInformation> = Vec::new();
    if let Some(alias_path) = head.strip_suffix("::") {
        let alias = &alias_path[crate::text::ident_start(alias_path)..];
        let imp = imports(text).into_iter().find(|i| i.alias == alias)?;
        let source = std::fs::read_to_string(module_file(&imp.name, dir)?).ok()?;
        for f in functions(&source).into_iter().filter(|f| f.name == name) {
            sigs.push(signature(f.signature(Some(alias)), &f.params, &f.doc));
        }
    } else if let Some(f) = functions(text).into_iter().find(|f| f.name == name) {
        sigs.push(signature(f.signature(None), &f.params, &f.doc));
    } else {
        let receiver = head.strip_suffix('.').map(|r| {
            let vars = variables_in_text(&a.catalogue, head);
            type_of_text(&|v| vars.get(v).cloned(), &a.catalogue, r)
        });
        for o in a.catalogue.iter().filter(|o| o.name == name && o.property.is_none()) {
            let params: Vec<String> = match &receiver {
                Some(Some(t)) if o.params.first().is_some_and(|(_, pt)| pt == t) => {
                    o.params[1..].iter().map(|(n, t)| format!("{n}: {t}")).collect()
                }
                Some(Some(_)) => continue,
                Some(None) if !o.params.is_empty() => o.params[1..].iter().map(|(n, t)| format!("{n}: {t}")).collect(),
                _ => o.params.iter().map(|(n, t)| format!("{n}: {t}")).collect(),
            };
            let ret = if o.returns == "nothing" { String::new() } else { format!(" -> {}", o.returns) };
            let label = format!("{name}({}){ret}", params.join(", "));
            sigs.push(signature(label, &params, &o.doc));
        }
    }
    if sigs.is_empty() {
        return None;
    }
    // The first overload with enough parameters for the argument being typed.
    let best = sigs.iter().position(|s| s.parameters.as_ref().is_some_and(|p| p.len() > active)).unwrap_or(0);
    Some(SignatureHelp { signatures: sigs, active_signature: Some(best as u32), active_parameter: Some(active as u32) })
}

fn signature(label: String, params: &[String], doc: &str) -> SignatureInformation {
    SignatureInformation {
        label,
        documentation: (!doc.is_empty()).then(|| Documentation::String(doc.to_string())),
        parameters: Some(
            params
                .iter()
                .map(|p| ParameterInformation { label: ParameterLabel::Simple(p.clone()), documentation: None })
                .collect(),
        ),
        active_parameter: None,
    }
}
