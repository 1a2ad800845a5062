//! Open pieces of outline joined end to end into closed contours.

use crate::profile::Vec2;

/// Open pieces chained end to end into closed contours (ends within `tol` join); pieces that do
/// not close are dropped. Ends are found through a grid of cells of side `tol` (the 3×3 cells
/// about an end hold every end within `tol`), so chaining is linear in the pieces.
pub(super) fn chain(pieces: Vec<Vec<Vec2>>, tol: f64) -> Vec<Vec<Vec2>> {
    use std::collections::HashMap;
    let cell = |p: Vec2| ((p.x / tol).floor() as i64, (p.y / tol).floor() as i64);
    // Cell → (piece, whether it is the piece's last point).
    let mut ends: HashMap<(i64, i64), Vec<(usize, bool)>> = HashMap::new();
    for (k, p) in pieces.iter().enumerate() {
        ends.entry(cell(p[0])).or_default().push((k, false));
        ends.entry(cell(p[p.len() - 1])).or_default().push((k, true));
    }
    let mut used = vec![false; pieces.len()];
    let find = |at: Vec2, used: &[bool], ends: &HashMap<(i64, i64), Vec<(usize, bool)>>| {
        let (cx, cy) = cell(at);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for &(k, last) in ends.get(&(cx + dx, cy + dy)).into_iter().flatten() {
                    let p = &pieces[k];
                    let q = if last { p[p.len() - 1] } else { p[0] };
                    if !used[k] && q.distance(at) <= tol {
                        return Some((k, last));
                    }
                }
            }
        }
        None
    };
    let mut out = Vec::new();
    for first in 0..pieces.len() {
        if used[first] {
            continue;
        }
        used[first] = true;
        let mut cur = pieces[first].clone();
        loop {
            let (start, end) = (cur[0], cur[cur.len() - 1]);
            if cur.len() > 2 && start.distance(end) <= tol {
                cur.pop();
                out.push(cur);
                break;
            }
            let Some((k, last)) = find(end, &used, &ends) else { break };
            used[k] = true;
            if last {
                cur.extend(pieces[k].iter().rev().skip(1));
            } else {
                cur.extend_from_slice(&pieces[k][1..]);
            }
        }
    }
    out
}
