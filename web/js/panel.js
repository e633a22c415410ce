// The object panel: one box per object of the scene with visibility and opacity, and per kind a
// plane's W/L target and position slider, a volume's frame slider and play, transfer-function
// editor, presets and clip planes. Rebuilt whole from S (buildPanel) after anything that adds,
// removes or moves its controls.
import {editInput} from './connection.js';
import {S, clipsMessage} from './state.js';
import {TfEditor} from './tf_editor.js';
import {add, dot, fmt, len, mul, norm, sub} from './vec.js';

const editors = new Map();  // volume name -> TfEditor

// The transfer-function editor of a volume, if the panel shows one.
export function tfEditor(volume) { return editors.get(volume); }

// Redraws every TF editor (their canvases follow the panel's size).
export function redrawEditors() {
  for (const ed of editors.values()) ed.draw();
}

// Shows a plane's window [centre, width] beside its W/L radio button.
export function showWindow(name, w) {
  const label = document.querySelector(`.object[data-name="${CSS.escape(name)}"] .wl-label`);
  if (label) label.textContent = windowText(w);
}

const windowText = (w) => `W/L target · W ${fmt(w[1], 0)} / L ${fmt(w[0], 0)}`;

function slider(label, min, max, step, value, onInput, onChange, digits = 2) {
  const row = document.createElement('div');
  row.className = 'row';
  const l = document.createElement('span');
  l.className = 'label';
  l.textContent = label;
  const input = document.createElement('input');
  input.type = 'range';
  input.min = min;
  input.max = max;
  input.step = step;
  input.value = value;
  const out = document.createElement('span');
  out.className = 'value';
  out.textContent = Number(value).toFixed(digits);
  input.addEventListener('input', () => {
    out.textContent = Number(input.value).toFixed(digits);
    onInput(Number(input.value));
  });
  input.addEventListener('change', () => onChange(Number(input.value)));
  row.append(l, input, out);
  return {row, input};
}

function button(text, onClick) {
  const b = document.createElement('button');
  b.type = 'button';
  b.textContent = text;
  b.addEventListener('click', onClick);
  return b;
}

// Rebuilds the panel (#objects) from S.objects.
export function buildPanel() {
  const root = document.getElementById('objects');
  for (const ed of editors.values()) ed.dispose();
  editors.clear();
  root.replaceChildren();
  for (const o of S.objects) {
    const box = document.createElement('div');
    box.className = 'object';
    box.dataset.name = o.name;
    const head = document.createElement('div');
    head.className = 'head';
    const cb = document.createElement('input');
    cb.type = 'checkbox';
    cb.checked = o.visible;
    cb.className = 'visible';
    cb.title = 'visible';
    cb.addEventListener('change', () => {
      o.visible = cb.checked;
      editInput(o.name, {visible: o.visible}, false);
    });
    const name = document.createElement('span');
    name.className = 'name';
    name.textContent = o.name;
    const kind = document.createElement('span');
    kind.className = 'kind';
    kind.textContent = o.kind;
    head.append(cb, name, kind);
    box.append(head);

    const sendOpacity = (moving) => editInput(o.name, {opacity: o.opacity}, moving);
    box.append(slider('opacity', 0, 1, 0.01, o.opacity,
                      (v) => { o.opacity = v; sendOpacity(true); },
                      (v) => { o.opacity = v; sendOpacity(false); }).row);

    if (o.kind === 'volume') buildVolume(box, o);
    if (o.kind === 'plane') buildPlane(box, o);
    root.append(box);
  }
}

// The radio that makes this plane the one a W/L drag edits.
function buildWindowTarget(box, o) {
  const row = document.createElement('div');
  row.className = 'row';
  const radio = document.createElement('input');
  radio.type = 'radio';
  radio.name = 'wl-plane';
  radio.checked = S.selectedPlane === o.name;
  radio.addEventListener('change', () => { S.selectedPlane = o.name; });
  const label = document.createElement('span');
  label.textContent = windowText(o.window);
  label.className = 'wl-label';
  row.append(radio, label);
  box.append(row);
}

function buildPlane(box, o) {
  if (o.volume) buildWindowTarget(box, o);
  const half = Math.max(o.size[0], o.size[1]) / 2;
  const offset = dot(sub(o.center, o.initialCenter), o.normal);
  const move = (v, moving) => {
    o.center = add(o.initialCenter, mul(o.normal, v));
    editInput(o.name, {center: o.center}, moving);
  };
  box.append(slider('position', -half, half, half / 500, offset, (v) => move(v, true),
                    (v) => move(v, false), 1).row);
}

// A multi-frame volume (fMRI, DWI, ...): a frame slider, and play / pause stepping through
// the frames about four times a second (each step re-runs only this volume's stage).
function buildFrames(box, o) {
  const frames = slider('frame', 0, o.frames - 1, 1, o.frame,
                        (v) => { o.frame = v; editInput(o.name, {frame: v}, true); },
                        (v) => { o.frame = v; editInput(o.name, {frame: v}, false); }, 0);
  let timer = null;
  const play = button('play', () => {
    if (timer) {
      clearInterval(timer);
      timer = null;
      play.textContent = 'play';
      return;
    }
    play.textContent = 'pause';
    timer = setInterval(() => {
      if (S.inFlight) return;  // the last frame is still rendering: do not queue up
      o.frame = (o.frame + 1) % o.frames;
      frames.input.value = o.frame;
      frames.row.querySelector('.value').textContent = String(o.frame);
      editInput(o.name, {frame: o.frame}, false);
    }, 250);
  });
  play.className = 'frame-play';
  frames.row.append(play);
  box.append(frames.row);
}

// A label volume's labels (those its voxels hold): visibility, colour, opacity, each an edit of
// that label alone (only this volume's stage re-runs).
function buildLabels(box, o) {
  const list = document.createElement('div');
  list.className = 'labels';
  const hex = (c) => '#' + c.map((x) => Math.round(255 * Math.min(1, Math.max(0, x)))
      .toString(16).padStart(2, '0')).join('');
  for (const l of o.labels) {
    const row = document.createElement('div');
    row.className = 'row label';
    row.dataset.value = String(l.value);
    const cb = document.createElement('input');
    cb.type = 'checkbox';
    cb.checked = l.visible;
    cb.title = 'visible';
    const colour = document.createElement('input');
    colour.type = 'color';
    colour.value = hex(l.color);
    colour.title = 'colour';
    const name = document.createElement('span');
    name.className = 'label-name';
    name.textContent = `${l.value} ${l.name}`;
    const send = (fields, moving) => {
      Object.assign(l, fields);
      editInput(o.name, {labels: [Object.assign({value: l.value}, fields)]}, moving);
    };
    cb.addEventListener('change', () => send({visible: cb.checked}, false));
    colour.addEventListener('input', () => {
      const v = colour.value;
      send({color: [1, 3, 5].map((i) => parseInt(v.slice(i, i + 2), 16) / 255)}, false);
    });
    const s = slider('', 0, 1, 0.01, l.opacity, (v) => send({opacity: v}, true),
                     (v) => send({opacity: v}, false));
    row.append(cb, colour, name, s.input);
    list.append(row);
  }
  box.append(list);
}

function buildVolume(box, o) {
  if (o.frames > 1) buildFrames(box, o);
  if (o.labels) {  // drawn through its colour table: no transfer function to edit
    buildLabels(box, o);
    return;
  }
  const ed = new TfEditor(o, S.histograms[o.name]);
  editors.set(o.name, ed);
  box.append(ed.root);
  const names = Object.keys(S.tfPresets || {});
  if (names.length) {
    // A preset replaces the points (the volume keeps its shading and unit distance).
    const row = document.createElement('div');
    row.className = 'row';
    const select = document.createElement('select');
    select.className = 'tf-preset';
    select.append(new Option('preset…', ''), ...names.map((n) => new Option(n, n)));
    select.value = o.presetName || '';  // the active preset, until the points are edited
    select.addEventListener('change', () => {
      const pts = S.tfPresets[select.value];
      if (!pts) return;
      o.tf = pts.map((p) => [...p]);
      o.maxAlpha = 0;
      o.presetName = select.value;
      ed.sendTf(false, true);
      buildPanel();
    });
    row.append(select);
    box.append(row);
  }
  const range = S.initialCamera ? 0.5 * len(sub(S.initialCamera.eye, S.initialCamera.target))
                                : 200;
  o.clips.forEach((c, i) => {
    const div = document.createElement('div');
    const selected = S.selectedClip && S.selectedClip.volume === o.name &&
                     S.selectedClip.index === i;
    div.className = 'clip' + (selected ? ' selected' : '');
    const moveClip = (v, moving) => {
      c.offset = v;
      S.selectedClip = {volume: o.name, index: i};
      editInput(o.name, {clip_planes: clipsMessage(o)}, moving);
    };
    const s = slider(`clip ${i + 1}`, -range, range, range / 500, c.offset,
                     (v) => moveClip(v, true), (v) => moveClip(v, false), 1);
    s.row.append(button('remove', () => {
      o.clips.splice(i, 1);
      S.selectedClip = null;
      editInput(o.name, {clip_planes: clipsMessage(o)}, false);
      buildPanel();
    }));
    s.input.addEventListener('pointerdown', () => { S.selectedClip = {volume: o.name, index: i}; });
    div.append(s.row);
    box.append(div);
  });
  const row = document.createElement('div');
  row.className = 'row';
  row.append(button('add clip plane', () => {
    // Through the camera target, facing the way the camera looks.
    o.clips.push({base: [...S.camera.target],
                  normal: norm(sub(S.camera.target, S.camera.eye)), offset: 0});
    S.selectedClip = {volume: o.name, index: o.clips.length - 1};
    editInput(o.name, {clip_planes: clipsMessage(o)}, false);
    buildPanel();
  }));
  box.append(row);
}
