// The view canvas: its backing store is the size still frames come at, which the page asks to be
// its area's CSS size times devicePixelRatio (a `settings` `viewport`; the server bounds it by
// --max-image-side); fitted into its area keeping that aspect, and drawn with each decoded frame
// (the newest wins). While a recording runs it also keeps a snapshot of each drawn frame.
import {drawColorBars} from './colorbar.js';
import {queueInput, reportLatencies, updateConverged} from './connection.js';
import {S} from './state.js';
import {frameDrawn, showMessage, updateStatus} from './stats.js';

let canvas = null, ctx = null;

// Takes the page's canvas; call once before the others.
export function initView(el) {
  canvas = el;
  ctx = canvas.getContext('2d', {alpha: true});
}

const MAX_SIDE = 2048;  // the server's default --max-image-side; it has the last word
let viewportTimer = 0;

// The device pixels of the 3-D view's area, at most MAX_SIDE a side (keeping the aspect).
function viewportSize() {
  const area = document.getElementById('cell-3d');
  const r = window.devicePixelRatio || 1;
  const w = area.clientWidth * r, h = area.clientHeight * r;
  if (!(w >= 16 && h >= 16)) return null;  // hidden (layout 1x3): keep the frames as they are
  const s = Math.min(1, MAX_SIDE / Math.max(w, h));
  return [Math.round(w * s), Math.round(h * s)];
}

// Asks for still frames of the view's size (after hello, and once a resize has settled).
export function sendViewport(delay = 0) {
  clearTimeout(viewportTimer);
  const ask = () => {
    const size = viewportSize();
    if (!size || (S.viewport && size[0] === S.viewport[0] && size[1] === S.viewport[1])) return;
    S.viewport = size;
    queueInput('viewport', {type: 'settings', viewport: size}, false);
  };
  if (delay > 0) viewportTimer = setTimeout(ask, delay);
  else ask();
}

// Black until the first frame, sized to the scene's image until a frame of the view's size comes.
export function resetView() {
  S.viewport = null;
  canvas.width = S.image.width;
  canvas.height = S.image.height;
  ctx.fillStyle = '#000';
  ctx.fillRect(0, 0, canvas.width, canvas.height);
  layoutCanvas();
  sendViewport();
}

// Fits the canvas into its area, keeping its backing store's aspect (the size of the still
// frames, so a converged frame is drawn 1:1).
export function layoutCanvas() {
  const area = document.getElementById('cell-3d');
  const aw = area.clientWidth, ah = area.clientHeight;
  const s = Math.min(aw / canvas.width, ah / canvas.height);
  if (!(s > 0)) return;
  canvas.style.width = `${Math.floor(canvas.width * s)}px`;
  canvas.style.height = `${Math.floor(canvas.height * s)}px`;
}

// Decodes and draws frame `id` (its `frame` message and image), unless a later one was drawn
// meanwhile; then counts it, updates convergence and the status line.
export async function drawFrame(meta, blob, id) {
  let bmp;
  try {
    const type = meta.format === 'png' ? 'image/png' : 'image/jpeg';
    bmp = await createImageBitmap(new Blob([blob], {type}),
                                  {colorSpaceConversion: 'none', premultiplyAlpha: 'none'});
  } catch (e) {
    showMessage('could not decode a frame: ' + e);
    return;
  }
  if (id < S.lastDrawnId) {  // a later frame was drawn while this one decoded
    bmp.close();
    return;
  }
  S.lastDrawnId = id;
  if (meta.format === 'png' && (bmp.width !== canvas.width || bmp.height !== canvas.height)) {
    // Still frames set the size (this page's viewport, or another window's, the latest asked).
    canvas.width = bmp.width;
    canvas.height = bmp.height;
    layoutCanvas();
  }
  const full = bmp.width === canvas.width && bmp.height === canvas.height;
  ctx.imageSmoothingEnabled = !full;
  ctx.imageSmoothingQuality = 'high';
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  ctx.drawImage(bmp, 0, 0, canvas.width, canvas.height);
  bmp.close();
  const now = performance.now();
  frameDrawn(meta, now);
  drawColorBars();  // an edit ends in a frame: the bars follow the transfer functions
  if (S.recording) record(now, meta);
  updateConverged();
  reportLatencies(false);
  updateStatus();
}

// Snapshots of every drawn frame (at most 256), so a test can time the approach to the
// converged image (stats.js finishRecording).
function record(now, meta) {
  if (S.recording.frames.length >= 256) return;
  const data = ctx.getImageData(0, 0, canvas.width, canvas.height).data;
  S.recording.frames.push({t: now, data: new Uint8ClampedArray(data), seq: meta.seq,
                           samples: meta.samples, scale: meta.scale, final: meta.final});
}
