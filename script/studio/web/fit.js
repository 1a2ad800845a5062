// Fits for the measure tool, in plain numbers (arrays [x, y, z], no three.js): a least-squares
// plane through points, and a circle through points that lie near a plane.
//
// The circle is fitted in two steps: the plane that minimises the sum of squared distances to
// the points (through their centroid, normal along the covariance matrix's eigenvector of the
// least eigenvalue, found by Jacobi rotations), then, in that plane, the algebraic circle fit of
// Kåsa: minimise Σ (x² + y² + D x + E y + F)², a linear least-squares problem in D, E, F, whose
// circle has centre (−D/2, −E/2) and radius √(D²/4 + E²/4 − F).
//   I. Kåsa, "A circle fitting procedure and its error analysis", IEEE Transactions on
//   Instrumentation and Measurement IM-25 (1), 1976, pp. 8–14.
// Kåsa's fit is exact for points on a circle and close for a full ring; on a short arc with
// noise it is biased towards small circles (see Chernov, "Circular and linear regression", 2010).

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const scale = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
const unit = (a) => scale(a, 1 / Math.hypot(...a));

// The eigenvalues and eigenvectors of the symmetric 3 × 3 matrix `m` (rows), by cyclic Jacobi
// rotations: { values: [λ0, λ1, λ2], vectors: [v0, v1, v2] } (unit vectors, unsorted).
export function symmetricEigen(m) {
  const a = m.map((row) => row.slice());
  const v = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]; // columns are the eigenvectors
  for (let sweep = 0; sweep < 50; sweep++) {
    const off = a[0][1] ** 2 + a[0][2] ** 2 + a[1][2] ** 2;
    const diag = a[0][0] ** 2 + a[1][1] ** 2 + a[2][2] ** 2;
    if (off <= 1e-30 * diag || off === 0) break;
    for (const [p, q] of [[0, 1], [0, 2], [1, 2]]) {
      if (a[p][q] === 0) continue;
      // The rotation that zeroes a[p][q] (Golub & Van Loan, Matrix Computations, § 8.5.2).
      const theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
      const t = Math.sign(theta || 1) / (Math.abs(theta) + Math.sqrt(theta * theta + 1));
      const c = 1 / Math.sqrt(t * t + 1), s = t * c;
      for (let k = 0; k < 3; k++) {
        const akp = a[k][p], akq = a[k][q];
        a[k][p] = c * akp - s * akq;
        a[k][q] = s * akp + c * akq;
      }
      for (let k = 0; k < 3; k++) {
        const apk = a[p][k], aqk = a[q][k];
        a[p][k] = c * apk - s * aqk;
        a[q][k] = s * apk + c * aqk;
      }
      for (let k = 0; k < 3; k++) {
        const vkp = v[k][p], vkq = v[k][q];
        v[k][p] = c * vkp - s * vkq;
        v[k][q] = s * vkp + c * vkq;
      }
    }
  }
  return { values: [a[0][0], a[1][1], a[2][2]], vectors: [0, 1, 2].map((j) => [v[0][j], v[1][j], v[2][j]]) };
}

// The least-squares plane through `points` (at least 3, not all on a line): { centroid, normal }
// (unit; its sign makes its largest component positive), or null.
export function fitPlane(points) {
  if (points.length < 3) return null;
  const n = points.length;
  const centroid = scale(points.reduce((s, p) => [s[0] + p[0], s[1] + p[1], s[2] + p[2]], [0, 0, 0]), 1 / n);
  const m = [[0, 0, 0], [0, 0, 0], [0, 0, 0]];
  for (const p of points) {
    const d = sub(p, centroid);
    for (let i = 0; i < 3; i++) for (let j = 0; j < 3; j++) m[i][j] += d[i] * d[j];
  }
  const { values, vectors } = symmetricEigen(m);
  const order = [0, 1, 2].sort((i, j) => values[i] - values[j]);
  // On a line, the two least eigenvalues are both ~0: no plane.
  if (values[order[1]] <= 1e-24 * Math.max(values[order[2]], 1e-300)) return null;
  let normal = unit(vectors[order[0]]);
  const big = normal.reduce((k, x, i) => (Math.abs(x) > Math.abs(normal[k]) ? i : k), 0);
  if (normal[big] < 0) normal = scale(normal, -1);
  return { centroid, normal };
}

// The solution of the 3 × 3 linear system m x = b (rows), by Cramer's rule; null when singular.
function solve3(m, b) {
  const det = (r) => r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1])
    - r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) + r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
  const d = det(m);
  if (!Number.isFinite(d) || Math.abs(d) < 1e-300) return null;
  return [0, 1, 2].map((c) => det(m.map((row, i) => row.map((x, j) => (j === c ? b[i] : x)))) / d);
}

// The circle through `points` (at least 3, not on a line): { centre, radius, normal, residual }
// (kernel frame; `residual`: the largest |distance from the centre − radius| over the points,
// measured in 3D, so it includes how far they are off the plane), or null.
export function fitCircle(points) {
  const plane = fitPlane(points);
  if (!plane) return null;
  const { centroid, normal } = plane;
  // An orthonormal basis (u, v) of the plane.
  const helper = Math.abs(normal[0]) < 0.9 ? [1, 0, 0] : [0, 1, 0];
  const u = unit(cross(normal, helper));
  const v = cross(normal, u);
  // Kåsa's normal equations in the plane's coordinates (x, y), relative to the centroid so the
  // sums stay well scaled.
  let sxx = 0, sxy = 0, syy = 0, sx = 0, sy = 0, sxz = 0, syz = 0, sz = 0;
  for (const p of points) {
    const d = sub(p, centroid);
    const x = dot(d, u), y = dot(d, v), z = x * x + y * y;
    sxx += x * x; sxy += x * y; syy += y * y; sx += x; sy += y;
    sxz += x * z; syz += y * z; sz += z;
  }
  const n = points.length;
  const def = solve3([[sxx, sxy, sx], [sxy, syy, sy], [sx, sy, n]], [-sxz, -syz, -sz]);
  if (!def) return null;
  const [D, E, F] = def;
  const cx = -D / 2, cy = -E / 2;
  const r2 = cx * cx + cy * cy - F;
  if (!(r2 > 0)) return null;
  const radius = Math.sqrt(r2);
  const centre = [0, 1, 2].map((k) => centroid[k] + cx * u[k] + cy * v[k]);
  const residual = Math.max(...points.map((p) => Math.abs(Math.hypot(...sub(p, centre)) - radius)));
  return { centre, radius, normal, residual };
}

// The area and unit normal of triangles given as x, y, z of each corner (9 numbers a
// triangle): the sum of their areas and the direction of the sum of their area vectors
// (null normal when that sum is zero).
export function areaAndNormal(corners) {
  let area = 0;
  let sum = [0, 0, 0];
  for (let i = 0; i + 8 < corners.length; i += 9) {
    const a = corners.slice(i, i + 3), b = corners.slice(i + 3, i + 6), c = corners.slice(i + 6, i + 9);
    const w = cross(sub(b, a), sub(c, a));
    area += Math.hypot(...w) / 2;
    sum = [sum[0] + w[0], sum[1] + w[1], sum[2] + w[2]];
  }
  const length = Math.hypot(...sum);
  return { area, normal: length > 0 ? scale(sum, 1 / length) : null };
}
