// The object panel: one box per object of the scene with visibility and opacity, and per kind a
// plane's W/L target and position slider, a volume's frame slider and play, transfer-function
// editor, presets and clip planes, a tractogram's colouring, radius, stride, minimum length and
// sphere region. Rebuilt whole from S (buildPanel) after anything that adds,
// removes or moves its controls.
import {editInput} from './connection.js';
import {sphereRegions} from './history.js';
import {SLAB_MODES} from './reading_frame.js';
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

// Shows a volume's 2-D window (the one its reading views use) in its box.
export function showVolumeWindow(o) {
  const label = document.querySelector(`.object[data-name="${CSS.escape(o.name)}"] .slice-window`);
  if (label && o.window) label.textContent = sliceWindowText(o.window);
}

const sliceWindowText = (w) => `2-D window · W ${fmt(w[1], 0)} / L ${fmt(w[0], 0)}`;

// The window of a volume's 2-D views, and the note when the rule refused the header's window.
function buildSliceWindow(box, o) {
  const row = document.createElement('div');
  row.className = 'row';
  const label = document.createElement('span');
  label.className = 'slice-window';
  label.textContent = sliceWindowText(o.window);
  row.append(label);
  box.append(row);
  if (!o.windowNote) return;
  const note = document.createElement('div');
  note.className = 'window-note';
  note.textContent = o.windowNote;
  box.append(note);
}

function slider(label, min, max, step, value, onInput, onChange, digits = 2) {
  const row = document.createElement('div');
  row.className = 'row';
  row.dataset.control = label;  // what tests and styles find it by
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
    if (o.kind === 'streamlines' && !o.connectome) buildStreamlines(box, o);
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
  if (o.volume) buildPlaneSlab(box, o);
}

// A plane's thick slab in 3-D: thickness (0: the plane alone) and MIP / MinIP / mean.
function buildPlaneSlab(box, o) {
  const send = (moving) => editInput(o.name, {slab: {...o.slab}}, moving);
  box.append(slider('slab mm', 0, 50, 0.5, o.slab.thickness,
                    (v) => { o.slab.thickness = v; send(true); },
                    (v) => { o.slab.thickness = v; send(false); }, 1).row);
  box.append(labelled('slab mode', select('slab-mode', SLAB_MODES.map((m) => [m, m]), o.slab.mode,
                                          (v) => { o.slab.mode = v; send(false); })));
}

// A multi-frame volume (fMRI, DWI, ...): a frame slider, and play / pause stepping through
// the frames at the toolbar's cine rate (each step re-runs only this volume's stage).
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
    }, 1000 / Math.min(60, Math.max(1, Number(document.getElementById('cine-fps').value) || 4)));
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
  // The 2-D views show the first volume through its window (the others in their TF's colours).
  const base = S.objects.find((x) => x.kind === 'volume' && x.bounds);
  if (o === base && o.window && !o.labels) buildSliceWindow(box, o);
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

const hexColour = (c) => '#' + c.map((x) => Math.round(255 * Math.min(1, Math.max(0, x)))
    .toString(16).padStart(2, '0')).join('');
const colourOfHex = (v) => [1, 3, 5].map((i) => parseInt(v.slice(i, i + 2), 16) / 255);

function select(className, options, value, onChange) {
  const el = document.createElement('select');
  el.className = className;
  el.append(...options.map(([v, text]) => new Option(text, v)));
  el.value = value;
  el.addEventListener('change', () => onChange(el.value));
  return el;
}

function labelled(label, ...controls) {
  const row = document.createElement('div');
  row.className = 'row';
  const l = document.createElement('span');
  l.className = 'label';
  l.textContent = label;
  row.append(l, ...controls);
  return row;
}

// A tractogram: its colouring (with a colour, or values through a colour map), tube radius,
// stride, minimum length and one sphere region (pass through or avoid) at the crosshair, else
// at the camera's target.
function buildStreamlines(box, o) {
  const modes = [['direction', 'direction'], ['streamline_direction', 'streamline direction'],
                 ['fixed', 'fixed colour']];
  if ((o.point_values || []).length) modes.push(['point_value', 'point values']);
  if ((o.streamline_values || []).length) modes.push(['streamline_value', 'streamline values']);
  if (o.has_groups) modes.push(['group', 'group']);
  box.append(labelled('colour', select('sl-color-by', modes, o.color_by, (v) => {
    o.color_by = v;
    const names = v === 'point_value' ? o.point_values : o.streamline_values;
    const fields = {color_by: v};
    if ((v === 'point_value' || v === 'streamline_value') && !(names || []).includes(o.value))
      fields.value = o.value = names[0];
    editInput(o.name, fields, false);
    buildPanel();
  })));
  if (o.color_by === 'fixed' || o.color_by === 'group') {
    const colour = document.createElement('input');
    colour.type = 'color';
    colour.className = 'sl-color';
    colour.value = hexColour(o.color || [1, 1, 1]);
    colour.addEventListener('input', () => {
      o.color = colourOfHex(colour.value);
      editInput(o.name, {color: o.color}, false);
    });
    box.append(labelled('', colour));
  }
  if (o.color_by === 'point_value' || o.color_by === 'streamline_value') {
    const names = o.color_by === 'point_value' ? o.point_values : o.streamline_values;
    box.append(labelled('values', select('sl-value', names.map((n) => [n, n]), o.value, (v) => {
      o.value = v;
      editInput(o.name, {value: v}, false);
    })));
    const maps = (o.colormaps || []).map((n) => [n, n]);
    box.append(labelled('map', select('sl-colormap', maps, o.colormap, (v) => {
      o.colormap = v;
      editInput(o.name, {colormap: v}, false);
    })));
  }
  const field = (key, moving) => editInput(o.name, {[key]: o[key]}, moving);
  const radius = slider('radius', 0.05, 3, 0.05, o.radius, (v) => { o.radius = v; field('radius', true); },
                        (v) => { o.radius = v; field('radius', false); });
  radius.input.classList.add('sl-radius');
  box.append(radius.row);
  const strideMax = Math.max(2, Math.min(1000, o.count || 2));
  const stride = slider('stride', 1, strideMax, 1, o.stride,
                        (v) => { o.stride = v; field('stride', true); },
                        (v) => { o.stride = v; field('stride', false); }, 0);
  stride.input.classList.add('sl-stride');
  box.append(stride.row);
  const minLength = slider('min length', 0, 200, 1, o.min_length,
                           (v) => { o.min_length = v; field('min_length', true); },
                           (v) => { o.min_length = v; field('min_length', false); }, 0);
  minLength.input.classList.add('sl-min-length');
  box.append(minLength.row);
  buildSphereRegion(box, o);
}

function buildSphereRegion(box, o) {
  const others = (o.regions || []).filter((r) => r.shape !== 'sphere');
  let sphere = (o.regions || []).find((r) => r.shape === 'sphere');
  const send = (moving) => {
    o.regions = [...others, ...(sphere ? [sphere] : [])];
    editInput(o.name, {regions: sphereRegions(o)}, moving);
  };
  const here = () => [...(S.point || (S.camera ? S.camera.target : [0, 0, 0]))];
  const on = document.createElement('input');
  on.type = 'checkbox';
  on.className = 'sl-region-on';
  on.checked = Boolean(sphere);
  on.title = 'sphere region';
  on.addEventListener('change', () => {
    sphere = on.checked ? {shape: 'sphere', center: here(), radius: 10, avoid: false} : null;
    send(false);
    buildPanel();
  });
  box.append(labelled('region', on));
  if (!sphere) return;
  const mode = select('sl-region-mode', [['pass', 'pass through'], ['avoid', 'avoid']],
                      sphere.avoid ? 'avoid' : 'pass', (v) => {
                        sphere.avoid = v === 'avoid';
                        send(false);
                      });
  const centre = button('centre here', () => {
    sphere.center = here();
    send(false);
    buildPanel();
  });
  centre.className = 'sl-region-centre';
  const text = document.createElement('span');
  text.className = 'value';
  text.textContent = sphere.center.map((c) => fmt(c, 1)).join(', ');
  box.append(labelled('', mode, centre, text));
  const r = slider('radius (mm)', 1, 60, 0.5, sphere.radius,
                   (v) => { sphere.radius = v; send(true); },
                   (v) => { sphere.radius = v; send(false); }, 1);
  r.input.classList.add('sl-region-radius');
  box.append(r.row);
}
