// Camera moves for the view: orbit about the target, pan, zoom, and the scene's millimetres per
// screen pixel at the target. Each takes the protocol camera {eye, target, up, fov_deg} it changes
// in place and, where a drag's pixels matter, the view's height in CSS pixels.
import {add, clamp, cross, len, mul, norm, rotate, sub} from './vec.js';

// The camera's distance to its target and its orthonormal frame (forward, right, up).
export function cameraFrame(c) {
  const offset = sub(c.eye, c.target);
  const dist = len(offset);
  const fwd = mul(offset, -1 / dist);
  const right = norm(cross(fwd, c.up));
  const up = cross(right, fwd);
  return {dist, fwd, right, up};
}

// Rotates the eye about the target: horizontal drag about the view's up, vertical about right.
// A drag over the view's height turns by half a turn.
export function orbit(c, dx, dy, viewHeight) {
  const f = cameraFrame(c);
  const k = Math.PI / Math.max(1, viewHeight);
  const a1 = -dx * k, a2 = -dy * k;
  let off = sub(c.eye, c.target);
  off = rotate(off, f.up, a1);
  const right = rotate(f.right, f.up, a1);
  off = rotate(off, right, a2);
  const up = norm(rotate(f.up, right, a2));
  c.eye = add(c.target, off);
  c.up = up;
}

// Millimetres of the scene per CSS pixel of the view, at the target's distance.
export function mmPerPixel(c, viewHeight) {
  const f = cameraFrame(c);
  return 2 * f.dist * Math.tan(c.fov_deg * Math.PI / 360) / Math.max(1, viewHeight);
}

// Moves eye and target together so the scene follows the pointer.
export function pan(c, dx, dy, viewHeight) {
  const f = cameraFrame(c);
  const s = mmPerPixel(c, viewHeight);
  const d = add(mul(f.right, -dx * s), mul(f.up, dy * s));
  c.eye = add(c.eye, d);
  c.target = add(c.target, d);
}

// Multiplies the eye's distance to the target by factor (kept within 1e-2 .. 1e7).
export function zoom(c, factor) {
  const f = cameraFrame(c);
  const dist = clamp(f.dist * factor, 1e-2, 1e7);
  c.eye = sub(c.target, mul(f.fwd, dist));
}
