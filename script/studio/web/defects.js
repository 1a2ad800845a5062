// The defects view: where a model is broken, drawn over it from `GET /model/V/I.defects`
// (the kernel's `defects()`, in the kernel's frame): open boundaries as red lines, a loop
// around each handle (tunnel) in magenta, edges and vertices where sheets touch in amber,
// self-crossing faces in a warning colour, degenerate faces as points; and the components, one
// checkbox each, drawn one by one from `GET /model/V/I.faces?component=K` in place of the model
// so each can be hidden. `state` tells tests what is drawn.

import * as THREE from 'three';

const STYLE = {
  boundaries: { color: 0xe01010, label: 'open boundary' },
  handles: { color: 0xc000d0, label: 'handle loop' },
  non_manifold_edges: { color: 0xe0a000, label: 'edge where sheets touch' },
};

export class Defects {
  // `viewer`: the 3D view; `fetchLayer(version, layer, suffix)`: a layer's resource (ok or null).
  constructor(viewer, fetchLayer) {
    this.viewer = viewer;
    this.fetchLayer = fetchLayer;
    this.group = new THREE.Group();
    viewer.scene.add(this.group);
    this.crossingMaterial = new THREE.MeshBasicMaterial({
      color: 0xff2a00, transparent: true, opacity: 0.8, side: THREE.DoubleSide, depthTest: false,
    });
    this.componentMaterial = new THREE.MeshStandardMaterial({ color: 0x8fa6c8, roughness: 0.6, side: THREE.DoubleSide });
    this.state = Defects.empty();
    this.shownFor = null;
  }

  // What is drawn: nothing.
  static empty() {
    return { on: false, loaded: false, counts: {}, crossings: 0, points: 0, components: [] };
  }

  // Draws the defects of every layer of `model` (a model message), replacing what was drawn.
  async show(model) {
    this.clear();
    this.state.on = true;
    this.shownFor = model.version;
    const found = await Promise.all(model.layers.map(async (_, i) => {
      const answer = await this.fetchLayer(model.version, i, 'defects');
      return answer ? answer.json() : null;
    }));
    if (this.shownFor !== model.version || !this.state.on) return this.state;
    const counts = {};
    const components = [];
    for (const [i, d] of found.entries()) {
      if (!d) continue;
      for (const [k, n] of Object.entries(d.counts)) counts[k] = (counts[k] ?? 0) + n;
      for (const [key, style] of Object.entries(STYLE)) {
        if (!d[key].length) continue;
        const lines = this.lines(d[key], style.color);
        lines.name = key;
        this.group.add(lines);
      }
      if (d.crossings.length) {
        const g = new THREE.BufferGeometry();
        g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(d.crossings), 3));
        const m = new THREE.Mesh(g, this.crossingMaterial);
        m.name = 'crossings';
        m.renderOrder = 3;
        this.group.add(m);
        this.state.crossings += d.crossings.length / 9;
      }
      const points = [...d.non_manifold_vertices, ...d.degenerate_faces];
      if (points.length) {
        const g = new THREE.BufferGeometry();
        g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(points), 3));
        const p = new THREE.Points(g, new THREE.PointsMaterial({ color: 0xe0a000, size: 8, sizeAttenuation: false, depthTest: false }));
        p.renderOrder = 4;
        this.group.add(p);
        this.state.points += points.length / 3;
      }
      for (const c of d.components) components.push({ layer: i, ...c });
    }
    this.state.counts = counts;
    if (components.length > 1) await this.showComponents(model.version, components);
    this.state.loaded = true;
    this.viewer.requestRender();
    return this.state;
  }

  // Each component as its own mesh in place of the model, so each can be hidden.
  async showComponents(version, components) {
    const meshes = await Promise.all(components.map(async (c) => {
      const answer = await this.fetchLayer(version, c.layer, 'faces', { component: c.component });
      return answer ? new Float32Array(await answer.arrayBuffer()) : new Float32Array();
    }));
    if (this.shownFor !== version || !this.state.on) return;
    this.viewer.models.visible = false;
    this.state.components = components.map((c, k) => {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(meshes[k], 3));
      g.computeVertexNormals();
      const m = new THREE.Mesh(g, this.componentMaterial);
      m.name = `component ${k}`;
      this.group.add(m);
      return { ...c, triangles: meshes[k].length / 9, visible: true, mesh: m };
    });
  }

  // Shows or hides component `k` (as listed in `state.components`).
  setComponent(k, visible) {
    const c = this.state.components[k];
    if (!c) return;
    c.visible = visible;
    c.mesh.visible = visible;
    this.viewer.requestRender();
  }

  // The triangles of the visible components (the model's, with none listed).
  visibleTriangles() {
    if (!this.state.components.length) return null;
    return this.state.components.filter((c) => c.visible).reduce((n, c) => n + c.triangles, 0);
  }

  // The drawn segments' ends of one kind ('boundaries', 'handles', 'non_manifold_edges'), for tests.
  segments(key) {
    const lines = this.group.children.filter((o) => o.name === key);
    return lines.flatMap((l) => Array.from(l.geometry.attributes.position.array));
  }

  lines(ends, color) {
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(ends), 3));
    const lines = new THREE.LineSegments(g, new THREE.LineBasicMaterial({ color, depthTest: false, linewidth: 2 }));
    lines.renderOrder = 5;
    return lines;
  }

  clear() {
    this.group.clear();
    this.viewer.models.visible = true;
    this.shownFor = null;
    this.state = Defects.empty();
    this.viewer.requestRender();
  }
}

// What the panel lists for defects found: one line per kind, with its colour's name.
export function describe(counts) {
  const names = {
    component: 'components', boundary: 'open boundaries (red)', handle: 'handles (magenta loops)',
    self_intersection: 'crossing face pairs (red faces)', non_manifold_edge: 'touching edges (amber)',
    non_manifold_vertex: 'touching vertices (amber)', degenerate_face: 'degenerate faces (amber points)',
  };
  return Object.entries(counts).map(([k, n]) => [names[k] ?? k, String(n)]);
}
