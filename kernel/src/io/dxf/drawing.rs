//! What a DXF draws: the `ENTITIES` section and the `BLOCKS` its `INSERT`s place, as pieces of
//! outline in drawing coordinates.
//!
//! Each list of entities (the `ENTITIES` section, each block) is first turned into a [`Sheet`]:
//! its own curves as points in its coordinates, and its inserts. Before anything is placed, the
//! points the `ENTITIES` section expands to are counted, each block's count memoised (a block
//! placed a million times is counted once), and a drawing over [`MAX_POINTS`] or the memory
//! budget is refused, as is a block that places itself (directly or through others), blocks
//! nested deeper than [`MAX_DEPTH`], or a block that is an external reference (another file: a
//! loader reads only the file it was asked to read). An `INSERT` of a block the file does not
//! define draws nothing, as AutoCAD and ezdxf do.

use std::collections::HashMap;
use std::path::Path;

use glam::DAffine2;

use super::curves::{arc_points, ellipse, nurbs, ocs, polyline, through};
use super::groups::Entity;
use super::{bad, MAX_POINTS};
use crate::io::IoError;
use crate::profile::Vec2;

/// The deepest blocks may be nested in one another.
pub const MAX_DEPTH: usize = 256;

/// A run of outline: closed (a contour as it is) or open (to be chained end to end).
pub(super) struct Piece {
    pub closed: bool,
    pub points: Vec<Vec2>,
}

/// An `INSERT` (a `MINSERT` when its array is more than one): a block placed `columns × rows`
/// times.
struct Insert {
    block: String,
    line: usize,
    /// From the insert's own coordinates (origin at its point, x along its rotation) to the
    /// sheet's.
    place: DAffine2,
    scale: Vec2,
    columns: u64,
    rows: u64,
    step: Vec2,
}

impl Insert {
    fn count(&self) -> u64 {
        self.columns.saturating_mul(self.rows)
    }

    /// Each placement's map from the block's coordinates (`base` its base point) to the
    /// sheet's: the array steps are in the insert's rotated but unscaled frame.
    fn placements(&self, base: Vec2) -> impl Iterator<Item = DAffine2> + '_ {
        let local = DAffine2::from_scale(self.scale) * DAffine2::from_translation(-base);
        (0..self.rows).flat_map(move |r| {
            (0..self.columns).map(move |c| {
                self.place
                    * DAffine2::from_translation(Vec2::new(c as f64 * self.step.x, r as f64 * self.step.y))
                    * local
            })
        })
    }
}

/// What one list of entities draws in its own coordinates.
#[derive(Default)]
struct Sheet {
    pieces: Vec<Piece>,
    inserts: Vec<Insert>,
}

impl Sheet {
    fn own_points(&self) -> u64 {
        self.pieces.iter().map(|p| p.points.len() as u64).sum()
    }
}

/// A block definition: its base point (the point an insert puts at its own), what it draws,
/// and the file it refers to when it is an external reference.
struct Block {
    base: Vec2,
    sheet: Sheet,
    external: Option<String>,
}

/// Counts points as sheets are read, refusing a file over [`MAX_POINTS`] of its own.
struct Tally(u64);

impl Tally {
    fn add(&mut self, n: usize, path: &Path, line: usize) -> Result<(), IoError> {
        self.0 += n as u64;
        if self.0 > MAX_POINTS as u64 {
            return Err(bad(path, line, format!("the drawing has more than {MAX_POINTS} points")));
        }
        Ok(())
    }
}

/// A `POLYLINE` being read: whether it is closed, its map to the sheet, its vertices with
/// their bulges.
type OpenPolyline = (bool, DAffine2, Vec<(Vec2, f64)>);

/// The sheet of `entities` (one section's or block's, in order).
fn sheet(entities: &[Entity], tally: &mut Tally, path: &Path, model_only: bool) -> Result<Sheet, IoError> {
    let mut out = Sheet::default();
    let mut poly: Option<OpenPolyline> = None;
    for e in entities {
        // Paper space (group 67 = 1) holds title blocks and views of the model, not the model.
        if model_only && e.int(67, 0, path)? == 1 {
            continue;
        }
        let mut piece: Option<(bool, Vec<Vec2>)> = None;
        match e.kind {
            "LWPOLYLINE" => {
                let is_closed = e.flags(path)? & 1 == 1;
                let m = ocs(e.extrusion(path)?, e.number(38, path)?.unwrap_or(0.0));
                let pts = polyline(&e.vertices(path)?, is_closed);
                piece = Some((is_closed, pts.into_iter().map(|p| m.transform_point2(p)).collect()));
            }
            "POLYLINE" => {
                let flags = e.flags(path)?;
                // Polygon meshes (16) and polyface meshes (64) are surfaces, not outlines; a 3D
                // polyline (8) is in drawing coordinates.
                if flags & (16 | 64) == 0 {
                    let m = if flags & 8 == 8 {
                        DAffine2::IDENTITY
                    } else {
                        ocs(e.extrusion(path)?, e.number(30, path)?.unwrap_or(0.0))
                    };
                    poly = Some((flags & 1 == 1, m, Vec::new()));
                } else {
                    poly = None;
                }
            }
            "VERTEX" => {
                if let Some((_, _, vs)) = poly.as_mut() {
                    let p = Vec2::new(e.required(10, path)?, e.required(20, path)?);
                    vs.push((p, e.number(42, path)?.unwrap_or(0.0)));
                }
            }
            "SEQEND" => {
                if let Some((is_closed, m, vs)) = poly.take() {
                    let pts = polyline(&vs, is_closed);
                    piece = Some((is_closed, pts.into_iter().map(|p| m.transform_point2(p)).collect()));
                }
            }
            "LINE" => {
                let (a, b) = (e.point(10, path)?, e.point(11, path)?);
                piece = Some((false, vec![a.truncate(), b.truncate()]));
            }
            "ARC" | "CIRCLE" => {
                let centre = e.point(10, path)?;
                let r = e.required(40, path)?;
                if r > 0.0 {
                    let (a0, sweep) = if e.kind == "CIRCLE" {
                        (0.0, std::f64::consts::TAU)
                    } else {
                        let (a, b) = (e.required(50, path)?.to_radians(), e.required(51, path)?.to_radians());
                        let sweep = (b - a).rem_euclid(std::f64::consts::TAU);
                        (a, if sweep == 0.0 { std::f64::consts::TAU } else { sweep })
                    };
                    let c = centre.truncate();
                    let mut pts = vec![c + r * Vec2::new(a0.cos(), a0.sin())];
                    arc_points(c, r, a0, sweep, &mut pts);
                    let full = e.kind == "CIRCLE";
                    if full {
                        pts.pop();
                    }
                    let m = ocs(e.extrusion(path)?, centre.z);
                    piece = Some((full, pts.into_iter().map(|p| m.transform_point2(p)).collect()));
                }
            }
            "ELLIPSE" => {
                let (centre, major) = (e.point(10, path)?, e.point(11, path)?);
                let ratio = e.required(40, path)?;
                if !(ratio > 0.0 && ratio <= 1.0 + 1e-9) {
                    return Err(bad(path, e.line, format!("ELLIPSE has axis ratio {ratio}, not in (0, 1]")));
                }
                if major.length() > 0.0 {
                    let (t0, t1) =
                        (e.number(41, path)?.unwrap_or(0.0), e.number(42, path)?.unwrap_or(std::f64::consts::TAU));
                    piece = Some(ellipse(centre, major, e.extrusion(path)?, ratio, t0, t1));
                }
            }
            "SPLINE" => piece = Some(spline(e, path)?),
            "INSERT" => {
                let Some(name) = e.text(2) else { return Err(bad(path, e.line, "INSERT has no block name (group 2)")) };
                let at = Vec2::new(e.required(10, path)?, e.required(20, path)?);
                let columns = e.int(70, 1, path)?.max(1) as u64;
                let rows = e.int(71, 1, path)?.max(1) as u64;
                let rotation = e.number(50, path)?.unwrap_or(0.0).to_radians();
                let z = e.number(30, path)?.unwrap_or(0.0);
                out.inserts.push(Insert {
                    block: name.to_uppercase(),
                    line: e.line,
                    place: ocs(e.extrusion(path)?, z) * DAffine2::from_angle_translation(rotation, at),
                    scale: Vec2::new(e.number(41, path)?.unwrap_or(1.0), e.number(42, path)?.unwrap_or(1.0)),
                    columns,
                    rows,
                    step: Vec2::new(e.number(44, path)?.unwrap_or(0.0), e.number(45, path)?.unwrap_or(0.0)),
                });
            }
            _ => {}
        }
        if let Some((closed, points)) = piece {
            tally.add(points.len(), path, e.line)?;
            if points.len() >= 2 {
                out.pieces.push(Piece { closed, points });
            }
        }
    }
    Ok(out)
}

/// A `SPLINE`'s points: from its control points, knots and weights when it has control
/// points, else through its fit points; closed when flag 1 (closed) or 2 (periodic) is set.
fn spline(e: &Entity, path: &Path) -> Result<(bool, Vec<Vec2>), IoError> {
    let flags = e.flags(path)?;
    let closed = flags & 3 != 0;
    let control = e.points(10, path)?;
    let why = |reason: String| bad(path, e.line, format!("SPLINE cannot be drawn: {reason}"));
    let mut pts = if control.is_empty() {
        let fit: Vec<Vec2> = e.points(11, path)?.iter().map(|p| p.truncate()).collect();
        if fit.len() < 2 {
            return Err(why("it has neither control points (10/20) nor two fit points (11/21)".into()));
        }
        through(&fit, closed)
    } else {
        let degree = e.int(71, 3, path)?;
        if !(1..=32).contains(&degree) {
            return Err(why(format!("its degree is {degree}, not 1 to 32")));
        }
        nurbs(degree as usize, &e.all(40, path)?, &control, Some(&e.all(41, path)?)).map_err(why)?
    };
    if closed && pts.len() > 2 && pts[0].distance(pts[pts.len() - 1]) <= 1e-12 * (1.0 + pts[0].length()) {
        pts.pop();
    }
    Ok((closed, pts))
}

/// The pieces the file draws: its `ENTITIES` section with every insert placed (see the
/// [module documentation](self)).
pub(super) fn pieces(entities: &[Entity], path: &Path) -> Result<Vec<Piece>, IoError> {
    let mut tally = Tally(0);
    let mut blocks: HashMap<String, Block> = HashMap::new();
    let mut top: Vec<Entity> = Vec::new();
    let mut section = "";
    let mut i = 0;
    while i < entities.len() {
        let e = &entities[i];
        i += 1;
        match e.kind {
            "SECTION" => section = e.text(2).unwrap_or(""),
            "ENDSEC" => section = "",
            "BLOCK" if section == "BLOCKS" => {
                let start = i;
                while i < entities.len() && entities[i].kind != "ENDBLK" && entities[i].kind != "ENDSEC" {
                    i += 1;
                }
                let body = &entities[start..i];
                let flags = e.flags(path)?;
                let name = e.text(2).or(e.text(3)).unwrap_or("").to_uppercase();
                let external = (flags & 4 != 0).then(|| e.text(1).unwrap_or("").to_string());
                let base = Vec2::new(e.number(10, path)?.unwrap_or(0.0), e.number(20, path)?.unwrap_or(0.0));
                let sheet = if external.is_some() { Sheet::default() } else { sheet(body, &mut tally, path, false)? };
                blocks.insert(name, Block { base, sheet, external });
            }
            _ if section == "ENTITIES" => top.push(Entity { kind: e.kind, line: e.line, groups: e.groups }),
            _ => {}
        }
    }
    let top = sheet(&top, &mut tally, path, true)?;
    let mut counts = HashMap::new();
    let total = expanded(&top, &blocks, &mut counts, &mut Vec::new(), path)?;
    if total > MAX_POINTS as u64 {
        return Err(bad(
            path,
            0,
            format!("its blocks' inserts expand to {total} points and placements, more than the {MAX_POINTS} a drawing may have"),
        ));
    }
    crate::limits::check_growth(|| format!("the outlines {} draws", path.display()), total as f64 * 24.0)
        .map_err(|e| bad(path, 0, e.to_string()))?;
    let mut out = Vec::new();
    draw(&top, DAffine2::IDENTITY, &blocks, &mut out, path)?;
    Ok(out)
}

/// The points and placements `sheet` expands to (each insert's placements counted too, so
/// that placing an empty block a billion times is refused), each block's count memoised in
/// `counts`; `open` is the chain of blocks being counted, to find a block that places itself.
fn expanded(
    sheet: &Sheet,
    blocks: &HashMap<String, Block>,
    counts: &mut HashMap<String, u64>,
    open: &mut Vec<String>,
    path: &Path,
) -> Result<u64, IoError> {
    let mut total = sheet.own_points();
    for insert in &sheet.inserts {
        let Some(block) = blocks.get(&insert.block) else { continue };
        if let Some(file) = &block.external {
            return Err(bad(
                path,
                insert.line,
                format!(
                    "INSERT of block `{}`, an external reference to `{file}`: only this file is read",
                    insert.block
                ),
            ));
        }
        let each = match counts.get(&insert.block) {
            Some(&n) => n,
            None => {
                if open.contains(&insert.block) {
                    return Err(bad(
                        path,
                        insert.line,
                        format!("block `{}` places itself (through {})", insert.block, open.join(" → ")),
                    ));
                }
                if open.len() >= MAX_DEPTH {
                    return Err(bad(path, insert.line, format!("blocks are nested deeper than {MAX_DEPTH}")));
                }
                open.push(insert.block.clone());
                let n = expanded(&block.sheet, blocks, counts, open, path)?;
                open.pop();
                counts.insert(insert.block.clone(), n);
                n
            }
        };
        total = total.saturating_add(insert.count().saturating_mul(each.saturating_add(1)));
    }
    Ok(total)
}

/// Adds what `sheet` draws, mapped by `to`, to `out` (its expansion already counted and
/// bounded by [`expanded`]).
fn draw(
    sheet: &Sheet,
    to: DAffine2,
    blocks: &HashMap<String, Block>,
    out: &mut Vec<Piece>,
    path: &Path,
) -> Result<(), IoError> {
    for p in &sheet.pieces {
        out.push(Piece { closed: p.closed, points: p.points.iter().map(|&q| to.transform_point2(q)).collect() });
    }
    crate::limits::charge(sheet.pieces.len() as u64 + 1).map_err(|e| bad(path, 0, e.to_string()))?;
    for insert in &sheet.inserts {
        let Some(block) = blocks.get(&insert.block) else { continue };
        for placement in insert.placements(block.base) {
            draw(&block.sheet, to * placement, blocks, out, path)?;
        }
    }
    Ok(())
}
