// packbench viewer: draws the packings embedded in this page with three.js (vendored,
// crates/bench/assets/three). Every number shown comes from packbench-core's analysis, which
// wrote the data block; this script only decodes, draws and lays out.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

const DATA = JSON.parse(document.getElementById('packbench-data').textContent);
const $ = (id) => document.getElementById(id);

// ---- packed arrays (little-endian typed arrays as base64, see viewer/encode.rs) ----
function bytes(b64) {
  const s = atob(b64);
  const out = new Uint8Array(s.length);
  for (let i = 0; i < s.length; i++) out[i] = s.charCodeAt(i);
  return out;
}
// [min, max] of an array of any length (spreading 10⁵ arguments into Math.min may overflow).
function extent(values) {
  let lo = Infinity, hi = -Infinity;
  for (const v of values) { if (v < lo) lo = v; if (v > hi) hi = v; }
  return [lo, hi];
}
const f32 = (b64) => new Float32Array(bytes(b64).buffer);
const u32 = (b64) => new Uint32Array(bytes(b64).buffer);

// ---- colour maps ----
const VIRIDIS = [[0.267, 0.005, 0.329], [0.229, 0.322, 0.546], [0.128, 0.567, 0.551], [0.369, 0.789, 0.383], [0.993, 0.906, 0.144]];
const FORCE = [[0.78, 0.81, 0.87], [0.96, 0.62, 0.22], [0.80, 0.12, 0.10], [0.35, 0.0, 0.05]];
function ramp(stops, t, out) {
  t = Math.min(1, Math.max(0, Number.isFinite(t) ? t : 0.5));
  const x = t * (stops.length - 1);
  const k = Math.min(stops.length - 2, Math.floor(x));
  const u = x - k;
  for (let c = 0; c < 3; c++) out[c] = stops[k][c] * (1 - u) + stops[k + 1][c] * u;
  return out;
}
const RATTLER = [0.85, 0.15, 0.24];
const JAMMED = [0.62, 0.70, 0.78];

// ---- view state shared by every panel ----
const state = {
  colour: 'diameter', contacts: false, container: true, images: false,
  slice: false, sliceAxis: 2, slicePos: 0.5, extra: [], frame: 0, link: true,
};
const panels = [];
let syncing = false;

const frameCount = Math.max(...DATA.panels.map((p) => p.frames.length));
const maxDim = Math.max(...DATA.panels.map((p) => p.dim));
const allFlat = DATA.panels.every((p) => p.dim === 2);

class PanelView {
  constructor(data, host) {
    this.data = data;
    this.dim = data.dim;
    this.flat = data.dim === 2;
    this.L = data.container.lengths;
    this.periodic = data.container.periodic;
    this.cache = new Map();
    this.el = document.createElement('div');
    this.el.className = 'panel';
    const heading = document.createElement('div');
    heading.className = 'heading';
    heading.textContent = data.label;
    this.summary = document.createElement('div');
    this.summary.className = 'summary';
    host.appendChild(this.el);
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.localClippingEnabled = true;
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
    this.el.append(this.renderer.domElement, heading, this.summary);
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0xffffff);
    this.centre = new THREE.Vector3(this.L[0] / 2, this.L[1] / 2, this.flat ? 0 : this.L[2] / 2);
    if (this.flat) {
      this.camera = new THREE.OrthographicCamera(-1, 1, 1, -1, 0.01, 1000 * Math.max(...this.L));
    } else {
      this.camera = new THREE.PerspectiveCamera(35, 1, 0.001 * this.radius(), 100 * this.radius());
      this.camera.up.set(0, 0, 1);
      const sun = new THREE.DirectionalLight(0xffffff, 2.2);
      sun.position.set(0.4, 0.8, 1);
      this.camera.add(sun);
      this.scene.add(new THREE.AmbientLight(0xffffff, 0.9));
    }
    this.scene.add(this.camera);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.enableRotate = !this.flat;
    this.controls.screenSpacePanning = true;
    this.controls.addEventListener('change', () => {
      this.render();
      if (state.link && !syncing) linkCameras(this);
    });
    const n = data.frames[0].n;
    const [ws, hs] = n > 20000 ? [10, 7] : n > 2000 ? [16, 11] : [28, 18];
    this.geometry = this.flat ? new THREE.CircleGeometry(1, 40) : new THREE.SphereGeometry(1, ws, hs);
    this.clipPlane = new THREE.Plane(new THREE.Vector3(0, 0, -1), 0);
    this.material = this.flat ? new THREE.MeshBasicMaterial() : new THREE.MeshLambertMaterial();
    this.lineMaterial = new THREE.LineBasicMaterial({ vertexColors: true });
    this.mesh = null;
    this.lines = null;
    this.box = null;
    this.resetCamera();
  }

  radius() { return 0.5 * Math.hypot(...this.L.slice(0, 3)); }

  resetCamera() {
    this.controls.target.copy(this.centre);
    if (this.flat) {
      this.camera.position.set(this.centre.x, this.centre.y, 10 * Math.max(...this.L));
      this.camera.zoom = 1;
    } else {
      const dist = (1.15 * this.radius()) / Math.sin(THREE.MathUtils.degToRad(this.camera.fov / 2));
      const dir = new THREE.Vector3(1.1, -1.7, 0.9).normalize();
      this.camera.position.copy(this.centre).addScaledVector(dir, dist);
    }
    this.camera.updateProjectionMatrix();
    this.controls.update();
  }

  resize() {
    const w = Math.max(1, this.el.clientWidth);
    const h = Math.max(1, this.el.clientHeight);
    this.renderer.setSize(w, h, false);
    const aspect = w / h;
    if (this.flat) {
      const half = 0.53 * Math.max(this.L[1], this.L[0] / aspect);
      Object.assign(this.camera, { left: -half * aspect, right: half * aspect, top: half, bottom: -half });
    } else {
      this.camera.aspect = aspect;
    }
    this.camera.updateProjectionMatrix();
  }

  arrays(k) {
    if (!this.cache.has(k)) {
      const f = this.data.frames[k];
      this.cache.set(k, {
        pos: f32(f.positions), dia: f32(f.diameters), pairs: u32(f.pairs),
        z: bytes(f.z), rattlers: bytes(f.rattlers), forces: f.forces ? f32(f.forces) : null,
        localPhi: f.local_phi ? f32(f.local_phi) : null,
      });
    }
    return this.cache.get(k);
  }

  frameIndex() { return Math.min(state.frame, this.data.frames.length - 1); }

  // Minimum-image offset along a periodic axis.
  wrap(dx, a) {
    if (!this.periodic[a]) return dx;
    const L = this.L[a];
    return dx - L * Math.round(dx / L);
  }

  // In-slice radius of particle i: its full radius for d ≤ 3; for d ≥ 4 the radius of the
  // 3-sphere where it cuts the hyperplane x_4.. = state.extra (0 when it does not cut it).
  cutRadius(a, i) {
    const d = this.dim;
    const r = 0.5 * a.dia[i];
    if (d <= 3) return r;
    let off2 = 0;
    for (let k = 3; k < d; k++) {
      const dx = this.wrap(a.pos[i * d + k] - state.extra[k - 3], k);
      off2 += dx * dx;
    }
    return off2 < r * r ? Math.sqrt(r * r - off2) : 0;
  }

  build() {
    const k = this.frameIndex();
    const a = this.arrays(k);
    const d = this.dim;
    const n = this.data.frames[k].n;
    const ball = !this.flat && state.contacts ? 0.4 : 1; // ball-and-stick when the network shows
    const xs = [];
    const cut = new Float32Array(n);
    const shifts = [[0], [0], [0]];
    for (let i = 0; i < n; i++) {
      const r = this.cutRadius(a, i);
      cut[i] = r;
      if (r <= 0) continue;
      const x = [a.pos[i * d], a.pos[i * d + 1], d >= 3 ? a.pos[i * d + 2] : 0];
      for (let ax = 0; ax < 3; ax++) {
        shifts[ax] = [0];
        if (state.images && ax < d && this.periodic[ax]) {
          if (x[ax] - r < 0) shifts[ax].push(1);
          if (x[ax] + r > this.L[ax]) shifts[ax].push(-1);
        }
      }
      for (const sx of shifts[0]) for (const sy of shifts[1]) for (const sz of shifts[2]) {
        xs.push(x[0] + sx * this.L[0], x[1] + sy * this.L[1], x[2] + (d >= 3 ? sz * this.L[2] : 0), r * ball, i);
      }
    }
    const count = xs.length / 5;
    if (!this.mesh || this.capacity < count) {
      if (this.mesh) { this.scene.remove(this.mesh); this.mesh.dispose(); }
      this.capacity = Math.max(count, n);
      this.mesh = new THREE.InstancedMesh(this.geometry, this.material, this.capacity);
      this.mesh.instanceColor = new THREE.InstancedBufferAttribute(new Float32Array(3 * this.capacity), 3);
      this.mesh.frustumCulled = false;
      this.scene.add(this.mesh);
    }
    const m = this.mesh.instanceMatrix.array;
    const col = this.mesh.instanceColor.array;
    const colourOf = this.colouring(a, n);
    const rgb = [0, 0, 0];
    m.fill(0, 0, 16 * count);
    for (let c = 0; c < count; c++) {
      const r = xs[5 * c + 3];
      // Column-major scale-then-translate matrix of instance c.
      m[16 * c] = r; m[16 * c + 5] = r; m[16 * c + 10] = r;
      m[16 * c + 12] = xs[5 * c]; m[16 * c + 13] = xs[5 * c + 1]; m[16 * c + 14] = xs[5 * c + 2];
      m[16 * c + 15] = 1;
      col.set(colourOf(xs[5 * c + 4], rgb), 3 * c);
    }
    this.mesh.count = count;
    this.mesh.instanceMatrix.needsUpdate = true;
    this.mesh.instanceColor.needsUpdate = true;
    this.el.dataset.spheres = String(count);
    this.buildLines(a, cut);
    this.buildContainer();
    this.applyClipping();
    this.updateSummary();
  }

  colouring(a, n) {
    if (state.colour === 'rattlers') return (i) => (a.rattlers[i] ? RATTLER : JAMMED);
    if (state.colour === 'contacts') {
      const zmax = Math.max(2 * this.dim + 2, extent(a.z)[1]);
      return (i, out) => ramp(VIRIDIS, a.z[i] / zmax, out);
    }
    if (state.colour === 'local_phi' && a.localPhi) {
      const [plo, phi] = extent(a.localPhi);
      const pspan = phi - plo > 1e-9 ? phi - plo : 0;
      return (i, out) => ramp(VIRIDIS, pspan > 0 ? (a.localPhi[i] - plo) / pspan : 0.55, out);
    }
    const [lo, hi] = extent(a.dia);
    const span = hi - lo > 1e-6 * hi ? hi - lo : 0;
    return (i, out) => ramp(VIRIDIS, span > 0 ? (a.dia[i] - lo) / span : 0.55, out);
  }

  buildLines(a, cut) {
    if (this.lines) { this.scene.remove(this.lines); this.lines.geometry.dispose(); this.lines = null; }
    if (!state.contacts) return;
    const d = this.dim;
    const pos = [];
    const col = [];
    let fmax = 0;
    if (a.forces) for (const f of a.forces) fmax = Math.max(fmax, f);
    const rgb = [0, 0, 0];
    const lift = this.flat ? 0.01 * Math.max(...this.L) : 0;
    for (let c = 0; c < a.pairs.length / 2; c++) {
      const i = a.pairs[2 * c], j = a.pairs[2 * c + 1];
      if (cut[i] <= 0 || cut[j] <= 0) continue;
      const xi = [0, 1, 2].map((ax) => (ax < d ? a.pos[i * d + ax] : 0));
      const dx = [0, 1, 2].map((ax) => (ax < d ? this.wrap(a.pos[j * d + ax] - xi[ax], ax) : 0));
      pos.push(xi[0], xi[1], xi[2] + lift, xi[0] + dx[0], xi[1] + dx[1], xi[2] + dx[2] + lift);
      const c3 = a.forces && fmax > 0 ? ramp(FORCE, a.forces[c] / fmax, rgb) : [0.19, 0.2, 0.25];
      col.push(...c3, ...c3);
    }
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.Float32BufferAttribute(pos, 3));
    g.setAttribute('color', new THREE.Float32BufferAttribute(col, 3));
    this.lines = new THREE.LineSegments(g, this.lineMaterial);
    this.lines.frustumCulled = false;
    this.scene.add(this.lines);
  }

  // The container as a wireframe over its first three axes (box, ball, shell, hemisphere-cut brick).
  buildContainer() {
    if (this.box) { this.scene.remove(this.box); this.box.geometry.dispose(); this.box = null; }
    if (!state.container) return;
    const L = [this.L[0], this.L[1], this.flat ? 0 : this.L[2]];
    const shape = this.data.container.shape;
    const seg = [];
    const line = (p, q) => seg.push(...p, ...q);
    const circle = (c, r, u, v, from = 0, to = 2 * Math.PI) => {
      const steps = 96;
      for (let s = 0; s < steps; s++) {
        const t0 = from + ((to - from) * s) / steps, t1 = from + ((to - from) * (s + 1)) / steps;
        const p = (t) => [0, 1, 2].map((k) => c[k] + r * (Math.cos(t) * u[k] + Math.sin(t) * v[k]));
        line(p(t0), p(t1));
      }
    };
    const X = [1, 0, 0], Y = [0, 1, 0], Z = [0, 0, 1];
    const boxEdges = () => {
      if (this.flat) {
        line([0, 0, 0], [L[0], 0, 0]); line([L[0], 0, 0], [L[0], L[1], 0]);
        line([L[0], L[1], 0], [0, L[1], 0]); line([0, L[1], 0], [0, 0, 0]);
        return;
      }
      for (const a of [0, L[0]]) for (const b of [0, L[1]]) line([a, b, 0], [a, b, L[2]]);
      for (const a of [0, L[0]]) for (const c of [0, L[2]]) line([a, 0, c], [a, L[1], c]);
      for (const b of [0, L[1]]) for (const c of [0, L[2]]) line([0, b, c], [L[0], b, c]);
    };
    // Radius of a ball over `axes` axes where the slice of axes 4.. cuts it.
    const sliced = (R, axes, centre) => {
      let off2 = 0;
      for (let k = 3; k < Math.min(axes, this.dim); k++) off2 += (state.extra[k - 3] - centre) ** 2;
      return Math.sqrt(Math.max(R * R - off2, 0));
    };
    const cylinder = (cx, cy, r) => {
      if (this.flat) { circle([cx, cy, 0], r, X, Y); return; }
      circle([cx, cy, 0], r, X, Y); circle([cx, cy, L[2]], r, X, Y);
      for (let s = 0; s < 8; s++) {
        const t = (s * Math.PI) / 4;
        const p = [cx + r * Math.cos(t), cy + r * Math.sin(t)];
        line([p[0], p[1], 0], [p[0], p[1], L[2]]);
      }
    };
    if (shape.kind === 'ball') {
      const R0 = L[0] / 2;
      if (shape.axes === 2 || this.flat) cylinder(R0, R0, R0);
      else {
        const R = sliced(R0, shape.axes, R0);
        const c = [R0, R0, R0];
        circle(c, R, X, Y); circle(c, R, X, Z); circle(c, R, Y, Z);
        for (const h of [-0.5, 0.5]) circle([R0, R0, R0 + h * R], R * Math.sqrt(0.75), X, Y);
      }
    } else if (shape.kind === 'cylindrical_shell') {
      const c = shape.outer_radius;
      cylinder(c, c, shape.inner_radius);
      cylinder(c, c, shape.outer_radius);
    } else if (shape.kind === 'hemisphere_cut_brick') {
      boxEdges();
      const [r0, r1] = shape.radii;
      const cy = L[1] / 2, cz = L[2] / 2;
      // Hemisphere of radius r0 on face x = 0 bulging into +x, r1 on x = L0 bulging into −x.
      for (const [x0, r, s] of [[0, r0, 1], [L[0], r1, -1]]) {
        const c = [x0, cy, this.flat ? 0 : cz];
        circle(c, r, [s, 0, 0], Y, -Math.PI / 2, Math.PI / 2);
        if (!this.flat) { circle(c, r, Y, Z); circle(c, r, [s, 0, 0], Z, -Math.PI / 2, Math.PI / 2); }
      }
    } else {
      boxEdges();
    }
    const walls = this.periodic.some((p) => !p) || shape.kind !== 'box';
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.Float32BufferAttribute(seg, 3));
    this.box = new THREE.LineSegments(g, new THREE.LineBasicMaterial({ color: walls ? 0x23272f : 0x8d99ae }));
    this.scene.add(this.box);
  }

  applyClipping() {
    const on = state.slice && !this.flat;
    const a = state.sliceAxis;
    this.clipPlane.normal.set(a === 0 ? -1 : 0, a === 1 ? -1 : 0, a === 2 ? -1 : 0);
    this.clipPlane.constant = state.slicePos * this.L[a];
    const planes = on ? [this.clipPlane] : [];
    this.material.clippingPlanes = planes;
    this.lineMaterial.clippingPlanes = planes;
    this.material.needsUpdate = true;
    this.lineMaterial.needsUpdate = true;
  }

  metrics() {
    const f = this.data.frames[this.frameIndex()];
    return f.metrics || null;
  }

  updateSummary() {
    const f = this.data.frames[this.frameIndex()];
    const m = f.metrics;
    let s = `${f.label}  φ = ${f.phi.toFixed(5)}`;
    if (m) s += `  z' = ${fixed(m.z_nonrattler, 3)}  rattlers ${m.rattlers}  iso_gap ${m.iso_gap}`;
    this.summary.textContent = s;
  }

  render() { this.renderer.render(this.scene, this.camera); }
}

function linkCameras(src) {
  syncing = true;
  for (const p of panels) {
    if (p === src || p.flat !== src.flat) continue;
    p.camera.position.copy(src.camera.position);
    p.camera.quaternion.copy(src.camera.quaternion);
    p.camera.zoom = src.camera.zoom;
    p.camera.updateProjectionMatrix();
    p.controls.target.copy(src.controls.target);
    p.render();
  }
  syncing = false;
}

// ---- layout and redraw ----
function redraw() {
  let total = 0;
  for (const p of panels) { p.build(); p.render(); total += Number(p.el.dataset.spheres); }
  document.documentElement.dataset.spheres = String(total);
  updateLegend();
  updateMetrics();
  updateTimeline();
}

function layout() {
  const k = panels.length;
  const cols = k <= 3 ? k : k <= 8 ? Math.ceil(k / 2) : Math.ceil(Math.sqrt(k));
  $('panels').style.gridTemplateColumns = `repeat(${cols}, minmax(0, 1fr))`;
  $('panels').style.gridTemplateRows = `repeat(${Math.ceil(k / cols)}, minmax(0, 1fr))`;
  for (const p of panels) { p.resize(); p.render(); }
}

function updateLegend() {
  const legend = $('legend');
  legend.replaceChildren();
  const p = panels[0];
  const a = p.arrays(p.frameIndex());
  let text;
  if (state.colour === 'rattlers') {
    text = ['non-rattler', 'rattler'];
    const sw = (c) => { const s = document.createElement('span'); s.style.cssText = `display:inline-block;width:12px;height:12px;background:rgb(${c.map((v) => Math.round(255 * v))})`; return s; };
    legend.append(sw(JAMMED), text[0], sw(RATTLER), text[1]);
    return;
  }
  const canvas = document.createElement('canvas');
  canvas.width = 150; canvas.height = 10;
  const g = canvas.getContext('2d');
  const rgb = [0, 0, 0];
  for (let x = 0; x < 150; x++) {
    ramp(VIRIDIS, x / 149, rgb);
    g.fillStyle = `rgb(${rgb.map((v) => Math.round(255 * v))})`;
    g.fillRect(x, 0, 1, 10);
  }
  const byPhi = state.colour === 'local_phi' && a.localPhi;
  const [dlo, dhi] = byPhi ? extent(a.localPhi) : extent(a.dia);
  const lo = state.colour === 'contacts' ? 0 : dlo;
  const hi = state.colour === 'contacts' ? Math.max(2 * p.dim + 2, extent(a.z)[1]) : dhi;
  const fmt = (v) => (state.colour === 'contacts' ? String(v) : v.toPrecision(3));
  legend.append(fmt(lo), canvas, fmt(hi), state.colour === 'contacts' ? 'contacts' : byPhi ? 'local φ' : 'D');
  if (state.contacts && a.forces) {
    const note = document.createElement('div');
    note.textContent = 'network: light → dark red = small → large force';
    legend.append(note);
  }
}

// Metrics serialised from non-finite numbers arrive as null.
const fixed = (v, k) => (v == null ? '—' : v.toFixed(k));
const sci = (v) => (v == null ? '—' : v.toExponential(2));
const ROWS = [
  ['method', (p) => p.data.method || '—'],
  ['termination', (p) => p.data.termination || '—'],
  ['N', (p, m) => m.n], ['d', (p, m) => m.dim],
  ['φ', (p, m) => fixed(m.phi, 6)],
  ['contacts', (p, m) => m.contacts],
  ['z (all)', (p, m) => fixed(m.z_mean, 3)],
  ["z' (non-rattlers)", (p, m) => fixed(m.z_nonrattler, 3)],
  ['rattlers', (p, m) => m.rattlers],
  ['N_dof', (p, m) => m.n_dof],
  ['iso_gap', (p, m) => `${m.iso_gap}${m.isostatic ? ' (isostatic)' : ''}`],
  ['max overlap', (p, m) => sci(m.max_overlap)],
  ['force balance', (p, m) => (m.force_balance == null ? 'not computed' : sci(m.force_balance))],
  ['polydispersity', (p, m) => fixed(m.polydispersity, 4)],
];

function updateMetrics() {
  const box = $('metrics');
  box.replaceChildren();
  const table = document.createElement('table');
  const head = table.insertRow();
  const th = (text) => { const c = document.createElement('th'); c.textContent = text; head.append(c); };
  th('');
  for (const p of panels) th(panels.length > 1 ? p.data.label : 'metrics');
  for (const [name, get] of ROWS) {
    const row = table.insertRow();
    row.insertCell().textContent = name;
    for (const p of panels) {
      const frames = p.data.frames;
      const m = p.metrics() || frames[frames.length - 1].metrics;
      row.insertCell().textContent = m ? String(get(p, m)) : '—';
    }
  }
  box.append(table);
  const p = panels[0];
  if (panels.length === 1 && !p.metrics()) {
    const note = document.createElement('p');
    note.textContent = 'Metrics are of the final packing; the current frame shows its φ and contacts.';
    box.append(note);
  }
  if (panels.length === 1 && p.data.parameters && typeof p.data.parameters === 'object') {
    const params = document.createElement('p');
    params.className = 'params';
    params.textContent = 'parameters: ' + Object.entries(p.data.parameters).map(([k, v]) => `${k}=${JSON.stringify(v)}`).join(', ');
    box.append(params);
  }
  const f = p.data.frames[p.frameIndex()];
  if (f.force_residual != null) {
    const note = document.createElement('p');
    note.textContent = `contact forces from the core's force balance (residual ${f.force_residual.toExponential(2)})`;
    box.append(note);
  }
}

// ---- timeline: frames of a run (with its φ and pressure/energy trace) or seeds of a comparison ----
function updateTimeline() {
  if (frameCount < 2) return;
  const p = panels[0];
  const f = p.data.frames[p.frameIndex()];
  $('frame').value = String(state.frame);
  $('frame-label').textContent = `${f.label}  (${state.frame + 1}/${frameCount})  φ = ${f.phi.toFixed(5)}`;
  drawTrace(p.data.trace, f.step);
}

function drawTrace(t, step) {
  const canvas = $('trace');
  if (DATA.frame_kind !== 'step' || !t || t.step.length < 2) { canvas.hidden = true; return; }
  canvas.hidden = false;
  const w = (canvas.width = Math.max(200, canvas.clientWidth));
  const h = canvas.height;
  const g = canvas.getContext('2d');
  g.clearRect(0, 0, w, h);
  const pad = { l: 56, r: 64, t: 8, b: 18 };
  const s0 = t.step[0], s1 = t.step[t.step.length - 1] || 1;
  const X = (s) => pad.l + ((s - s0) / Math.max(s1 - s0, 1e-12)) * (w - pad.l - pad.r);
  const series = (xs, ys, colour, log, label, side) => {
    if (ys.length < 2) return;
    const v = ys.map((y) => (log ? Math.log10(y) : y));
    const [lo, hi] = extent(v);
    const Y = (y) => h - pad.b - ((y - lo) / Math.max(hi - lo, 1e-12)) * (h - pad.t - pad.b);
    for (const [faint, upto] of [[true, Infinity], [false, step ?? Infinity]]) {
      g.strokeStyle = colour; g.globalAlpha = faint ? 0.25 : 1; g.lineWidth = faint ? 1 : 2;
      g.beginPath();
      let started = false;
      for (let k = 0; k < xs.length && xs[k] <= upto; k++) {
        if (!started) { g.moveTo(X(xs[k]), Y(v[k])); started = true; } else g.lineTo(X(xs[k]), Y(v[k]));
      }
      g.stroke();
    }
    g.globalAlpha = 1; g.fillStyle = colour; g.font = '11px monospace';
    const fmt = (y) => (log ? `1e${y.toFixed(1)}` : y.toPrecision(4));
    const x = side === 'l' ? 2 : w - pad.r + 4;
    g.fillText(fmt(hi), x, pad.t + 9); g.fillText(fmt(lo), x, h - pad.b);
    g.fillText(label, x, h / 2);
  };
  series(t.step, t.phi, '#2463b5', false, 'φ', 'l');
  if (t.value.length > 1) {
    const positive = t.value.every((y) => y > 0);
    const [vlo, vhi] = extent(t.value);
    const log = positive && vhi / vlo > 100;
    series(t.value_step, t.value, '#d9622b', log, t.label.slice(0, 9), 'r');
  }
  if (step != null) {
    g.strokeStyle = '#1d2230'; g.lineWidth = 1;
    g.beginPath(); g.moveTo(X(step), pad.t); g.lineTo(X(step), h - pad.b); g.stroke();
  }
  g.fillStyle = '#1d2230'; g.font = '11px monospace';
  g.fillText(`step ${s0}`, pad.l, h - 4); g.fillText(`${s1}`, w - pad.r - 40, h - 4);
}

let timer = null;
function setPlaying(on) {
  if (timer) { clearInterval(timer); timer = null; }
  $('play').textContent = on ? '❚❚' : '▶';
  if (!on) return;
  if (state.frame >= frameCount - 1) state.frame = 0;
  timer = setInterval(() => {
    if (state.frame >= frameCount - 1) { setPlaying(false); return; }
    state.frame += 1;
    redraw();
  }, 250);
}

function screenshot() {
  const rects = panels.map((p) => p.renderer.domElement.getBoundingClientRect());
  const x0 = Math.min(...rects.map((r) => r.left)), y0 = Math.min(...rects.map((r) => r.top));
  const scale = panels[0].renderer.getPixelRatio();
  const out = document.createElement('canvas');
  out.width = Math.ceil((Math.max(...rects.map((r) => r.right)) - x0) * scale);
  out.height = Math.ceil((Math.max(...rects.map((r) => r.bottom)) - y0) * scale);
  const g = out.getContext('2d');
  g.fillStyle = '#ffffff'; g.fillRect(0, 0, out.width, out.height);
  panels.forEach((p, k) => {
    p.render();
    const r = rects[k];
    g.drawImage(p.renderer.domElement, (r.left - x0) * scale, (r.top - y0) * scale, r.width * scale, r.height * scale);
    g.fillStyle = '#1d2230'; g.font = `${12 * scale}px sans-serif`;
    g.fillText(`${p.data.label}: ${p.summary.textContent}`, (r.left - x0 + 6) * scale, (r.top - y0 + 16) * scale);
  });
  const a = document.createElement('a');
  a.href = out.toDataURL('image/png');
  a.download = 'packbench-view.png';
  a.click();
}

// ---- start ----
$('title').textContent = DATA.title;
for (const data of DATA.panels) panels.push(new PanelView(data, $('panels')));
if (allFlat) $('slice-box').hidden = true;
if (panels.length > 1) $('link-box').hidden = false;
for (let k = 3; k < maxDim; k++) {
  const L = Math.max(...DATA.panels.filter((p) => p.dim > k).map((p) => p.container.lengths[k]));
  state.extra.push(L / 2);
  const label = document.createElement('label');
  const slider = document.createElement('input');
  Object.assign(slider, { type: 'range', min: 0, max: L, step: L / 500, value: L / 2 });
  const text = document.createElement('span');
  const show = () => { text.textContent = `slice x${k + 1} = ${Number(slider.value).toFixed(3)}`; };
  show();
  slider.addEventListener('input', () => { state.extra[k - 3] = Number(slider.value); show(); redraw(); });
  label.append(text, slider);
  $('extra-axes').append(label);
}
if (frameCount > 1) {
  $('timeline').hidden = false;
  $('frame').max = String(frameCount - 1);
  state.frame = frameCount - 1;
  $('frame').addEventListener('input', (e) => { state.frame = Number(e.target.value); redraw(); });
  $('play').addEventListener('click', () => setPlaying(!timer));
}
const bind = (id, key, parse) => $(id).addEventListener('input', (e) => { state[key] = parse(e.target); redraw(); });
bind('colour', 'colour', (el) => el.value);
bind('contacts', 'contacts', (el) => el.checked);
bind('container', 'container', (el) => el.checked);
bind('images', 'images', (el) => el.checked);
bind('slice', 'slice', (el) => el.checked);
bind('slice-axis', 'sliceAxis', (el) => Number(el.value));
bind('slice-pos', 'slicePos', (el) => Number(el.value));
$('link').addEventListener('input', (e) => { state.link = e.target.checked; });
$('reset').addEventListener('click', () => { for (const p of panels) { p.resetCamera(); p.render(); } });
$('screenshot').addEventListener('click', screenshot);
new ResizeObserver(layout).observe($('panels'));
layout();
redraw();
document.documentElement.dataset.loadMs = String(Math.round(performance.now()));
document.documentElement.dataset.ready = '1';
