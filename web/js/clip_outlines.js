// Clip planes drawn where they cut: in the 3-D view the polygon where each visible volume's clip
// plane meets the volume's box, projected through the camera; in each 2-D view the line where it
// meets the view's plane. Each has a handle (a disc at the plane's point, or the line's point
// nearest the view's centre) that a drag moves along the plane's normal. Pure geometry over S;
// the drawing contexts and pixel mappings come from the callers (colorbar.js, slices.js).
import {S, clipsMessage} from './state.js';
import {add, cross, dot, mul, norm, sub} from './vec.js';
import {editInput} from './connection.js';

export const HANDLE_RADIUS = 7;  // CSS pixels

// Every clip plane of a visible volume: {o (the volume), index, c (the local clip), point, normal}.
function clips() {
  const out = [];
  for (const o of S.objects)
    if (o.kind === 'volume' && o.visible && o.bounds)
      o.clips.forEach((c, index) =>
        out.push({o, index, c, point: add(c.base, mul(c.normal, c.offset)), normal: c.normal}));
  return out;
}

const isSelected = (k) =>
  Boolean(S.selectedClip) && S.selectedClip.volume === k.o.name && S.selectedClip.index === k.index;

// The polygon where the plane (point p, unit normal n) cuts the box [lo, hi], in order round it.
export function boxSection(lo, hi, p, n) {
  const corner = (i) => [i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], i & 4 ? hi[2] : lo[2]];
  const pts = [];
  for (let i = 0; i < 8; ++i)
    for (const bit of [1, 2, 4]) {
      if (i & bit) continue;  // each edge once, from its lower corner
      const a = corner(i), b = corner(i | bit);
      const da = dot(sub(a, p), n), db = dot(sub(b, p), n);
      if ((da < 0) === (db < 0) || da === db) continue;
      pts.push(add(a, mul(sub(b, a), da / (da - db))));
    }
  if (pts.length < 3) return [];
  const centre = mul(pts.reduce(add), 1 / pts.length);
  const u = norm(sub(pts[0], centre)), v = cross(n, u);
  return pts.map((q) => [Math.atan2(dot(sub(q, centre), v), dot(sub(q, centre), u)), q])
      .sort((x, y) => x[0] - y[0]).map((x) => x[1]);
}

// The camera's projection of world points to CSS pixels of a w x h view, and the millimetres one
// pixel spans at a point (for turning a drag into a distance).
export function projector(w, h) {
  const c = S.camera;
  const fwd = norm(sub(c.target, c.eye));
  const right = norm(cross(fwd, c.up)), up = cross(right, fwd);
  const ortho = S.projection === 'orthographic';
  const halfH = ortho ? 0.5 * S.orthoHeight : Math.tan(c.fov_deg * Math.PI / 360);
  const depth = (p) => (ortho ? 1 : dot(sub(p, c.eye), fwd));
  return {
    right, up,
    toScreen(p) {
      const v = sub(p, c.eye), z = depth(p);
      if (!(z > 1e-6)) return null;  // behind the eye
      const s = h / (2 * halfH * z);
      return [w / 2 + dot(v, right) * s, h / 2 - dot(v, up) * s];
    },
    mmPerPixel(p) { return 2 * halfH * Math.max(depth(p), 1e-6) / h; },
  };
}

// Draws the 3-D outlines and handles into g, the view's image at (x0, y0) of size w x h (CSS px
// of the overlay, which covers the view's cell); keeps the handles in S.clipHandles3d.
export function drawClipOutlines3d(g, x0, y0, w, h) {
  S.clipHandles3d = [];
  if (!S.camera) return;
  const proj = projector(w, h);
  for (const k of clips()) {
    const poly = boxSection(k.o.bounds[0], k.o.bounds[1], k.point, k.normal)
        .map((q) => proj.toScreen(q));
    if (poly.length < 3 || poly.some((q) => !q)) continue;
    const colour = isSelected(k) ? '#fd4' : '#4cf';
    g.strokeStyle = colour;
    g.lineWidth = isSelected(k) ? 2 : 1.5;
    g.beginPath();
    poly.forEach((q, i) => (i ? g.lineTo(x0 + q[0], y0 + q[1]) : g.moveTo(x0 + q[0], y0 + q[1])));
    g.closePath();
    g.stroke();
    // The handle at the polygon's centre, with a tick along the normal (the side that is kept).
    const centre = mul(boxSection(k.o.bounds[0], k.o.bounds[1], k.point, k.normal).reduce(add),
                       1 / poly.length);
    const at = proj.toScreen(centre);
    const tip = proj.toScreen(add(centre, mul(k.normal, 24 * proj.mmPerPixel(centre))));
    if (!at) continue;
    if (tip) {
      g.beginPath();
      g.moveTo(x0 + at[0], y0 + at[1]);
      g.lineTo(x0 + tip[0], y0 + tip[1]);
      g.stroke();
    }
    disc(g, x0 + at[0], y0 + at[1], colour);
    S.clipHandles3d.push({volume: k.o.name, index: k.index, x: x0 + at[0], y: y0 + at[1],
                          point: centre});
  }
}

function disc(g, x, y, colour) {
  g.fillStyle = colour;
  g.strokeStyle = '#000';
  g.lineWidth = 1;
  g.beginPath();
  g.arc(x, y, HANDLE_RADIUS, 0, 2 * Math.PI);
  g.fill();
  g.stroke();
}

// A 2-D view {point, right, down, mm, width, height}: its plane's centre, in-plane axes (unit,
// world), mm per backing pixel and image size; `r` the backing pixels per CSS pixel. Draws each
// clip plane's line across the view with a handle; returns the handles (backing pixels).
export function drawClipLines2d(g, view, r) {
  const handles = [];
  for (const k of clips()) {
    const line = lineIn(view, k);
    if (!line) continue;
    const colour = isSelected(k) ? '#fd4' : '#4cf';
    g.strokeStyle = colour;
    g.lineWidth = (isSelected(k) ? 2 : 1.5) * r;
    g.setLineDash([6 * r, 4 * r]);
    g.beginPath();
    g.moveTo(line.a[0], line.a[1]);
    g.lineTo(line.b[0], line.b[1]);
    g.stroke();
    g.setLineDash([]);
    disc(g, line.handle[0], line.handle[1], colour);
    handles.push({volume: k.o.name, index: k.index, x: line.handle[0], y: line.handle[1]});
  }
  return handles;
}

// Where the clip plane k crosses the view: the segment's ends inside the image and the handle (the
// line's point nearest the image's centre), in backing pixels; null when it does not cross.
function lineIn(view, k) {
  const nu = dot(view.right, k.normal), nv = dot(view.down, k.normal);
  const m = Math.hypot(nu, nv);
  if (m < 1e-6) return null;  // parallel to the view's plane
  // In image pixels (x, y) about the centre: nu * x + nv * y = d, in mm / mm-per-pixel.
  const d = dot(sub(k.point, view.point), k.normal) / view.mm;
  const cx = view.width / 2, cy = view.height / 2;
  const foot = [cx + nu * d / (m * m), cy + nv * d / (m * m)];
  const dir = [-nv / m, nu / m];
  // Clip the infinite line to the image's rectangle.
  let t0 = -1e9, t1 = 1e9;
  for (const [o, dd, lo, hi] of [[foot[0], dir[0], 0, view.width], [foot[1], dir[1], 0, view.height]]) {
    if (Math.abs(dd) < 1e-12) {
      if (o < lo || o > hi) return null;
      continue;
    }
    const ta = (lo - o) / dd, tb = (hi - o) / dd;
    t0 = Math.max(t0, Math.min(ta, tb));
    t1 = Math.min(t1, Math.max(ta, tb));
  }
  if (t0 >= t1) return null;
  const at = (t) => [foot[0] + dir[0] * t, foot[1] + dir[1] * t];
  return {a: at(t0), b: at(t1), handle: at(Math.min(t1, Math.max(t0, 0)))};
}

// The handle within reach of (x, y) in `handles` (same pixels), or null.
export function handleAt(handles, x, y, reach) {
  let best = null, bestD = reach;
  for (const h of handles || []) {
    const dd = Math.hypot(h.x - x, h.y - y);
    if (dd <= bestD) {
      best = h;
      bestD = dd;
    }
  }
  return best;
}

// A drag of a handle: moves that clip plane along its normal by the world displacement the drag
// stands for (`worldDelta`, mm), an edit while moving and a final one on release.
export function startClipDrag(handle) {
  const o = S.byName.get(handle.volume);
  if (!o || !o.clips[handle.index]) return null;
  S.selectedClip = {volume: o.name, index: handle.index};
  const c = o.clips[handle.index];
  return {o, c, offset0: c.offset};
}

export function moveClip(drag, worldDelta, moving) {
  drag.c.offset = drag.offset0 + dot(worldDelta, drag.c.normal);
  editInput(drag.o.name, {clip_planes: clipsMessage(drag.o)}, moving);
}
