// The studio page: wires the connection, the 3D view and the panel (facts, layers, toggles,
// animation timeline, parameters, downloads, the measure tool). A click on the model shows the
// recipe lines that made the face under it; with measure on, it measures instead (measure.js).
// `window.studio` tells tests what is on show (`studio.measure`: the measure tool's state;
// `studio.defects`: the defects view's, defects.js).

import { Viewer } from './viewer.js';
import { Measure } from './measure.js';
import { Defects, describe } from './defects.js';
import { connect, postJson, sendParams, token } from './connection.js';
import { renderParams, paramsFromAddress, paramsToAddress } from './controls.js';

const $ = (id) => document.getElementById(id);
const viewer = new Viewer($('view'));
const studio = (window.studio = { version: 0, triangles: 0, error: null, loads: 0 });
let shown = 0;
let loading = Promise.resolve();
let specs = [];
let current = null; // the model message on show
let values = {};

// A layer's resource of model `version` (`suffix`: `defects`, `faces`...), or null when gone.
async function fetchLayer(version, layer, suffix, query = {}) {
  const answer = await fetch(`/model/${version}/${layer}.${suffix}?${new URLSearchParams({ token, ...query })}`);
  return answer.ok ? answer : null;
}
const defects = new Defects(viewer, fetchLayer);
studio.defects = defects.state;

// The defects panel: what was found, and a checkbox per component.
function showDefects() {
  const s = defects.state;
  studio.defects = s;
  $('defects').setAttribute('aria-pressed', String(s.on));
  $('defects-note').hidden = !s.on;
  $('defects-none').hidden = !(s.loaded && Object.keys(s.counts).length === 0);
  $('defect-counts').replaceChildren(...describe(s.counts).flatMap(([k, v]) => {
    const dt = document.createElement('dt'); dt.textContent = k;
    const dd = document.createElement('dd'); dd.textContent = v;
    return [dt, dd];
  }));
  $('components').replaceChildren(...s.components.map((c, k) => {
    const li = document.createElement('li');
    const box = document.createElement('input');
    box.type = 'checkbox'; box.checked = c.visible; box.id = `component-${k}`;
    box.onchange = () => {
      defects.setComponent(k, box.checked);
      studio.triangles = defects.visibleTriangles() ?? viewer.triangles();
    };
    const genus = c.genus ? `, genus ${c.genus}` : '';
    li.append(box, ` component ${k + 1}: ${c.faces} faces${genus}`);
    return li;
  }));
  studio.triangles = defects.visibleTriangles() ?? viewer.triangles();
}

// Each layer of a boolean result coloured by the operand each face came from, or as it is.
async function setProvenance(on) {
  if (!current) return;
  const files = await Promise.all(current.layers.map(async (l) => {
    if (!on || !l.provenance) return null;
    const answer = await fetch(`${l.provenance}?${new URLSearchParams({ token })}`);
    return answer.ok ? answer.arrayBuffer() : null;
  }));
  studio.provenance = await viewer.setProvenance(files);
  $('provenance-note').hidden = !on;
  studio.triangles = defects.visibleTriangles() ?? viewer.triangles();
}

async function setDefects(on) {
  if (on && current) await defects.show(current);
  else defects.clear();
  showDefects();
}

function showParams() {
  renderParams($('params'), specs, values, (changed) => {
    values = changed;
    paramsToAddress(changed, token);
    sendParams(changed);
  });
}

const fmt = (x) => (Number.isInteger(x) ? String(x) : x.toPrecision(6).replace(/\.?0+$/, ''));

function showFacts(layers, runMs) {
  const sum = (key) => layers.reduce((s, l) => s + l.facts[key], 0);
  const f = layers.map((l) => l.facts);
  const min = [0, 1, 2].map((k) => Math.min(...f.map((x) => x.bounds.min[k])));
  const max = [0, 1, 2].map((k) => Math.max(...f.map((x) => x.bounds.max[k])));
  const rows = [
    ['vertices', sum('vertices')], ['triangles', sum('triangles')],
    ['closed', f.every((x) => x.closed) ? 'yes' : 'no'], ['manifold', f.every((x) => x.manifold) ? 'yes' : 'no'],
    ['genus', f.map((x) => x.genus).join(', ')], ['volume', fmt(sum('volume'))],
    ['bounds', `${min.map(fmt).join(', ')} … ${max.map(fmt).join(', ')}`], ['run time', `${runMs.toFixed(0)} ms`],
  ];
  $('facts').replaceChildren(...rows.flatMap(([k, v]) => {
    const dt = document.createElement('dt'); dt.textContent = k;
    const dd = document.createElement('dd'); dd.textContent = v; dd.id = `fact-${k.replace(' ', '-')}`;
    return [dt, dd];
  }));
}

function showLayers(layers, objects, version) {
  $('layers-section').hidden = layers.length < 2;
  $('layers').replaceChildren(...layers.map((l) => {
    const li = document.createElement('li');
    const box = document.createElement('input');
    box.type = 'checkbox'; box.checked = true;
    box.onchange = () => {
      // The layer as drawn: its view coloured by operand while that is on.
      const view = viewer.models.children.find((o) => o.name === l.name && o.userData.provenanceOf);
      (view ?? objects[l.name]).visible = box.checked;
      const lines = viewer.overlay.getObjectByName(l.name);
      if (lines) lines.visible = box.checked;
      viewer.requestRender();
      studio.triangles = viewer.triangles();
      studio.controlEdges = viewer.controlEdges();
    };
    const name = document.createElement('span'); name.className = 'layer-name'; name.textContent = ` ${l.name}`;
    li.append(box, name, ` (${l.facts.triangles} triangles)`);
    return li;
  }));
  $('downloads').replaceChildren(...layers.flatMap((l, i) => ['glb', 'obj', 'stl'].map((ext) => {
    const a = document.createElement('a');
    a.href = `/download/${version}/${i}.${ext}?token=${encodeURIComponent(token)}`;
    a.textContent = layers.length > 1 ? `${l.name}.${ext}` : `.${ext}`;
    return a;
  })));
}

// A model other than the one on show (a page that changes its parameters may go back to a
// model made earlier, with a smaller number).
async function showModel(message) {
  if (message.version === shown) return;
  const started = Date.now();
  const objects = await viewer.show(message.layers, message.files);
  const loaded = Date.now();
  shown = message.version;
  current = message;
  showSource(null);
  measure.clear();
  showMeasure();
  showFacts(message.layers, message.run_ms);
  showLayers(message.layers, objects, message.version);
  showWarnings(message.warnings ?? []);
  if (defects.state.on) await setDefects(true);
  $('provenance-label').hidden = !message.layers.some((l) => l.provenance);
  studio.provenance = 0;
  if ($('provenance').checked) await setProvenance(true);
  $('animation').hidden = !viewer.duration;
  const control = message.layers.some((l) => l.control);
  $('control-label').hidden = !control;
  $('control-note').hidden = control;
  $('timeline').max = viewer.duration || 1;
  Object.assign(studio, {
    version: message.version, triangles: defects.visibleTriangles() ?? viewer.triangles(),
    controlEdges: viewer.controlEdges(), loads: studio.loads + 1,
  });
  document.title = `blocksmith: ${studio.triangles} triangles`;
  // When the model reached the screen: after the next frame is drawn (for latency scripts),
  // with when its message arrived, its layers started loading and had loaded (wall clock, ms).
  const { version, received } = message;
  requestAnimationFrame(() => requestAnimationFrame(() => {
    studio.shown = { version, at: Date.now(), sincePageStart: performance.now(), received, started, loaded };
  }));
}

// Messages are handled one after the other, a model only once it has loaded, so an error that
// follows a model is never hidden by that model's late arrival.
function onMessage(message) {
  message.received ??= Date.now();
  loading = loading.then(() => handle(message)).catch((e) => showError(`cannot show the model: ${e}`));
}

async function handle(message) {
  switch (message.type) {
    case 'hello':
      // A new connection: whatever model it sends is news, even with a number already seen.
      shown = 0;
      studio.connections = (studio.connections ?? 0) + 1;
      break;
    case 'model':
      await showModel(message);
      specs = message.params ?? [];
      showParams();
      showError(null);
      setStatus('live');
      break;
    case 'error':
      showError(message.text);
      break;
    case 'running':
      setStatus('running');
      break;
    case 'highlight':
      // An editor's cursor rests on a call: light up the faces it made.
      await light({ file: message.file, line: message.line, column: message.column });
      break;
    case 'params':
      // The parameters in force for this page: those of its address over the studio's own.
      values = message.values;
      paramsToAddress(values, token);
      showParams();
      break;
  }
}

// From the model to the recipe: a click (not a drag) on the model asks the server for the face
// under it and the calls that made it, first call first; the list shows them, the faces of the
// first call light up, and an editor following the studio (`blocksmith lsp`) shows its line.
const where = (s) => `${(s.file ?? 'recipe').split('/').pop()}:${s.line}:${s.column}`;

function showSource(picked) {
  studio.picked = picked;
  const list = $('source');
  if (!picked) {
    list.replaceChildren();
    return;
  }
  if (picked.steps.length === 0) {
    const li = document.createElement('li');
    li.textContent = 'No recipe line recorded for this face (a loaded file, or a mesh from outside a recipe).';
    list.replaceChildren(li);
    return;
  }
  list.replaceChildren(...picked.steps.map((s, i) => {
    const li = document.createElement('li');
    const call = document.createElement('code'); call.textContent = s.call;
    li.append(call, ` at ${where(s)}`);
    li.title = s.file ?? '';
    li.className = i === 0 ? 'first' : '';
    li.onclick = () => light(s);
    return li;
  }));
  if (picked.editor) {
    const li = document.createElement('li');
    li.className = 'note';
    li.textContent = 'shown in the editor';
    list.append(li);
  }
}

// Lights up the faces made by the call written at `site` ({file, line, column}), in every layer.
async function light(site) {
  if (!current) return;
  const query = new URLSearchParams({ line: site.line, column: site.column ?? 0, token });
  if (site.file) query.set('file', site.file);
  const arrays = await Promise.all(current.layers.map(async (_, i) => {
    const answer = await fetch(`/model/${current.version}/${i}.faces?${query}`);
    return answer.ok ? new Float32Array(await answer.arrayBuffer()) : null;
  }));
  studio.lit = viewer.setLit(arrays);
  studio.litSite = site;
}

async function pickAt(x, y) {
  if (!current) return null;
  const hit = viewer.pick(x, y);
  if (!hit) return null;
  const layer = current.layers.findIndex((l) => l.name === hit.layer);
  const picked = await postJson('/api/pick', { version: current.version, layer: Math.max(layer, 0), point: hit.point });
  showSource(picked);
  if (picked.steps.length) await light(picked.steps[0]);
  else studio.lit = viewer.setLit([]);
  return picked;
}

// The measure tool. Its face areas come from the polygon under the click, which the server
// knows (the .glb holds triangles only); the editor is not told of these picks.
const measure = new Measure(viewer, async (hit) => {
  if (!current) return null;
  let root = hit.object;
  while (root.parent && root.parent !== viewer.models) root = root.parent;
  const layer = current.layers.findIndex((l) => l.name === root.name);
  const body = { version: current.version, layer: Math.max(layer, 0), point: hit.point.toArray(), editor: false };
  return (await postJson('/api/pick', body)).triangles ?? null;
});
let measureClicks = 0;
let copied = null;
Object.defineProperty(studio, 'measure', {
  enumerable: true,
  get: () => ({ on: measure.on, clicks: measureClicks, copied, ...measure.state }),
});

const triple = (p) => p.map(fmt).join(', ');

function showMeasure() {
  const s = measure.state;
  const rows = [];
  s.points.forEach((m, i) => rows.push([`point ${'AB'[i]}`, `${triple(m.point)} (${m.kind})`]));
  if (s.distance !== null) {
    rows.push(['distance', fmt(s.distance)]);
    ['dx', 'dy', 'dz'].forEach((k, i) => rows.push([k, fmt(s.deltas[i])]));
  }
  if (s.area !== null) {
    rows.push([s.face.polygon ? 'face area' : 'triangle area', fmt(s.area)]);
    rows.push(['normal', s.normal ? triple(s.normal) : 'none (no area)']);
  }
  if (s.ring.length) rows.push(['ring', `${s.ring.length} point${s.ring.length === 1 ? '' : 's'}`]);
  if (s.circle) {
    rows.push(['centre', triple(s.circle.centre)], ['radius', fmt(s.circle.radius)], ['circle normal', triple(s.circle.normal)]);
  }
  $('measured').replaceChildren(...rows.flatMap(([k, v]) => {
    const dt = document.createElement('dt'); dt.textContent = k;
    const dd = document.createElement('dd'); dd.textContent = v;
    return [dt, dd];
  }));
  $('fit-circle').disabled = s.ring.length < 3;
  $('measure-copy').disabled = !s.assert;
  $('measure-assert').hidden = !s.assert;
  $('measure-assert').textContent = s.assert ?? '';
}

// Puts `text` on the clipboard; whether that worked (a page without the clipboard's permission
// falls back to a selected text area; the line is on show to copy by hand either way).
async function copyText(text) {
  try {
    await navigator.clipboard.writeText(text);
    return true;
  } catch {
    const area = document.createElement('textarea');
    area.value = text;
    document.body.append(area);
    area.select();
    const ok = document.execCommand('copy');
    area.remove();
    return ok;
  }
}

$('measure').onclick = () => {
  measure.on = !measure.on;
  $('measure').setAttribute('aria-pressed', String(measure.on));
  $('measure-note').hidden = !measure.on;
  $('measure-actions').hidden = !measure.on;
  showMeasure();
};
$('fit-circle').onclick = () => {
  const fitted = measure.fitCircle();
  showMeasure();
  if (!fitted) {
    const dd = document.createElement('dd');
    dd.textContent = 'none: the ring needs three points or more, not on one line';
    const dt = document.createElement('dt'); dt.textContent = 'circle';
    $('measured').append(dt, dd);
  }
};
$('measure-clear').onclick = () => {
  measure.clear();
  copied = null;
  showMeasure();
};
$('measure-copy').onclick = async () => {
  const text = measure.state.assert;
  if (!text) return;
  copied = null;
  copied = { text, clipboard: await copyText(text) };
};

let pressed = null;
$('view').addEventListener('pointerdown', (e) => { pressed = [e.clientX, e.clientY]; });
$('view').addEventListener('pointerup', (e) => {
  // A click, not the end of a turn of the view.
  if (pressed && Math.hypot(e.clientX - pressed[0], e.clientY - pressed[1]) < 4) {
    if (measure.on) {
      measure.click(e.clientX, e.clientY, e.shiftKey)
        .catch((err) => showError(`cannot measure: ${err}`))
        .finally(() => { measureClicks += 1; showMeasure(); });
    } else {
      pickAt(e.clientX, e.clientY).catch((err) => showError(`cannot pick: ${err}`));
    }
  }
  pressed = null;
});
studio.pickAt = pickAt;
studio.screenOf = (p) => viewer.screenOf(p);
studio.litCorners = () => viewer.litCorners();
studio.light = light;

function showError(text) {
  studio.error = text;
  $('error').hidden = !text;
  $('error').textContent = text ?? '';
  if (text) setStatus('live');
}

// A run's warnings (dropped results, blocks that touch without connecting), each at its line
// as the terminal prints it.
function showWarnings(list) {
  studio.warnings = list;
  $('warnings').hidden = list.length === 0;
  $('warnings').textContent = list.join('\n');
}

function setStatus(state) {
  $('status').textContent = state;
  $('status').className = `status ${state}`;
}

$('colours').onchange = (e) => viewer.setColours(e.target.checked);
$('wireframe').onchange = (e) => viewer.setWireframe(e.target.checked);
$('provenance').onchange = (e) => setProvenance(e.target.checked).catch((err) => showError(`cannot colour by operand: ${err}`));
studio.shownColours = () => viewer.shownColours();
$('grid').onchange = (e) => viewer.setHelpers(e.target.checked);
$('control').onchange = (e) => {
  viewer.setControl(e.target.checked);
  studio.controlEdges = viewer.controlEdges();
};
$('fit').onclick = () => viewer.fit();
$('defects').onclick = () => setDefects(!defects.state.on).catch((e) => showError(`cannot show the defects: ${e}`));
studio.defectSegments = (key) => defects.segments(key);
$('play').onclick = () => {
  viewer.setPlaying(!viewer.playing);
  $('play').textContent = viewer.playing ? 'pause' : 'play';
};
$('timeline').oninput = (e) => {
  viewer.setPlaying(false);
  $('play').textContent = 'play';
  viewer.setTime(Number(e.target.value));
};
viewer.onFrame = () => {
  if (!viewer.duration) return;
  const t = viewer.time();
  studio.time = t;
  if (viewer.playing) $('timeline').value = t;
  $('time').textContent = `${t.toFixed(2)} s`;
};

studio.bounds = () => viewer.bounds();
studio.controlBounds = () => viewer.controlBounds();
studio.frames = () => viewer.frames;
studio.inView = () => viewer.inView();
if (!token) {
  showError('This page needs the address the studio printed, with its token (`?token=…`): '
    + 'the studio answers only the page it gave to you.');
}
connect(onMessage, setStatus, () => ({ ...paramsFromAddress(), ...values }));
