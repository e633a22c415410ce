// The 2-D reading views: axial, coronal and sagittal images of every shown volume through the
// crosshair point, rendered by the server (`slice` messages, docs/viewer.md), with the crosshair,
// mesh outlines and orientation letters drawn over them; a click moves the crosshair in all
// three, the wheel and arrow keys step slices, and the readout shows each volume's value there.
// Right drag (or ctrl / W/L mode drag) sets the base volume's window, ctrl or shift + wheel and
// a pinch zoom, a middle (or shift) drag pans; zoom and pan per view, or shared when linked.
// Alt drag turns the crosshair's axes (oblique views), and each view may show a thick slab
// (reading_frame.js). With a measurement tool chosen, a click places its points instead
// (measure.js), drawn over the views.
import {HANDLE_RADIUS, drawClipLines2d, handleAt, moveClip, startClipDrag} from './clip_outlines.js';
import {editInput, send} from './connection.js';
import {drawAnnotations2d, measureClick} from './measure.js';
import {showVolumeWindow} from './panel.js';
import {AXES, axisLines, crosshairRotation, frameOf, isOblique, lettersOf, normalOf, pitchAlong,
        rangeAlong, resetRotation, rotateCrosshair, rotationAxes, setupSlabControls,
        showSlabControls, slabOf} from './reading_frame.js';
import {S} from './state.js';
import {add, clamp, cross, dot, fmt, mul, sub} from './vec.js';

const MAX_SIDE = 2048;
// Zoom, relative to the scale that fits the volume's box in the view: its limits, and the wheel's
// rate (a zoom of exp(0.0015) per pixel of deltaY, as the 3-D view's).
export const ZOOM_LIMITS = [0.1, 40];
export const WHEEL_ZOOM_RATE = 0.0015;
// Window/level by dragging (as the 3-D view's W/L): the width times exp(0.005) per CSS pixel
// right, the centre up by the width / 256 per pixel down.
export const WL_WIDTH_RATE = 0.005;
export const WL_LEVEL_STEPS = 256;
// A moving view's images: this scale of the side, when that leaves at least MIN_MOVING_SIDE.
const MOVING_SCALE = 0.5;
const MIN_MOVING_SIDE = 128;

const views = {};  // axis -> {cell, image, overlay, answer, pending, again, seq, marks, ...}
let seq = 1;
// Zoom and pan per view: {zoom, pan: [3] mm from the volume box's centre}; one shared when linked.
const newNav = () => ({zoom: 1, pan: [0, 0, 0]});
const navs = {axial: newNav(), coronal: newNav(), sagittal: newNav()};
let linked = null;  // the shared nav while the views are linked
const navOf = (axis) => linked || navs[axis];

// The volume the views are built around: the first one (its box and voxel pitch).
function baseVolume() {
  return S.objects.find((o) => o.kind === 'volume' && o.bounds) || null;
}

function centreOf(v) {
  return v.bounds[0].map((lo, i) => 0.5 * (lo + v.bounds[1][i]));
}

// What a view shows: the volume box's centre panned, moved along its normal to the crosshair.
function viewPoint(axis) {
  const v = baseVolume();
  const c = centreOf(v).map((x, i) => x + navOf(axis).pan[i]);
  const n = normalOf(axis);
  return add(c, mul(n, dot(sub(S.point, c), n)));
}

function backingSize(el) {
  const r = window.devicePixelRatio || 1;
  return [Math.max(1, Math.min(MAX_SIDE, Math.round(el.clientWidth * r))),
          Math.max(1, Math.min(MAX_SIDE, Math.round(el.clientHeight * r)))];
}

// Millimetres per backing pixel so that the volume's box fits every view of this size, over the
// view's zoom.
function mmPerPixel(axis, w, h) {
  const v = baseVolume();
  const ext = v.bounds[1].map((hi, i) => hi - v.bounds[0][i] + v.pitch[i]);
  return 1.05 * Math.max(...ext) / Math.max(1, Math.min(w, h)) / navOf(axis).zoom;
}

// The views a zoom or pan of `axis` changes: all shown ones when linked.
const navAxes = (axis) => (linked ? shownAxes() : [axis]);

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
  let [w, h] = backingSize(view.cell);
  let mm = mmPerPixel(axis, w, h);
  // While a window, pan or pinch drag goes on: JPEG at half the side (a quarter of the pixels to
  // sample and encode), the same field of view; full PNG once it stops, as the 3-D view does.
  const moving = (S.drag && ['slice-wl', 'slice-pan', 'slice-pinch', 'slice-rotate']
                                 .includes(S.drag.mode)) || view.slabMoving ||
                 view.pointMoving;
  if (moving && Math.min(w, h) >= 2 * MIN_MOVING_SIDE) {
    const side = Math.round(w * MOVING_SCALE);
    mm *= w / side;
    h = Math.round(h * MOVING_SCALE);
    w = side;
  }
  view.pending = true;
  view.again = false;
  view.seq = seq++;
  const message = {type: 'slice', seq: view.seq, view: axis, point: viewPoint(axis), width: w,
                   height: h, mm_per_pixel: mm};
  const base = baseVolume();
  if (base.window) message.window = base.window.slice();
  if (moving) message.format = 'jpeg';
  if (isOblique()) message.rotation = crosshairRotation();
  const slab = slabOf(base, axis);
  if (slab.thickness > 0) message.thick_slab = slab;
  // What this request's image will show, and the inputs waiting for it.
  view.sent.set(view.seq, {window: message.window || null, marks: view.marks,
                           at: performance.now()});
  view.marks = [];
  send(message);
}

// An input that changes `axes`' images: its latency is taken when the last of them is drawn.
function markInput(kind, axes) {
  const rec = {kind, t0: performance.now(), waiting: new Set(axes)};
  for (const axis of axes) views[axis].marks.push(rec);
}

// The window [centre, width] the 2-D views show their base volume through (a W/L preset or
// drag), written to the scene (the base volume's `window`) unless `moving`.
export function setSliceWindow(w, moving = false) {
  const base = baseVolume();
  if (!base) return;
  base.window = w.slice();
  showVolumeWindow(base);
  markInput('wl', shownAxes());
  refreshSlices();
  if (!moving) editInput(base.name, {window: base.window}, false);
}

// Links the 2-D views' zoom and pan (they share the last zoomed or panned view's), or unlinks
// them (each keeps the shared one).
export function linkViews(on) {
  if (on && !linked) linked = structuredClone(navs[S.navAxis || 'axial']);
  if (!on && linked) for (const axis of AXES) navs[axis] = structuredClone(linked);
  if (!on) linked = null;
  refreshSlices();
}

// Zooms `axis` (and the linked views) by `factor` about backing pixel (x, y) of it, which stays
// on the same point; the zoom stays within ZOOM_LIMITS.
function zoomView(axis, factor, x, y) {
  const nav = navOf(axis), a = views[axis].answer;
  const zoom = clamp(nav.zoom * factor, ZOOM_LIMITS[0], ZOOM_LIMITS[1]);
  if (!a || !Number.isFinite(zoom) || zoom === nav.zoom) return;
  const f = zoom / nav.zoom, q = worldOf(axis, x, y);  // q - a.point lies in the view's plane
  nav.pan = nav.pan.map((p, i) => p + (q[i] - a.point[i]) * (1 - 1 / f));
  nav.zoom = zoom;
  S.navAxis = axis;
  markInput('zoom', navAxes(axis));
  for (const other of navAxes(axis)) request(other);
}

// Pans `axis` (and the linked views) so that the image follows the pointer: `pan0` moved by a
// drag of (dx, dy) backing pixels.
function panView(axis, pan0, dx, dy) {
  const nav = navOf(axis), f = frameOf(axis, views[axis].answer);
  const mm = views[axis].answer.mm_per_pixel;
  nav.pan = pan0.map((p, i) => p - (dx * f.right[i] + dy * f.down[i]) * mm);
  S.navAxis = axis;
  markInput('pan', navAxes(axis));
  for (const other of navAxes(axis)) request(other);
}

// Window/level from a drag of (dx, dy) CSS pixels from window0 [centre, width].
export function draggedWindow(window0, dx, dy) {
  const [c0, w0] = window0;
  return [c0 + dy * Math.max(Math.abs(w0), 1e-3) / WL_LEVEL_STEPS,
          Math.max(1e-6, w0 * Math.exp(dx * WL_WIDTH_RATE))];
}

// Every shown view asks for its image again (the scene or the layout changed).
export function refreshSlices() {
  showSlabControls(baseVolume());
  for (const axis of shownAxes()) request(axis);
}

// A view's pixel (backing store) of a world point, by the geometry of its last image.
function pixelOf(axis, p) {
  const a = views[axis].answer;
  const f = frameOf(axis, a);
  const d = p.map((x, i) => x - a.point[i]);
  const dot = (u) => d[0] * u[0] + d[1] * u[1] + d[2] * u[2];
  return [a.width / 2 + dot(f.right) / a.mm_per_pixel, a.height / 2 + dot(f.down) / a.mm_per_pixel];
}

function worldOf(axis, x, y) {
  const a = views[axis].answer;
  const f = frameOf(axis, a);
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
  // Image pixels per CSS pixel: the device's ratio, less for a moving view's smaller image.
  const r = (window.devicePixelRatio || 1) * a.width / backingSize(view.cell)[0];
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
  const frame = frameOf(axis, a);
  view.handles = drawClipLines2d(g, {point: a.point, right: frame.right, down: frame.down,
                                     mm: a.mm_per_pixel, width: a.width, height: a.height}, r);
  // The crosshair: where the other two views' planes cross this one (oblique when turned).
  const [cx, cy] = pixelOf(axis, S.point);
  const reach = o.width + o.height;
  g.strokeStyle = 'rgba(80, 220, 120, 0.8)';
  g.lineWidth = r;
  g.beginPath();
  for (const [dx, dy] of axisLines(axis, frame)) {
    g.moveTo(cx - dx * reach, cy - dy * reach);
    g.lineTo(cx + dx * reach, cy + dy * reach);
  }
  g.stroke();
  drawScaleBar(g, a, r);
  drawAnnotations2d(g, {axis, normal: frame.normal, point: a.point,
                        tolerance: 0.5 * pitchAlong(baseVolume().pitch, frame.normal), r,
                        pixelOf: (p) => pixelOf(axis, p)});
  g.fillStyle = '#fc6';
  g.font = `${Math.round(13 * r)}px sans-serif`;
  const [top, bottom, left, right] = lettersOf(frame);
  g.textAlign = 'center';
  g.fillText(top, o.width / 2, 15 * r);
  g.fillText(bottom, o.width / 2, o.height - 6 * r);
  g.textAlign = 'left';
  g.fillText(left, 5 * r, o.height / 2);
  g.textAlign = 'right';
  g.fillText(right, o.width - 5 * r, o.height / 2);
  // The window this image was drawn with, and the zoom when it is not the fitting one.
  g.textAlign = 'left';
  g.fillStyle = '#ddd';
  g.font = `${Math.round(11 * r)}px sans-serif`;
  const w = view.shownWindow;
  if (w) g.fillText(`W ${fmt(w[1], 0)} / L ${fmt(w[0], 0)}`, 5 * r, 14 * r);
  const zoom = navOf(axis).zoom;
  if (zoom !== 1) g.fillText(`${fmt(zoom, 2)}×`, 5 * r, 28 * r);
  const slab = a.thick_slab;
  if (slab && slab.thickness > 0)
    g.fillText(`${slab.mode.toUpperCase()} ${fmt(slab.thickness, 1)} mm`, 5 * r, 42 * r);
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
  const received = performance.now();
  // The next request may go while this image decodes (one in flight); a newer image drawn
  // first wins.
  if (meta.seq === view.seq) view.pending = false;
  view.decoding = (view.decoding || 0) + 1;
  let bmp;
  try {
    // The values are display values already (the PNG says gamma 1): no conversion.
    bmp = await createImageBitmap(new Blob([blob], {type: `image/${meta.format || 'png'}`}),
                                  {colorSpaceConversion: 'none', premultiplyAlpha: 'none'});
  } catch (e) {
    view.decoding--;
    if (view.again) request(meta.view);
    return;
  }
  view.decoding--;
  if (meta.seq < (view.drawnSeq || 0)) {
    bmp.close();
    return;
  }
  view.drawnSeq = meta.seq;
  view.image.width = bmp.width;
  view.image.height = bmp.height;
  view.image.getContext('2d').drawImage(bmp, 0, 0);
  bmp.close();
  view.answer = meta;
  const sent = view.sent.get(meta.seq);
  // This image shows the inputs of its request and of every earlier one.
  const shown = [];
  for (const [seq, s] of view.sent)
    if (seq <= meta.seq) {
      shown.push(...s.marks);
      view.sent.delete(seq);
    }
  if (sent) {
    // Where a view's time goes: the server's render and encoding, the round trip, the decoding.
    S.sliceTimings = (S.sliceTimings || []).slice(-499);
    S.sliceTimings.push({format: meta.format, render_ms: meta.render_ms, encode_ms: meta.encode_ms,
                         round_trip_ms: received - sent.at,
                         decode_ms: performance.now() - received});
    view.shownWindow = sent.window;
    // Latency of a W/L, zoom or pan input: from the event to the last view it changed drawn.
    for (const rec of shown) {
      rec.waiting.delete(meta.view);
      if (rec.waiting.size) continue;
      S.inputLatencies = S.inputLatencies || {};
      (S.inputLatencies[rec.kind] = S.inputLatencies[rec.kind] || [])
          .push(performance.now() - rec.t0);
    }
  }
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
  for (const v of Object.values(views)) {
    v.pending = false;
    v.sent.clear();
  }
}

// A `probe` answer: the readout.
export function onProbe(m) {
  S.readout = m;
  const lines = [`crosshair ${m.point.map((x) => x.toFixed(1)).join(', ')} mm (LPS)`];
  // Oblique views: the trilinear sample there, as the views' pixels sample it.
  const oblique = isOblique();
  for (const v of m.values) {
    const raw = oblique && v.sample !== undefined ? v.sample : v.value;
    const value = raw === null ? '—'
                               : Number(raw.toPrecision(6)) + (oblique ? ' (trilinear)' : '');
    lines.push(`${v.name}: ${value}${v.units ? ' ' + v.units : ''}` +
               (v.label ? ` ${v.label}` : '') + (v.index ? `  [${v.index.join(', ')}]` : ''));
  }
  document.getElementById('readout').textContent = lines.join('\n');
}

// Moves the crosshair to world point p: the other views' images and every crosshair follow.
export function setPoint(p, except) {
  const old = S.point;
  S.point = p.slice();
  S.pointSetAt = performance.now();
  // Only a view whose plane moves needs a new image (a step moves one); the others redraw their
  // crosshair.
  const moved = shownAxes().filter((axis) => axis !== except && !(
    old && views[axis].answer && Math.abs(dot(sub(p, old), normalOf(axis))) < 1e-9));
  slabViewsFollow(moved);
  for (const axis of shownAxes()) {
    if (moved.includes(axis)) request(axis);
    else if (views[axis].answer) drawOverlay(axis);
  }
  if (!moved.length) S.pointSetAt = null;  // every view shows it already
  send({type: 'probe', point: S.point});
}

// Views with a thick slab follow crosshair moves (steps, cine, clicks) at half side in JPEG, as
// a drag, and take their full PNG once the moves pause for SLAB_SETTLE_MS.
const SLAB_SETTLE_MS = 200;
let slabSettle = 0;
function slabViewsFollow(axes) {
  const base = baseVolume();
  const slabbed = axes.filter((a) => views[a] && slabOf(base, a).thickness > 0);
  if (!slabbed.length) return;
  for (const a of slabbed) views[a].pointMoving = true;
  clearTimeout(slabSettle);
  slabSettle = setTimeout(() => {
    for (const a of slabbed) {
      views[a].pointMoving = false;
      request(a);
    }
  }, SLAB_SETTLE_MS);
}

// One slice step (of the base volume's voxel pitch) along `axis`'s normal, `count` times.
function step(axis, count) {
  const v = baseVolume();
  if (!v || !S.point) return;
  const n = normalOf(axis);
  // Superior, posterior, left: forward; clamped to the volume's box.
  const [lo, hi] = rangeAlong(v.bounds, S.point, n);
  setPoint(add(S.point, mul(n, clamp(count * pitchAlong(v.pitch, n), lo, hi))));
}

// Cine: `axis`'s slice steps forward `fps` times a second (from the last slice back to the
// first), by the clock: a late tick takes the steps it owes, so the slices go by at the rate
// set however the frames keep up. Null stops it.
let cine = null;
export function setCine(axis, fps) {
  if (cine) clearInterval(cine.timer);
  cine = null;
  S.cine = null;
  if (!axis || !(fps > 0)) return;
  const state = {axis, fps, t0: performance.now(), steps: 0, timer: 0};
  state.timer = setInterval(() => {
    const due = Math.floor((performance.now() - state.t0) * state.fps / 1000);
    for (; state.steps < due; ++state.steps) cineStep(axis);
  }, Math.max(5, 500 / fps));
  cine = state;
  S.cine = state;
}

function cineStep(axis) {
  const v = baseVolume();
  if (!v || !S.point) return;
  const n = normalOf(axis), d = pitchAlong(v.pitch, n);
  const [lo, hi] = rangeAlong(v.bounds, S.point, n);
  setPoint(add(S.point, mul(n, d > hi + 1e-6 ? lo : d)));
}

// After hello: the crosshair at the base volume's centre, the views' events.
export function setupSlices() {
  for (const cell of document.querySelectorAll('.slice-cell')) {
    const axis = cell.dataset.axis;
    const view = {cell, image: cell.querySelector('.slice'), overlay: cell.querySelector('.overlay'),
                  answer: null, pending: false, again: false, seq: 0, marks: [],
                  sent: new Map(), decoding: 0, drawnSeq: 0, touches: new Map()};
    views[axis] = view;
    const backing = (ev) => {
      const r = view.image.getBoundingClientRect();
      return [(ev.clientX - r.left) * view.answer.width / r.width,
              (ev.clientY - r.top) * view.answer.height / r.height];
    };
    view.image.addEventListener('contextmenu', (ev) => ev.preventDefault());
    view.image.addEventListener('mousedown', (ev) => {
      if (ev.button === 1) ev.preventDefault();  // no autoscroll: the middle button pans
    });
    view.image.addEventListener('pointerdown', (ev) => {
      if (!view.answer) return;
      if (ev.pointerType === 'touch') {
        view.touches.set(ev.pointerId, {x: ev.clientX, y: ev.clientY});
        view.image.setPointerCapture(ev.pointerId);
        if (view.touches.size >= 2) {  // a second finger: pinch zoom and pan, no crosshair
          view.tap = null;
          view.pinch = pinchState();
          S.drag = {mode: 'slice-pinch'};
          return;
        }
      }
      if (ev.button === 0 && ev.altKey && !ev.ctrlKey && !ev.shiftKey) {  // turn the crosshair
        ev.preventDefault();
        view.image.setPointerCapture(ev.pointerId);
        const [x, y] = backing(ev), [cx, cy] = pixelOf(axis, S.point);
        const f = frameOf(axis, view.answer);
        view.drag = {mode: 'rotate', a0: Math.atan2(y - cy, x - cx), axes0: rotationAxes(),
                     k: cross(f.right, f.down)};
        S.drag = {mode: 'slice-rotate'};
        return;
      }
      const wl = ev.button === 2 ||
                 (ev.button === 0 && (ev.ctrlKey || ev.metaKey || S.wlMode) && !ev.shiftKey);
      const pan = ev.button === 1 || (ev.button === 0 && ev.shiftKey);
      if ((wl && baseVolume().window) || pan) {
        ev.preventDefault();
        view.image.setPointerCapture(ev.pointerId);
        view.drag = {mode: wl ? 'wl' : 'pan', x0: ev.clientX, y0: ev.clientY,
                     window0: wl ? baseVolume().window.slice() : null,
                     pan0: navOf(axis).pan.slice()};
        S.drag = {mode: 'slice-' + view.drag.mode};  // no other window's state is taken mid-drag
        return;
      }
      if (ev.button !== 0) return;
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
      const k = view.answer.width / view.image.getBoundingClientRect().width;  // backing / CSS
      if (!ev.ctrlKey && !ev.metaKey && !ev.altKey && ev.pointerType !== 'touch' &&
          measureClick({axis, x, y, r: k, world: worldOf(axis, x, y),
                        right: frameOf(axis, view.answer).right,
                        down: frameOf(axis, view.answer).down, volume: baseVolume().name,
                        pixelOf: (p) => pixelOf(axis, p)}))
        return;  // a measurement's point, not the crosshair
      if (ev.pointerType === 'touch') {  // the crosshair on lifting, unless a pinch begins
        view.tap = {id: ev.pointerId, x, y};
        return;
      }
      setPoint(worldOf(axis, x, y), axis);
    });
    const dragClip = (ev, moving) => {
      const d = view.clipDrag;
      if (!d) return;
      const [x, y] = backing(ev);
      const f = frameOf(axis, view.answer), mm = view.answer.mm_per_pixel;
      moveClip(d, f.right.map((v, i) => ((x - d.x0) * v + (y - d.y0) * f.down[i]) * mm), moving);
      for (const other of shownAxes()) if (views[other].answer) drawOverlay(other);
      if (moving) return;
      view.clipDrag = null;
      S.drag = null;
    };
    // A W/L or pan drag: from where it started, so no move is lost or counted twice.
    const dragView = (ev, moving) => {
      const d = view.drag;
      if (!d) return false;
      if (!moving) {  // released: the last images are PNG
        view.drag = null;
        S.drag = null;
      }
      if (d.mode === 'rotate') {  // about the view's normal, by the pointer's turn about the point
        const [x, y] = backing(ev), [cx, cy] = pixelOf(axis, S.point);
        rotateCrosshair(d.k, Math.atan2(y - cy, x - cx) - d.a0, d.axes0);
        markInput('rotate', shownAxes());
        refreshSlices();
        send({type: 'probe', point: S.point});
        return true;
      }
      const dx = ev.clientX - d.x0, dy = ev.clientY - d.y0;
      if (d.mode === 'wl') {
        document.getElementById('wl-preset').value = '';  // no preset's window any more
        if (dx || dy || moving) setSliceWindow(draggedWindow(d.window0, dx, dy), moving);
        else setSliceWindow(d.window0, true);  // a click: nothing to write
      } else if (dx || dy || !moving) {
        const r = view.image.getBoundingClientRect();
        panView(axis, d.pan0, dx * view.answer.width / r.width, dy * view.answer.height / r.height);
      }
      return true;
    };
    // Two fingers' midpoint and distance, in CSS pixels (a moving image has fewer pixels).
    const pinchState = () => {
      const [p, q] = [...view.touches.values()];
      const r = view.image.getBoundingClientRect();
      return {x: (p.x + q.x) / 2 - r.left, y: (p.y + q.y) / 2 - r.top,
              dist: Math.hypot(p.x - q.x, p.y - q.y)};
    };
    // Two fingers: their distance zooms about their midpoint, which the image follows.
    const pinch = (ev, moving) => {
      if (!view.touches.has(ev.pointerId)) return false;
      if (!moving) {
        view.touches.delete(ev.pointerId);
        view.pinch = null;
        if (view.tap && view.tap.id === ev.pointerId) {  // a tap: the crosshair goes there
          const t = view.tap;
          view.tap = null;
          setPoint(worldOf(axis, t.x, t.y), axis);
          return true;
        }
        if (!S.drag || S.drag.mode !== 'slice-pinch') return false;  // a one-finger drag's end
        if (!view.touches.size) {
          S.drag = null;
          for (const other of navAxes(axis)) request(other);  // PNG again
        }
        return true;
      }
      view.touches.set(ev.pointerId, {x: ev.clientX, y: ev.clientY});
      if (view.touches.size < 2) return false;
      const now = pinchState();
      const last = view.pinch;
      view.pinch = now;
      if (!last) return true;
      const k = view.answer.width / view.image.getBoundingClientRect().width;  // backing / CSS
      panView(axis, navOf(axis).pan.slice(), (now.x - last.x) * k, (now.y - last.y) * k);
      if (last.dist > 0 && now.dist > 0) zoomView(axis, now.dist / last.dist, now.x * k, now.y * k);
      return true;
    };
    view.image.addEventListener('pointermove', (ev) => {
      if (pinch(ev, true) || dragView(ev, true)) return;
      dragClip(ev, true);
    });
    for (const type of ['pointerup', 'pointercancel'])
      view.image.addEventListener(type, (ev) => {
        if (pinch(ev, false) || dragView(ev, false)) return;
        dragClip(ev, false);
      });
    view.image.addEventListener('wheel', (ev) => {
      ev.preventDefault();
      if (ev.ctrlKey || ev.shiftKey || ev.metaKey) {  // zoom (a touchpad's pinch comes as ctrl)
        if (!view.answer) return;
        const scale = ev.deltaMode === 1 ? 16 : ev.deltaMode === 2 ? 400 : 1;
        const d = (ev.deltaY || ev.deltaX) * scale;
        const [x, y] = backing(ev);
        zoomView(axis, Math.exp(-clamp(d, -500, 500) * WHEEL_ZOOM_RATE), x, y);
        return;
      }
      step(axis, ev.deltaY > 0 ? -1 : 1);
    }, {passive: false});
    cell.addEventListener('pointerenter', () => { S.hoverAxis = axis; });
    cell.addEventListener('pointerleave', () => { S.hoverAxis = null; });
  }
  window.addEventListener('keydown', (ev) => {
    if (!S.hoverAxis) return;
    if (ev.key === 'c' && !ev.ctrlKey && !ev.metaKey && !ev.altKey) {  // cine on / off
      const on = !(cine && cine.axis === S.hoverAxis);
      setCine(on ? S.hoverAxis : null, Number(document.getElementById('cine-fps').value));
      return;
    }
    const counts = {ArrowUp: 1, ArrowDown: -1, PageUp: 10, PageDown: -10};
    if (!(ev.key in counts)) return;
    ev.preventDefault();
    step(S.hoverAxis, counts[ev.key]);
  });
  setupSlabControls(setSlab);
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

// Every shown view's overlay again (the measurements changed).
export function redrawSliceOverlays() {
  for (const axis of shownAxes()) if (views[axis] && views[axis].answer) drawOverlay(axis);
}

// For tests: a world point's page (client) pixel in `axis`'s view, as its last image placed it.
export function pagePixelOf(axis, p) {
  const v = views[axis];
  if (!v || !v.answer) return null;
  const [x, y] = pixelOf(axis, p), r = v.image.getBoundingClientRect();
  return [r.left + x * r.width / v.answer.width, r.top + y * r.height / v.answer.height];
}

// A view's thick slab {thickness, mode} (0 mm: none), shown at once and written to the scene (the
// base volume's `slabs`) unless `moving`.
export function setSlab(axis, slab, moving = false) {
  const base = baseVolume();
  if (!base) return;
  base.slabs = Object.assign({}, base.slabs || {});
  if (slab.thickness > 0) base.slabs[axis] = {thickness: slab.thickness, mode: slab.mode};
  else delete base.slabs[axis];
  showSlabControls(base);
  if (views[axis]) {
    views[axis].slabMoving = moving;  // typing: JPEG at half the side, as a drag; PNG on change
    markInput(moving ? 'slab' : 'slab-set', [axis]);
    request(axis);
  }
  if (!moving) editInput(base.name, {slabs: base.slabs}, false);
}

// "reset" for the 2-D views: every view back to the fitting zoom, centred, and square again.
export function resetSliceViews() {
  resetRotation();
  for (const axis of AXES) navs[axis] = newNav();
  if (linked) linked = newNav();
  refreshSlices();
}

// For tests: each shown view's last image (centre point, mm per backing and per CSS pixel, the
// window it was drawn with) and its zoom.
export function sliceViews() {
  const out = {};
  for (const axis of shownAxes()) {
    const v = views[axis];
    if (!v || !v.answer) continue;
    const a = v.answer, r = v.image.getBoundingClientRect();
    // The backing store is stretched to the cell: mm per CSS pixel along x and y.
    out[axis] = {point: a.point.slice(), mm_per_pixel: a.mm_per_pixel,
                 mm_per_css_px: [a.mm_per_pixel * a.width / r.width,
                                 a.mm_per_pixel * a.height / r.height],
                 window: v.shownWindow ? v.shownWindow.slice() : null, zoom: navOf(axis).zoom,
                 right: frameOf(axis, a).right, down: frameOf(axis, a).down,
                 normal: frameOf(axis, a).normal, thick_slab: a.thick_slab || null,
                 letters: lettersOf(frameOf(axis, a)),
                 format: a.format,
                 width: a.width, height: a.height,
                 pending: v.pending || v.again || v.decoding > 0 || v.marks.length > 0};
  }
  return out;
}

// For tests: the base volume's name, the window its 2-D views use and the rule's note.
export function sliceWindow() {
  const b = baseVolume();
  return b ? {name: b.name, window: b.window ? b.window.slice() : null, note: b.windowNote} : null;
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
    const n = a && frameOf(axis, a).normal;
    if (!a || Math.abs(dot(sub(S.point, a.point), n)) > 1e-6) continue;
    const [x, y] = pixelOf(axis, S.point);
    out[axis] = worldOf(axis, x, y);  // on the plane the image shows
  }
  return out;
}
