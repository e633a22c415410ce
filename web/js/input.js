// Pointer, wheel and touch input on the view canvas. Left drag orbits; right, middle or shift
// drag pans; the wheel and a pinch zoom; ctrl (or W/L mode) drag sets the selected plane's
// window and level; alt drag moves the selected clip plane along its normal, and so does a drag
// of a clip plane's handle (clip_outlines.js), following the pointer. Each becomes a
// camera or edit input (connection.js), moving while it goes on and final on release.
import {mmPerPixel, orbit, pan, zoom} from './camera.js';
import {HANDLE_RADIUS, handleAt, moveClip, projector, startClipDrag} from './clip_outlines.js';
import {cameraInput, editInput} from './connection.js';
import {pick3d} from './measure.js';
import {buildPanel, showWindow} from './panel.js';
import {S, clipsMessage} from './state.js';
import {clamp, dot, mul} from './vec.js';

let canvas = null;

// Binds the view canvas's input; call once.
export function setupInput(el) {
  canvas = el;
  canvas.addEventListener('contextmenu', (ev) => ev.preventDefault());
  canvas.addEventListener('pointerdown', (ev) => {
    if (!S.camera) return;
    if (ev.button === 0 && !ev.ctrlKey && !ev.metaKey && !ev.shiftKey && !ev.altKey &&
        ev.pointerType !== 'touch') {  // the 3-D ruler: a click picks a point, nothing turns
      const r = canvas.getBoundingClientRect();
      if (pick3d(ev.clientX - r.left, ev.clientY - r.top, r.width, r.height)) {
        ev.preventDefault();
        return;
      }
    }
    canvas.setPointerCapture(ev.pointerId);
    canvas.focus();
    S.pointers.set(ev.pointerId, {x: ev.clientX, y: ev.clientY});
    if (ev.pointerType === 'touch') {
      S.drag = {mode: 'touch'};
    } else {
      let mode = 'orbit';
      if (ev.button === 2 || ev.button === 1 || ev.shiftKey) mode = 'pan';
      if (ev.button === 0 && (ev.ctrlKey || ev.metaKey || S.wlMode)) mode = 'wl';
      if (ev.button === 0 && ev.altKey) mode = 'clip';
      const handle = ev.button === 0 && mode === 'orbit' ? handle3dAt(ev) : null;
      S.drag = {mode, x0: ev.clientX, y0: ev.clientY};
      if (handle) {
        S.drag.handle = startClipDrag(handle);
        S.drag.mode = S.drag.handle ? 'handle' : 'orbit';
        S.drag.point = handle.point;
      }
      if (mode === 'wl') {
        S.drag.wl = startWindowLevel();
        if (!S.drag.wl) S.drag.mode = 'none';
      }
      if (mode === 'clip') {
        S.drag.clip = selectedClip();
        if (S.drag.clip) S.drag.offset0 = S.drag.clip.c.offset;
        else S.drag.mode = 'none';
      }
    }
    canvas.classList.add('dragging');
    ev.preventDefault();
  });
  canvas.addEventListener('pointermove', (ev) => {
    const prev = S.pointers.get(ev.pointerId);
    if (!prev || !S.drag) return;
    const dx = ev.clientX - prev.x, dy = ev.clientY - prev.y;
    if (S.drag.mode === 'touch') {
      touchMove(ev);
      return;
    }
    S.pointers.set(ev.pointerId, {x: ev.clientX, y: ev.clientY});
    if (dx === 0 && dy === 0) return;
    const d = S.drag;
    if (d.mode === 'orbit') { orbit(S.camera, dx, dy, canvas.clientHeight); cameraInput(true); }
    else if (d.mode === 'pan') { pan(S.camera, dx, dy, canvas.clientHeight); cameraInput(true); }
    else if (d.mode === 'wl') applyWindowLevel(d, ev.clientX - d.x0, ev.clientY - d.y0, true);
    else if (d.mode === 'clip') moveClipByDrag(d, ev.clientY - d.y0, true);
    else if (d.mode === 'handle') dragHandle(d, ev, true);
  });
  const end = (ev) => {
    if (!S.pointers.has(ev.pointerId)) return;
    S.pointers.delete(ev.pointerId);
    if (canvas.hasPointerCapture(ev.pointerId)) canvas.releasePointerCapture(ev.pointerId);
    const d = S.drag;
    if (d && d.mode === 'touch') {
      d.last = null;  // the remaining fingers start a fresh gesture, without a jump
      if (S.pointers.size > 0) return;
    }
    S.drag = null;
    canvas.classList.remove('dragging');
    if (!d) return;
    if (d.mode === 'orbit' || d.mode === 'pan' || d.mode === 'touch') cameraInput(false);
    else if (d.mode === 'wl') applyWindowLevel(d, ev.clientX - d.x0, ev.clientY - d.y0, false);
    else if (d.mode === 'clip') moveClipByDrag(d, ev.clientY - d.y0, false);
    else if (d.mode === 'handle') {
      dragHandle(d, ev, false);
      buildPanel();
    }
  };
  canvas.addEventListener('pointerup', end);
  canvas.addEventListener('pointercancel', end);
  canvas.addEventListener('wheel', (ev) => {
    if (!S.camera) return;
    ev.preventDefault();
    const scale = ev.deltaMode === 1 ? 16 : ev.deltaMode === 2 ? 400 : 1;
    zoom(S.camera, Math.exp(clamp(ev.deltaY * scale, -500, 500) * 0.0015));
    cameraInput(true);
    clearTimeout(S.wheelTimer);
    S.wheelTimer = setTimeout(() => {
      S.wheelTimer = 0;
      cameraInput(false);
    }, 250);
  }, {passive: false});
}

// One finger orbits; two pan by their midpoint and zoom by their distance.
function touchMove(ev) {
  const d = S.drag;
  S.pointers.set(ev.pointerId, {x: ev.clientX, y: ev.clientY});
  const pts = [...S.pointers.values()];
  const now = pts.length >= 2
      ? {n: 2, x: (pts[0].x + pts[1].x) / 2, y: (pts[0].y + pts[1].y) / 2,
         dist: Math.hypot(pts[0].x - pts[1].x, pts[0].y - pts[1].y)}
      : {n: 1, x: pts[0].x, y: pts[0].y, dist: 0};
  const last = d.last;
  d.last = now;
  if (!last || last.n !== now.n) return;
  if (now.n === 1) {
    orbit(S.camera, now.x - last.x, now.y - last.y, canvas.clientHeight);
  } else {
    pan(S.camera, now.x - last.x, now.y - last.y, canvas.clientHeight);
    if (now.dist > 0 && last.dist > 0) zoom(S.camera, last.dist / now.dist);
  }
  cameraInput(true);
}

// ---------------------------------------------------------------- window / level
function startWindowLevel() {
  const p = S.selectedPlane && S.byName.get(S.selectedPlane);
  return p ? {plane: p, window0: [...p.window]} : null;
}

// Horizontal drag scales the window's width exponentially; vertical moves its centre by the
// width / 256 per pixel.
function applyWindowLevel(drag, dx, dy, moving) {
  const p = drag.wl.plane;
  const [c0, w0] = drag.wl.window0;
  const width = Math.max(1e-6, w0 * Math.exp(dx * 0.005));
  const centre = c0 + dy * Math.max(Math.abs(w0), 1e-3) / 256;
  p.window = [centre, width];
  editInput(p.name, {window: p.window}, moving);
  showWindow(p.name, p.window);
}

// ---------------------------------------------------------------- clip planes
// The clip plane an alt drag moves: the selected one, else the last of the first volume with any.
function selectedClip() {
  const sc = S.selectedClip;
  if (sc) {
    const o = S.byName.get(sc.volume);
    if (o && o.clips[sc.index]) return {o, c: o.clips[sc.index]};
  }
  for (const o of S.objects)
    if (o.kind === 'volume' && o.clips.length) return {o, c: o.clips[o.clips.length - 1]};
  return null;
}

// The clip-plane handle under the pointer (colorbar.js draws them in the cell's pixels).
function handle3dAt(ev) {
  const cell = document.getElementById('cell-3d').getBoundingClientRect();
  return handleAt(S.clipHandles3d, ev.clientX - cell.left, ev.clientY - cell.top,
                  1.5 * HANDLE_RADIUS);
}

// A handle follows the pointer: the drag as a displacement in the view's plane at the handle's
// depth, of which the part along the plane's normal moves the plane.
// A plane facing the camera (normal within 60 degrees of the view direction) takes the vertical
// drag instead, as alt+drag does: down moves it towards the viewer.
function dragHandle(d, ev, moving) {
  const proj = projector(canvas.clientWidth, canvas.clientHeight);
  const mm = proj.mmPerPixel(d.point);
  const dx = (ev.clientX - d.x0) * mm, dy = (ev.clientY - d.y0) * mm;
  const n = d.handle.c.normal;
  const facing = dot(n, proj.right) ** 2 + dot(n, proj.up) ** 2 < 0.25;
  const delta = facing ? mul(n, -dy) : proj.right.map((x, i) => x * dx - proj.up[i] * dy);
  moveClip(d.handle, delta, moving);
}

// Dragging down moves the plane against its normal by the scene's mm per pixel at the target.
function moveClipByDrag(d, dy, moving) {
  const {o, c} = d.clip;
  c.offset = d.offset0 - dy * mmPerPixel(S.camera, canvas.clientHeight);
  editInput(o.name, {clip_planes: clipsMessage(o)}, moving);
  if (!moving) buildPanel();
}
