// The toolbar: method and quality selectors, reset view, W/L mode, save scene and screenshot,
// and what the server answers to the last two (downloads).
import {cameraInput, queueInput, send} from './connection.js';
import {S} from './state.js';
import {stats} from './stats.js';
import {copyCamera} from './vec.js';

// Fills the method and quality selectors from S (after hello and after a changed state).
export function buildSelectors() {
  const method = document.getElementById('method');
  method.replaceChildren(...S.methods.map((name) => new Option(name, name, false,
                                                                name === S.method)));
  const quality = document.getElementById('quality');
  const spps = [1, 4, 9, 16];
  if (!spps.includes(S.spp)) spps.push(S.spp);
  spps.sort((a, b) => a - b);
  quality.replaceChildren(...spps.map((n) => new Option(`${n} spp`, String(n), false,
                                                         n === S.spp)));
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
  });
  const wl = document.getElementById('wl-mode');
  wl.addEventListener('click', () => {
    S.wlMode = !S.wlMode;
    wl.setAttribute('aria-pressed', String(S.wlMode));
  });
  document.getElementById('save').addEventListener('click', () => send({type: 'save'}));
  document.getElementById('screenshot')
      .addEventListener('click', () => send({type: 'screenshot'}));
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
