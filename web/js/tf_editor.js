// The transfer-function editor of one volume: its control points over the log histogram on a
// canvas (x = value, y = alpha / the editor's max alpha), dragged, added by double-click and
// deleted by right-click; every change is sent as an edit of the volume.
import {editInput} from './connection.js';
import {clamp} from './vec.js';

export class TfEditor {
  // obj: the volume's local object (state.js), whose `tf` points it edits; hist: its histogram
  // from hello ({range, counts}) or undefined. `root` is the element to put in the panel.
  constructor(obj, hist) {
    this.obj = obj;
    this.hist = hist || null;
    this.root = document.createElement('div');
    this.canvas = document.createElement('canvas');
    this.canvas.className = 'tf-editor';
    this.canvas.dataset.volume = obj.name;
    if (!(obj.maxAlpha > 0)) {  // kept on the object so a rebuilt panel keeps its scale
      const top = Math.max(0, ...obj.tf.map((p) => p[4]));
      obj.maxAlpha = niceCeil(top > 0 ? top * 1.1 : 1);
    }
    const row = document.createElement('div');
    row.className = 'row';
    const l = document.createElement('span');
    l.className = 'label';
    l.textContent = 'max α';
    const input = document.createElement('input');
    input.type = 'number';
    input.min = '0.001';
    input.step = 'any';
    input.value = String(obj.maxAlpha);
    input.style.width = '80px';
    input.addEventListener('change', () => {
      const v = Number(input.value);
      if (v > 0 && Number.isFinite(v)) obj.maxAlpha = v;
      this.draw();
    });
    row.append(l, input);
    this.root.append(this.canvas, row);
    this.dragIndex = -1;
    this.hover = -1;
    this.computeDomain();
    this.bind();
    this.resize = new ResizeObserver(() => this.draw());
    this.resize.observe(this.canvas);
  }

  // Stops redrawing on resize (the panel is being rebuilt).
  dispose() { this.resize.disconnect(); }

  computeDomain() {
    let lo = Infinity, hi = -Infinity;
    if (this.hist && this.hist.range) [lo, hi] = this.hist.range;
    for (const p of this.obj.tf) {
      lo = Math.min(lo, p[0]);
      hi = Math.max(hi, p[0]);
    }
    if (!(hi > lo)) { lo = Number.isFinite(lo) ? lo - 1 : 0; hi = lo + 2; }
    this.lo = lo;
    this.hi = hi;
  }

  get cssW() { return this.canvas.clientWidth || 300; }
  get cssH() { return this.canvas.clientHeight || 120; }
  static get pad() { return 6; }

  toX(value) {
    const p = TfEditor.pad;
    return p + (value - this.lo) / (this.hi - this.lo) * (this.cssW - 2 * p);
  }
  toY(alpha) {
    const p = TfEditor.pad;
    return this.cssH - p - clamp(alpha / this.obj.maxAlpha, 0, 1) * (this.cssH - 2 * p);
  }
  fromX(x) {
    const p = TfEditor.pad;
    return this.lo + (x - p) / (this.cssW - 2 * p) * (this.hi - this.lo);
  }
  fromY(y) {
    const p = TfEditor.pad;
    return clamp((this.cssH - p - y) / (this.cssH - 2 * p), 0, 1) * this.obj.maxAlpha;
  }

  local(ev) {
    const r = this.canvas.getBoundingClientRect();
    return [ev.clientX - r.left, ev.clientY - r.top];
  }

  hit(x, y) {
    let best = -1, bestD = 8;
    this.obj.tf.forEach((p, i) => {
      const d = Math.hypot(this.toX(p[0]) - x, this.toY(p[4]) - y);
      if (d <= bestD) { best = i; bestD = d; }
    });
    return best;
  }

  // The point's position in the page (client coordinates), for tests that drag it.
  clientPos(i) {
    const r = this.canvas.getBoundingClientRect();
    const p = this.obj.tf[i];
    return {x: r.left + this.toX(p[0]), y: r.top + this.toY(p[4])};
  }

  // Sends the volume's points as an edit (moving while a drag goes on). An edit of the points
  // makes them the user's own: no preset is active any more, unless `preset` says it is one.
  sendTf(moving, preset = false) {
    if (!preset) this.obj.presetName = '';
    editInput(this.obj.name, {transfer_function: this.obj.tf.map((p) => [...p])}, moving);
  }

  bind() {
    const c = this.canvas;
    c.addEventListener('pointerdown', (ev) => {
      if (ev.button !== 0) return;
      const [x, y] = this.local(ev);
      this.dragIndex = this.hit(x, y);
      if (this.dragIndex < 0) return;
      c.setPointerCapture(ev.pointerId);
      ev.preventDefault();
      this.draw();
    });
    c.addEventListener('pointermove', (ev) => {
      if (this.dragIndex < 0) {
        // Hovering: the point under the pointer shows its value and opacity.
        const [x, y] = this.local(ev);
        const hover = this.hit(x, y);
        if (hover !== this.hover) {
          this.hover = hover;
          this.draw();
        }
        return;
      }
      const [x, y] = this.local(ev);
      this.movePoint(this.dragIndex, this.fromX(x), this.fromY(y));
      this.sendTf(true);
      this.draw();
    });
    const end = (ev) => {
      if (this.dragIndex < 0) return;
      if (c.hasPointerCapture(ev.pointerId)) c.releasePointerCapture(ev.pointerId);
      this.dragIndex = -1;
      this.sendTf(false);
      this.draw();
    };
    c.addEventListener('pointerup', end);
    c.addEventListener('pointerleave', () => {
      if (this.hover >= 0) {
        this.hover = -1;
        this.draw();
      }
    });
    c.addEventListener('pointercancel', end);
    c.addEventListener('dblclick', (ev) => {
      const [x, y] = this.local(ev);
      if (this.hit(x, y) >= 0) return;
      const value = this.fromX(x);
      const pts = this.obj.tf;
      let i = 0;
      while (i < pts.length && pts[i][0] < value) i++;
      if ((i > 0 && pts[i - 1][0] === value) || (i < pts.length && pts[i][0] === value)) return;
      const rgb = interpolateRgb(pts, value);
      pts.splice(i, 0, [value, rgb[0], rgb[1], rgb[2], this.fromY(y)]);
      this.sendTf(false);
      this.draw();
    });
    c.addEventListener('contextmenu', (ev) => {
      ev.preventDefault();
      const [x, y] = this.local(ev);
      const i = this.hit(x, y);
      if (i < 0 || this.obj.tf.length <= 2) return;
      this.obj.tf.splice(i, 1);
      this.sendTf(false);
      this.draw();
    });
  }

  // Moves point i, keeping it strictly between its neighbours so the value order holds.
  movePoint(i, value, alpha) {
    const pts = this.obj.tf;
    const gap = (this.hi - this.lo) * 1e-4;
    const lo = i > 0 ? pts[i - 1][0] + gap : -Infinity;
    const hi = i + 1 < pts.length ? pts[i + 1][0] - gap : Infinity;
    pts[i][0] = lo <= hi ? clamp(value, lo, hi) : pts[i][0];
    pts[i][4] = clamp(alpha, 0, this.obj.maxAlpha);
  }

  // Redraws histogram, curve and points at the canvas's CSS size and the device's pixel ratio.
  draw() {
    const c = this.canvas;
    const dpr = window.devicePixelRatio || 1;
    const w = this.cssW, h = this.cssH;
    if (c.width !== Math.round(w * dpr) || c.height !== Math.round(h * dpr)) {
      c.width = Math.round(w * dpr);
      c.height = Math.round(h * dpr);
    }
    const g = c.getContext('2d');
    g.setTransform(dpr, 0, 0, dpr, 0, 0);
    g.clearRect(0, 0, w, h);
    const p = TfEditor.pad;
    if (this.hist && this.hist.counts && this.hist.counts.length) {
      const counts = this.hist.counts;
      const top = Math.log1p(Math.max(...counts)) || 1;
      const [hlo, hhi] = this.hist.range;
      const bw = (hhi - hlo) / counts.length;
      g.fillStyle = '#3a3f4c';
      counts.forEach((n, k) => {
        const x0 = this.toX(hlo + k * bw), x1 = this.toX(hlo + (k + 1) * bw);
        const bh = Math.log1p(n) / top * (h - 2 * p);
        g.fillRect(x0, h - p - bh, Math.max(1, x1 - x0), bh);
      });
    }
    const pts = this.obj.tf;
    g.strokeStyle = '#d8dae0';
    g.lineWidth = 1;
    g.beginPath();
    pts.forEach((q, i) => {
      const x = this.toX(q[0]), y = this.toY(q[4]);
      if (i === 0) g.moveTo(x, y); else g.lineTo(x, y);
    });
    g.stroke();
    pts.forEach((q, i) => {
      g.beginPath();
      g.arc(this.toX(q[0]), this.toY(q[4]), i === this.dragIndex ? 6 : 4.5, 0, 2 * Math.PI);
      g.fillStyle = `rgb(${q.slice(1, 4).map((v) => Math.round(clamp(v, 0, 1) * 255)).join(',')})`;
      g.fill();
      g.strokeStyle = '#fff';
      g.stroke();
    });
    // The value axis: its ends and middle, in the volume's units.
    g.fillStyle = '#9aa0ad';
    g.font = '10px sans-serif';
    g.textBaseline = 'bottom';
    const mid = 0.5 * (this.lo + this.hi);
    [[this.lo, 'left', p], [mid, 'center', this.toX(mid)], [this.hi, 'right', w - p]].forEach(
        ([v, align, x]) => {
          g.textAlign = align;
          g.fillText(axisLabel(v) + (align === 'right' && this.obj.units ? ' ' + this.obj.units : ''),
                     x, h - 1);
        });
    // The point being dragged or hovered: its value and opacity.
    const shown = this.dragIndex >= 0 ? this.dragIndex : this.hover;
    if (shown >= 0 && shown < pts.length) {
      g.textAlign = 'left';
      g.textBaseline = 'top';
      g.fillStyle = '#e8eaf0';
      g.fillText(`value ${axisLabel(pts[shown][0])}, α ${Number(pts[shown][4].toPrecision(3))}`,
                 p, p);
    }
    this.shownLabel = shown >= 0 && shown < pts.length ? pts[shown][0] : null;
  }
}

// A value as the axis shows it: whole above 100, else three significant digits.
function axisLabel(v) {
  return Math.abs(v) >= 100 ? v.toFixed(0) : String(Number(v.toPrecision(3)));
}

// The smallest of 1, 2, 2.5, 5 times a power of ten at or above x (at most max(1, x)).
function niceCeil(x) {
  const e = Math.pow(10, Math.floor(Math.log10(x)));
  for (const m of [1, 2, 2.5, 5, 10]) if (m * e >= x) return Math.min(m * e, Math.max(1, x));
  return x;
}

// The colour of the points' piecewise-linear curve at value.
function interpolateRgb(pts, value) {
  if (!pts.length) return [1, 1, 1];
  if (value <= pts[0][0]) return pts[0].slice(1, 4);
  for (let i = 1; i < pts.length; i++) {
    if (value <= pts[i][0]) {
      const a = pts[i - 1], b = pts[i];
      const t = (value - a[0]) / (b[0] - a[0] || 1);
      return [1, 2, 3].map((k) => a[k] + t * (b[k] - a[k]));
    }
  }
  return pts[pts.length - 1].slice(1, 4);
}
