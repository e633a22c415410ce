// What the page measures, and the status line that shows it. `stats` is published as
// window.viewerStats (main.js), which the browser test reads; a recording (window.viewer's
// startRecording / finishRecording) keeps every drawn frame to time the approach to convergence.
import {S, isMoving} from './state.js';
import {fmt} from './vec.js';

export const stats = {
  latencies: [],
  framesDrawn: 0,
  lastFrame: null,
  converged: false,
  frames: [],           // the last 400 drawn frames' metadata plus drawn_at
  lastSentSeq: 0,
  errors: [],
  saved: null,
  screenshots: 0,
  connected: false,
};

export function median(xs) {
  if (!xs.length) return NaN;
  const s = [...xs].sort((a, b) => a - b);
  const n = s.length;
  return n % 2 ? s[(n - 1) / 2] : 0.5 * (s[n / 2 - 1] + s[n / 2]);
}

// Counts a frame drawn at `now` (performance.now()): its input-to-frame latency, the frame
// list, and the frames per second while moving.
export function frameDrawn(meta, now) {
  const t0 = S.sentT0.get(meta.seq);
  if (t0 !== undefined) stats.latencies.push(now - t0);
  for (const k of [...S.sentT0.keys()]) if (k <= meta.seq) S.sentT0.delete(k);

  stats.framesDrawn++;
  stats.lastFrame = Object.assign({}, meta, {drawn_at: now});
  stats.frames.push(stats.lastFrame);
  if (stats.frames.length > 400) stats.frames.splice(0, stats.frames.length - 400);
  S.drawTimes.push(now);
  while (S.drawTimes.length && now - S.drawTimes[0] > 1000) S.drawTimes.shift();
  if (isMoving() && S.drawTimes.length >= 2)
    S.movingFps = (S.drawTimes.length - 1) * 1000 / (now - S.drawTimes[0]);
}

// ---------------------------------------------------------------- the status line
let statusEl = null;
let messageUntil = 0, messageText = '';

// The element the status line is written to (the page's footer).
export function bindStatus(el) { statusEl = el; }

// Shows text in the status line for four seconds.
export function showMessage(text) {
  messageText = text;
  messageUntil = performance.now() + 4000;
  updateStatus();
}

export function updateStatus() {
  const f = stats.lastFrame;
  const parts = [];
  if (f) {
    parts.push(`frame ${fmt(f.render_ms)} ms`, `encode ${fmt(f.encode_ms)} ms`,
               `${f.samples}/${f.spp} spp`, `stages ${f.stages_run}/${f.stages}`,
               `scale ${fmt(f.scale, 2)}`, f.format);
    // A volume too large to hold: shown at a pyramid level until the full-resolution frame.
    if (f.full_resolution !== undefined)
      parts.push(f.full_resolution ? 'full resolution'
                 : f.refinement !== undefined ? `finer levels (step ${f.refinement + 1}), refining`
                 : 'coarse level, refining');
  }
  parts.push(`${fmt(S.movingFps, 0)} fps moving`);
  const last = stats.latencies.slice(-50);
  parts.push(`latency ${fmt(median(last), 0)} ms (median of ${last.length})`);
  if (stats.converged) parts.push('converged');
  if (performance.now() < messageUntil) parts.push(messageText);
  statusEl.textContent = parts.join(' · ');
}

// ---------------------------------------------------------------- recording (--measure)
// view.js adds a snapshot of every drawn frame to S.recording while one runs.
export function startRecording(release) { S.recording = {release, frames: []}; }

function psnr(a, b) {
  let se = 0, n = 0;
  for (let i = 0; i < a.length; i += 4) {
    for (let k = 0; k < 3; k++) {
      const d = a[i + k] - b[i + k];
      se += d * d;
    }
    n += 3;
  }
  if (se === 0) return Infinity;
  return 10 * Math.log10(255 * 255 / (se / n));
}

// Ends the recording: PSNR (8-bit RGB) of each recorded frame against the last one, and when it
// was drawn (ms after `release`).
export function finishRecording() {
  const rec = S.recording;
  S.recording = null;
  if (!rec || !rec.frames.length) return [];
  const last = rec.frames[rec.frames.length - 1].data;
  return rec.frames.map((f) => ({t_ms: f.t - rec.release, psnr_db: psnr(f.data, last),
                                 samples: f.samples, scale: f.scale, final: f.final}));
}
