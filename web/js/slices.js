// The 2-D reading views: axial, coronal and sagittal images of every shown volume through the
// crosshair point, rendered by the server (`slice` messages, docs/viewer.md), with the crosshair,
// mesh outlines and orientation letters drawn over them; a click moves the crosshair in all
// three, the wheel and arrow keys step slices, and the readout shows each volume's value there.
import {HANDLE_RADIUS, drawClipLines2d, handleAt, moveClip, startClipDrag} from './clip_outlines.js';
import {send} from './connection.js';
import {S} from './state.js';

const AXES = ['axial', 'coronal', 'sagittal'];
// Screen directions in LPS (right, down) and the plane's normal, as the server draws them.
const FRAME = {
  axial: {right: [1, 0, 0], down: [0, 1, 0], normal: 2},
  coronal: {right: [1, 0, 0], down: [0, 0, -1], normal: 1},
  sagittal: {right: [0, 1, 0], down: [0, 0, -1], normal: 0},
};
// The letters at the top, bottom, left and right of each view.
const LETTERS = {axial: ['A', 'P', 'R', 'L'], coronal: ['S', 'I', 'R', 'L'],
                 sagittal: ['S', 'I', 'A', 'P']};
const MAX_SIDE = 2048;

const views = {};  // axis -> {cell, image, overlay, answer, pending, again, seq}
let seq = 1;

// The volume the views are built around: the first one (its box and voxel pitch).
function baseVolume() {
  return S.objects.find((o) => o.kind === 'volume' && o.bounds) || null;
}

function centreOf(v) {
  return v.bounds[0].map((lo, i) => 0.5 * (lo + v.bounds[1][i]));
}

// What a view shows: the volume box's centre, moved along the view's normal to the crosshair.
function viewPoint(axis) {
  const v = baseVolume();
  const c = centreOf(v);
  c[FRAME[axis].normal] = S.point[FRAME[axis].normal];
  return c;
}

function backingSize(el) {
  const r = window.devicePixelRatio || 1;
  return [Math.max(1, Math.min(MAX_SIDE, Math.round(el.clientWidth * r))),
          Math.max(1, Math.min(MAX_SIDE, Math.round(el.clientHeight * r)))];
}

// Millimetres per backing pixel so that the volume's box fits every view of this size.
function mmPerPixel(w, h) {
  const v = baseVolume();
  const ext = v.bounds[1].map((hi, i) => hi - v.bounds[0][i] + v.pitch[i]);
  return 1.05 * Math.max(...ext) / Math.max(1, Math.min(w, h));
}

function shownAxes() {
  const layout = document.getElementById('view-area').className;
  return layout.includes('1x1') ? [] : AXES;
}

// Asks for one view's image; one request in flight per view, the latest asked once it returns.
function request(axis) {
  const view = views[axis];
  if (!view || !baseVolume() || !S.point) return;
  if (view.pending) {
    view.again = true;
    return;
  }
  const [w, h] = backingSize(view.cell);
  view.pending = true;
  view.again = false;
  view.seq = seq++;
  const message = {type: 'slice', seq: view.seq, view: axis, point: viewPoint(axis), width: w,
                   height: h, mm_per_pixel: mmPerPixel(w, h)};
  if (S.sliceWindow) message.window = S.sliceWindow;
  send(message);
}

// The window [centre, width] the 2-D views show their base volume through (a W/L preset).
export function setSliceWindow(w) {
  S.sliceWindow = w.slice();
  refreshSlices();
}

// Every shown view asks for its image again (the scene or the layout changed).
export function refreshSlices() {
  for (const axis of shownAxes()) request(axis);
}

// A view's pixel (backing store) of a world point, by the geometry of its last image.
function pixelOf(axis, p) {
  const a = views[axis].answer;
  const f = FRAME[axis];
  const d = p.map((x, i) => x - a.point[i]);
  const dot = (u) => d[0] * u[0] + d[1] * u[1] + d[2] * u[2];
  return [a.width / 2 + dot(f.right) / a.mm_per_pixel, a.height / 2 + dot(f.down) / a.mm_per_pixel];
}

function worldOf(axis, x, y) {
  const a = views[axis].answer;
  const f = FRAME[axis];
  return a.point.map((c, i) => c + (x - a.width / 2) * a.mm_per_pixel * f.right[i] +
                                   (y - a.height / 2) * a.mm_per_pixel * f.down[i]);
}

function drawOverlay(axis) {
  const view = views[axis];
  const a = view.answer;
  const o = view.overlay;
  if (!a) return;
  o.width = a.width;
  o.height = a.height;
  const g = o.getContext('2d');
  g.clearRect(0, 0, o.width, o.height);
  const r = window.devicePixelRatio || 1;
  g.lineWidth = 1.5 * r;
  for (const m of a.outlines || []) {
    // Display colours, as the mesh's material gives them.
    g.strokeStyle = `rgb(${m.color.map((c) => Math.round(255 * c)).join(',')})`;
    g.beginPath();
    for (const s of m.segments) {
      g.moveTo(s[0], s[1]);
      g.lineTo(s[2], s[3]);
    }
    g.stroke();
  }
  view.handles = drawClipLines2d(g, {point: a.point, right: FRAME[axis].right,
                                     down: FRAME[axis].down, mm: a.mm_per_pixel, width: a.width,
                                     height: a.height}, r);
  const [cx, cy] = pixelOf(axis, S.point);
  g.strokeStyle = 'rgba(80, 220, 120, 0.8)';
  g.lineWidth = r;
  g.beginPath();
  g.moveTo(0, cy);
  g.lineTo(o.width, cy);
  g.moveTo(cx, 0);
  g.lineTo(cx, o.height);
  g.stroke();
  drawScaleBar(g, a, r);
  g.fillStyle = '#fc6';
  g.font = `${Math.round(13 * r)}px sans-serif`;
  const [top, bottom, left, right] = LETTERS[axis];
  g.textAlign = 'center';
  g.fillText(top, o.width / 2, 15 * r);
  g.fillText(bottom, o.width / 2, o.height - 6 * r);
  g.textAlign = 'left';
  g.fillText(left, 5 * r, o.height / 2);
  g.textAlign = 'right';
  g.fillText(right, o.width - 5 * r, o.height / 2);
}

// A scale bar at the bottom right: the longest of 1, 2, 5 x 10^k mm within a fifth of the view.
function drawScaleBar(g, a, r) {
  const most = 0.2 * a.width * a.mm_per_pixel;
  const e = Math.pow(10, Math.floor(Math.log10(most)));
  const mm = [5, 2, 1].map((m) => m * e).find((v) => v <= most) || e;
  const px = mm / a.mm_per_pixel, x1 = a.width - 12 * r, y = a.height - 12 * r;
  g.strokeStyle = '#ddd';
  g.lineWidth = 2 * r;
  g.beginPath();
  g.moveTo(x1 - px, y - 4 * r);
  g.lineTo(x1 - px, y);
  g.lineTo(x1, y);
  g.lineTo(x1, y - 4 * r);
  g.stroke();
  g.fillStyle = '#ddd';
  g.font = `${Math.round(11 * r)}px sans-serif`;
  g.textAlign = 'center';
  g.fillText(`${mm} mm`, x1 - px / 2, y - 6 * r);
  views[a.view].scaleMm = mm;
}

// A `slice` answer and its PNG.
export async function onSlice(meta, blob) {
  const view = views[meta.view];
  if (!view) return;
  if (meta.seq === view.seq) view.pending = false;
  let bmp;
  try {
    // The values are display values already (the PNG says gamma 1): no conversion.
    bmp = await createImageBitmap(new Blob([blob], {type: 'image/png'}),
                                  {colorSpaceConversion: 'none', premultiplyAlpha: 'none'});
  } catch (e) {
    return;
  }
  view.image.width = bmp.width;
  view.image.height = bmp.height;
  view.image.getContext('2d').drawImage(bmp, 0, 0);
  bmp.close();
  view.answer = meta;
  S.slicesDrawn = (S.slicesDrawn || 0) + 1;
  drawOverlay(meta.view);
  // Latency of a crosshair move or slice step: from the input to the last view showing it.
  if (S.pointSetAt !== null && S.pointSetAt !== undefined &&
      Object.keys(crosshairs()).length === shownAxes().length) {
    S.sliceLatencies = S.sliceLatencies || [];
    S.sliceLatencies.push(performance.now() - S.pointSetAt);
    S.pointSetAt = null;
  }
  if (view.again) request(meta.view);
}

// An error answered some request: no view waits for an answer any more.
export function onSliceError() {
  for (const v of Object.values(views)) v.pending = false;
}

// A `probe` answer: the readout.
export function onProbe(m) {
  S.readout = m;
  const lines = [`crosshair ${m.point.map((x) => x.toFixed(1)).join(', ')} mm (LPS)`];
  for (const v of m.values) {
    const value = v.value === null ? '—' : Number(v.value.toPrecision(6));
    lines.push(`${v.name}: ${value}${v.units ? ' ' + v.units : ''}` +
               (v.index ? `  [${v.index.join(', ')}]` : ''));
  }
  document.getElementById('readout').textContent = lines.join('\n');
}

// Moves the crosshair to world point p: the other views' images and every crosshair follow.
export function setPoint(p, except) {
  S.point = p.slice();
  S.pointSetAt = performance.now();
  for (const axis of shownAxes()) {
    if (axis !== except) request(axis);
    else drawOverlay(axis);
  }
  send({type: 'probe', point: S.point});
}

// One slice step (of the base volume's voxel pitch) along `axis`'s normal, `count` times.
function step(axis, count) {
  const v = baseVolume();
  if (!v || !S.point) return;
  const n = FRAME[axis].normal;
  const p = S.point.slice();
  // Superior, posterior, left: forward; clamped to the volume's box.
  p[n] = Math.min(v.bounds[1][n], Math.max(v.bounds[0][n], p[n] + count * v.pitch[n]));
  setPoint(p);
}

// After hello: the crosshair at the base volume's centre, the views' events.
export function setupSlices() {
  for (const cell of document.querySelectorAll('.slice-cell')) {
    const axis = cell.dataset.axis;
    const view = {cell, image: cell.querySelector('.slice'), overlay: cell.querySelector('.overlay'),
                  answer: null, pending: false, again: false, seq: 0};
    views[axis] = view;
    const backing = (ev) => {
      const r = view.image.getBoundingClientRect();
      return [(ev.clientX - r.left) * view.answer.width / r.width,
              (ev.clientY - r.top) * view.answer.height / r.height];
    };
    view.image.addEventListener('pointerdown', (ev) => {
      if (!view.answer) return;
      const [x, y] = backing(ev);
      const r = window.devicePixelRatio || 1;
      const handle = handleAt(view.handles, x, y, 1.5 * HANDLE_RADIUS * r);
      const drag = handle && startClipDrag(handle);
      if (drag) {  // a clip plane's handle: the plane follows the pointer along its normal
        view.image.setPointerCapture(ev.pointerId);
        view.clipDrag = Object.assign(drag, {x0: x, y0: y});
        S.drag = {mode: 'slice-clip'};  // no other window's state is taken mid-drag
        return;
      }
      setPoint(worldOf(axis, x, y), axis);
    });
    const dragClip = (ev, moving) => {
      const d = view.clipDrag;
      if (!d) return;
      const [x, y] = backing(ev);
      const f = FRAME[axis], mm = view.answer.mm_per_pixel;
      moveClip(d, f.right.map((v, i) => ((x - d.x0) * v + (y - d.y0) * f.down[i]) * mm), moving);
      for (const other of shownAxes()) if (views[other].answer) drawOverlay(other);
      if (moving) return;
      view.clipDrag = null;
      S.drag = null;
    };
    view.image.addEventListener('pointermove', (ev) => dragClip(ev, true));
    view.image.addEventListener('pointerup', (ev) => dragClip(ev, false));
    view.image.addEventListener('pointercancel', (ev) => dragClip(ev, false));
    view.image.addEventListener('wheel', (ev) => {
      ev.preventDefault();
      step(axis, ev.deltaY > 0 ? -1 : 1);
    }, {passive: false});
    cell.addEventListener('pointerenter', () => { S.hoverAxis = axis; });
    cell.addEventListener('pointerleave', () => { S.hoverAxis = null; });
  }
  window.addEventListener('keydown', (ev) => {
    if (!S.hoverAxis) return;
    const counts = {ArrowUp: 1, ArrowDown: -1, PageUp: 10, PageDown: -10};
    if (!(ev.key in counts)) return;
    ev.preventDefault();
    step(S.hoverAxis, counts[ev.key]);
  });
  const layout = document.getElementById('layout');
  layout.addEventListener('change', () => setLayout(layout.value));
  window.addEventListener('resize', refreshSlices);
}

// '1x1', '2x2' or '1x3'.
export function setLayout(name) {
  document.getElementById('view-area').className = 'layout-' + name;
  document.getElementById('layout').value = name;
  window.dispatchEvent(new Event('resize'));
  if (!S.point && baseVolume()) setPoint(centreOf(baseVolume()));
  refreshSlices();
}

// For tests: the scale bar's length in mm of each view.
export function scaleBars() {
  const out = {};
  for (const axis of AXES) if (views[axis] && views[axis].scaleMm) out[axis] = views[axis].scaleMm;
  return out;
}

// For tests: each shown 2-D view's clip-plane handles in page (client) pixels, with the view's
// millimetres per CSS pixel.
export function sliceClipHandles() {
  const out = {};
  for (const axis of shownAxes()) {
    const v = views[axis];
    if (!v.answer) continue;
    const r = v.image.getBoundingClientRect(), k = r.width / v.answer.width;
    out[axis] = {mm_per_px: v.answer.mm_per_pixel / k,
                 handles: (v.handles || []).map((h) => ({volume: h.volume, index: h.index,
                                                        x: r.left + h.x * k, y: r.top + h.y * k}))};
  }
  return out;
}

// For tests: where each view's crosshair is, in world coordinates, as drawn; only the views whose
// image is of the crosshair's current plane.
export function crosshairs() {
  const out = {};
  for (const axis of AXES) {
    const a = views[axis] && views[axis].answer;
    if (!a || a.point[FRAME[axis].normal] !== S.point[FRAME[axis].normal]) continue;
    const [x, y] = pixelOf(axis, S.point);
    const w = worldOf(axis, x, y);
    w[FRAME[axis].normal] = a.point[FRAME[axis].normal];  // the plane the image shows
    out[axis] = w;
  }
  return out;
}
