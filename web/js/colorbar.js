// The 3-D view's overlay: clip-plane outlines (clip_outlines.js), the measurements (measure.js),
// the orientation marker, and
// colour bars, labelled with their values: one per visible volume (its transfer function's
// visible range within the data's) and one per colour map the planes show.
import {drawClipOutlines3d} from './clip_outlines.js';
import {drawAnnotations3d} from './measure.js';
import {S} from './state.js';

const BAR_W = 12, BAR_H = 140, MAX_CAPTION = 160;

// The sRGB curve (src/core/colour.hpp): colours are display values, light adds linearly.
const srgbDecode = (v) => v <= 0.04045 ? v / 12.92 : Math.pow((v + 0.055) / 1.055, 2.4);
const srgbEncode = (v) => v <= 0.0031308 ? 12.92 * v : 1.055 * Math.pow(v, 1 / 2.4) - 0.055;

// The TF's colour and opacity at `v` (linear between its points).
function tfAt(tf, v) {
  if (v <= tf[0][0]) return tf[0].slice(1);
  for (let i = 1; i < tf.length; ++i) {
    if (v <= tf[i][0]) {
      const a = tf[i - 1], b = tf[i];
      const t = b[0] > a[0] ? (v - a[0]) / (b[0] - a[0]) : 1;
      return [1, 2, 3, 4].map((k) => a[k] + (b[k] - a[k]) * t);
    }
  }
  return tf[tf.length - 1].slice(1);
}

const label = (v) => Math.abs(v) >= 100 || v === 0 ? v.toFixed(0) : Number(v.toPrecision(3));

// `text` cut to at most `width` pixels in the context's font, ending with an ellipsis when cut.
function fitText(g, text, width) {
  if (g.measureText(text).width <= width) return text;
  let n = text.length;
  while (n > 1 && g.measureText(text.slice(0, n) + '…').width > width) --n;
  return text.slice(0, n) + '…';
}

// The values a volume's bar spans: its transfer function's visible part (from the point before
// the first with opacity to the point after the last, as render --colorbar's bars), within the
// data's own range where the two overlap: a preset's -3024 .. 3071 on a CT of -1024 .. 1800
// shows -1024 .. 1800. Null when nothing shows.
function visibleRange(o) {
  const tf = o.tf;
  if (!tf || tf.length < 2) return null;
  const first = tf.findIndex((p) => p[4] > 0);
  if (first < 0) return null;
  let last = tf.length - 1;
  while (tf[last][4] <= 0) --last;
  let lo = tf[Math.max(0, first - 1)][0], hi = tf[Math.min(tf.length - 1, last + 1)][0];
  if (!(hi > lo)) [lo, hi] = [tf[0][0], tf[tf.length - 1][0]];
  const data = (S.histograms[o.name] || {}).range;
  if (data && data[1] > lo && data[0] < hi) [lo, hi] = [Math.max(lo, data[0]), Math.min(hi, data[1])];
  return hi > lo ? [lo, hi] : null;
}

// The orientation marker at the bottom left: the patient's axes as the camera sees them, each
// labelled with the side it points to (L, P, S; the opposite ends R, A, I).
function drawOrientation(g, height) {
  const c = S.camera;
  if (!c) return;
  const f = c.eye.map((e, i) => c.target[i] - e);
  const n = Math.hypot(...f);
  const fwd = f.map((x) => x / n);
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                           a[0] * b[1] - a[1] * b[0]];
  let right = cross(fwd, c.up);
  const rn = Math.hypot(...right);
  right = right.map((x) => x / rn);
  const up = cross(right, fwd);
  const ox = 44, oy = height - 44, len = 30;
  const axes = [[[1, 0, 0], 'L', 'R', '#e66'], [[0, 1, 0], 'P', 'A', '#6c6'],
                [[0, 0, 1], 'S', 'I', '#69f']];
  // Far ends first, so the nearer axes are drawn over them.
  axes.sort((a, b) => (a[0][0] * fwd[0] + a[0][1] * fwd[1] + a[0][2] * fwd[2]) -
                      (b[0][0] * fwd[0] + b[0][1] * fwd[1] + b[0][2] * fwd[2]));
  g.font = 'bold 11px sans-serif';
  g.textAlign = 'center';
  g.textBaseline = 'middle';
  for (const [d, plus, minus, colour] of axes) {
    const sx = d[0] * right[0] + d[1] * right[1] + d[2] * right[2];
    const sy = -(d[0] * up[0] + d[1] * up[1] + d[2] * up[2]);
    g.strokeStyle = colour;
    g.lineWidth = 2;
    g.beginPath();
    g.moveTo(ox - sx * len * 0.6, oy - sy * len * 0.6);
    g.lineTo(ox + sx * len, oy + sy * len);
    g.stroke();
    g.fillStyle = colour;
    g.fillText(plus, ox + sx * (len + 9), oy + sy * (len + 9));
    g.fillText(minus, ox - sx * (len * 0.6 + 8), oy - sy * (len * 0.6 + 8));
  }
  g.textBaseline = 'alphabetic';
}

// Redraws the bars (after hello, a state, or a frame: edits end in one).
export function drawColorBars() {
  const c = document.getElementById('colorbars');
  if (!c) return;
  const r = window.devicePixelRatio || 1;
  c.width = Math.max(1, Math.round(c.clientWidth * r));
  c.height = Math.max(1, Math.round(c.clientHeight * r));
  const g = c.getContext('2d');
  g.clearRect(0, 0, c.width, c.height);
  // One bar per visible volume from its transfer function (each colour weighted by its opacity
  // relative to the function's largest), then one per colour map the planes show, from the
  // server (as render --colorbar draws them: nothing where the plane shows nothing).
  const bars = S.objects.filter((o) => o.kind === 'volume' && o.visible && o.tf && !o.labels &&
                                       visibleRange(o))
      .map((o) => {
        const top = Math.max(...o.tf.map((p) => p[4])) || 1;
        const [lo, hi] = visibleRange(o);
        return {name: o.name, units: o.units, lo, hi, colour: (t) => {
          const [cr, cg, cb, ca] = tfAt(o.tf, lo + (hi - lo) * t);
          return [cr, cg, cb, Math.min(1, ca / top)];
        }};
      })
      .concat((S.planeBars || []).map((b) => ({
        name: `${b.name} on ${b.shown_by}`, units: b.units, lo: b.range[0], hi: b.range[1],
        colour: (t) => {
          const [cr, cg, cb, ca] = b.colors[Math.min(63, Math.max(0, Math.round(t * 63)))];
          return [cr, cg, cb, ca > 0 ? 1 : 0];
        }})));
  g.scale(r, r);
  // The image's place in the cell (it keeps its aspect), for the clip planes' outlines.
  const view = document.getElementById('view').getBoundingClientRect();
  const cell = c.getBoundingClientRect();
  drawClipOutlines3d(g, view.left - cell.left, view.top - cell.top, view.width, view.height);
  drawAnnotations3d(g, view.left - cell.left, view.top - cell.top, view.width, view.height);
  drawOrientation(g, c.clientHeight);
  g.font = '11px sans-serif';
  // Right to left, each bar in a column wide enough for its tick labels and its caption (cut
  // to MAX_CAPTION with an ellipsis), so that nothing is cut at the view's edge or overlaps;
  // bars that no longer fit are left out.
  S.colorBarLayout = [];
  let right = c.clientWidth - 6;
  for (const b of bars) {
    const caption = fitText(g, b.name + (b.units ? ` (${b.units})` : ''), MAX_CAPTION);
    const cw = g.measureText(caption).width;
    const lw = Math.max(g.measureText(label(b.hi)).width, g.measureText(label(b.lo)).width);
    const cx = right - Math.max(BAR_W / 2, cw / 2);
    const x = cx - BAR_W / 2;
    const left = Math.min(cx - cw / 2, x - 3 - lw);
    if (left < 2) break;
    const y = 24;
    for (let t = 0; t < BAR_H; ++t) {
      const [cr, cg, cb, w] = b.colour(1 - t / (BAR_H - 1));
      // Display colours (as scene files give them) over black with weight w, in linear light.
      const s = (v) => Math.round(255 * srgbEncode(Math.max(0, Math.min(1, srgbDecode(v) * w))));
      g.fillStyle = `rgb(${s(cr)},${s(cg)},${s(cb)})`;
      g.fillRect(x, y + t, BAR_W, 1);
    }
    g.strokeStyle = '#666';
    g.strokeRect(x - 0.5, y - 0.5, BAR_W + 1, BAR_H + 1);
    g.fillStyle = '#ddd';
    g.textAlign = 'right';
    g.fillText(label(b.hi), x - 3, y + 9);
    g.fillText(label(b.lo), x - 3, y + BAR_H);
    g.textAlign = 'center';
    g.fillText(caption, cx, y + BAR_H + 14);
    S.colorBarLayout.push({name: b.name, lo: b.lo, hi: b.hi, left, right, caption,
                           width: c.clientWidth});
    right = left - 12;
  }
  S.colorBars = S.colorBarLayout.map((b) => b.name);
}
