// The measure tool: while it is on, a click on the view measures instead of picking. Each click
// snaps to the nearest vertex within SNAP_PIXELS of the pointer, else to the nearest point of a
// drawn edge within SNAP_PIXELS, else takes the point of the surface under it; hidden vertices
// and edges (behind the model) are never snapped to. Two clicks: their distance and deltas, and
// a line between them. A click on a face: that face's area and normal (the face is the clicked
// polygon, whose triangles the server sends with a pick; the clicked triangle when it cannot).
// Shift-clicks build a ring of points; `fitCircle` fits a circle through them (fit.js).
// `assert` is the `assert_near(...)` line of a `blocksmith test` script that checks the last
// distance or circle. All points are in the kernel's frame (+Z up), as the page draws them.

import * as THREE from 'three';
import { areaAndNormal, fitCircle } from './fit.js';

// How near the pointer (CSS pixels) a vertex or an edge must be to be snapped to.
export const SNAP_PIXELS = 8;
// Two triangles sharing an edge at an angle below this (degrees) are one flat surface: the edge
// between them is a diagonal of a polygon, not an edge to snap to.
export const FLAT_ANGLE = 0.5;

// The shortest decimal that rounds to the same 32-bit float as `x`: the drawn meshes hold f32
// positions, so a vertex read back from them shows as the recipe wrote it (1, not 0.99999994;
// 0.3, not 0.30000001192092896).
export function fromF32(x) {
  const f = Math.fround(x);
  if (f === 0) return 0;
  for (let digits = 1; digits < 9; digits++) {
    const y = Number(f.toPrecision(digits));
    if (Math.fround(y) === f) return y;
  }
  return f;
}

// `x` as a Rhai number literal (`float`: with a point when it is whole).
function literal(x, float = false) {
  const s = String(Object.is(x, -0) ? 0 : x);
  return float && /^-?\d+$/.test(s) ? `${s}.0` : s;
}

// The tolerance of an assert on values of size `scale` known within `error`: a power of ten, a
// millionth of the scale's order of magnitude (1e-6 up to 10, 1e-5 up to 100, ...), or more
// when twice the error is more; as a literal (`1e-6`).
function tolerance(error, scale) {
  const floor = Math.floor(Math.log10(Math.max(1, scale))) - 6;
  const k = error > 0 ? Math.max(floor, Math.ceil(Math.log10(2 * error) - 1e-9)) : floor;
  return `1e${k}`;
}

// `x` rounded to the grid of step 10^k, k chosen so `scale` has about 7 significant digits.
function rounded(x, scale) {
  const k = Math.floor(Math.log10(Math.max(scale, 1e-300))) - 6;
  const step = 10 ** k;
  return k < 0 ? Number((Math.round(x / step) * step).toFixed(-k)) : Math.round(x / step) * step;
}

const distance = (a, b) => Math.hypot(b[0] - a[0], b[1] - a[1], b[2] - a[2]);

// The feature edges of `geometry` (per three.js geometry, computed once): pairs of vertex
// indices whose positions are an edge of one triangle only (a border) or of two triangles at
// FLAT_ANGLE or more. Vertices are matched by position, since `creased` splits them at sharp edges.
const edgesOf = new WeakMap();
function featureEdges(geometry) {
  let found = edgesOf.get(geometry);
  if (found) return found;
  const pos = geometry.attributes.position;
  const count = geometry.index ? geometry.index.count : pos.count;
  const corner = (i) => (geometry.index ? geometry.index.getX(i) : i);
  const ids = new Map(); // position → first vertex there
  const idOf = (v) => {
    const key = `${pos.getX(v)},${pos.getY(v)},${pos.getZ(v)}`;
    if (!ids.has(key)) ids.set(key, v);
    return ids.get(key);
  };
  const edges = new Map(); // "a,b" (a < b, first vertices) → unit normals of its triangles
  const a = new THREE.Vector3(), b = new THREE.Vector3(), c = new THREE.Vector3();
  for (let t = 0; t + 2 < count; t += 3) {
    const v = [corner(t), corner(t + 1), corner(t + 2)];
    a.fromBufferAttribute(pos, v[0]);
    b.fromBufferAttribute(pos, v[1]).sub(a);
    c.fromBufferAttribute(pos, v[2]).sub(a);
    const n = b.cross(c);
    if (n.lengthSq() === 0) continue; // a sliver: no direction to compare
    n.normalize();
    const id = v.map(idOf);
    for (let k = 0; k < 3; k++) {
      const p = id[k], q = id[(k + 1) % 3];
      const key = p < q ? `${p},${q}` : `${q},${p}`;
      if (!edges.has(key)) edges.set(key, []);
      edges.get(key).push(n.clone());
    }
  }
  const cos = Math.cos(THREE.MathUtils.degToRad(FLAT_ANGLE));
  const pairs = [];
  for (const [key, normals] of edges) {
    if (normals.length === 2 && normals[0].dot(normals[1]) >= cos) continue;
    pairs.push(...key.split(',').map(Number));
  }
  found = Uint32Array.from(pairs);
  edgesOf.set(geometry, found);
  return found;
}

export class Measure {
  // `viewer`: the page's Viewer; `pickFace(hit)`: resolves to the triangles (x, y, z of each
  // corner, kernel frame) of the polygon under a ray hit, or null.
  constructor(viewer, pickFace) {
    this.viewer = viewer;
    this.pickFace = pickFace;
    this.on = false;
    this.raycaster = new THREE.Raycaster();
    this.marks = new THREE.Group(); // kernel frame, drawn over the model
    this.marks.renderOrder = 3;
    viewer.scene.add(this.marks);
    this.pointMaterial = new THREE.PointsMaterial({ color: 0xd0006f, size: 8, sizeAttenuation: false, depthTest: false });
    this.ringMaterial = new THREE.PointsMaterial({ color: 0x0070c0, size: 7, sizeAttenuation: false, depthTest: false });
    this.lineMaterial = new THREE.LineBasicMaterial({ color: 0xd0006f, depthTest: false });
    this.circleMaterial = new THREE.LineBasicMaterial({ color: 0x0070c0, depthTest: false });
    this.clear();
  }

  // Forgets every point and result.
  clear() {
    // What tests read (`studio.measure`): points [{point, kind}], distance, deltas [dx, dy, dz],
    // face {area, normal, triangles, polygon}, ring [[x, y, z]], circle {centre, radius, normal,
    // residual}, assert (text).
    this.state = { points: [], distance: null, deltas: null, area: null, normal: null, face: null, ring: [], circle: null, assert: null };
    this.draw();
  }

  // The visible layers' roots.
  roots() {
    return this.viewer.models.children.filter((o) => o.visible);
  }

  // Sets the raycaster through canvas point (x, y), CSS pixels of the page.
  aim(x, y) {
    const rect = this.viewer.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2(((x - rect.left) / rect.width) * 2 - 1, -((y - rect.top) / rect.height) * 2 + 1);
    this.raycaster.setFromCamera(ndc, this.viewer.camera);
  }

  // Whether world point `p` is seen from the camera: the first surface on the ray to it is
  // not nearer than it (by a millionth of the way, for the surfaces `p` lies on).
  seen(p) {
    const eye = this.viewer.camera.getWorldPosition(new THREE.Vector3());
    const to = p.clone().sub(eye);
    const far = to.length();
    this.raycaster.set(eye, to.divideScalar(far));
    const hit = this.raycaster.intersectObjects(this.roots(), true)[0];
    return !hit || hit.distance >= far * (1 - 1e-6) - 1e-9;
  }

  // The point a click at canvas point (x, y) measures: { point: [x, y, z] (kernel frame, at f32
  // precision), kind: 'vertex' | 'edge' | 'face', hit (the surface under the pointer, or null) },
  // or null where there is nothing to measure.
  snap(x, y) {
    const camera = this.viewer.camera;
    camera.updateMatrixWorld();
    this.aim(x, y);
    const hit = this.raycaster.intersectObjects(this.roots(), true)[0] ?? null;
    const ray = this.raycaster.ray.clone();
    const px = (p) => {
      const [sx, sy] = this.viewer.screenOf(p.toArray());
      return Math.hypot(sx - x, sy - y);
    };
    const meshes = [];
    for (const root of this.roots()) root.traverseVisible((o) => { if (o.isMesh) meshes.push(o); });
    // Vertices near the pointer, nearest first; the first one seen.
    const near = [];
    const v = new THREE.Vector3();
    for (const mesh of meshes) {
      const count = mesh.geometry.attributes.position.count;
      for (let i = 0; i < count; i++) {
        mesh.getVertexPosition(i, v).applyMatrix4(mesh.matrixWorld);
        const d = px(v);
        if (d <= SNAP_PIXELS) near.push([d, v.clone()]);
      }
    }
    near.sort((a, b) => a[0] - b[0]);
    const vertex = near.find(([, p]) => this.seen(p));
    if (vertex) return { point: vertex[1].toArray().map(fromF32), kind: 'vertex', hit };
    // Points of feature edges nearest the pointer's ray, then as for vertices.
    const along = [];
    const a = new THREE.Vector3(), b = new THREE.Vector3(), onEdge = new THREE.Vector3();
    for (const mesh of meshes) {
      const pairs = featureEdges(mesh.geometry);
      for (let k = 0; k < pairs.length; k += 2) {
        mesh.getVertexPosition(pairs[k], a).applyMatrix4(mesh.matrixWorld);
        mesh.getVertexPosition(pairs[k + 1], b).applyMatrix4(mesh.matrixWorld);
        ray.distanceSqToSegment(a, b, null, onEdge);
        const d = px(onEdge);
        if (d <= SNAP_PIXELS) along.push([d, onEdge.clone()]);
      }
    }
    along.sort((p, q) => p[0] - q[0]);
    const edge = along.find(([, p]) => this.seen(p));
    if (edge) return { point: edge[1].toArray().map(fromF32), kind: 'edge', hit };
    if (hit) return { point: hit.point.toArray().map(fromF32), kind: 'face', hit };
    return null;
  }

  // A click at canvas point (x, y); `ring`: a shift-click, which adds the point to the ring.
  // Resolves to the state once the click's results (a face's area) are in.
  async click(x, y, ring) {
    const s = this.snap(x, y);
    if (!s) return this.state;
    const state = this.state;
    if (ring) {
      state.ring.push(s.point);
      state.circle = null;
      this.draw();
      return state;
    }
    if (state.points.length >= 2) state.points = [];
    state.points.push({ point: s.point, kind: s.kind });
    if (state.points.length === 2) {
      const [p, q] = state.points.map((m) => m.point);
      state.deltas = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
      state.distance = distance(p, q);
      const scale = Math.max(1, ...p.map(Math.abs), ...q.map(Math.abs));
      state.assert = `assert_near(distance(vec3(${p.map((c) => literal(c)).join(', ')}), vec3(${q.map((c) => literal(c)).join(', ')})), `
        + `${literal(state.distance, true)}, ${tolerance(0, scale)});`;
    } else {
      state.distance = null;
      state.deltas = null;
    }
    this.draw();
    if (s.hit) await this.measureFace(s.hit);
    this.draw();
    return state;
  }

  // The area and normal of the face under `hit`: its polygon's triangles from the server, or
  // else the hit triangle's own corners.
  async measureFace(hit) {
    let corners = null;
    let polygon = true;
    try {
      corners = await this.pickFace(hit);
    } catch {
      corners = null;
    }
    if (!corners || corners.length === 0) {
      polygon = false;
      const mesh = hit.object, v = new THREE.Vector3();
      corners = [hit.face.a, hit.face.b, hit.face.c].flatMap((i) => mesh.getVertexPosition(i, v).applyMatrix4(mesh.matrixWorld).toArray());
    }
    const { area, normal } = areaAndNormal(corners);
    Object.assign(this.state, { area, normal, face: { triangles: corners.length / 9, polygon } });
  }

  // Fits a circle through the ring (at least 3 points); the state's circle, or null.
  fitCircle() {
    const state = this.state;
    const circle = state.ring.length >= 3 ? fitCircle(state.ring) : null;
    state.circle = circle;
    if (circle) {
      // The line checks the distance from the (rounded) centre to the ring's first point, within
      // how far the ring is off the circle (and no closer than a millionth of its size).
      const scale = Math.max(circle.radius, ...circle.centre.map(Math.abs));
      const centre = circle.centre.map((c) => rounded(c, scale));
      const radius = rounded(circle.radius, scale);
      const off = Math.max(...state.ring.map((p) => Math.abs(distance(centre, p) - radius)));
      const first = state.ring[0];
      state.assert = `assert_near(distance(vec3(${centre.map((c) => literal(c)).join(', ')}), vec3(${first.map((c) => literal(c)).join(', ')})), `
        + `${literal(radius, true)}, ${tolerance(off, scale)});`;
    }
    this.draw();
    return circle;
  }

  // Draws the points, the line between a pair, the ring and its circle.
  draw() {
    this.marks.clear();
    const state = this.state;
    const points = (list, material) => {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.Float32BufferAttribute(list.flat(), 3));
      this.marks.add(new THREE.Points(g, material));
    };
    if (state.points.length) points(state.points.map((m) => m.point), this.pointMaterial);
    if (state.points.length === 2) {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.Float32BufferAttribute(state.points.flatMap((m) => m.point), 3));
      this.marks.add(new THREE.Line(g, this.lineMaterial));
    }
    if (state.ring.length) points(state.ring, this.ringMaterial);
    if (state.circle) {
      const { centre, radius, normal } = state.circle;
      const n = new THREE.Vector3(...normal);
      const u = new THREE.Vector3(1, 0, 0).cross(n);
      if (u.lengthSq() < 1e-6) u.set(0, 1, 0).cross(n);
      u.normalize();
      const w = n.clone().cross(u);
      const loop = [];
      for (let i = 0; i < 96; i++) {
        const t = (2 * Math.PI * i) / 96;
        loop.push(...[0, 1, 2].map((k) => centre[k] + radius * (Math.cos(t) * u.getComponent(k) + Math.sin(t) * w.getComponent(k))));
      }
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.Float32BufferAttribute(loop, 3));
      this.marks.add(new THREE.LineLoop(g, this.circleMaterial));
    }
    this.marks.children.forEach((o) => { o.renderOrder = 3; });
    this.viewer.requestRender();
  }
}
