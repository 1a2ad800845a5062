// The 3D view: three.js with the kernel's +Z up, a grid on the XY plane and axes, orbit / pan /
// zoom, fit to view on the first model (the whole bounding box in the frame; later models keep
// the camera), normals that follow the model's sharp edges (see `creased`), feature colours or a
// plain material, wireframe, the control mesh a surface was made from (lines over it), and the
// playback of a model's animation (the measure tool, measure.js, draws its marks in the same
// scene). It draws only when something changed (a model, the camera,
// a toggle, the size, a playing animation): an idle page costs nothing, and a new model is drawn
// once, not behind a queue of frames of the old one.

import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';

// The view keeps the kernel's +Z up. glTF is +Y up: the files the server sends are written with
// kernel (x, y, z) as glTF (x, z, -y), so each is turned a quarter about +X back to the kernel's.
THREE.Object3D.DEFAULT_UP.set(0, 0, 1);

// The colours of `blocksmith render` (script/src/studio/render.rs), linear RGB.
const BACKGROUND = [0.86, 0.87, 0.89];
const PLAIN = [0.55, 0.6, 0.68];

// Faces meeting at a vertex at more than this angle are shaded apart (a sharp edge); below it
// the shading is smooth across them. A box's faces are flat, a sphere's round.
export const SHARP_ANGLE = 40;

// `geometry` (indexed, as the .glb files are) with normals that follow its sharp edges: at
// each vertex, its faces are grouped by normal (a face joins the first group whose mean normal
// is within SHARP_ANGLE of its own), each group gets a vertex of its own with the group's
// area-weighted normal. A smooth mesh keeps its vertices; a box's corners become three each.
// Geometry with morph targets keeps its own normals (they move with the targets).
export function creased(geometry, angle = SHARP_ANGLE) {
  const index = geometry.index;
  const position = geometry.attributes.position;
  if (!index || Object.keys(geometry.morphAttributes).length) {
    if (!index) geometry.computeVertexNormals();
    return geometry;
  }
  const cos = Math.cos(THREE.MathUtils.degToRad(angle));
  const ids = index.array, faces = ids.length / 3, n = position.count;
  // Each face's area-weighted normal (twice the area).
  const fn = new Float32Array(faces * 3);
  const a = new THREE.Vector3(), b = new THREE.Vector3(), c = new THREE.Vector3();
  for (let f = 0; f < faces; f++) {
    a.fromBufferAttribute(position, ids[3 * f]);
    b.fromBufferAttribute(position, ids[3 * f + 1]).sub(a);
    c.fromBufferAttribute(position, ids[3 * f + 2]).sub(a);
    b.cross(c);
    fn[3 * f] = b.x; fn[3 * f + 1] = b.y; fn[3 * f + 2] = b.z;
  }
  // The faces around each vertex (compressed rows).
  const start = new Uint32Array(n + 1);
  for (let i = 0; i < ids.length; i++) start[ids[i] + 1]++;
  for (let v = 0; v < n; v++) start[v + 1] += start[v];
  const fill = start.slice(0, n), around = new Uint32Array(ids.length);
  for (let i = 0; i < ids.length; i++) around[fill[ids[i]]++] = i; // the corner (3 f + k)
  // Group each vertex's corners; a group past the first is a new vertex.
  const source = []; // the old vertex of each new one
  const newIndex = new Uint32Array(ids.length);
  const normals = []; // per new vertex, summed
  for (let v = 0; v < n; v++) {
    const groups = []; // [new vertex, sx, sy, sz]
    for (let j = start[v]; j < start[v + 1]; j++) {
      const corner = around[j], f = Math.floor(corner / 3);
      const x = fn[3 * f], y = fn[3 * f + 1], z = fn[3 * f + 2];
      const len = Math.hypot(x, y, z);
      let g = groups.find((g) => {
        const gl = Math.hypot(g[1], g[2], g[3]);
        return len === 0 || gl === 0 || (x * g[1] + y * g[2] + z * g[3]) >= cos * len * gl;
      });
      if (!g) {
        g = [groups.length === 0 ? v : n + source.length, 0, 0, 0];
        if (groups.length) source.push(v);
        groups.push(g);
      }
      g[1] += x; g[2] += y; g[3] += z;
      newIndex[corner] = g[0];
    }
    for (const g of groups) normals[g[0]] = [g[1], g[2], g[3]];
  }
  const total = n + source.length;
  const out = new THREE.BufferGeometry();
  for (const [name, attr] of Object.entries(geometry.attributes)) {
    if (name === 'normal') continue;
    const size = attr.itemSize, array = new attr.array.constructor(total * size);
    for (let v = 0; v < n; v++) for (let k = 0; k < size; k++) array[v * size + k] = attr.getComponent(v, k);
    source.forEach((v, i) => { for (let k = 0; k < size; k++) array[(n + i) * size + k] = attr.getComponent(v, k); });
    out.setAttribute(name, new THREE.BufferAttribute(array, size, attr.normalized));
  }
  const normal = new Float32Array(total * 3);
  for (let v = 0; v < total; v++) {
    const s = normals[v] ?? [0, 0, 1], len = Math.hypot(...s) || 1;
    normal[3 * v] = s[0] / len; normal[3 * v + 1] = s[1] / len; normal[3 * v + 2] = s[2] / len;
  }
  out.setAttribute('normal', new THREE.BufferAttribute(normal, 3));
  out.setIndex(new THREE.BufferAttribute(total > 65535 ? newIndex : Uint16Array.from(newIndex), 1));
  for (const g of geometry.groups) out.addGroup(g.start, g.count, g.materialIndex);
  return out;
}

// Readies a loaded glTF scene's meshes to be drawn: creases split, their own material kept
// (for the colour toggle), both sides lit.
function drawable(root) {
  root.traverse((o) => {
    if (o.isMesh) {
      o.geometry = creased(o.geometry);
      o.userData.own = o.material;
      o.material.side = THREE.DoubleSide;
    }
  });
}

export class Viewer {
  constructor(container) {
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio);
    container.appendChild(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color().setRGB(...BACKGROUND, THREE.LinearSRGBColorSpace);
    this.camera = new THREE.PerspectiveCamera(40, 1, 0.01, 1000);
    this.camera.up.set(0, 0, 1);
    this.camera.position.set(4, -6, 4);
    this.camera.add(new THREE.DirectionalLight(0xffffff, 2.2).translateX(-2).translateY(3).translateZ(1));
    this.scene.add(this.camera, new THREE.HemisphereLight(0xffffff, 0x9999aa, 1.4));
    this.helpers = new THREE.Group();
    this.scene.add(this.helpers);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.models = new THREE.Group();
    this.scene.add(this.models);
    // Control meshes arrive in the kernel's frame (Z up), so they are not turned like the glTF.
    this.overlay = new THREE.Group();
    this.overlay.visible = false;
    this.scene.add(this.overlay);
    // The faces a recipe line made, lit over the model (kernel frame, as the server sends them).
    this.lit = new THREE.Group();
    this.scene.add(this.lit);
    this.litMaterial = new THREE.MeshBasicMaterial({
      color: 0xff8a00, transparent: true, opacity: 0.75, side: THREE.DoubleSide,
      polygonOffset: true, polygonOffsetFactor: -2, polygonOffsetUnits: -2,
    });
    this.raycaster = new THREE.Raycaster();
    this.overlayMaterial = new THREE.LineBasicMaterial({ color: 0x1a1a80, depthTest: false, transparent: true, opacity: 0.85 });
    this.plain = new THREE.MeshStandardMaterial({ roughness: 0.6, metalness: 0.05, side: THREE.DoubleSide });
    this.plain.color.setRGB(...PLAIN, THREE.LinearSRGBColorSpace);
    this.colours = true;
    this.wireframe = false;
    this.fitted = false;
    this.mixers = [];
    this.clock = new THREE.Clock();
    this.playing = true;
    this.loader = new GLTFLoader();
    this.frames = 0;
    this.pending = false;
    this.controls.addEventListener('change', () => this.requestRender());
    new ResizeObserver(() => this.resize(container)).observe(container);
    this.resize(container);
  }

  // Draws at the next animation frame (once, however often it is asked for before then).
  requestRender() {
    if (this.pending) return;
    this.pending = true;
    requestAnimationFrame(() => this.frame());
  }

  // Whether an animation is running (then every frame is drawn).
  get animating() { return this.playing && this.mixers.length > 0; }

  resize(container) {
    const w = Math.max(container.clientWidth, 1), h = Math.max(container.clientHeight, 1);
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.requestRender();
  }

  frame() {
    this.pending = false;
    const dt = this.clock.getDelta();
    if (this.animating) this.mixers.forEach((m) => m.update(dt));
    this.renderer.render(this.scene, this.camera);
    this.frames += 1;
    this.onFrame?.();
    if (this.animating) this.requestRender();
  }

  // Starts or stops the animation; the clock restarts so a pause is not counted as played.
  setPlaying(on) {
    this.playing = on;
    this.clock.getDelta();
    this.requestRender();
  }

  // Parses the layers ({name, control?}) from their files (each layer's .glb, then each
  // control mesh's edges as little-endian f32 x, y, z per end) and swaps them in whole;
  // resolves to the three.js objects by layer name.
  async show(layers, files) {
    let next = layers.length;
    const ends = layers.map((l) => (l.control ? new Float32Array(files[next++]) : null));
    const loaded = await Promise.all(layers.map((l, i) => this.loader.parseAsync(files[i], '')));
    this.models.clear();
    this.overlay.clear();
    this.lit.clear();
    ends.forEach((e, i) => {
      if (!e) return;
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute('position', new THREE.BufferAttribute(e, 3));
      const lines = new THREE.LineSegments(geometry, this.overlayMaterial);
      lines.name = layers[i].name;
      lines.renderOrder = 1;
      this.overlay.add(lines);
    });
    this.mixers = [];
    this.duration = 0;
    const objects = {};
    loaded.forEach((gltf, i) => {
      const root = gltf.scene;
      root.name = layers[i].name;
      // An exact quarter turn (rotation.x = π/2 would leave 6e-17 where 0 is, and the measure
      // tool reads vertex positions through this matrix).
      root.matrixAutoUpdate = false;
      root.matrix.set(1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1);
      root.updateMatrixWorld(true);
      drawable(root);
      if (gltf.animations.length) {
        const mixer = new THREE.AnimationMixer(root);
        gltf.animations.forEach((clip) => {
          mixer.clipAction(clip).play();
          this.duration = Math.max(this.duration, clip.duration);
        });
        this.mixers.push(mixer);
      }
      this.models.add(root);
      objects[root.name] = root;
    });
    this.applyMaterials();
    this.placeHelpers();
    if (!this.fitted) {
      this.fit();
      this.fitted = true;
    }
    this.clock.getDelta();
    this.requestRender();
    return objects;
  }

  // The model's surface under the canvas point (x, y) in CSS pixels: the layer's name and the
  // point in the kernel's frame (the view's), or null where there is no model.
  pick(x, y) {
    const rect = this.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2(((x - rect.left) / rect.width) * 2 - 1, -((y - rect.top) / rect.height) * 2 + 1);
    this.raycaster.setFromCamera(ndc, this.camera);
    const visible = this.models.children.filter((o) => o.visible);
    const hit = this.raycaster.intersectObjects(visible, true)[0];
    if (!hit) return null;
    let root = hit.object;
    while (root.parent && root.parent !== this.models) root = root.parent;
    return { layer: root.name, point: hit.point.toArray() };
  }

  // Where the kernel-frame point p ([x, y, z]) is on the canvas, in CSS pixels of the page.
  screenOf(p) {
    const rect = this.renderer.domElement.getBoundingClientRect();
    const v = new THREE.Vector3(...p).project(this.camera);
    return [rect.left + ((v.x + 1) / 2) * rect.width, rect.top + ((1 - v.y) / 2) * rect.height];
  }

  // The lit triangles' corners (kernel frame), for tests.
  litCorners() {
    return this.lit.children.flatMap((m) => Array.from(m.geometry.attributes.position.array));
  }

  // Lights up triangles (per layer, a Float32Array of x, y, z per corner, kernel frame); none
  // clears. Returns how many triangles are lit.
  setLit(arrays) {
    this.lit.clear();
    let n = 0;
    for (const a of arrays) {
      if (!a || a.length === 0) continue;
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute('position', new THREE.BufferAttribute(a, 3));
      const mesh = new THREE.Mesh(geometry, this.litMaterial);
      mesh.renderOrder = 2;
      this.lit.add(mesh);
      n += a.length / 9;
    }
    this.requestRender();
    return n;
  }

  triangles() {
    let n = 0;
    // Of the layers shown: a hidden layer (or the model hidden under its coloured-by-operand
    // view) hides its meshes.
    this.models.traverseVisible((o) => {
      if (o.isMesh) n += (o.geometry.index ? o.geometry.index.count : o.geometry.attributes.position.count) / 3;
    });
    return n;
  }

  applyMaterials() {
    this.models.traverse((o) => {
      if (!o.isMesh) return;
      const own = o.userData.own;
      const m = this.colours && own.vertexColors ? own : this.plain;
      m.wireframe = this.wireframe;
      o.material = m;
    });
    this.requestRender();
  }

  setColours(on) { this.colours = on; this.applyMaterials(); }
  setWireframe(on) { this.wireframe = on; this.plain.wireframe = on; this.applyMaterials(); }
  // Draws each layer coloured by operand in place of itself (`files`: per layer, a `.glb`
  // ArrayBuffer of its provenance view, or null to keep it), or each layer as it is again when
  // every entry is null. Returns how many layers are recoloured.
  async setProvenance(files) {
    for (const view of this.models.children.filter((o) => o.userData.provenanceOf)) {
      view.userData.provenanceOf.visible = view.visible;
      view.removeFromParent();
    }
    const layers = [...this.models.children];
    const views = await Promise.all(files.map((f) => (f ? this.loader.parseAsync(f, '') : null)));
    let n = 0;
    views.forEach((gltf, i) => {
      const own = layers[i];
      if (!gltf || !own) return;
      const root = gltf.scene;
      root.name = own.name;
      root.matrixAutoUpdate = false;
      root.matrix.copy(own.matrix);
      root.updateMatrixWorld(true);
      drawable(root);
      root.userData.provenanceOf = own;
      root.visible = own.visible;
      own.visible = false;
      this.models.add(root);
      n += 1;
    });
    this.applyMaterials();
    return n;
  }

  // The distinct vertex colours of the visible meshes (as 0–255 RGB strings), for tests.
  shownColours() {
    const seen = new Set();
    this.models.traverseVisible((o) => {
      if (!o.isMesh) return;
      const c = o.geometry.attributes.color;
      if (!c || !o.material.vertexColors) return;
      for (let k = 0; k < c.count; k++) seen.add([c.getX(k), c.getY(k), c.getZ(k)].map((x) => Math.round(x * 255)).join(','));
    });
    return [...seen];
  }

  setHelpers(on) { this.helpers.visible = on; this.requestRender(); }
  setControl(on) { this.overlay.visible = on; this.requestRender(); }

  // The models' bounds as drawn now (animated vertices where they are at this frame):
  // [min x, y, z, max x, y, z] in the view's frame.
  bounds() {
    const box = new THREE.Box3().setFromObject(this.models, true);
    return [...box.min.toArray(), ...box.max.toArray()];
  }

  // The control meshes' bounds, drawn or not: [min x, y, z, max x, y, z] (kernel frame);
  // null when there is none.
  controlBounds() {
    const box = new THREE.Box3().setFromObject(this.overlay, true);
    return box.isEmpty() ? null : [...box.min.toArray(), ...box.max.toArray()];
  }

  // The control-mesh edges on show (0 when the overlay is off).
  controlEdges() {
    if (!this.overlay.visible) return 0;
    return this.overlay.children.reduce((n, l) => n + (l.visible ? l.geometry.attributes.position.count / 2 : 0), 0);
  }

  // A grid on the XY plane under the model, sized to it, and axes at the origin.
  placeHelpers() {
    const box = new THREE.Box3().setFromObject(this.models);
    if (box.isEmpty()) return;
    const size = box.getSize(new THREE.Vector3());
    const extent = Math.max(size.x, size.y, size.z, 1e-6);
    const step = 10 ** Math.floor(Math.log10(extent / 2));
    const span = Math.ceil((extent * 2) / step) * step;
    this.helpers.clear();
    const grid = new THREE.GridHelper(span, Math.round(span / step), 0x999999, 0xc8c8c8);
    grid.rotation.x = Math.PI / 2;
    grid.position.set(Math.round(box.getCenter(new THREE.Vector3()).x / step) * step,
      Math.round(box.getCenter(new THREE.Vector3()).y / step) * step, box.min.z);
    this.helpers.add(grid, new THREE.AxesHelper(extent * 0.6));
  }

  // The camera looks at the models' bounding box from the usual direction, as close as it can
  // with every corner of the box inside the frame (both ways: a tall model in a wide view and
  // a wide one in a tall view), and a margin.
  fit() {
    const box = new THREE.Box3().setFromObject(this.models);
    if (box.isEmpty()) return;
    const centre = box.getCenter(new THREE.Vector3());
    const direction = new THREE.Vector3(1, -1.4, 0.9).normalize();
    this.camera.position.copy(centre).add(direction);
    this.camera.lookAt(centre);
    this.camera.updateMatrixWorld();
    const toCamera = this.camera.matrixWorldInverse;
    const tanV = Math.tan(THREE.MathUtils.degToRad(this.camera.fov / 2));
    const tanH = tanV * this.camera.aspect;
    const origin = centre.clone().applyMatrix4(toCamera);
    let distance = 0, depth = 0;
    for (let i = 0; i < 8; i++) {
      const corner = new THREE.Vector3(i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y, i & 4 ? box.max.z : box.min.z);
      const p = corner.applyMatrix4(toCamera).sub(origin); // relative to the centre, camera axes
      // Seen from `d` along +z (camera space), the corner is at depth d - p.z.
      distance = Math.max(distance, p.z + Math.abs(p.x) / tanH, p.z + Math.abs(p.y) / tanV);
      depth = Math.max(depth, Math.abs(p.z));
    }
    distance = (distance || 1) * 1.08;
    this.camera.position.copy(centre).addScaledVector(direction, distance);
    this.camera.near = Math.max(distance - depth, distance / 100) / 10;
    this.camera.far = (distance + depth) * 10;
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(centre);
    this.controls.update();
    this.requestRender();
  }

  // Whether every corner of the models' bounding box is inside the frame now.
  inView() {
    const box = new THREE.Box3().setFromObject(this.models);
    if (box.isEmpty()) return true;
    this.camera.updateMatrixWorld();
    for (let i = 0; i < 8; i++) {
      const p = new THREE.Vector3(i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y, i & 4 ? box.max.z : box.min.z);
      p.project(this.camera);
      if (Math.abs(p.x) > 1 || Math.abs(p.y) > 1 || p.z > 1 || p.z < -1) return false;
    }
    return true;
  }

  // The animation's time, in seconds, and setting it (scrubbing).
  time() { return this.mixers.length ? this.mixers[0].time % (this.duration || 1) : 0; }
  setTime(t) { this.mixers.forEach((m) => m.setTime(t)); this.requestRender(); }
}
