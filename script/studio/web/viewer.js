// The 3D view: three.js with the kernel's +Z up, a grid on the XY plane and axes, orbit / pan /
// zoom, fit to view on the first model (later models keep the camera), feature colours or a
// plain material, wireframe, the control mesh a surface was made from (lines over it), and the
// playback of a model's animation. It draws only when something changed (a model, the camera,
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
      root.rotation.x = Math.PI / 2;
      root.traverse((o) => {
        if (o.isMesh) {
          o.userData.own = o.material;
          o.material.side = THREE.DoubleSide;
        }
      });
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

  triangles() {
    let n = 0;
    this.models.traverse((o) => {
      if (o.isMesh && o.visible) n += (o.geometry.index ? o.geometry.index.count : o.geometry.attributes.position.count) / 3;
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

  fit() {
    const box = new THREE.Box3().setFromObject(this.models);
    if (box.isEmpty()) return;
    const centre = box.getCenter(new THREE.Vector3());
    const radius = box.getSize(new THREE.Vector3()).length() / 2 || 1;
    const distance = radius / Math.sin(THREE.MathUtils.degToRad(this.camera.fov / 2));
    const direction = new THREE.Vector3(1, -1.4, 0.9).normalize();
    this.camera.position.copy(centre).addScaledVector(direction, distance);
    this.camera.near = distance / 100;
    this.camera.far = distance * 100;
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(centre);
    this.controls.update();
    this.requestRender();
  }

  // The animation's time, in seconds, and setting it (scrubbing).
  time() { return this.mixers.length ? this.mixers[0].time % (this.duration || 1) : 0; }
  setTime(t) { this.mixers.forEach((m) => m.setTime(t)); this.requestRender(); }
}
