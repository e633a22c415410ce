// The WebSocket of docs/viewer.md's protocol: connecting, sending, and flow control (one input
// message in flight, further input merged per key until a frame answers it). The server's
// messages go to the handlers given to connect(); frames, errors and flow control are kept here.
import {editCommitted} from './history.js';
import {S, token} from './state.js';
import {showMessage, stats} from './stats.js';
import {copyCamera} from './vec.js';

let ws = null;
let open = false;
let connEl = null;
let resync = null;  // handlers.resync: applies the latest state once the page is idle

// Sends one message now; false when the socket is not open.
export function send(obj) {
  if (!open) return false;
  ws.send(JSON.stringify(obj));
  return true;
}

// Queues an input; merged with a pending one of the same key, sent when nothing is in flight.
export function queueInput(key, fields, moving) {
  const now = performance.now();
  const p = S.pending.get(key);
  if (p) {
    Object.assign(p.msg, fields);
    p.msg.moving = moving;
  } else {
    S.pending.set(key, {msg: Object.assign({}, fields, {moving}), t0: now});
  }
  stats.converged = false;
  pump();
}

function pump() {
  if (S.inFlight || !open || S.pending.size === 0) return;
  const [key, p] = S.pending.entries().next().value;
  S.pending.delete(key);
  const seq = S.nextSeq++;
  p.msg.seq = seq;
  send(p.msg);
  S.lastSentSeq = seq;
  stats.lastSentSeq = seq;
  S.sentT0.set(seq, p.t0);
  // A server that never answers must not freeze the page; frames normally come much sooner.
  S.inFlight = {seq, moving: p.msg.moving, timer: setTimeout(() => acknowledge(seq), 5000)};
  updateConverged();
}

function acknowledge(seq) {
  if (S.inFlight && seq >= S.inFlight.seq) {
    clearTimeout(S.inFlight.timer);
    S.inFlight = null;
    pump();
    // All of this page's input answered: take what the others did meanwhile.
    if (!S.inFlight && resync) resync();
  }
}

// Queues the page's camera move: from the camera the page last sent (or took from the server)
// to S.camera. The server applies the move to the camera it has, so a move made while another
// window moved the camera adds to that window's move instead of undoing it (docs/viewer.md).
// `set`: the camera as it is, not a move (reset view, snap to a standard view).
export function cameraInput(moving, set = false) {
  const p = S.pending.get('camera');
  const fields = Object.assign({type: 'camera'}, copyCamera(S.camera));
  if (!set) fields.from = p && p.msg.from ? p.msg.from : copyCamera(S.cameraSent || S.camera);
  else if (p) delete p.msg.from;
  S.cameraSent = copyCamera(S.camera);
  queueInput('camera', fields, moving);
}

// Queues an edit of one object; edits of different objects are separate messages. A final one
// is a step of the page's undo history.
export function editInput(name, fields, moving) {
  queueInput('edit:' + name, Object.assign({type: 'edit', object: name}, fields), moving);
  if (!moving) editCommitted(name, fields);
}

// stats.converged: the last drawn frame is final and shows every input sent.
export function updateConverged() {
  const f = stats.lastFrame;
  stats.converged = Boolean(f && f.final && f.seq >= S.lastSentSeq && !S.inFlight &&
                            S.pending.size === 0 && S.lastDrawnId === S.frameId);
  if (stats.converged) reportLatencies(true);
}

// Sends the latencies measured since the last report (every 50, or all at convergence), so the
// server can log them.
export function reportLatencies(force) {
  const fresh = stats.latencies.length - S.reportedLatencies;
  if (fresh <= 0 || (!force && fresh < 50)) return;
  if (send({type: 'stats', latency_ms: stats.latencies.slice(S.reportedLatencies)}))
    S.reportedLatencies = stats.latencies.length;
}

// Shows the connection's state in the toolbar; cls is '', 'ok' or 'bad'.
export function setConnection(text, cls) {
  connEl.textContent = text;
  connEl.className = 'connection ' + (cls || '');
}

// Opens the WebSocket; el shows its state. handlers: hello(m), state(m), saved(m),
// frame(meta, blob, id) for a frame to draw (id grows with each), screenshot(blob), and the
// answers probe(m), measure(m), pick(m), error(m).
export function connect(el, handlers) {
  resync = handlers.resync || null;
  connEl = el;
  const proto = location.protocol === 'https:' ? 'wss:' : 'ws:';
  // Without a token in the address (a reload) the upgrade carries the session's cookie.
  const query = token ? `?token=${encodeURIComponent(token)}` : '';
  ws = new WebSocket(`${proto}//${location.host}/ws${query}`);
  ws.binaryType = 'blob';
  ws.onopen = () => {
    open = true;
    stats.connected = true;
    setConnection('connected', 'ok');
    pump();
  };
  ws.onclose = () => {
    open = false;
    stats.connected = false;
    setConnection('disconnected (reload the page)', 'bad');
  };
  ws.onerror = () => setConnection('connection error', 'bad');
  ws.onmessage = (ev) => {
    if (typeof ev.data === 'string') {
      let m;
      try {
        m = JSON.parse(ev.data);
      } catch (e) {
        return;
      }
      onText(m, handlers);
    } else {
      onBinary(ev.data, handlers);
    }
  };
}

function onText(m, handlers) {
  switch (m.type) {
    case 'hello': handlers.hello(m); break;
    case 'state': handlers.state(m); break;
    case 'frame': {
      const drop = m.seq < S.lastSentSeq;
      S.expect = {kind: 'frame', meta: m, drop, id: drop ? 0 : ++S.frameId};
      if (!drop) acknowledge(m.seq);
      break;
    }
    case 'screenshot': S.expect = {kind: 'screenshot', meta: m}; break;
    case 'slice': S.expect = {kind: 'slice', meta: m}; break;
    case 'probe': if (handlers.probe) handlers.probe(m); break;
    case 'measure': if (handlers.measure) handlers.measure(m); break;
    case 'pick': if (handlers.pick) handlers.pick(m); break;
    case 'saved': handlers.saved(m); break;
    case 'error': {
      stats.errors.push(m.message);
      showMessage('server: ' + m.message);
      // The state is unchanged and the message that failed gets no frame.
      if (S.inFlight) acknowledge(S.inFlight.seq);
      if (handlers.error) handlers.error(m);
      break;
    }
    default: break;
  }
}

function onBinary(blob, handlers) {
  const e = S.expect;
  S.expect = null;
  if (!e) return;
  if (e.kind === 'slice') {
    if (handlers.slice) handlers.slice(e.meta, blob);
    return;
  }
  if (e.kind === 'frame') {
    if (!e.drop) handlers.frame(e.meta, blob, e.id);
  } else if (e.kind === 'screenshot') {
    stats.screenshots++;
    handlers.screenshot(blob);
  }
}
