//! A recipe's parameters listed, as `blocksmith params` prints them: a text table or JSON.

use std::fmt::Write as _;

use serde_json::{json, Value};

use super::spec::{ParamKind, ParamSpec};
use crate::record::ParamCheck;

/// How `blocksmith params` prints.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ListFormat {
    /// An aligned table ([`to_text`]).
    #[default]
    Text,
    /// JSON ([`to_json`]).
    Json,
}

/// The parameters as an aligned table, one line each after a header: name, type, default,
/// range (`from 1 to 12, step 1`, or the choices) and doc. Empty for no parameters.
#[must_use]
pub fn to_text(params: &[ParamSpec]) -> String {
    if params.is_empty() {
        return String::new();
    }
    let rows: Vec<[String; 5]> = params
        .iter()
        .map(|p| {
            [
                p.name.clone(),
                p.kind.name().to_string(),
                p.default.to_string(),
                range(p),
                p.doc.clone().unwrap_or_default(),
            ]
        })
        .collect();
    let header = ["name", "type", "default", "range", "doc"].map(String::from);
    let mut widths = [0usize; 5];
    for row in std::iter::once(&header).chain(&rows) {
        for (w, cell) in widths.iter_mut().zip(row) {
            *w = (*w).max(cell.chars().count());
        }
    }
    let mut out = String::new();
    for row in std::iter::once(&header).chain(&rows) {
        let mut line = String::from("  ");
        for (i, cell) in row.iter().enumerate() {
            let _ = write!(line, "{cell:<w$}  ", w = widths[i]);
        }
        out.push_str(line.trim_end());
        out.push('\n');
    }
    out
}

/// The listing as JSON: `{"params": [...], "checks": [...]}`, each parameter as
/// [`ParamSpec::to_json`], each `param_check` the run reached as `{message, passed, line}`.
#[must_use]
pub fn to_json(params: &[ParamSpec], checks: &[ParamCheck]) -> Value {
    json!({
        "params": params.iter().map(ParamSpec::to_json).collect::<Vec<_>>(),
        "checks": checks
            .iter()
            .map(|c| json!({ "message": c.message, "passed": c.passed, "line": c.line }))
            .collect::<Vec<_>>(),
    })
}

/// The range column: the choices, or the bounds and step.
fn range(p: &ParamSpec) -> String {
    if p.kind == ParamKind::Choice {
        return p.choices.iter().map(Value::to_string).collect::<Vec<_>>().join(" | ");
    }
    let bounds = match (p.min, p.max) {
        (Some(lo), Some(hi)) => format!("{lo} to {hi}"),
        (Some(lo), None) => format!(">= {lo}"),
        (None, Some(hi)) => format!("<= {hi}"),
        (None, None) => String::new(),
    };
    match (bounds.is_empty(), p.step) {
        (_, None) => bounds,
        (true, Some(s)) => format!("step {s}"),
        (false, Some(s)) => format!("{bounds}, step {s}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(name: &str, kind: ParamKind, default: Value) -> ParamSpec {
        ParamSpec {
            name: name.into(),
            kind,
            value: default.clone(),
            default,
            set: false,
            min: None,
            max: None,
            step: None,
            choices: vec![],
            doc: None,
        }
    }

    #[test]
    fn the_table_aligns_name_type_default_range_and_doc() {
        let teeth = ParamSpec {
            min: Some(6.0),
            max: Some(40.0),
            step: Some(1.0),
            doc: Some("number of teeth".into()),
            ..spec("teeth", ParamKind::Int, json!(12))
        };
        let wood =
            ParamSpec { choices: vec![json!("oak"), json!("pine")], ..spec("wood", ParamKind::Choice, json!("oak")) };
        let text = to_text(&[teeth, wood, spec("r", ParamKind::Float, json!(1.5))]);
        let expected = "  name   type    default  range            doc\n\
                        \x20 teeth  int     12       6 to 40, step 1  number of teeth\n\
                        \x20 wood   choice  \"oak\"    \"oak\" | \"pine\"\n\
                        \x20 r      float   1.5\n";
        assert_eq!(text, expected);
        assert_eq!(to_text(&[]), "");
    }

    #[test]
    fn json_lists_every_declared_field() {
        let p = ParamSpec { min: Some(0.0), doc: Some("d".into()), ..spec("r", ParamKind::Float, json!(1.5)) };
        assert_eq!(
            to_json(&[p], &[ParamCheck { message: "r < 2".into(), passed: false, line: 3 }]),
            json!({
                "params": [{"name": "r", "kind": "float", "default": 1.5, "value": 1.5, "set": false, "min": 0.0, "doc": "d"}],
                "checks": [{"message": "r < 2", "passed": false, "line": 3}],
            })
        );
    }
}
