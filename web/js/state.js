// The page's session state, S: what `hello` and `state` messages said (camera, method, spp,
// objects), the flow-control counters of the input in flight, and the interaction in progress.
// Modules share it only by importing S; this module changes it for the server's messages.
import {copyCamera, dot, len, norm, sub, add, mul} from './vec.js';

// The session token of the page's address (every request and the WebSocket carry it). The page
// then takes it out of the address bar (history, screen shares, copied links); a reload carries
// it in the cookie the server set with the page.
export const token = new URLSearchParams(location.search).get('token') || '';
if (token && window.history && history.replaceState) {
  const url = new URL(location.href);
  url.searchParams.delete('token');
  history.replaceState(history.state, '', url.pathname + url.search + url.hash);
}

export const S = {
  image: {width: 512, height: 512},
  camera: null,
  initialCamera: null,
  method: '',
  spp: 1,
  methods: [],
  objects: [],          // local copies of hello's objects, edited by the panel
  byName: new Map(),
  histograms: {},
  tfPresets: {},         // preset name -> TF points, from hello
  // flow control: one input message in flight, the rest merged per key until it is answered
  nextSeq: 1,
  lastSentSeq: 0,
  inFlight: null,       // {seq, moving, timer}
  pending: new Map(),   // key -> {msg, t0}
  sentT0: new Map(),    // seq -> time of the oldest input event merged into that message
  cameraSent: null,     // the camera as this page last sent it: the `from` of its next move
  latestState: null,    // a state that came while the page was busy, taken once it is idle
  // frames
  expect: null,         // what the next binary message is: {kind: 'frame'|'screenshot', ...}
  frameId: 0,
  lastDrawnId: 0,
  drawTimes: [],        // performance.now() of recent draws, for fps
  movingFps: NaN,
  reportedLatencies: 0,
  // interaction
  drag: null,
  pointers: new Map(),
  wheelTimer: 0,
  wlMode: false,
  selectedPlane: null,  // name
  selectedClip: null,   // {volume, index}
  panelBusy: false,
  recording: null,      // {release, frames} while window.viewer records (stats.js)
};

// A transfer function's control points ([[value, r, g, b, a], ...]) from either form the server
// sends (the array, or {points: array}), copied.
export const tfPoints = (tf) => {
  const pts = Array.isArray(tf) ? tf : (tf && Array.isArray(tf.points) ? tf.points : []);
  return pts.map((p) => [...p]);
};

function localObject(o) {
  const l = {name: o.name, kind: o.kind, visible: o.visible !== false,
             opacity: o.opacity === undefined ? 1 : o.opacity};
  if (o.kind === 'volume') {
    l.tf = tfPoints(o.transfer_function);
    l.frame = o.frame || 0;
    l.frames = o.frames || 1;
    l.clips = (o.clip_planes || []).map((c) => ({base: [...c.point], normal: norm(c.normal),
                                                 offset: 0}));
    if (o.bounds) l.bounds = o.bounds.map((b) => [...b]);  // the reading views' box and step
    if (o.pitch) l.pitch = [...o.pitch];
    l.units = o.units || '';
    l.window = o.window ? [...o.window] : null;  // its 2-D views' [centre, width]
    l.windowNote = o.window_note || '';          // why the header's window is not used
    l.slabs = JSON.parse(JSON.stringify(o.slabs || {}));  // its 2-D views' thick slabs
    if (o.labels) l.labels = o.labels.map((x) => ({...x, color: [...x.color]}));
  } else if (o.kind === 'streamlines') {
    takeStreamlines(l, o);
  } else if (o.kind === 'plane') {
    l.center = [...o.center];
    l.initialCenter = [...o.center];
    l.normal = norm(o.normal);
    l.size = Array.isArray(o.size) ? o.size : [o.size, o.size];
    l.window = [...o.window];
    l.slab = o.slab ? {...o.slab} : {thickness: 0, mode: 'mip'};  // its thick slab in 3-D
    l.volume = o.volume;
  }
  return l;
}

// A streamline object's look and selection (state.objects' fields; docs/viewer.md).
const STREAMLINE_FIELDS = ['color_by', 'color', 'value', 'colormap', 'range', 'radius', 'stride',
                           'min_length', 'regions', 'count', 'point_values', 'streamline_values',
                           'has_groups', 'colormaps'];
function takeStreamlines(l, o) {
  for (const key of STREAMLINE_FIELDS)
    if (o[key] !== undefined) l[key] = JSON.parse(JSON.stringify(o[key]));
}

// The camera's projection, which the page never changes but needs for its overlays.
function takeProjection(c) {
  S.projection = c.projection || 'perspective';
  S.orthoHeight = c.ortho_height || 200;
}

// Takes a `hello`: the session's settings, camera and objects, replacing everything before.
export function takeHello(m) {
  S.methods = m.methods || [];
  S.method = m.method;
  S.spp = m.spp;
  S.image = m.image;
  S.camera = copyCamera(m.camera);
  S.cameraSent = copyCamera(m.camera);
  takeProjection(m.camera);
  S.initialCamera = copyCamera(m.initial_camera || m.camera);
  S.histograms = m.histograms || {};
  S.planeBars = m.colour_bars || [];
  S.tfPresets = m.tf_presets || {};
  S.objects = (m.objects || []).map(localObject);
  S.byName = new Map(S.objects.map((o) => [o.name, o]));
  // Window/level applies to MPR planes, which show a volume.
  S.selectedPlane = (S.objects.find((o) => o.kind === 'plane' && o.volume) || {}).name || null;
  S.selectedClip = null;
}

// Takes another client's edits (or ours, echoed) from a `state`, only while this page has no
// input of its own; a state that comes meanwhile is kept, and taken once the page's input is
// all answered (connection.js calls resync). True when something changed (the toolbar and panel
// then need a rebuild).
export function takeState(m) {
  if (m) S.latestState = m;
  m = S.latestState;
  if (!m || S.inFlight || S.pending.size || S.drag || S.pointers.size || S.panelBusy) return false;
  S.latestState = null;
  const before = JSON.stringify([S.camera, S.method, S.spp, S.objects]);
  if (m.camera) {
    S.camera = copyCamera(m.camera);
    S.cameraSent = copyCamera(m.camera);
    takeProjection(m.camera);
  }
  if (m.method) S.method = m.method;
  if (m.spp) S.spp = m.spp;
  if (m.colour_bars) S.planeBars = m.colour_bars;
  for (const o of m.objects || []) {
    const l = S.byName.get(o.name);
    if (!l) continue;
    if (o.visible !== undefined) l.visible = o.visible;
    if (o.opacity !== undefined) l.opacity = o.opacity;
    if (l.kind === 'volume') {
      if (o.transfer_function) l.tf = tfPoints(o.transfer_function);
      if (o.frame !== undefined) l.frame = o.frame;
      if (o.window) l.window = [...o.window];
      l.windowNote = o.window_note || '';
      if (o.slabs) l.slabs = JSON.parse(JSON.stringify(o.slabs));
      if (o.labels) l.labels = o.labels.map((x) => ({...x, color: [...x.color]}));
      if (o.clip_planes) {
        const same = o.clip_planes.length === l.clips.length;
        l.clips = o.clip_planes.map((c, i) => {
          const old = same ? l.clips[i] : null;
          if (old && len(sub(norm(c.normal), old.normal)) < 1e-9) {
            // keep the slider's base; the offset is what moved
            return {base: old.base, normal: old.normal,
                    offset: dot(sub(c.point, old.base), old.normal)};
          }
          return {base: [...c.point], normal: norm(c.normal), offset: 0};
        });
      }
    } else if (l.kind === 'streamlines') {
      takeStreamlines(l, o);
    } else if (l.kind === 'plane') {
      if (o.center) l.center = [...o.center];
      if (o.window) l.window = [...o.window];
      if (o.slab) l.slab = {...o.slab};
    }
  }
  return JSON.stringify([S.camera, S.method, S.spp, S.objects]) !== before;
}

// A volume's clip planes as an edit message's `clip_planes`.
export function clipsMessage(o) {
  return o.clips.map((c) => ({point: add(c.base, mul(c.normal, c.offset)), normal: c.normal}));
}

// Whether the user is moving something: a drag, touch, wheel, or moving input not yet answered.
export function isMoving() {
  return Boolean(S.drag) || S.pointers.size > 0 || Boolean(S.wheelTimer) ||
         (S.inFlight && S.inFlight.moving) || [...S.pending.values()].some((p) => p.msg.moving);
}
