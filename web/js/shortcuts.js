// Keyboard shortcuts (listed in the help overlay, "?"), the "advanced" switch that shows the
// method menu and the status line, and "copy link": the view as an address without the token.
import {cameraInput, editInput} from './connection.js';
import {applyFields, editFields, redo, undo} from './history.js';
import {setAnnotations} from './measure.js';
import {crosshairRotation, isOblique, setCrosshairRotation} from './reading_frame.js';
import {setLayout} from './slices.js';
import {S} from './state.js';
import {snapView} from './toolbar.js';
import {copyCamera} from './vec.js';

const KEYS = [
  ['1 / 2 / 3', 'layout: 3-D, 2×2, 1×3'],
  ['a p l r s i', 'look from anterior, posterior, left, right, superior, inferior'],
  ['Home', 'reset the view'],
  ['w', 'window/level mode on or off'],
  ['↑ ↓, Page Up / Down', 'over a 2-D view: one slice, ten slices'],
  ['Ctrl+Z, Ctrl+Shift+Z / Ctrl+Y', 'undo, redo this window\'s last object edit'],
  ['?', 'this list'],
];

function toggleHelp(show) {
  const el = document.getElementById('shortcuts');
  el.hidden = show === undefined ? !el.hidden : !show;
}

function onKey(ev) {
  const t = ev.target;
  if (t && (t.tagName === 'INPUT' || t.tagName === 'SELECT' || t.tagName === 'TEXTAREA')) return;
  const k = ev.key;
  if ((ev.ctrlKey || ev.metaKey) && !ev.altKey && (k === 'z' || k === 'Z' || k === 'y')) {
    if (k === 'y' || ev.shiftKey) redo();
    else undo();
    ev.preventDefault();
    return;
  }
  if (ev.ctrlKey || ev.metaKey || ev.altKey) return;
  if (k === '?') toggleHelp();
  else if (k === 'Escape') toggleHelp(false);
  else if (k === '1' || k === '2' || k === '3') setLayout({1: '1x1', 2: '2x2', 3: '1x3'}[k]);
  else if ('aplrsi'.includes(k) && k.length === 1) snapView(k.toUpperCase());
  else if (k === 'Home') document.getElementById('reset-view').click();
  else if (k === 'w') document.getElementById('wl-mode').click();
  else return;
  ev.preventDefault();
}

// The page's address for this view: camera, layout, crosshair (and its turn), each object's edits
// (visibility, opacity, transfer function, window, position, clip planes, frame, slabs) and the
// measurements in the fragment (never the token; the one who opens it needs their own).
export function viewLink() {
  const view = {
    camera: S.camera,
    layout: document.getElementById('layout').value,
    point: S.point || null,
    rotation: isOblique() ? crosshairRotation() : null,  // the oblique views' crosshair
    objects: S.objects.map((o) => [o.name, editFields(o)]),
    annotations: S.annotations,
  };
  return location.origin + location.pathname + '#view=' + encodeURIComponent(JSON.stringify(view));
}

// Applies a link's view (after hello): the camera as it was, the layout, the crosshair, and the
// objects' edits where they differ (each an edit of this window, so it can be undone).
export function applyViewLink() {
  const m = /#view=(.*)$/.exec(location.hash);
  if (!m) return;
  // Once: a reconnect's hello must not turn the view back.
  history.replaceState(history.state, '', location.pathname + location.search);
  let view;
  try {
    view = JSON.parse(decodeURIComponent(m[1]));
  } catch (e) {
    return;
  }
  if (view.camera && view.camera.eye && view.camera.target && view.camera.up) {
    S.camera = copyCamera(view.camera);
    cameraInput(false, true);
  }
  for (const [name, fields] of view.objects || []) {
    const o = S.byName.get(name);
    if (!o || !fields || typeof fields !== 'object') continue;
    const now = editFields(o), changed = {};
    for (const key of Object.keys(now))
      if (key in fields && JSON.stringify(fields[key]) !== JSON.stringify(now[key]))
        changed[key] = fields[key];
    if (!Object.keys(changed).length) continue;
    applyFields(o, changed);
    editInput(name, changed, false);
  }
  // The measurements as they were (one step of this window's history; the server checks them).
  if (Array.isArray(view.annotations) &&
      JSON.stringify(view.annotations) !== JSON.stringify(S.annotations))
    setAnnotations(view.annotations);
  if (Array.isArray(view.point) && view.point.length === 3) S.point = view.point.map(Number);
  if (Array.isArray(view.rotation) && view.rotation.length === 3)
    setCrosshairRotation(view.rotation);
  if (['1x1', '2x2', '1x3'].includes(view.layout)) setLayout(view.layout);
}

export function setupShortcuts() {
  const list = document.getElementById('shortcut-list');
  for (const [keys, what] of KEYS) {
    const dt = document.createElement('dt');
    dt.textContent = keys;
    const dd = document.createElement('dd');
    dd.textContent = what;
    list.append(dt, dd);
  }
  window.addEventListener('keydown', onKey);
  document.getElementById('shortcuts').addEventListener('click', () => toggleHelp(false));
  const advanced = document.getElementById('advanced');
  const apply = () => document.body.classList.toggle('advanced', advanced.checked);
  advanced.addEventListener('change', apply);
  apply();
  document.getElementById('copy-link').addEventListener('click', async () => {
    const link = viewLink();
    S.copiedLink = link;
    try {
      await navigator.clipboard.writeText(link);
    } catch (e) {
      window.prompt('copy this link', link);  // no clipboard (plain http on another host)
    }
  });
}
