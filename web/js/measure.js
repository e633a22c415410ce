// Measurements (docs/viewer.md, "Measurements"): the ruler, angle, ellipse and polygon tools of
// the 2-D views and the 3-D ruler (two picked points), kept as the scene's `annotations` (an
// `annotations` message: one document edit, a step of the undo history), drawn over the 2-D views
// and listed in the panel with what the server measures (`measure`: lengths, angles, and ROI
// statistics over the voxels in world space).
import {projector} from './clip_outlines.js';
import {queueInput, send} from './connection.js';
import {annotationsCommitted} from './history.js';
import {S} from './state.js';
import {fmt} from './vec.js';

// Points each tool takes before it is done (a polygon: until its first corner is clicked again
// or Enter is pressed).
const NEEDS = {ruler: 2, angle: 3, ellipse: 2, polygon: Infinity, ruler3d: 2};
const MAX_POLYGON_POINTS = 256;  // as the scene parser's cap
const MAX_LABEL_BYTES = 200;    // as the scene parser's cap
const CLOSE_RADIUS = 8;          // CSS pixels from the first corner that close a polygon
const COLOUR = '#ffa726';

let draft = null;           // {tool, axis, points: [[3], ...]} being placed
let serverList = [];        // the annotations as the server last said (hello, state)
const results = new Map();  // JSON of an annotation -> the server's measurement of it
const asked = new Set();    // annotations whose measurement is on its way
let redraw = () => {};      // slices.js: draws every 2-D view's overlay again
let measureSeq = 1;

S.annotations = [];
S.measureTool = 'none';

const keyOf = (a) => JSON.stringify([a.kind, a.points, a.volume || '']);

export function setupMeasure(redrawViews) {
  redraw = redrawViews;
  const tool = document.getElementById('measure-tool');
  tool.addEventListener('change', () => setTool(tool.value));
  window.addEventListener('keydown', (ev) => {
    if (!draft) return;
    if (ev.key === 'Escape') {
      draft = null;
      redraw();
    } else if (ev.key === 'Enter' && draft.tool === 'polygon' && draft.points.length >= 3) {
      finish();
    }
  });
}

export function setTool(name) {
  S.measureTool = name in NEEDS ? name : 'none';
  document.getElementById('measure-tool').value = S.measureTool;
  draft = null;
  redraw();
}

// The server's list (hello, and every state): the page's own unless an edit of it is on its way.
export function takeAnnotations(list) {
  if (!Array.isArray(list)) return;
  serverList = list.map(copy);
  if (![...S.pending.keys()].includes('annotations')) S.annotations = serverList.map(copy);
  measureMissing();
  showList();
  redraw();
}

// A refused edit (an error): back to what the server has.
export function annotationsRefused() {
  S.annotations = serverList.map(copy);
  showList();
  redraw();
}

const copy = (a) => JSON.parse(JSON.stringify(a));

// Replaces the scene's annotations: one document edit, and (unless an undo or redo replays it)
// one step of the history.
export function setAnnotations(list, record = true) {
  const before = S.annotations.map(copy);
  S.annotations = list.map(copy);
  queueInput('annotations', {type: 'annotations', annotations: S.annotations.map(copy)}, false);
  if (record) annotationsCommitted(before, S.annotations.map(copy));
  measureMissing();
  showList();
  redraw();
}

const askedBySeq = new Map();  // a measure message's seq -> the keys it asked for, in order

function measureMissing() {
  const missing = S.annotations.filter((a) => !results.has(keyOf(a)) && !asked.has(keyOf(a)));
  for (let i = 0; i < missing.length; i += 64) {  // the server's cap per message
    const part = missing.slice(i, i + 64);
    const seq = measureSeq++;
    askedBySeq.set(seq, part.map(keyOf));
    for (const a of part) asked.add(keyOf(a));
    send({type: 'measure', seq, annotations: part});
  }
}

// A `measure` answer: the measurements of the annotations its message asked for, in order.
export function onMeasure(m) {
  const keys = askedBySeq.get(m.seq) || [];
  askedBySeq.delete(m.seq);
  (m.measurements || []).forEach((r, i) => {
    if (i >= keys.length) return;
    results.set(keys[i], r);
    asked.delete(keys[i]);
  });
  S.lastMeasureMs = m.ms;
  showList();
  redraw();
}

// A refused measure message (an error): asked again with the next edit.
export function measureRefused() {
  askedBySeq.clear();
  asked.clear();
}

// What an annotation measures, as text ('…' until the server answers).
export function measurementText(a) {
  const r = results.get(keyOf(a));
  if (!r) return '…';
  if (a.kind === 'ruler') return `${fmt(r.length_mm, 2)} mm`;
  if (a.kind === 'angle') return r.angle_deg === null ? '—' : `${fmt(r.angle_deg, 1)}°`;
  let t = `${fmt(r.area_mm2, 1)} mm²`;
  if (r.voxels > 0)
    t += `, mean ${Number(r.mean.toPrecision(5))} ± ${Number(r.sd.toPrecision(4))}` +
         `${r.units ? ' ' + r.units : ''}, min ${Number(r.min.toPrecision(5))}, ` +
         `max ${Number(r.max.toPrecision(5))}, ${r.voxels} voxels`;
  return t;
}

// What the views write beside an annotation: its label, then what it measures.
const labelText = (a) => (a.label ? `${a.label}: ` : '') + measurementText(a);

function showList() {
  const el = document.getElementById('measurements');
  if (!el) return;
  el.replaceChildren();
  S.annotations.forEach((a, i) => {
    const row = document.createElement('div');
    row.className = 'measurement';
    const text = document.createElement('span');
    text.textContent = `${i + 1} ${a.kind}${a.label ? ' ' + a.label : ''}: ${measurementText(a)}`;
    text.title = 'double-click to label it';
    text.addEventListener('dblclick', () => relabel(i));
    const del = document.createElement('button');
    del.type = 'button';
    del.textContent = '×';
    del.title = 'delete this measurement';
    del.addEventListener('click', () => setAnnotations(S.annotations.filter((_, k) => k !== i)));
    row.append(text, del);
    el.append(row);
  });
}

// Asks for annotation i's label (empty: none), at most MAX_LABEL_BYTES of UTF-8 as the scene's.
function relabel(i) {
  const a = S.annotations[i];
  let label = window.prompt('label', (a && a.label) || '');
  if (label === null || !a) return;
  while (new TextEncoder().encode(label).length > MAX_LABEL_BYTES) label = label.slice(0, -1);
  const list = S.annotations.map(copy);
  if (label) list[i].label = label;
  else delete list[i].label;
  setAnnotations(list);
}

// A 2-D view's click while a tool is chosen: a point of the measurement being placed. `view`:
// {axis, x, y (backing pixels), r (backing per CSS pixel), world [3], pixelOf(p), right, down,
// volume (the base volume's name)}. True when the click was the tool's.
export function measureClick(view) {
  const tool = S.measureTool;
  if (!(tool in NEEDS) || tool === 'ruler3d') return false;
  if (!draft || draft.axis !== view.axis || draft.tool !== tool)
    draft = {tool, axis: view.axis, points: [], volume: view.volume, right: view.right,
             down: view.down};
  if (tool === 'polygon' && draft.points.length >= 3) {
    const [fx, fy] = view.pixelOf(draft.points[0]);
    if (Math.hypot(view.x - fx, view.y - fy) <= CLOSE_RADIUS * view.r) {
      finish();
      return true;
    }
  }
  draft.points.push(view.world.slice());
  if (tool === 'polygon' && draft.points.length >= MAX_POLYGON_POINTS) finish();
  else if (draft.points.length >= NEEDS[tool]) finish();
  else redraw();
  return true;
}

// The draft becomes an annotation.
function finish() {
  const d = draft;
  draft = null;
  let a = null;
  const volume = d.volume;
  if (d.tool === 'ruler' || d.tool === 'ruler3d') a = {kind: 'ruler', points: d.points};
  else if (d.tool === 'angle') a = {kind: 'angle', points: d.points};
  else if (d.tool === 'polygon') a = {kind: 'polygon', points: d.points, volume};
  else if (d.tool === 'ellipse') {
    // The box from the centre to the second click: semi-axes along the view's right and down.
    const [c, q] = d.points;
    const delta = q.map((x, i) => x - c[i]);
    const along = (u) => delta[0] * u[0] + delta[1] * u[1] + delta[2] * u[2];
    const du = along(d.right), dv = along(d.down);
    if (Math.abs(du) < 1e-6 || Math.abs(dv) < 1e-6) {  // no area: nothing to measure
      redraw();
      return;
    }
    a = {kind: 'ellipse', volume,
         points: [c, c.map((x, i) => x + du * d.right[i]), c.map((x, i) => x + dv * d.down[i])]};
  }
  if (a && !a.volume) delete a.volume;
  if (a) setAnnotations([...S.annotations, a]);
  else redraw();
}

// The 3-D view's click with the 3-D ruler: asks where the ray meets a shown object.
export function pick3d(x, y, width, height) {
  if (S.measureTool !== 'ruler3d') return false;
  send({type: 'pick', seq: measureSeq++, x, y, width, height});
  return true;
}

// A `pick` answer: the next point of the 3-D ruler (a miss picks nothing).
export function onPick(m) {
  S.lastPick = m;
  if (!m.point || S.measureTool !== 'ruler3d') return;
  if (!draft || draft.tool !== 'ruler3d') draft = {tool: 'ruler3d', axis: null, points: []};
  draft.points.push(m.point);
  if (draft.points.length >= 2) finish();
}

// Draws the annotations that lie in a 2-D view's plane (and the draft placed in it) over its
// overlay. `view`: {axis, normal (a unit vector), point (on the plane), tolerance (mm),
// pixelOf(p), r}.
export function drawAnnotations2d(g, view) {
  const off = (p) => p.reduce((s, x, i) => s + (x - view.point[i]) * view.normal[i], 0);
  const inPlane = (a) => a.points.every((p) => Math.abs(off(p)) <= view.tolerance);
  g.save();
  g.strokeStyle = COLOUR;
  g.fillStyle = COLOUR;
  g.lineWidth = 1.5 * view.r;
  g.font = `${Math.round(12 * view.r)}px sans-serif`;
  g.textAlign = 'left';
  const placed = [];
  for (const a of S.annotations) {
    if (!inPlane(a)) continue;
    outline(g, a, view);
    const [x, y] = view.pixelOf(a.points[a.points.length - 1]);
    placeLabel(g, placed, labelText(a), x + 6 * view.r, y + 14 * view.r, 14 * view.r);
  }
  if (draft && draft.axis === view.axis) {
    g.setLineDash([4 * view.r, 3 * view.r]);
    outline(g, {kind: draft.tool === 'polygon' ? 'open' : 'ruler', points: draft.points}, view);
  }
  g.restore();
}

// Draws every annotation over the 3-D view, its image at (x0, y0) of size w x h CSS pixels of
// g's canvas: through the camera, as `intermix render` draws them (the parts behind the eye
// left out), each labelled.
export function drawAnnotations3d(g, x0, y0, w, h) {
  if (!S.camera || !S.annotations.length) return;
  const proj = projector(w, h);
  g.save();
  g.strokeStyle = COLOUR;
  g.fillStyle = COLOUR;
  g.lineWidth = 1.5;
  g.font = '12px sans-serif';
  g.textAlign = 'left';
  const placed = [];
  for (const a of S.annotations) {
    const pts = a.points.map((p) => proj.toScreen(p));
    if (pts.some((p) => !p)) continue;
    outline(g, a, {r: 1, pixelOf: (p) => {
      const q = proj.toScreen(p);
      return [x0 + q[0], y0 + q[1]];
    }});
    const last = pts[pts.length - 1];
    placeLabel(g, placed, labelText(a), x0 + last[0] + 6, y0 + last[1] + 14, 14);
  }
  g.restore();
}

// Writes a label at (x, y) (its baseline), moved down a line at a time (at most 16) while it
// would cover one already in `placed` (annotations seen edge-on share a line), as render does.
function placeLabel(g, placed, text, x, y, line) {
  const w = g.measureText(text).width;
  const hits = (b) => x < b.x + b.w && b.x < x + w && y - line < b.y && b.y - line < y;
  for (let i = 0; i < 16 && placed.some(hits); ++i) y += line;
  placed.push({x, y, w});
  g.fillText(text, x, y);
}

function outline(g, a, view) {
  const px = a.points.map(view.pixelOf);
  g.beginPath();
  if (a.kind === 'ellipse') {
    // c + cos t (p1 - c) + sin t (p2 - c), in pixels.
    const [c, p, q] = px;
    for (let i = 0; i <= 96; ++i) {
      const t = 2 * Math.PI * i / 96;
      const x = c[0] + Math.cos(t) * (p[0] - c[0]) + Math.sin(t) * (q[0] - c[0]);
      const y = c[1] + Math.cos(t) * (p[1] - c[1]) + Math.sin(t) * (q[1] - c[1]);
      if (i) g.lineTo(x, y);
      else g.moveTo(x, y);
    }
  } else {
    px.forEach(([x, y], i) => (i ? g.lineTo(x, y) : g.moveTo(x, y)));
    if (a.kind === 'polygon') g.closePath();
  }
  g.stroke();
  for (const [x, y] of px) {
    g.beginPath();
    g.arc(x, y, 2.5 * view.r, 0, 2 * Math.PI);
    g.fill();
  }
}

// For tests: the annotations and, in the same order, the server's measurement of each (null
// while on its way).
export function measurements() {
  return S.annotations.map((a) => ({annotation: copy(a),
                                    measurement: results.get(keyOf(a)) || null}));
}
