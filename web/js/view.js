// The view canvas: sized to the session's image at hello, fitted into its area keeping the
// aspect ratio, and drawn with each decoded frame (the newest wins). While a recording runs it
// also keeps a snapshot of each drawn frame.
import {drawColorBars} from './colorbar.js';
import {reportLatencies, updateConverged} from './connection.js';
import {S} from './state.js';
import {frameDrawn, showMessage, updateStatus} from './stats.js';

let canvas = null, ctx = null;

// Takes the page's canvas; call once before the others.
export function initView(el) {
  canvas = el;
  ctx = canvas.getContext('2d', {alpha: true});
}

// Sizes the canvas's backing store to S.image (from hello), black until the first frame.
export function resetView() {
  canvas.width = S.image.width;
  canvas.height = S.image.height;
  ctx.fillStyle = '#000';
  ctx.fillRect(0, 0, canvas.width, canvas.height);
  layoutCanvas();
}

// Fits the canvas into its area, keeping the image's aspect ratio (the backing store stays the
// image size, so a converged frame is drawn 1:1).
export function layoutCanvas() {
  const area = document.getElementById('cell-3d');
  const aw = area.clientWidth, ah = area.clientHeight;
  const s = Math.min(aw / S.image.width, ah / S.image.height);
  if (!(s > 0)) return;
  canvas.style.width = `${Math.floor(S.image.width * s)}px`;
  canvas.style.height = `${Math.floor(S.image.height * s)}px`;
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
