// Undo and redo of this page's object edits (visibility, opacity, transfer function, windows,
// plane position, clip planes, frame, labels) and of its measurements (the scene's annotations,
// a step holding the list before and after). A gesture counts once: connection.js reports each
// final (not moving) edit here with the fields it sent, and the values before are those of the last
// commit of that object, so a drag of many moving edits undoes in one step. Other windows' edits
// (a `state`) become the new "before" without entering this page's history.
import {S, clipsMessage} from './state.js';
import {norm} from './vec.js';

const MAX_STEPS = 200;
const undoStack = [], redoStack = [];
let committed = new Map();  // object name -> its edit fields as last committed
let send = null;            // connection.js editInput, given at setup (no import cycle)
let onApplied = () => {};   // rebuilds the panel and views after an undo or redo
let replaying = false;
let sendAnnotations = null;  // measure.js setAnnotations, given at setup

// An object's editable fields, as an `edit` message holds them.
export function editFields(o) {
  const f = {visible: o.visible, opacity: o.opacity};
  if (o.kind === 'volume') {
    f.transfer_function = o.tf.map((p) => [...p]);
    f.clip_planes = clipsMessage(o);
    if (o.window) f.window = [...o.window];  // its 2-D views' window
    f.slabs = JSON.parse(JSON.stringify(o.slabs || {}));  // and thick slabs
    if (o.frames > 1) f.frame = o.frame;
    if (o.labels)
      f.labels = o.labels.map((l) => ({value: l.value, visible: l.visible, opacity: l.opacity,
                                       color: [...l.color]}));
  } else if (o.kind === 'plane') {
    f.window = [...o.window];
    f.center = [...o.center];
    if (o.slab) f.slab = {...o.slab};  // its thick slab
  } else if (o.kind === 'streamlines') {
    for (const key of STREAMLINE_EDITS) f[key] = JSON.parse(JSON.stringify(o[key] ?? null));
    f.regions = sphereRegions(o);
  }
  return f;
}

// Sets an object's local fields from edit-message fields (an undo, a redo, a link).
export function applyFields(o, f) {
  if ('visible' in f) o.visible = Boolean(f.visible);
  if ('opacity' in f) o.opacity = Number(f.opacity);
  if (o.kind === 'volume') {
    if (f.transfer_function) o.tf = f.transfer_function.map((p) => [...p]);
    if (f.clip_planes)
      o.clips = f.clip_planes.map((c) => ({base: [...c.point], normal: norm(c.normal), offset: 0}));
    if (f.window) o.window = [...f.window];
    if (f.slabs) o.slabs = JSON.parse(JSON.stringify(f.slabs));
    if ('frame' in f) o.frame = f.frame;
    if (f.labels && o.labels)
      for (const row of f.labels) {
        const l = o.labels.find((x) => x.value === row.value);
        if (l) Object.assign(l, row, row.color ? {color: [...row.color]} : {});
      }
  } else if (o.kind === 'plane') {
    if (f.window) o.window = [...f.window];
    if (f.center) o.center = [...f.center];
    if (f.slab) o.slab = {...f.slab};
  } else if (o.kind === 'streamlines') {
    for (const key of STREAMLINE_EDITS)
      if (key in f) o[key] = JSON.parse(JSON.stringify(f[key]));
    if (f.regions)
      o.regions = [...(o.regions || []).filter((r) => r.shape !== 'sphere'),
                   ...f.regions.map((r) => ({shape: 'sphere', center: [...r.sphere.center],
                                             radius: r.sphere.radius, avoid: Boolean(r.avoid)}))];
  }
}

// A tractogram's edit fields besides its regions (docs/viewer.md, `edit`).
const STREAMLINE_EDITS = ['color_by', 'color', 'value', 'colormap', 'range', 'radius', 'stride',
                          'min_length'];
// Its sphere regions as an edit's `regions`.
export const sphereRegions = (o) => (o.regions || []).filter((r) => r.shape === 'sphere').map(
    (r) => ({sphere: {center: [...r.center], radius: r.radius}, avoid: Boolean(r.avoid)}));

// Every object's fields become the committed ones (after hello and after another window's state).
export function resetCommitted() {
  committed = new Map(S.objects.map((o) => [o.name, editFields(o)]));
  updateButtons();
}

export function setupHistory(editInput, applied, annotationsInput) {
  send = editInput;
  onApplied = applied;
  sendAnnotations = annotationsInput;
  document.getElementById('undo').addEventListener('click', undo);
  document.getElementById('redo').addEventListener('click', redo);
  updateButtons();
}

// connection.js: the page sent a final edit of `name` with `fields`.
export function editCommitted(name, fields) {
  const o = S.byName.get(name);
  const before = committed.get(name);
  if (!o || !before) return;
  const after = editFields(o);
  committed.set(name, after);
  if (replaying) return;
  const step = {name, before: {}, after: {}};
  for (const key of Object.keys(fields))
    if (key in before && JSON.stringify(before[key]) !== JSON.stringify(after[key])) {
      step.before[key] = before[key];
      step.after[key] = after[key];
    }
  if (!Object.keys(step.before).length) return;
  undoStack.push(step);
  if (undoStack.length > MAX_STEPS) undoStack.shift();
  redoStack.length = 0;
  updateButtons();
}

// measure.js: the page changed the scene's annotations from `before` to `after`.
export function annotationsCommitted(before, after) {
  if (replaying || JSON.stringify(before) === JSON.stringify(after)) return;
  undoStack.push({annotations: true, before, after});
  if (undoStack.length > MAX_STEPS) undoStack.shift();
  redoStack.length = 0;
  updateButtons();
}

function replay(step, fields) {
  if (step.annotations) {
    sendAnnotations(fields, false);
    updateButtons();
    return;
  }
  const o = S.byName.get(step.name);
  if (!o) return;
  applyFields(o, fields);
  replaying = true;
  try {
    send(step.name, fields, false);
  } finally {
    replaying = false;
  }
  onApplied();
  updateButtons();
}

export function undo() {
  const step = undoStack.pop();
  if (!step) return;
  redoStack.push(step);
  replay(step, step.before);
}

export function redo() {
  const step = redoStack.pop();
  if (!step) return;
  undoStack.push(step);
  replay(step, step.after);
}

function updateButtons() {
  const u = document.getElementById('undo'), r = document.getElementById('redo');
  if (u) u.disabled = !undoStack.length;
  if (r) r.disabled = !redoStack.length;
}

// For tests: how many steps each way.
export const historyDepth = () => ({undo: undoStack.length, redo: redoStack.length});
