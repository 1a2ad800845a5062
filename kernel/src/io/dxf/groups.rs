//! The file as group pairs, and one entity's groups: a group code on one line, its value on the
//! next (AutoCAD DXF Reference, "DXF Format"); an entity is a `0` group (its type) and the
//! groups after it up to the next `0`.

use std::path::Path;

use glam::DVec3;

use super::bad;
use crate::io::IoError;
use crate::profile::Vec2;

/// One group: its code, its value, and the 1-based line of the code.
pub(super) struct Group<'a> {
    pub code: i32,
    pub value: &'a str,
    pub line: usize,
}

/// The file's groups.
pub(super) fn groups<'a>(text: &'a str, path: &Path) -> Result<Vec<Group<'a>>, IoError> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::with_capacity(lines.len() / 2);
    let mut i = 0;
    while i < lines.len() {
        let code_text = lines[i].trim();
        if code_text.is_empty() && i + 1 == lines.len() {
            break;
        }
        let code: i32 =
            code_text.parse().map_err(|_| bad(path, i + 1, format!("group code `{code_text:.20}` is not a number")))?;
        let Some(value) = lines.get(i + 1) else {
            return Err(bad(path, i + 1, format!("group code {code} has no value line")));
        };
        out.push(Group { code, value: value.trim(), line: i + 1 });
        i += 2;
    }
    Ok(out)
}

/// An entity's groups (those after its `0` group, up to the next `0`).
pub(super) struct Entity<'a, 'g> {
    pub kind: &'a str,
    pub line: usize,
    pub groups: &'g [Group<'a>],
}

/// The file's entities in order (groups before the first `0` group belong to none).
pub(super) fn entities<'a, 'g>(groups: &'g [Group<'a>]) -> Vec<Entity<'a, 'g>> {
    let starts: Vec<usize> = (0..groups.len()).filter(|&i| groups[i].code == 0).collect();
    starts
        .iter()
        .enumerate()
        .map(|(k, &i)| {
            let end = starts.get(k + 1).copied().unwrap_or(groups.len());
            Entity { kind: groups[i].value, line: groups[i].line, groups: &groups[i + 1..end] }
        })
        .collect()
}

impl<'a> Entity<'a, '_> {
    /// The value of the first group `code`, as a number.
    pub fn number(&self, code: i32, path: &Path) -> Result<Option<f64>, IoError> {
        match self.groups.iter().find(|g| g.code == code) {
            None => Ok(None),
            Some(g) => parse(g, path).map(Some),
        }
    }

    /// The value of the first group `code`, as a number; an error naming the entity without it.
    pub fn required(&self, code: i32, path: &Path) -> Result<f64, IoError> {
        self.number(code, path)?.ok_or_else(|| bad(path, self.line, format!("{} has no group {code}", self.kind)))
    }

    /// The value of the first group `code` as a whole number, or `default`; an error when it is
    /// not a whole number.
    pub fn int(&self, code: i32, default: i64, path: &Path) -> Result<i64, IoError> {
        let Some(g) = self.groups.iter().find(|g| g.code == code) else { return Ok(default) };
        let v = parse(g, path)?;
        if v.fract() != 0.0 || v.abs() > 1e15 {
            return Err(bad(path, g.line + 1, format!("`{:.30}` is not a whole number", g.value)));
        }
        Ok(v as i64)
    }

    /// The flags (group 70), 0 when absent.
    pub fn flags(&self, path: &Path) -> Result<i64, IoError> {
        self.int(70, 0, path)
    }

    /// The value of the first group `code` as text.
    pub fn text(&self, code: i32) -> Option<&'a str> {
        self.groups.iter().find(|g| g.code == code).map(|g| g.value)
    }

    /// Every group `code`, as numbers, in order.
    pub fn all(&self, code: i32, path: &Path) -> Result<Vec<f64>, IoError> {
        self.groups.iter().filter(|g| g.code == code).map(|g| parse(g, path)).collect()
    }

    /// The point of groups `x`, `x + 10`, `x + 20` (z 0 when absent).
    pub fn point(&self, x: i32, path: &Path) -> Result<DVec3, IoError> {
        Ok(DVec3::new(self.required(x, path)?, self.required(x + 10, path)?, self.number(x + 20, path)?.unwrap_or(0.0)))
    }

    /// Repeated points of groups `x`, `x + 10` and optional `x + 20`, in order (a spline's
    /// control points are groups 10/20/30, its fit points 11/21/31).
    pub fn points(&self, x: i32, path: &Path) -> Result<Vec<DVec3>, IoError> {
        let mut out: Vec<DVec3> = Vec::new();
        let mut pending = None;
        for g in self.groups {
            if g.code == x {
                pending = Some(parse(g, path)?);
            } else if g.code == x + 10 {
                let Some(px) = pending.take() else {
                    return Err(bad(path, g.line, format!("a y ({}) without its x ({x})", x + 10)));
                };
                out.push(DVec3::new(px, parse(g, path)?, 0.0));
            } else if g.code == x + 20 {
                if let Some(last) = out.last_mut() {
                    last.z = parse(g, path)?;
                }
            }
        }
        Ok(out)
    }

    /// Vertices from repeated 10/20 groups with their bulges (42, after their vertex).
    pub fn vertices(&self, path: &Path) -> Result<Vec<(Vec2, f64)>, IoError> {
        let mut out: Vec<(Vec2, f64)> = Vec::new();
        let mut x = None;
        for g in self.groups {
            match g.code {
                10 => x = Some(parse(g, path)?),
                20 => {
                    let Some(px) = x.take() else { return Err(bad(path, g.line, "a y (20) without its x (10)")) };
                    out.push((Vec2::new(px, parse(g, path)?), 0.0));
                }
                42 => {
                    if let Some(last) = out.last_mut() {
                        last.1 = parse(g, path)?;
                    }
                }
                _ => {}
            }
        }
        Ok(out)
    }

    /// The extrusion direction (groups 210/220/230), +z when absent.
    pub fn extrusion(&self, path: &Path) -> Result<DVec3, IoError> {
        let n = DVec3::new(
            self.number(210, path)?.unwrap_or(0.0),
            self.number(220, path)?.unwrap_or(0.0),
            self.number(230, path)?.unwrap_or(1.0),
        );
        n.try_normalize().ok_or_else(|| bad(path, self.line, format!("{} has a zero extrusion direction", self.kind)))
    }
}

/// A group's value as a finite number.
pub(super) fn parse(g: &Group, path: &Path) -> Result<f64, IoError> {
    let v: f64 = g.value.parse().map_err(|_| bad(path, g.line + 1, format!("`{:.30}` is not a number", g.value)))?;
    if !v.is_finite() {
        return Err(bad(path, g.line + 1, format!("`{:.30}` is not a finite number", g.value)));
    }
    Ok(v)
}
