// Small 3-vector math, camera copies and number formatting for the viewer's modules. No DOM, no
// state: every function returns a new value.

export const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
export const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
export const mul = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
export const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
export const cross = (a, b) =>
  [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
export const len = (a) => Math.sqrt(dot(a, a));
// The unit vector along a; [0, 0, 1] for the zero vector.
export const norm = (a) => { const l = len(a); return l > 0 ? mul(a, 1 / l) : [0, 0, 1]; };
// Rodrigues' rotation of v about the unit axis k by angle a (radians).
export const rotate = (v, k, a) => {
  const c = Math.cos(a), s = Math.sin(a);
  return add(add(mul(v, c), mul(cross(k, v), s)), mul(k, dot(k, v) * (1 - c)));
};
export const clamp = (x, lo, hi) => Math.min(hi, Math.max(lo, x));
// A deep copy of a protocol camera {eye, target, up, fov_deg}.
export const copyCamera = (c) =>
  ({eye: [...c.eye], target: [...c.target], up: [...c.up], fov_deg: c.fov_deg});
// x with `digits` decimals, '–' when it is not a finite number.
export const fmt = (x, digits = 1) => (Number.isFinite(x) ? x.toFixed(digits) : '–');
