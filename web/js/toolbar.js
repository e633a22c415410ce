// The toolbar: method and quality selectors, reset view, W/L mode, save scene and screenshot,
// and what the server answers to the last two (downloads).
import {cameraInput, editInput, queueInput, send} from './connection.js';
import {showWindow} from './panel.js';
import {downloadView} from './screenshot.js';
import {linkViews, resetSliceViews, setSliceWindow} from './slices.js';
import {S} from './state.js';
import {stats} from './stats.js';
import {copyCamera} from './vec.js';

// Fills the method and quality selectors from S (after hello and after a changed state).
export function buildSelectors() {
  const method = document.getElementById('method');
  method.replaceChildren(...S.methods.map((name) => new Option(name, name, false,
                                                                name === S.method)));
  const quality = document.getElementById('quality');
  const spps = Object.keys(QUALITY).map(Number);
  if (!spps.includes(S.spp)) spps.push(S.spp);
  spps.sort((a, b) => a - b);
  quality.replaceChildren(...spps.map((n) => new Option(
      QUALITY[n] ? `${QUALITY[n]} (${n} spp)` : `${n} spp`, String(n), false, n === S.spp)));
}

// Still-frame quality by name: the samples per pixel frames converge to.
const QUALITY = {1: 'draft', 4: 'normal', 16: 'best'};

// Radiology's window/level presets [level, width] (HU), for MPR planes and the 2-D views.
export const WL_PRESETS = {
  brain: [40, 80], subdural: [75, 215], stroke: [40, 40], bone: [400, 1800],
  lung: [-600, 1500], abdomen: [50, 400], liver: [30, 150], mediastinum: [50, 350],
};

// The six standard views: where the eye is from the target (LPS: +x left, +y posterior, +z
// superior) and which way is up (superior, or anterior looking along the body's axis).
const SNAPS = {
  A: {dir: [0, -1, 0], up: [0, 0, 1]}, P: {dir: [0, 1, 0], up: [0, 0, 1]},
  L: {dir: [1, 0, 0], up: [0, 0, 1]}, R: {dir: [-1, 0, 0], up: [0, 0, 1]},
  S: {dir: [0, 0, 1], up: [0, -1, 0]}, I: {dir: [0, 0, -1], up: [0, -1, 0]},
};

// Turns the camera to a standard view about its target, at its distance.
export function snapView(name) {
  const s = SNAPS[name];
  if (!s || !S.camera) return;
  const c = S.camera;
  const d = Math.hypot(...c.eye.map((e, i) => e - c.target[i]));
  c.eye = c.target.map((t, i) => t + s.dir[i] * d);
  c.up = s.up.slice();
  cameraInput(false, true);
}

// Binds the toolbar's controls; call once.
export function setupToolbar() {
  document.getElementById('method').addEventListener('change', (e) => {
    S.method = e.target.value;
    queueInput('settings', {type: 'settings', method: S.method}, false);
  });
  document.getElementById('quality').addEventListener('change', (e) => {
    S.spp = Number(e.target.value);
    queueInput('settings', {type: 'settings', spp: S.spp}, false);
  });
  document.getElementById('reset-view').addEventListener('click', () => {
    if (!S.initialCamera) return;
    S.camera = copyCamera(S.initialCamera);
    cameraInput(false, true);
    resetSliceViews();  // the 2-D views' zoom and pan too
  });
  const link = document.getElementById('link-views');
  link.addEventListener('change', () => linkViews(link.checked));
  for (const b of document.querySelectorAll('#snap button'))
    b.addEventListener('click', () => snapView(b.dataset.view));
  const preset = document.getElementById('wl-preset');
  preset.replaceChildren(new Option('W/L preset…', ''),
                         ...Object.keys(WL_PRESETS).map((n) => new Option(n, n)));
  preset.addEventListener('change', () => {
    const w = WL_PRESETS[preset.value];
    if (!w) return;
    S.wlPreset = preset.value;
    // The 2-D views' base volume, and the selected MPR plane: [centre, width]; the panel shows
    // both windows as they now are.
    setSliceWindow([w[0], w[1]]);
    if (S.selectedPlane) {
      const o = S.byName.get(S.selectedPlane);
      if (o) {
        o.window = [w[0], w[1]];
        editInput(o.name, {window: o.window}, false);
        showWindow(o.name, o.window);
      }
    }
  });
  const wl = document.getElementById('wl-mode');
  wl.addEventListener('click', () => {
    S.wlMode = !S.wlMode;
    wl.setAttribute('aria-pressed', String(S.wlMode));
  });
  document.getElementById('save').addEventListener('click', () => send({type: 'save'}));
  document.getElementById('screenshot').addEventListener('click', () => {
    const what = document.getElementById('shot-view').value;
    if (what === 'full') send({type: 'screenshot'});
    else downloadView(what, Number(document.getElementById('shot-scale').value));
  });
}

// The `saved` answer: shows the name the server saved the scene under (beside the scene file;
// never a server path) and downloads the file.
export function onSaved(m) {
  stats.saved = {file: m.file};
  document.getElementById('saved-path').textContent = 'saved: ' + m.file;
  const name = m.file || 'scene.json';
  download(new Blob([m.text || ''], {type: 'application/json'}),
           name.endsWith('.json') ? name : name + '.json');
}

// The screenshot's PNG: downloads it.
export function onScreenshot(blob) {
  download(new Blob([blob], {type: 'image/png'}), 'intermix-screenshot.png');
}

function download(blob, name) {
  const a = document.createElement('a');
  a.href = URL.createObjectURL(blob);
  a.download = name;
  document.body.appendChild(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 10000);
}
