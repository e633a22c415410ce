// Oblique reading views and thick slabs (docs/viewer.md, "Thick slabs and oblique views"): the
// crosshair's rotation of the patient axes (Alt+drag in a 2-D view turns it about that view's
// normal), each view's frame and orientation letters under it, and each view's slab (thickness
// and MIP / MinIP / mean), kept in the scene as the base volume's `slabs`.
import {cross, dot, len, mul, norm, rotate, sub} from './vec.js';

export const AXES = ['axial', 'coronal', 'sagittal'];
// Screen directions in LPS (right, down) and the normal of each axis's view, as the server draws
// them unrotated; `n` is the normal's patient axis.
export const BASE_FRAME = {
  axial: {right: [1, 0, 0], down: [0, 1, 0], normal: [0, 0, 1], n: 2},
  coronal: {right: [1, 0, 0], down: [0, 0, -1], normal: [0, 1, 0], n: 1},
  sagittal: {right: [0, 1, 0], down: [0, 0, -1], normal: [1, 0, 0], n: 0},
};
export const SLAB_MODES = ['mip', 'minip', 'mean'];
export const MAX_SLAB_MM = 1000;  // the server's limit (scene_json::kMaxSlabThicknessMm)

// Where the crosshair's rotation takes L, P and S (unit columns of the rotation).
let axes = [[1, 0, 0], [0, 1, 0], [0, 0, 1]];

// The rotation as a `slice` message's `rotation`: rows.
export const crosshairRotation = () => [0, 1, 2].map((i) => axes.map((c) => c[i]));
export const isOblique = () =>
  axes.some((c, j) => c.some((x, i) => Math.abs(x - (i === j ? 1 : 0)) > 1e-9));
export function resetRotation() { axes = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]; }
// Sets the rotation from rows (a test, a link); nothing when it is not one.
export function setCrosshairRotation(rows) {
  const cols = [0, 1, 2].map((j) => rows.map((r) => Number(r[j])));
  const ok = cols.every((c) => Math.abs(len(c) - 1) < 1e-6) &&
             Math.abs(dot(cols[0], cols[1])) < 1e-6 && dot(cross(cols[0], cols[1]), cols[2]) > 0;
  if (ok) axes = orthonormal(cols);
  return ok;
}

// The unit normal of `axis`'s view under the rotation.
export const normalOf = (axis) => axes[BASE_FRAME[axis].n].slice();

// Turns the crosshair by `angle` (radians) about the unit vector k (a view's normal): that
// view's plane stays, the other two turn about it.
export function rotateCrosshair(k, angle, from = axes) {
  axes = orthonormal(from.map((c) => rotate(c, norm(k), angle)));
}
export const rotationAxes = () => axes.map((c) => c.slice());

function orthonormal(cols) {
  const x = norm(cols[0]);
  const y = norm(sub(cols[1], mul(x, dot(cols[1], x))));
  return [x, y, cross(x, y)];
}

// A view's frame (unit right, down, normal): its last image's, else the axis's unrotated.
export function frameOf(axis, answer) {
  if (answer && answer.right)
    return {right: answer.right, down: answer.down, normal: answer.normal};
  return BASE_FRAME[axis];
}

// The nearest patient direction of a unit vector, as a letter.
const letter = (v) => {
  const i = [0, 1, 2].reduce((a, b) => (Math.abs(v[b]) > Math.abs(v[a]) ? b : a), 0);
  return v[i] > 0 ? 'LPS'[i] : 'RAI'[i];
};
// The letters at the top, bottom, left and right of a view of frame f.
export const lettersOf = (f) => [letter(mul(f.down, -1)), letter(f.down),
                                 letter(mul(f.right, -1)), letter(f.right)];

// Where the other two views' planes cross `axis`'s: unit directions in its pixels [dx, dy].
export function axisLines(axis, f) {
  return AXES.filter((a) => a !== axis).map((a) => {
    const d = cross(f.normal, normalOf(a));
    const v = [dot(d, f.right), dot(d, f.down)];
    const l = Math.hypot(v[0], v[1]) || 1;
    return [v[0] / l, v[1] / l];
  });
}

// How far one slice step goes along a unit normal: the voxel pitch along it.
export const pitchAlong = (pitch, n) => Math.abs(n[0]) * pitch[0] + Math.abs(n[1]) * pitch[1] +
                                        Math.abs(n[2]) * pitch[2];

// The range of t for which p + t n stays in the box [lo, hi].
export function rangeAlong(bounds, p, n) {
  let lo = Infinity, hi = -Infinity;
  for (let c = 0; c < 8; ++c) {
    const corner = [0, 1, 2].map((i) => bounds[(c >> i) & 1][i]);
    const t = dot(sub(corner, p), n);
    lo = Math.min(lo, t);
    hi = Math.max(hi, t);
  }
  return [lo, hi];
}

// A view's slab {thickness, mode} of the base volume `base` (thickness 0: none).
export function slabOf(base, axis) {
  const s = base && base.slabs && base.slabs[axis];
  return s ? {thickness: s.thickness, mode: s.mode || 'mip'} : {thickness: 0, mode: 'mip'};
}

// The per-view slab controls (in each 2-D view's corner): `onChange(axis, slab, moving)`.
export function setupSlabControls(onChange) {
  for (const cell of document.querySelectorAll('.slice-cell')) {
    const axis = cell.dataset.axis;
    const box = cell.querySelector('.slab-control');
    if (!box) continue;
    const thickness = box.querySelector('.slab-thickness');
    const mode = box.querySelector('.slab-mode');
    const read = () => ({
      thickness: Math.min(MAX_SLAB_MM, Math.max(0, Number(thickness.value) || 0)),
      mode: mode.value});
    // Typing or the spinner: the views follow at once; the scene takes it on change.
    thickness.addEventListener('input', () => onChange(axis, read(), true));
    thickness.addEventListener('change', () => onChange(axis, read(), false));
    mode.addEventListener('change', () => onChange(axis, read(), false));
    for (const type of ['pointerdown', 'wheel', 'keydown'])
      box.addEventListener(type, (ev) => ev.stopPropagation());
  }
}

// Shows the base volume's slabs in the controls (after hello, state, undo).
export function showSlabControls(base) {
  for (const cell of document.querySelectorAll('.slice-cell')) {
    const box = cell.querySelector('.slab-control');
    if (!box) continue;
    const s = slabOf(base, cell.dataset.axis);
    const t = box.querySelector('.slab-thickness');
    if (document.activeElement !== t) t.value = String(s.thickness);
    box.querySelector('.slab-mode').value = s.mode;
  }
}
