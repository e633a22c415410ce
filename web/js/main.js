// The viewer page's entry module (docs/viewer.md), imported by index.html: wires the modules
// together once the page's elements exist and connects. It also publishes window.viewerStats
// (stats.js) and window.viewer, the hooks the browser test (tests/viewer/) drives the page with.
import {connect, editInput} from './connection.js';
import {setupInput} from './input.js';
import {buildPanel, redrawEditors, tfEditor} from './panel.js';
import {S, takeHello, takeState} from './state.js';
import {bindStatus, finishRecording, startRecording, stats, updateStatus} from './stats.js';
import {buildSelectors, onSaved, onScreenshot, setupToolbar} from './toolbar.js';
import {drawColorBars} from './colorbar.js';
import {historyDepth, resetCommitted, setupHistory} from './history.js';
import {applyViewLink, setupShortcuts, viewLink} from './shortcuts.js';
import {crosshairs, onProbe, onSlice, onSliceError, pagePixelOf, redrawSliceOverlays,
        refreshSlices, scaleBars, setLayout, setCine, setupSlices, sliceClipHandles, sliceViews,
        sliceWindow} from './slices.js';
import {captureView} from './screenshot.js';
import {annotationsRefused, measureRefused, measurements, onMeasure, onPick, setAnnotations,
        setTool, setupMeasure, takeAnnotations} from './measure.js';
import {copyCamera} from './vec.js';
import {drawFrame, initView, layoutCanvas, resetView, sendViewport} from './view.js';

window.viewerStats = stats;

window.viewer = {
  // the page position of a TF control point, to drag it with real mouse events
  tfPoint(volume, index) {
    const ed = tfEditor(volume);
    return ed && index < ed.obj.tf.length ? ed.clientPos(index) : null;
  },
  tfPoints(volume) {
    const o = S.byName.get(volume);
    return o && o.tf ? o.tf.map((p) => [...p]) : null;
  },
  // the value the TF editor shows for its hovered or dragged point (null when none)
  tfHoverValue(volume) {
    const ed = tfEditor(volume);
    return ed ? ed.shownLabel : null;
  },
  camera() { return S.camera ? copyCamera(S.camera) : null; },
  // centre of an element of the page, by CSS selector
  center(selector) {
    const el = document.querySelector(selector);
    if (!el) return null;
    el.scrollIntoView({block: 'center'});
    const r = el.getBoundingClientRect();
    return {x: r.left + r.width / 2, y: r.top + r.height / 2, w: r.width, h: r.height};
  },
  startRecording,
  // PSNR (8-bit RGB) of each recorded frame against the last one, and when it was drawn.
  finishRecording,
  now() { return performance.now(); },
  // the reading views: layout, crosshair point, each view's crosshair as drawn, the readout
  setLayout,
  slicePoint() { return S.point ? S.point.slice() : null; },
  cine(axis, fps) { setCine(axis, fps); },
  cineState() { return S.cine ? {axis: S.cine.axis, fps: S.cine.fps, steps: S.cine.steps, ms: performance.now() - S.cine.t0} : null; },
  crosshairs,
  readout() { return S.readout || null; },
  slicesDrawn() { return S.slicesDrawn || 0; },
  scaleBars,
  colorBars() { return (S.colorBars || []).slice(); },
  colorBarLayout() { return (S.colorBarLayout || []).slice(); },
  viewLink,
  historyDepth,
  sliceLatencies() { return (S.sliceLatencies || []).slice(); },
  // each 2-D view's image (point, mm per pixel, window, zoom), the base volume's window, and the
  // latencies of W/L, zoom and pan inputs (to the last view they changed drawn)
  sliceViews,
  sliceWindow,
  // a screenshot of a view or the layout as the page composes it: its size and how many of its
  // pixels are not the background
  capture(what, scale) {
    const c = captureView(what, scale);
    if (!c) return null;
    const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    let lit = 0;
    for (let i = 0; i < d.length; i += 4) if (d[i] + d[i + 1] + d[i + 2] > 60) lit++;
    return {width: c.width, height: c.height, lit: lit / (c.width * c.height)};
  },
  sliceTimings() { return (S.sliceTimings || []).slice(); },
  inputLatencies(kind) { return ((S.inputLatencies || {})[kind] || []).slice(); },
  // every view shows the crosshair's latest point
  slicesSettled() { return S.pointSetAt === null || S.pointSetAt === undefined; },
  // clip-plane handles: the 3-D view's (page pixels, with the world point each stands on) and
  // each 2-D view's
  clipHandles() {
    const cell = document.getElementById('cell-3d').getBoundingClientRect();
    return {view3d: (S.clipHandles3d || []).map((h) => ({volume: h.volume, index: h.index,
                                                         x: cell.left + h.x, y: cell.top + h.y,
                                                         point: h.point})),
            slices: sliceClipHandles()};
  },
  // measurements: the tool, the annotations with the server's measurement of each, a world
  // point's page (client) pixel in a 2-D view, and the last pick and measure answers
  setMeasureTool(name) { setTool(name); },
  measurements,
  pagePixelOf,
  lastPick() { return S.lastPick || null; },
  lastMeasureMs() { return S.lastMeasureMs ?? null; },
  // the size the page asked still frames to have (its view's device pixels)
  viewport() { return S.viewport ? S.viewport.slice() : null; },
};

function onHello(m) {
  takeHello(m);
  takeAnnotations(m.annotations || []);
  resetCommitted();
  resetView();
  buildSelectors();
  buildPanel();
  updateStatus();
  refreshSlices();
  applyViewLink();
}

function onState(m) {
  if (m) takeAnnotations(m.annotations);
  if (!takeState(m)) return;
  resetCommitted();  // another window's edits are where this one's undo starts from
  buildSelectors();
  buildPanel();
  refreshSlices();  // visibility and transfer functions show in the 2-D views too
}

function start() {
  const canvas = document.getElementById('view');
  initView(canvas);
  bindStatus(document.getElementById('status'));
  const connEl = document.getElementById('connection');
  setupToolbar();
  setupInput(canvas);
  setupSlices();
  setupShortcuts();
  setupHistory(editInput, () => {
    buildPanel();
    redrawEditors();
    drawColorBars();
    refreshSlices();
  }, setAnnotations);
  setupMeasure(() => {
    redrawSliceOverlays();
    drawColorBars();  // the 3-D view's overlay: its annotations
  });
  document.getElementById('help-button').addEventListener('click', (ev) => {
    ev.stopPropagation();
    document.getElementById('shortcuts').hidden = false;
  });
  // A panel control being dragged is not rebuilt under the pointer by another client's state.
  document.getElementById('panel').addEventListener('pointerdown', () => { S.panelBusy = true; });
  window.addEventListener('pointerup', () => {
    S.panelBusy = false;
    setTimeout(() => onState(null), 0);  // after the drag ends: a state kept meanwhile
  }, true);
  window.addEventListener('resize', () => {
    sendViewport(150);
    layoutCanvas();
    drawColorBars();
    redrawEditors();
  });
  layoutCanvas();
  connect(connEl, {hello: onHello, state: onState, saved: onSaved, frame: drawFrame,
                   screenshot: onScreenshot, resync: () => onState(null), slice: onSlice,
                   probe: onProbe, measure: onMeasure, pick: onPick,
                   error: () => {
                     onSliceError();
                     measureRefused();
                     annotationsRefused();
                   }});
}

if (document.readyState === 'loading') document.addEventListener('DOMContentLoaded', start);
else start();
