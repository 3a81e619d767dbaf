// vbrain's web page: the model inlined in the page, an organ tree (show, hide, opacity per organ
// and group), click to name an organ, labels, a lesson's steps, and a quiz that reports its score
// to a learning platform (SCORM 1.2) where one hosts the page. Space: glTF (metres, +Y
// superior, +Z anterior); colours in the description are sRGB. Every text from the set is shown
// with textContent, never parsed as HTML.
import * as THREE from 'three';
import { GLTFLoader } from 'three/gltf-loader';
import { OrbitControls } from 'three/orbit-controls';

const data = JSON.parse(document.getElementById('vbrain-data').textContent);
const $ = (id) => document.getElementById(id);
$('title').textContent = data.title;

// The renderer keeps its image so that tests and screenshots can read it.
const view = $('view');
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true, stencil: true });
renderer.setPixelRatio(window.devicePixelRatio);
renderer.localClippingEnabled = true;
view.appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0x1e2128);
scene.add(new THREE.HemisphereLight(0xffffff, 0x3a3f4a, 2.2));
const key = new THREE.DirectionalLight(0xffffff, 1.6);
scene.add(key);
const camera = new THREE.PerspectiveCamera(30, 1, 0.001, 10);
scene.add(camera);
camera.add(key);
key.position.set(0.3, 0.5, 1);
const controls = new OrbitControls(camera, renderer.domElement);
controls.addEventListener('change', () => render());

/** An object's name as the model gives it (three.js keeps a sanitised copy in `name`). */
const nameOf = (n) => n.userData?.name ?? n.name;

/** id -> { mesh, material, extras, label, shown, opacity, ... } for each organ in the model. */
const organs = new Map();
let selected = null;

function decodeModel() {
  const text = document.getElementById('vbrain-glb').textContent.trim();
  const binary = atob(text);
  const bytes = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; i++) bytes[i] = binary.charCodeAt(i);
  return bytes.buffer;
}

function resize() {
  const w = view.parentElement.clientWidth, h = view.parentElement.clientHeight;
  renderer.setSize(w, h);
  camera.aspect = w / Math.max(h, 1);
  camera.updateProjectionMatrix();
  render();
}

// A still view with faded organs converges: frames drawn with the camera moved by less than a
// pixel are averaged (hashed alpha differs from frame to frame), up to ACCUMULATED frames. Any
// change draws one plain frame at once and starts again.
const ACCUMULATED = 32;
const accumulation = { frame: 0, scheduled: false, drawn: null, sum: null, waiting: [] };
/** Resolves once the view has stopped refining (at once when it is not refining). */
function settled() {
  return new Promise((resolve) => {
    if (accumulation.scheduled) accumulation.waiting.push(resolve);
    else resolve();
  });
}
function refined() {
  for (const resolve of accumulation.waiting.splice(0)) resolve();
}
// Hashed alpha's pattern is fixed on the surface; each accumulated frame moves it by a seed, so
// that the average converges to the opacity instead of keeping one grain.
const hashSeed = { value: new THREE.Vector3() };
function seedHash(shader) {
  shader.uniforms.hashSeed = hashSeed;
  shader.fragmentShader = 'uniform vec3 hashSeed;\n' +
    shader.fragmentShader.replace('getAlphaHashThreshold( vPosition )', 'getAlphaHashThreshold( vPosition + hashSeed )');
}
const quad = new THREE.Mesh(new THREE.PlaneGeometry(2, 2));
const quadScene = new THREE.Scene();
quadScene.add(quad);
const quadCamera = new THREE.OrthographicCamera(-1, 1, 1, -1, 0, 1);
const average = new THREE.ShaderMaterial({
  uniforms: { map: { value: null }, weight: { value: 1 } },
  vertexShader: 'varying vec2 vUv; void main() { vUv = uv; gl_Position = vec4(position.xy, 0.0, 1.0); }',
  fragmentShader:
    'uniform sampler2D map; uniform float weight; varying vec2 vUv;\n' +
    'void main() { gl_FragColor = vec4(texture2D(map, vUv).rgb, weight); }',
  blending: THREE.CustomBlending,
  blendSrc: THREE.SrcAlphaFactor,
  blendDst: THREE.OneMinusSrcAlphaFactor,
  depthTest: false,
  depthWrite: false,
});
const show = new THREE.MeshBasicMaterial({ depthTest: false, depthWrite: false });

// Cut faces: where a step's planes cut an organ, its inside shows as a solid face in its colour,
// as in the viewer (the stencil method): along each pixel's ray the organ's back faces on the kept
// side add one and its front faces take one away, so the count is odd where the plane lies inside
// the organ; a plane drawn there in the organ's colour (faded as the organ is) is the cut face.
const caps = new THREE.Group();
scene.add(caps);
let capsWanted = { planes: [], whole: [] };
let capsDirty = false;
let capsShown = true;

function buildCaps() {
  capsDirty = false;
  for (const c of caps.children) c.material.dispose();
  caps.clear();
  if (!capsShown) return;
  const { planes, whole } = capsWanted;
  let order = 1;
  for (const plane of planes) {
    const others = planes.filter((p) => p !== plane);
    for (const o of organs.values()) {
      if (!o.mesh.visible || whole.includes(o.id)) continue;
      o.mesh.updateMatrixWorld();
      for (const [side, op] of [[THREE.BackSide, THREE.IncrementWrapStencilOp], [THREE.FrontSide, THREE.DecrementWrapStencilOp]]) {
        const count = new THREE.MeshBasicMaterial({
          side, clippingPlanes: [plane], depthWrite: false, depthTest: false, colorWrite: false,
          stencilWrite: true, stencilFunc: THREE.AlwaysStencilFunc, stencilFail: op, stencilZFail: op, stencilZPass: op,
        });
        const mesh = new THREE.Mesh(o.mesh.geometry, count);
        mesh.matrixAutoUpdate = false;
        mesh.matrix.copy(o.mesh.matrixWorld);
        mesh.renderOrder = order;
        caps.add(mesh);
      }
      const face = new THREE.MeshLambertMaterial({
        color: o.material.color, side: THREE.DoubleSide, clippingPlanes: others,
        opacity: o.opacity, alphaHash: o.opacity < 1,
        stencilWrite: true, stencilRef: 0, stencilFunc: THREE.NotEqualStencilFunc,
        stencilFail: THREE.ReplaceStencilOp, stencilZFail: THREE.ReplaceStencilOp, stencilZPass: THREE.ReplaceStencilOp,
      });
      face.onBeforeCompile = seedHash;
      const cap = new THREE.Mesh(new THREE.PlaneGeometry(2, 2), face);
      plane.coplanarPoint(cap.position);
      cap.lookAt(cap.position.clone().sub(plane.normal));
      cap.renderOrder = order + 0.5;
      cap.onAfterRender = (r) => r.clearStencil();
      caps.add(cap);
      order += 1;
    }
  }
}

function render() {
  if (capsDirty) buildCaps();
  camera.clearViewOffset();
  renderer.setRenderTarget(null);
  renderer.render(scene, camera);
  placeLabels();
  accumulation.frame = 0;
  const faded = [...organs.values()].some((o) => o.mesh.visible && o.opacity < 1);
  if (faded && !accumulation.scheduled) {
    accumulation.scheduled = true;
    requestAnimationFrame(refine);
  } else if (!faded) {
    refined();
  }
}

/** Adds one jittered frame to the average and shows it. */
function refine() {
  accumulation.scheduled = false;
  const size = renderer.getDrawingBufferSize(new THREE.Vector2());
  for (const key of ['drawn', 'sum']) {
    const t = accumulation[key];
    if (!t || t.width !== size.x || t.height !== size.y) {
      t?.dispose();
      accumulation[key] = new THREE.WebGLRenderTarget(size.x, size.y, {
        type: THREE.HalfFloatType, samples: 4, stencilBuffer: true,
      });
    }
  }
  const k = accumulation.frame;
  // Offsets in a quasi-random (R2) sequence within a pixel.
  const jitter = [((k * 0.7548776662) % 1) - 0.5, ((k * 0.5698402909) % 1) - 0.5];
  camera.setViewOffset(size.x, size.y, k === 0 ? 0 : jitter[0], k === 0 ? 0 : jitter[1], size.x, size.y);
  hashSeed.value.set((k * 0.7548776662) % 1, (k * 0.5698402909) % 1, (k * 0.3819660113) % 1);
  renderer.setRenderTarget(accumulation.drawn);
  renderer.render(scene, camera);
  camera.clearViewOffset();
  hashSeed.value.set(0, 0, 0);
  average.uniforms.map.value = accumulation.drawn.texture;
  average.uniforms.weight.value = 1 / (k + 1);
  quad.material = average;
  renderer.setRenderTarget(accumulation.sum);
  renderer.autoClear = false;
  renderer.render(quadScene, quadCamera);
  renderer.autoClear = true;
  if (show.map !== accumulation.sum.texture) {
    show.map = accumulation.sum.texture;
    show.needsUpdate = true;
  }
  quad.material = show;
  renderer.setRenderTarget(null);
  renderer.render(quadScene, quadCamera);
  accumulation.frame = k + 1;
  if (accumulation.frame < ACCUMULATED && !accumulation.scheduled) {
    accumulation.scheduled = true;
    requestAnimationFrame(refine);
  } else if (!accumulation.scheduled) {
    refined();
  }
}

// Opacity: below 1, hashed alpha (order-independent screen-door), with depth as for opaque organs.
function setOpacity(o, a) {
  o.opacity = a;
  const m = o.material;
  m.opacity = a;
  m.transparent = false;
  m.depthWrite = true;
  m.alphaHash = a < 1;
  m.onBeforeCompile = seedHash;
  m.needsUpdate = true;
  o.mesh.visible = o.shown && a > 0;
  capsDirty = true;
  if (o.slider) o.slider.value = a;
}

function setShown(o, shown) {
  o.shown = shown;
  o.mesh.visible = shown && o.opacity > 0;
  capsDirty = true;
  if (o.checkbox) o.checkbox.checked = shown;
}

function refreshGroups() {
  for (const g of groups) {
    const list = g.members.map((id) => organs.get(id));
    g.checkbox.checked = list.every((o) => o.shown);
    g.checkbox.indeterminate = !g.checkbox.checked && list.some((o) => o.shown);
    g.slider.value = Math.max(...list.map((o) => o.opacity));
  }
}

function select(id) {
  if (selected) organs.get(selected).material.emissive.setHex(organs.get(selected).emissive);
  selected = id;
  for (const o of organs.values()) o.nameElement?.classList.toggle('selected', o.id === id);
  const box = $('info');
  if (!id) {
    box.style.display = 'none';
    render();
    return;
  }
  const o = organs.get(id);
  o.material.emissive.setHex(0x1f4a70);
  $('selected-name').textContent = o.label;
  $('selected-latin').textContent = o.extras.latin || '';
  $('selected-info').textContent = o.extras.info || '';
  box.style.display = 'block';
  render();
}

// The organ tree, from the model's nodes: groups are nodes without a mesh.
const groups = [];
function buildTree(node, parent) {
  for (const child of node.children) {
    const id = child.userData?.id;
    if (id !== undefined && organs.has(id)) {
      const o = organs.get(id);
      const row = document.createElement('div');
      row.className = 'organ';
      o.checkbox = document.createElement('input');
      o.checkbox.type = 'checkbox';
      o.checkbox.checked = o.shown;
      o.checkbox.setAttribute('aria-label', 'Show ' + o.label);
      o.checkbox.addEventListener('change', () => { setShown(o, o.checkbox.checked); refreshGroups(); render(); });
      o.slider = slider('Opacity of ' + o.label, o.opacity, (a) => { setOpacity(o, a); render(); });
      o.nameElement = document.createElement('span');
      o.nameElement.className = 'name';
      o.nameElement.textContent = o.label;
      o.nameElement.title = o.label;
      o.nameElement.addEventListener('click', () => select(o.id));
      row.append(o.checkbox, o.slider, o.nameElement);
      parent.appendChild(row);
    } else if (child.isObject3D && child.children.length > 0) {
      const details = document.createElement('details');
      details.open = groups.length < 3;
      const summary = document.createElement('summary');
      const box = document.createElement('input');
      box.type = 'checkbox';
      box.setAttribute('aria-label', 'Show group ' + nameOf(child));
      const name = document.createElement('span');
      name.className = 'name';
      name.textContent = nameOf(child);
      name.title = nameOf(child);
      const members = [];
      child.traverse((n) => { if (n.userData?.id !== undefined && organs.has(n.userData.id)) members.push(n.userData.id); });
      box.addEventListener('click', (e) => e.stopPropagation());
      box.addEventListener('change', () => {
        for (const m of members) setShown(organs.get(m), box.checked);
        refreshGroups();
        render();
      });
      const range = slider('Opacity of group ' + nameOf(child), 1, (a) => {
        for (const m of members) setOpacity(organs.get(m), a);
        render();
      });
      range.addEventListener('click', (e) => e.stopPropagation());
      groups.push({ checkbox: box, members, slider: range });
      summary.append(box, range, name);
      details.appendChild(summary);
      parent.appendChild(details);
      buildTree(child, details);
    }
  }
}

function slider(label, value, changed) {
  const s = document.createElement('input');
  s.type = 'range';
  s.min = 0;
  s.max = 1;
  s.step = 0.05;
  s.value = value;
  s.setAttribute('aria-label', label);
  s.addEventListener('input', () => changed(parseFloat(s.value)));
  return s;
}

// Labels: each labelled organ's anchor is the vertex nearest the middle of its front-facing,
// uncut vertices; tags are laid out top to bottom, each moved clear of those placed before it,
// with a leader line to its anchor.
let labelled = [];

/** The anchor of organ `o` in world space, or null where none of it faces the camera. */
function anchorOf(o) {
  const positions = o.mesh.geometry.attributes.position;
  const normals = o.mesh.geometry.attributes.normal;
  const world = o.mesh.matrixWorld;
  const turn = new THREE.Matrix3().getNormalMatrix(world);
  const planes = o.material.clippingPlanes ?? [];
  const step = Math.max(1, Math.floor(positions.count / 3000));
  const front = [];
  const p = new THREE.Vector3(), n = new THREE.Vector3(), toEye = new THREE.Vector3();
  for (let i = 0; i < positions.count; i += step) {
    p.fromBufferAttribute(positions, i).applyMatrix4(world);
    n.fromBufferAttribute(normals, i).applyMatrix3(turn);
    if (n.dot(toEye.subVectors(camera.position, p)) > 0 && planes.every((q) => q.distanceToPoint(p) >= 0)) {
      front.push(p.clone());
    }
  }
  if (front.length === 0) return null;
  const middle = front.reduce((sum, q) => sum.add(q), new THREE.Vector3()).divideScalar(front.length);
  return front.reduce((best, q) => (q.distanceToSquared(middle) < best.distanceToSquared(middle) ? q : best));
}

function placeLabels() {
  const layer = $('labels');
  layer.replaceChildren();
  const w = renderer.domElement.clientWidth, h = renderer.domElement.clientHeight;
  const anchors = [];
  for (const id of labelled) {
    const o = organs.get(id);
    const at = o && o.mesh.visible ? anchorOf(o) : null;
    if (!at) continue;
    const p = at.project(camera);
    if (p.z > 1 || Math.abs(p.x) > 1 || Math.abs(p.y) > 1) continue;
    anchors.push({ o, x: ((p.x + 1) / 2) * w, y: ((1 - p.y) / 2) * h });
  }
  anchors.sort((a, b) => a.y - b.y);
  const lines = document.createElementNS('http://www.w3.org/2000/svg', 'svg');
  lines.setAttribute('width', w);
  lines.setAttribute('height', h);
  layer.appendChild(lines);
  const placed = [];
  const overlaps = (r) => placed.some((q) => r.x < q.x + q.w + 4 && q.x < r.x + r.w + 4 && r.y < q.y + q.h + 2 && q.y < r.y + r.h + 2);
  for (const a of anchors) {
    const tag = document.createElement('div');
    tag.className = 'label';
    tag.textContent = a.o.label;
    layer.appendChild(tag);
    const r = { w: tag.offsetWidth, h: tag.offsetHeight };
    r.x = Math.min(Math.max(a.x - r.w / 2, 0), w - r.w);
    // Above the anchor, else further up or down, a row at a time, until clear of the others.
    const rows = [-1.6, -2.8, 0.8, -4.0, 2.0, -5.2, 3.2, -6.4, 4.4];
    const free = rows.map((k) => ({ ...r, y: a.y + k * r.h })).find((c) => c.y >= 0 && c.y + c.h <= h && !overlaps(c));
    if (!free) {
      tag.remove();
      continue;
    }
    placed.push(free);
    tag.style.left = free.x + 'px';
    tag.style.top = free.y + 'px';
    const line = document.createElementNS('http://www.w3.org/2000/svg', 'line');
    const end = free.y + free.h / 2 < a.y ? free.y + free.h : free.y;
    for (const [k, v] of [['x1', a.x], ['y1', a.y], ['x2', Math.min(Math.max(a.x, free.x), free.x + free.w)], ['y2', end]]) {
      line.setAttribute(k, v);
    }
    const dot = document.createElementNS('http://www.w3.org/2000/svg', 'circle');
    for (const [k, v] of [['cx', a.x], ['cy', a.y], ['r', 2.5]]) dot.setAttribute(k, v);
    lines.append(line, dot);
  }
}

// A view: the organs' visibility, opacity, colour and placement, the camera, outlines, labels, cuts.
function showView(v) {
  for (const [id, s] of Object.entries(v.organs)) {
    const o = organs.get(id);
    if (!o) continue;
    setShown(o, s.visible);
    setOpacity(o, s.opacity);
    // Territory colouring: the model's vertex colours (on a white material) where it has them.
    const tinted = v.territories && o.mesh.geometry.hasAttribute('color');
    o.material.vertexColors = tinted;
    if (tinted) o.material.color.setRGB(1, 1, 1);
    else o.material.color.setRGB(s.colour[0], s.colour[1], s.colour[2], THREE.SRGBColorSpace);
    o.emissive = v.highlight.includes(id) ? 0x5a3a00 : 0x000000;
    o.material.emissive.setHex(o.emissive);
    if (s.matrix) o.mesh.matrix.fromArray(s.matrix);
    else o.mesh.matrix.identity();
    o.mesh.matrix.decompose(o.mesh.position, o.mesh.quaternion, o.mesh.scale);
  }
  const clipPlanes = v.clip.map((p) => new THREE.Plane(new THREE.Vector3(...p.normal), p.constant));
  for (const o of organs.values()) {
    o.material.clippingPlanes = v.whole.includes(o.id) ? [] : clipPlanes;
    o.material.needsUpdate = true;
  }
  capsWanted = { planes: clipPlanes, whole: v.whole };
  capsDirty = true;
  labelled = v.labels;
  camera.position.set(...v.camera.eye);
  camera.up.set(...v.camera.up);
  camera.fov = v.camera.fov;
  controls.target.set(...v.camera.target);
  camera.updateProjectionMatrix();
  controls.update();
  refreshGroups();
  select(v.selection && organs.has(v.selection) ? v.selection : null);
}

/**
 * A caption's Markdown, the subset the viewer draws: paragraphs (between blank lines), lines
 * starting "- " as a list, **bold** and *italic* runs. Built from elements and text nodes, never
 * parsed as HTML.
 */
function setCaption(element, text) {
  element.replaceChildren();
  for (const paragraph of text.split(/\n\s*\n/)) {
    let list = null;
    let para = null;
    for (const line of paragraph.split('\n')) {
      if (!line.trim()) continue;
      const item = line.match(/^- (.*)$/);
      if (item) {
        if (!list) {
          list = element.appendChild(document.createElement('ul'));
          para = null;
        }
        appendRuns(list.appendChild(document.createElement('li')), item[1]);
      } else {
        list = null;
        if (para) para.appendChild(document.createTextNode(' '));
        else para = element.appendChild(document.createElement('p'));
        appendRuns(para, line);
      }
    }
  }
}

/** A line's runs, split at "**" (bold on or off) and "*" (italic on or off), as the viewer does. */
function appendRuns(element, line) {
  let bold = false;
  let italic = false;
  let run = '';
  const flush = () => {
    if (!run) return;
    let node = document.createTextNode(run);
    if (italic) node = wrap('em', node);
    if (bold) node = wrap('strong', node);
    element.appendChild(node);
    run = '';
  };
  for (let i = 0; i < line.length; i++) {
    if (line[i] !== '*') {
      run += line[i];
      continue;
    }
    flush();
    if (line[i + 1] === '*') {
      bold = !bold;
      i++;
    } else {
      italic = !italic;
    }
  }
  flush();
}

function wrap(tag, node) {
  const element = document.createElement(tag);
  element.appendChild(node);
  return element;
}

let step = 0;
function showStep(k) {
  step = Math.max(0, Math.min(data.views.length - 1, k));
  const v = data.views[step];
  showView(v);
  $('step-title').textContent = v.title;
  setCaption($('caption'), v.caption);
  $('step-count').textContent = `${step + 1} / ${data.views.length}`;
  $('previous').disabled = step === 0;
  $('next').disabled = step === data.views.length - 1;
}

/** The organ drawn first at a point of the view (normalised device coordinates), or null. */
function pick(ndc) {
  const ray = new THREE.Raycaster();
  ray.setFromCamera(ndc, camera);
  const visible = [...organs.values()].filter((o) => o.mesh.visible).map((o) => o.mesh);
  const kept = (h) => (h.object.material.clippingPlanes ?? []).every((p) => p.distanceToPoint(h.point) >= 0);
  const hit = ray.intersectObjects(visible, false).find(kept);
  return hit ? hit.object.userData.id : null;
}

// Click (not drag) to name an organ, or to answer a locate question.
let down = null;
renderer.domElement.addEventListener('pointerdown', (e) => { down = [e.clientX, e.clientY]; });
renderer.domElement.addEventListener('pointerup', (e) => {
  if (!down || Math.hypot(e.clientX - down[0], e.clientY - down[1]) > 4) return;
  const r = renderer.domElement.getBoundingClientRect();
  const id = pick(new THREE.Vector2(((e.clientX - r.left) / r.width) * 2 - 1, -((e.clientY - r.top) / r.height) * 2 + 1));
  if (quizAsks('locate')) {
    if (id) answer(id);
  } else {
    select(id);
  }
});

/**
 * A point of the canvas (CSS pixels from its top left), not covered by a panel, where organ `id`
 * is what a click picks, or null: for tests, which click there as a student would.
 */
function pointOn(id) {
  const o = organs.get(id);
  if (!o || !o.mesh.visible) return null;
  const g = o.mesh.geometry, position = g.attributes.position, index = g.index;
  const triangles = index ? index.count / 3 : position.count / 3;
  const corner = (t, k) => new THREE.Vector3().fromBufferAttribute(position, index ? index.getX(3 * t + k) : 3 * t + k);
  const r = renderer.domElement.getBoundingClientRect();
  const step = Math.max(1, Math.floor(triangles / 2000));
  for (let t = 0; t < triangles; t += step) {
    const centre = corner(t, 0).add(corner(t, 1)).add(corner(t, 2)).divideScalar(3).applyMatrix4(o.mesh.matrixWorld);
    const ndc = centre.project(camera);
    if (Math.abs(ndc.x) > 0.95 || Math.abs(ndc.y) > 0.95 || ndc.z > 1) continue;
    const at = { x: ((ndc.x + 1) / 2) * r.width, y: ((1 - ndc.y) / 2) * r.height };
    const uncovered = document.elementFromPoint(r.left + at.x, r.top + at.y) === renderer.domElement;
    if (uncovered && pick(new THREE.Vector2(ndc.x, ndc.y)) === id) return at;
  }
  return null;
}

// The quiz: each question shows its view (what hides the structure faded; a name question's
// structure outlined) and asks to click the structure or to pick its name; then the score and
// the missed structures. On a learning platform (a SCORM 1.2 API on a parent or opener window)
// the page reports the score and passed or failed against the pass mark, and finishes.
const quiz = { k: -1, score: 0, answered: true, missed: [] };
const scorm = { api: findScormApi(), open: false };

function findScormApi() {
  const search = (w) => {
    for (let i = 0; w && i < 16; i++) {
      try {
        if (w.API) return w.API;
      } catch (e) {
        return null; // a window of another origin
      }
      if (w.parent === w) break;
      w = w.parent;
    }
    return null;
  };
  return search(window) ?? (window.opener ? search(window.opener) : null);
}

function quizAsks(kind) {
  return quiz.k >= 0 && !quiz.answered && data.quiz.questions[quiz.k].kind === kind;
}

const lowerFirst = (s) => s.charAt(0).toLowerCase() + s.slice(1);

function startQuiz() {
  Object.assign(quiz, { k: 0, score: 0, missed: [] });
  $('lesson').style.display = 'none';
  $('quiz').style.display = 'block';
  $('quiz-review').replaceChildren();
  $('quiz-next').style.display = '';
  askQuestion();
}

function askQuestion() {
  const q = data.quiz.questions[quiz.k];
  quiz.answered = false;
  showView(q.view);
  select(null);
  const n = data.quiz.questions.length;
  $('quiz-count').textContent = `Question ${quiz.k + 1} of ${n}`;
  $('quiz-question').textContent =
    q.kind === 'locate' ? `Click the ${lowerFirst(q.organ.name)}.` : 'Name the outlined structure.';
  const choices = $('quiz-choices');
  choices.replaceChildren();
  if (q.kind === 'name') {
    for (const c of q.choices) {
      const b = choices.appendChild(document.createElement('button'));
      b.textContent = c.name;
      b.addEventListener('click', () => answer(c.id));
    }
  }
  $('quiz-feedback').textContent = '';
  $('quiz-next').disabled = true;
  $('quiz-next').textContent = quiz.k + 1 < n ? 'Next question' : 'See the score';
}

function answer(id) {
  if (quiz.answered) return;
  quiz.answered = true;
  const q = data.quiz.questions[quiz.k];
  const right = id === q.organ.id;
  if (right) quiz.score++;
  else quiz.missed.push(q.organ);
  const target = lowerFirst(q.organ.name);
  const got = lowerFirst(organs.get(id)?.label ?? q.choices.find((c) => c.id === id)?.name ?? id);
  $('quiz-feedback').textContent = right
    ? `Right: the ${target}.`
    : q.kind === 'locate'
      ? `No: that is the ${got}. The ${target} is shown in blue.`
      : `No: this is the ${target}, shown in blue.`;
  // The answer selected: tinted blue, its name and text beside the view.
  select(q.organ.id);
  for (const b of $('quiz-choices').querySelectorAll('button')) b.disabled = true;
  $('quiz-next').disabled = false;
  render();
}

function nextQuestion() {
  if (quiz.k + 1 < data.quiz.questions.length) {
    quiz.k++;
    askQuestion();
  } else {
    finishQuiz();
  }
}

function finishQuiz() {
  const n = data.quiz.questions.length;
  const percent = Math.round((100 * quiz.score) / n);
  const passed = percent >= data.quiz.passMark;
  quiz.k = -1;
  $('quiz-count').textContent = 'Done';
  $('quiz-question').textContent =
    `Score: ${quiz.score} of ${n} (${percent} %), ${passed ? 'passed' : 'not passed'} (pass mark ${data.quiz.passMark} %).`;
  $('quiz-choices').replaceChildren();
  $('quiz-feedback').textContent = quiz.missed.length ? 'Missed (click one to see it):' : 'Nothing missed.';
  const review = $('quiz-review');
  review.replaceChildren();
  for (const m of quiz.missed) {
    const b = review.appendChild(document.createElement('button'));
    b.textContent = m.name;
    b.addEventListener('click', () => {
      const o = organs.get(m.id);
      if (o) {
        setShown(o, true);
        setOpacity(o, 1);
      }
      select(m.id);
    });
  }
  $('quiz-next').style.display = 'none';
  if (scorm.open) {
    const set = (key, value) => scorm.api.LMSSetValue(key, String(value));
    set('cmi.core.score.raw', percent);
    set('cmi.core.score.min', 0);
    set('cmi.core.score.max', 100);
    set('cmi.core.lesson_status', passed ? 'passed' : 'failed');
    scorm.api.LMSCommit('');
    scorm.api.LMSFinish('');
    scorm.open = false;
    $('quiz-feedback').textContent += ' Your score was sent to the course.';
  }
}

function closeQuiz() {
  quiz.k = -1;
  quiz.answered = true;
  $('quiz').style.display = 'none';
  if (data.lesson) {
    $('lesson').style.display = 'block';
    showStep(step);
  } else {
    showView(data.views[0]);
  }
}

new GLTFLoader().parse(decodeModel(), '', (gltf) => {
  const root = gltf.scene;
  root.traverse((n) => {
    if (n.isMesh && n.userData?.id !== undefined) {
      n.matrixAutoUpdate = true;
      organs.set(n.userData.id, {
        id: n.userData.id, mesh: n, material: n.material, extras: n.userData, label: nameOf(n),
        shown: true, opacity: n.material.opacity, emissive: 0x000000,
      });
    }
  });
  for (const o of organs.values()) setOpacity(o, o.opacity);
  scene.add(root);
  buildTree(root.children[0] ?? root, $('tree'));
  $('show-all').addEventListener('click', () => {
    for (const o of organs.values()) setShown(o, true);
    refreshGroups();
    render();
  });
  $('loading').remove();
  if (data.lesson) {
    $('lesson').style.display = 'block';
    $('previous').addEventListener('click', () => showStep(step - 1));
    $('next').addEventListener('click', () => showStep(step + 1));
    document.addEventListener('keydown', (e) => {
      if (quiz.k >= 0) return;
      if (e.key === 'PageDown' || e.key === 'ArrowRight') showStep(step + 1);
      if (e.key === 'PageUp' || e.key === 'ArrowLeft') showStep(step - 1);
    });
    showStep(0);
  } else {
    showView(data.views[0]);
  }
  if (data.quiz) {
    $('quiz-start').hidden = false;
    $('quiz-start').textContent = `Take the quiz (${data.quiz.questions.length} questions)`;
    $('quiz-start').addEventListener('click', startQuiz);
    $('quiz-next').addEventListener('click', nextQuestion);
    $('quiz-close').addEventListener('click', closeQuiz);
    if (scorm.api) {
      scorm.open = String(scorm.api.LMSInitialize('')) === 'true';
      window.addEventListener('pagehide', () => {
        if (scorm.open) scorm.api.LMSFinish('');
        scorm.open = false;
      });
    }
  }
  window.addEventListener('resize', resize);
  resize();
  // For tests: the cut faces on or off; the question asked; where to click an organ.
  const setCaps = (on) => { capsShown = on; capsDirty = true; render(); };
  const question = () => (quiz.k >= 0 ? data.quiz.questions[quiz.k] : null);
  window.vbrain = { render, settled, organs: organs.size, setCaps, step: (k) => showStep(k), question, pointOn };
  document.body.dataset.ready = '1';
}, (error) => {
  $('loading').textContent = 'The model could not be read: ' + error;
});
