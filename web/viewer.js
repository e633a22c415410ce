// intermix viewer: talks docs/viewer.md's protocol over one WebSocket, draws frames on a canvas
// and turns mouse, wheel, touch and panel input into camera, edit and settings messages.
'use strict';

(() => {
  const token = new URLSearchParams(location.search).get('token') || '';

  // ---------------------------------------------------------------- small vector math
  const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
  const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
  const mul = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
  const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const cross = (a, b) =>
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  const len = (a) => Math.sqrt(dot(a, a));
  const norm = (a) => { const l = len(a); return l > 0 ? mul(a, 1 / l) : [0, 0, 1]; };
  // Rodrigues' rotation of v about the unit axis k by angle a (radians).
  const rotate = (v, k, a) => {
    const c = Math.cos(a), s = Math.sin(a);
    return add(add(mul(v, c), mul(cross(k, v), s)), mul(k, dot(k, v) * (1 - c)));
  };
  const clamp = (x, lo, hi) => Math.min(hi, Math.max(lo, x));
  const copyCamera = (c) =>
    ({eye: [...c.eye], target: [...c.target], up: [...c.up], fov_deg: c.fov_deg});
  const fmt = (x, digits = 1) => (Number.isFinite(x) ? x.toFixed(digits) : '–');

  // ---------------------------------------------------------------- session state
  const S = {
    ws: null,
    open: false,
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
    inFlight: null,       // {seq, timer}
    pending: new Map(),   // key -> {msg, t0}
    sentT0: new Map(),    // seq -> time of the oldest input event merged into that message
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
    recording: null,
  };

  const stats = {
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
  window.viewerStats = stats;

  let canvas, ctx, statusEl, connEl;

  // ---------------------------------------------------------------- sending
  function send(obj) {
    if (!S.open) return false;
    S.ws.send(JSON.stringify(obj));
    return true;
  }

  // Queues an input; merged with a pending one of the same key, sent when nothing is in flight.
  function queueInput(key, fields, moving) {
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
    if (S.inFlight || !S.open || S.pending.size === 0) return;
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
    }
  }

  function cameraInput(moving) {
    queueInput('camera', Object.assign({type: 'camera'}, copyCamera(S.camera)), moving);
  }

  function editInput(name, fields, moving) {
    queueInput('edit:' + name, Object.assign({type: 'edit', object: name}, fields), moving);
  }

  // ---------------------------------------------------------------- receiving
  function connect() {
    const proto = location.protocol === 'https:' ? 'wss:' : 'ws:';
    const ws = new WebSocket(`${proto}//${location.host}/ws?token=${encodeURIComponent(token)}`);
    ws.binaryType = 'blob';
    S.ws = ws;
    ws.onopen = () => {
      S.open = true;
      stats.connected = true;
      setConnection('connected', 'ok');
      pump();
    };
    ws.onclose = () => {
      S.open = false;
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
        onText(m);
      } else {
        onBinary(ev.data);
      }
    };
  }

  function setConnection(text, cls) {
    connEl.textContent = text;
    connEl.className = 'connection ' + (cls || '');
  }

  function onText(m) {
    switch (m.type) {
      case 'hello': onHello(m); break;
      case 'state': onState(m); break;
      case 'frame': {
        const drop = m.seq < S.lastSentSeq;
        S.expect = {kind: 'frame', meta: m, drop, id: drop ? 0 : ++S.frameId};
        if (!drop) acknowledge(m.seq);
        break;
      }
      case 'screenshot': S.expect = {kind: 'screenshot', meta: m}; break;
      case 'saved': onSaved(m); break;
      case 'error': {
        stats.errors.push(m.message);
        showMessage('server: ' + m.message);
        // The state is unchanged and the message that failed gets no frame.
        if (S.inFlight) acknowledge(S.inFlight.seq);
        break;
      }
      default: break;
    }
  }

  function onBinary(blob) {
    const e = S.expect;
    S.expect = null;
    if (!e) return;
    if (e.kind === 'frame') {
      if (!e.drop) drawFrame(e.meta, blob, e.id);
    } else if (e.kind === 'screenshot') {
      stats.screenshots++;
      download(new Blob([blob], {type: 'image/png'}), 'intermix-screenshot.png');
    }
  }

  async function drawFrame(meta, blob, id) {
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
    if (S.recording) record(now, meta);
    updateConverged();
    reportLatencies(false);
    updateStatus();
  }

  function isMoving() {
    return Boolean(S.drag) || S.pointers.size > 0 || Boolean(S.wheelTimer) ||
           (S.inFlight && S.inFlight.moving) || [...S.pending.values()].some((p) => p.msg.moving);
  }

  function updateConverged() {
    const f = stats.lastFrame;
    stats.converged = Boolean(f && f.final && f.seq >= S.lastSentSeq && !S.inFlight &&
                              S.pending.size === 0 && S.lastDrawnId === S.frameId);
    if (stats.converged) reportLatencies(true);
  }

  // Sends the latencies measured since the last report, so the server can log them.
  function reportLatencies(force) {
    const fresh = stats.latencies.length - S.reportedLatencies;
    if (fresh <= 0 || (!force && fresh < 50)) return;
    if (send({type: 'stats', latency_ms: stats.latencies.slice(S.reportedLatencies)}))
      S.reportedLatencies = stats.latencies.length;
  }

  function median(xs) {
    if (!xs.length) return NaN;
    const s = [...xs].sort((a, b) => a - b);
    const n = s.length;
    return n % 2 ? s[(n - 1) / 2] : 0.5 * (s[n / 2 - 1] + s[n / 2]);
  }

  let messageUntil = 0, messageText = '';
  function showMessage(text) {
    messageText = text;
    messageUntil = performance.now() + 4000;
    updateStatus();
  }

  function updateStatus() {
    const f = stats.lastFrame;
    const parts = [];
    if (f) {
      parts.push(`frame ${fmt(f.render_ms)} ms`, `encode ${fmt(f.encode_ms)} ms`,
                 `${f.samples}/${f.spp} spp`, `stages ${f.stages_run}/${f.stages}`,
                 `scale ${fmt(f.scale, 2)}`, f.format);
    }
    parts.push(`${fmt(S.movingFps, 0)} fps moving`);
    const last = stats.latencies.slice(-50);
    parts.push(`latency ${fmt(median(last), 0)} ms (median of ${last.length})`);
    if (stats.converged) parts.push('converged');
    if (performance.now() < messageUntil) parts.push(messageText);
    statusEl.textContent = parts.join(' · ');
  }

  // ---------------------------------------------------------------- hello and state
  const tfPoints = (tf) => {
    const pts = Array.isArray(tf) ? tf : (tf && Array.isArray(tf.points) ? tf.points : []);
    return pts.map((p) => [...p]);
  };

  function onHello(m) {
    S.methods = m.methods || [];
    S.method = m.method;
    S.spp = m.spp;
    S.image = m.image;
    S.camera = copyCamera(m.camera);
    S.initialCamera = copyCamera(m.initial_camera || m.camera);
    S.histograms = m.histograms || {};
    S.tfPresets = m.tf_presets || {};
    canvas.width = S.image.width;
    canvas.height = S.image.height;
    ctx.fillStyle = '#000';
    ctx.fillRect(0, 0, canvas.width, canvas.height);
    layoutCanvas();
    S.objects = (m.objects || []).map(localObject);
    S.byName = new Map(S.objects.map((o) => [o.name, o]));
    // Window/level applies to MPR planes, which show a volume.
    S.selectedPlane = (S.objects.find((o) => o.kind === 'plane' && o.volume) || {}).name || null;
    S.selectedClip = null;
    buildSelectors();
    buildPanel();
    updateStatus();
  }

  function localObject(o) {
    const l = {name: o.name, kind: o.kind, visible: o.visible !== false,
               opacity: o.opacity === undefined ? 1 : o.opacity};
    if (o.kind === 'volume') {
      l.tf = tfPoints(o.transfer_function);
      l.frame = o.frame || 0;
      l.frames = o.frames || 1;
      l.clips = (o.clip_planes || []).map((c) => ({base: [...c.point], normal: norm(c.normal),
                                                   offset: 0}));
    } else if (o.kind === 'plane') {
      l.center = [...o.center];
      l.initialCenter = [...o.center];
      l.normal = norm(o.normal);
      l.size = Array.isArray(o.size) ? o.size : [o.size, o.size];
      l.window = [...o.window];
      l.volume = o.volume;
    }
    return l;
  }

  // Another client's edits (or ours, echoed): taken while this page has no input of its own.
  function onState(m) {
    if (S.inFlight || S.pending.size || S.drag || S.pointers.size || S.panelBusy) return;
    const before = JSON.stringify([S.camera, S.method, S.spp, S.objects]);
    if (m.camera) S.camera = copyCamera(m.camera);
    if (m.method) S.method = m.method;
    if (m.spp) S.spp = m.spp;
    for (const o of m.objects || []) {
      const l = S.byName.get(o.name);
      if (!l) continue;
      if (o.visible !== undefined) l.visible = o.visible;
      if (o.opacity !== undefined) l.opacity = o.opacity;
      if (l.kind === 'volume') {
        if (o.transfer_function) l.tf = tfPoints(o.transfer_function);
        if (o.frame !== undefined) l.frame = o.frame;
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
      } else if (l.kind === 'plane') {
        if (o.center) l.center = [...o.center];
        if (o.window) l.window = [...o.window];
      }
    }
    if (JSON.stringify([S.camera, S.method, S.spp, S.objects]) === before) return;
    buildSelectors();
    buildPanel();
  }

  function onSaved(m) {
    stats.saved = {path: m.path};
    document.getElementById('saved-path').textContent = 'saved: ' + m.path;
    const base = (m.path || 'scene.json').split(/[\\/]/).pop() || 'scene.json';
    download(new Blob([m.text || ''], {type: 'application/json'}),
             base.endsWith('.json') ? base : base + '.json');
  }

  function download(blob, name) {
    const a = document.createElement('a');
    a.href = URL.createObjectURL(blob);
    a.download = name;
    document.body.appendChild(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(a.href), 10000);
  }

  // ---------------------------------------------------------------- toolbar
  function buildSelectors() {
    const method = document.getElementById('method');
    method.replaceChildren(...S.methods.map((name) => new Option(name, name, false,
                                                                  name === S.method)));
    const quality = document.getElementById('quality');
    const spps = [1, 4, 9, 16];
    if (!spps.includes(S.spp)) spps.push(S.spp);
    spps.sort((a, b) => a - b);
    quality.replaceChildren(...spps.map((n) => new Option(`${n} spp`, String(n), false,
                                                           n === S.spp)));
  }

  function setupToolbar() {
    document.getElementById('method').addEventListener('change', (e) => {
      S.method = e.target.value;
      queueInput('settings', {type: 'settings', method: S.method}, false);
    });
    document.getElementById('quality').addEventListener('change', (e) => {
      S.spp = Number(e.target.value);
      queueInput('settings', {type: 'settings', spp: S.spp}, false);
    });
    document.getElementById('reset-view').addEventListener('click', () => {
      if (!S.initialCamera) return;
      S.camera = copyCamera(S.initialCamera);
      cameraInput(false);
    });
    const wl = document.getElementById('wl-mode');
    wl.addEventListener('click', () => {
      S.wlMode = !S.wlMode;
      wl.setAttribute('aria-pressed', String(S.wlMode));
    });
    document.getElementById('save').addEventListener('click', () => send({type: 'save'}));
    document.getElementById('screenshot')
        .addEventListener('click', () => send({type: 'screenshot'}));
  }

  // ---------------------------------------------------------------- object panel
  function slider(label, min, max, step, value, onInput, onChange, digits = 2) {
    const row = document.createElement('div');
    row.className = 'row';
    const l = document.createElement('span');
    l.className = 'label';
    l.textContent = label;
    const input = document.createElement('input');
    input.type = 'range';
    input.min = min;
    input.max = max;
    input.step = step;
    input.value = value;
    const out = document.createElement('span');
    out.className = 'value';
    out.textContent = Number(value).toFixed(digits);
    input.addEventListener('input', () => {
      out.textContent = Number(input.value).toFixed(digits);
      onInput(Number(input.value));
    });
    input.addEventListener('change', () => onChange(Number(input.value)));
    row.append(l, input, out);
    return {row, input};
  }

  function button(text, onClick) {
    const b = document.createElement('button');
    b.type = 'button';
    b.textContent = text;
    b.addEventListener('click', onClick);
    return b;
  }

  const editors = new Map();  // volume name -> TfEditor

  function buildPanel() {
    const root = document.getElementById('objects');
    for (const ed of editors.values()) ed.dispose();
    editors.clear();
    root.replaceChildren();
    for (const o of S.objects) {
      const box = document.createElement('div');
      box.className = 'object';
      box.dataset.name = o.name;
      const head = document.createElement('div');
      head.className = 'head';
      const cb = document.createElement('input');
      cb.type = 'checkbox';
      cb.checked = o.visible;
      cb.className = 'visible';
      cb.title = 'visible';
      cb.addEventListener('change', () => {
        o.visible = cb.checked;
        editInput(o.name, {visible: o.visible}, false);
      });
      const name = document.createElement('span');
      name.className = 'name';
      name.textContent = o.name;
      const kind = document.createElement('span');
      kind.className = 'kind';
      kind.textContent = o.kind;
      head.append(cb, name, kind);
      box.append(head);

      const sendOpacity = (moving) => editInput(o.name, {opacity: o.opacity}, moving);
      box.append(slider('opacity', 0, 1, 0.01, o.opacity,
                        (v) => { o.opacity = v; sendOpacity(true); },
                        (v) => { o.opacity = v; sendOpacity(false); }).row);

      if (o.kind === 'volume') buildVolume(box, o);
      if (o.kind === 'plane') buildPlane(box, o);
      root.append(box);
    }
  }

  // The radio that makes this plane the one a W/L drag edits.
  function buildWindowTarget(box, o) {
    const row = document.createElement('div');
    row.className = 'row';
    const radio = document.createElement('input');
    radio.type = 'radio';
    radio.name = 'wl-plane';
    radio.checked = S.selectedPlane === o.name;
    radio.addEventListener('change', () => { S.selectedPlane = o.name; });
    const label = document.createElement('span');
    label.textContent = `W/L target · window ${fmt(o.window[0], 0)} / ${fmt(o.window[1], 0)}`;
    label.className = 'wl-label';
    row.append(radio, label);
    box.append(row);
  }

  function buildPlane(box, o) {
    if (o.volume) buildWindowTarget(box, o);
    const half = Math.max(o.size[0], o.size[1]) / 2;
    const offset = dot(sub(o.center, o.initialCenter), o.normal);
    const move = (v, moving) => {
      o.center = add(o.initialCenter, mul(o.normal, v));
      editInput(o.name, {center: o.center}, moving);
    };
    box.append(slider('position', -half, half, half / 500, offset, (v) => move(v, true),
                      (v) => move(v, false), 1).row);
  }

  function clipsMessage(o) {
    return o.clips.map((c) => ({point: add(c.base, mul(c.normal, c.offset)), normal: c.normal}));
  }

  // A multi-frame volume (fMRI, DWI, ...): a frame slider, and play / pause stepping through
  // the frames about four times a second (each step re-runs only this volume's stage).
  function buildFrames(box, o) {
    const frames = slider('frame', 0, o.frames - 1, 1, o.frame,
                          (v) => { o.frame = v; editInput(o.name, {frame: v}, true); },
                          (v) => { o.frame = v; editInput(o.name, {frame: v}, false); }, 0);
    let timer = null;
    const play = button('play', () => {
      if (timer) {
        clearInterval(timer);
        timer = null;
        play.textContent = 'play';
        return;
      }
      play.textContent = 'pause';
      timer = setInterval(() => {
        if (S.inFlight) return;  // the last frame is still rendering: do not queue up
        o.frame = (o.frame + 1) % o.frames;
        frames.input.value = o.frame;
        frames.row.querySelector('.value').textContent = String(o.frame);
        editInput(o.name, {frame: o.frame}, false);
      }, 250);
    });
    play.className = 'frame-play';
    frames.row.append(play);
    box.append(frames.row);
  }

  function buildVolume(box, o) {
    if (o.frames > 1) buildFrames(box, o);
    const ed = new TfEditor(o, S.histograms[o.name]);
    editors.set(o.name, ed);
    box.append(ed.root);
    const names = Object.keys(S.tfPresets || {});
    if (names.length) {
      // A preset replaces the points (the volume keeps its shading and unit distance).
      const row = document.createElement('div');
      row.className = 'row';
      const select = document.createElement('select');
      select.className = 'tf-preset';
      select.append(new Option('preset…', ''), ...names.map((n) => new Option(n, n)));
      select.addEventListener('change', () => {
        const pts = S.tfPresets[select.value];
        if (!pts) return;
        o.tf = pts.map((p) => [...p]);
        o.maxAlpha = 0;
        ed.sendTf(false);
        buildPanel();
      });
      row.append(select);
      box.append(row);
    }
    const range = S.initialCamera ? 0.5 * len(sub(S.initialCamera.eye, S.initialCamera.target))
                                  : 200;
    o.clips.forEach((c, i) => {
      const div = document.createElement('div');
      const selected = S.selectedClip && S.selectedClip.volume === o.name &&
                       S.selectedClip.index === i;
      div.className = 'clip' + (selected ? ' selected' : '');
      const moveClip = (v, moving) => {
        c.offset = v;
        S.selectedClip = {volume: o.name, index: i};
        editInput(o.name, {clip_planes: clipsMessage(o)}, moving);
      };
      const s = slider(`clip ${i + 1}`, -range, range, range / 500, c.offset,
                       (v) => moveClip(v, true), (v) => moveClip(v, false), 1);
      s.row.append(button('remove', () => {
        o.clips.splice(i, 1);
        S.selectedClip = null;
        editInput(o.name, {clip_planes: clipsMessage(o)}, false);
        buildPanel();
      }));
      s.input.addEventListener('pointerdown', () => { S.selectedClip = {volume: o.name, index: i}; });
      div.append(s.row);
      box.append(div);
    });
    const row = document.createElement('div');
    row.className = 'row';
    row.append(button('add clip plane', () => {
      // Through the camera target, facing the way the camera looks.
      o.clips.push({base: [...S.camera.target],
                    normal: norm(sub(S.camera.target, S.camera.eye)), offset: 0});
      S.selectedClip = {volume: o.name, index: o.clips.length - 1};
      editInput(o.name, {clip_planes: clipsMessage(o)}, false);
      buildPanel();
    }));
    box.append(row);
  }

  // ---------------------------------------------------------------- transfer function editor
  // Control points over the log histogram: x = value, y = alpha / the editor's max alpha.
  class TfEditor {
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
      this.computeDomain();
      this.bind();
      this.resize = new ResizeObserver(() => this.draw());
      this.resize.observe(this.canvas);
    }

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

    sendTf(moving) {
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
        if (this.dragIndex < 0) return;
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
    }
  }

  function niceCeil(x) {
    const e = Math.pow(10, Math.floor(Math.log10(x)));
    for (const m of [1, 2, 2.5, 5, 10]) if (m * e >= x) return Math.min(m * e, Math.max(1, x));
    return x;
  }

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

  // ---------------------------------------------------------------- camera interaction
  function cameraFrame() {
    const c = S.camera;
    const offset = sub(c.eye, c.target);
    const dist = len(offset);
    const fwd = mul(offset, -1 / dist);
    const right = norm(cross(fwd, c.up));
    const up = cross(right, fwd);
    return {dist, fwd, right, up};
  }

  // Rotates the eye about the target: horizontal drag about the view's up, vertical about right.
  function orbit(dx, dy) {
    const f = cameraFrame();
    const k = Math.PI / Math.max(1, canvas.clientHeight);
    const a1 = -dx * k, a2 = -dy * k;
    let off = sub(S.camera.eye, S.camera.target);
    off = rotate(off, f.up, a1);
    const right = rotate(f.right, f.up, a1);
    off = rotate(off, right, a2);
    const up = norm(rotate(f.up, right, a2));
    S.camera.eye = add(S.camera.target, off);
    S.camera.up = up;
  }

  function mmPerPixel() {
    const f = cameraFrame();
    return 2 * f.dist * Math.tan(S.camera.fov_deg * Math.PI / 360) /
           Math.max(1, canvas.clientHeight);
  }

  function pan(dx, dy) {
    const f = cameraFrame();
    const s = mmPerPixel();
    const d = add(mul(f.right, -dx * s), mul(f.up, dy * s));
    S.camera.eye = add(S.camera.eye, d);
    S.camera.target = add(S.camera.target, d);
  }

  function zoom(factor) {
    const f = cameraFrame();
    const dist = clamp(f.dist * factor, 1e-2, 1e7);
    S.camera.eye = sub(S.camera.target, mul(f.fwd, dist));
  }

  function startWindowLevel() {
    const p = S.selectedPlane && S.byName.get(S.selectedPlane);
    return p ? {plane: p, window0: [...p.window]} : null;
  }

  function applyWindowLevel(drag, dx, dy, moving) {
    const p = drag.wl.plane;
    const [c0, w0] = drag.wl.window0;
    const width = Math.max(1e-6, w0 * Math.exp(dx * 0.005));
    const centre = c0 + dy * Math.max(Math.abs(w0), 1e-3) / 256;
    p.window = [centre, width];
    editInput(p.name, {window: p.window}, moving);
    const label = document.querySelector(`.object[data-name="${CSS.escape(p.name)}"] .wl-label`);
    if (label) label.textContent = `W/L target · window ${fmt(centre, 0)} / ${fmt(width, 0)}`;
  }

  function selectedClip() {
    const sc = S.selectedClip;
    if (sc) {
      const o = S.byName.get(sc.volume);
      if (o && o.clips[sc.index]) return {o, c: o.clips[sc.index]};
    }
    for (const o of S.objects)
      if (o.kind === 'volume' && o.clips.length) return {o, c: o.clips[o.clips.length - 1]};
    return null;
  }

  function setupCanvas() {
    canvas.addEventListener('contextmenu', (ev) => ev.preventDefault());
    canvas.addEventListener('pointerdown', (ev) => {
      if (!S.camera) return;
      canvas.setPointerCapture(ev.pointerId);
      canvas.focus();
      S.pointers.set(ev.pointerId, {x: ev.clientX, y: ev.clientY});
      if (ev.pointerType === 'touch') {
        S.drag = {mode: 'touch'};
      } else {
        let mode = 'orbit';
        if (ev.button === 2 || ev.button === 1 || ev.shiftKey) mode = 'pan';
        if (ev.button === 0 && (ev.ctrlKey || ev.metaKey || S.wlMode)) mode = 'wl';
        if (ev.button === 0 && ev.altKey) mode = 'clip';
        S.drag = {mode, x0: ev.clientX, y0: ev.clientY};
        if (mode === 'wl') {
          S.drag.wl = startWindowLevel();
          if (!S.drag.wl) S.drag.mode = 'none';
        }
        if (mode === 'clip') {
          S.drag.clip = selectedClip();
          if (S.drag.clip) S.drag.offset0 = S.drag.clip.c.offset;
          else S.drag.mode = 'none';
        }
      }
      canvas.classList.add('dragging');
      ev.preventDefault();
    });
    canvas.addEventListener('pointermove', (ev) => {
      const prev = S.pointers.get(ev.pointerId);
      if (!prev || !S.drag) return;
      const dx = ev.clientX - prev.x, dy = ev.clientY - prev.y;
      if (S.drag.mode === 'touch') {
        touchMove(ev);
        return;
      }
      S.pointers.set(ev.pointerId, {x: ev.clientX, y: ev.clientY});
      if (dx === 0 && dy === 0) return;
      const d = S.drag;
      if (d.mode === 'orbit') { orbit(dx, dy); cameraInput(true); }
      else if (d.mode === 'pan') { pan(dx, dy); cameraInput(true); }
      else if (d.mode === 'wl') applyWindowLevel(d, ev.clientX - d.x0, ev.clientY - d.y0, true);
      else if (d.mode === 'clip') moveClipByDrag(d, ev.clientY - d.y0, true);
    });
    const end = (ev) => {
      if (!S.pointers.has(ev.pointerId)) return;
      S.pointers.delete(ev.pointerId);
      if (canvas.hasPointerCapture(ev.pointerId)) canvas.releasePointerCapture(ev.pointerId);
      const d = S.drag;
      if (d && d.mode === 'touch') {
        d.last = null;  // the remaining fingers start a fresh gesture, without a jump
        if (S.pointers.size > 0) return;
      }
      S.drag = null;
      canvas.classList.remove('dragging');
      if (!d) return;
      if (d.mode === 'orbit' || d.mode === 'pan' || d.mode === 'touch') cameraInput(false);
      else if (d.mode === 'wl') applyWindowLevel(d, ev.clientX - d.x0, ev.clientY - d.y0, false);
      else if (d.mode === 'clip') moveClipByDrag(d, ev.clientY - d.y0, false);
    };
    canvas.addEventListener('pointerup', end);
    canvas.addEventListener('pointercancel', end);
    canvas.addEventListener('wheel', (ev) => {
      if (!S.camera) return;
      ev.preventDefault();
      const scale = ev.deltaMode === 1 ? 16 : ev.deltaMode === 2 ? 400 : 1;
      zoom(Math.exp(clamp(ev.deltaY * scale, -500, 500) * 0.0015));
      cameraInput(true);
      clearTimeout(S.wheelTimer);
      S.wheelTimer = setTimeout(() => {
        S.wheelTimer = 0;
        cameraInput(false);
      }, 250);
    }, {passive: false});
  }

  // One finger orbits; two pan by their midpoint and zoom by their distance.
  function touchMove(ev) {
    const d = S.drag;
    S.pointers.set(ev.pointerId, {x: ev.clientX, y: ev.clientY});
    const pts = [...S.pointers.values()];
    const now = pts.length >= 2
        ? {n: 2, x: (pts[0].x + pts[1].x) / 2, y: (pts[0].y + pts[1].y) / 2,
           dist: Math.hypot(pts[0].x - pts[1].x, pts[0].y - pts[1].y)}
        : {n: 1, x: pts[0].x, y: pts[0].y, dist: 0};
    const last = d.last;
    d.last = now;
    if (!last || last.n !== now.n) return;
    if (now.n === 1) {
      orbit(now.x - last.x, now.y - last.y);
    } else {
      pan(now.x - last.x, now.y - last.y);
      if (now.dist > 0 && last.dist > 0) zoom(last.dist / now.dist);
    }
    cameraInput(true);
  }

  function moveClipByDrag(d, dy, moving) {
    const {o, c} = d.clip;
    c.offset = d.offset0 - dy * mmPerPixel();
    editInput(o.name, {clip_planes: clipsMessage(o)}, moving);
    if (!moving) buildPanel();
  }

  // Fits the canvas into its area, keeping the image's aspect ratio (the backing store stays the
  // image size, so a converged frame is drawn 1:1).
  function layoutCanvas() {
    const area = document.getElementById('view-area');
    const aw = area.clientWidth, ah = area.clientHeight;
    const s = Math.min(aw / S.image.width, ah / S.image.height);
    if (!(s > 0)) return;
    canvas.style.width = `${Math.floor(S.image.width * s)}px`;
    canvas.style.height = `${Math.floor(S.image.height * s)}px`;
  }

  // ---------------------------------------------------------------- recording (--measure)
  // Snapshots of every drawn frame, so a test can time the approach to the converged image.
  function record(now, meta) {
    if (S.recording.frames.length >= 256) return;
    const data = ctx.getImageData(0, 0, canvas.width, canvas.height).data;
    S.recording.frames.push({t: now, data: new Uint8ClampedArray(data), seq: meta.seq,
                             samples: meta.samples, scale: meta.scale, final: meta.final});
  }

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

  window.viewer = {
    // the page position of a TF control point, to drag it with real mouse events
    tfPoint(volume, index) {
      const ed = editors.get(volume);
      return ed && index < ed.obj.tf.length ? ed.clientPos(index) : null;
    },
    tfPoints(volume) {
      const o = S.byName.get(volume);
      return o && o.tf ? o.tf.map((p) => [...p]) : null;
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
    startRecording(release) { S.recording = {release, frames: []}; },
    // PSNR (8-bit RGB) of each recorded frame against the last one, and when it was drawn.
    finishRecording() {
      const rec = S.recording;
      S.recording = null;
      if (!rec || !rec.frames.length) return [];
      const last = rec.frames[rec.frames.length - 1].data;
      return rec.frames.map((f) => ({t_ms: f.t - rec.release, psnr_db: psnr(f.data, last),
                                     samples: f.samples, scale: f.scale, final: f.final}));
    },
    now() { return performance.now(); },
  };

  // ---------------------------------------------------------------- start
  function start() {
    canvas = document.getElementById('view');
    ctx = canvas.getContext('2d', {alpha: true});
    statusEl = document.getElementById('status');
    connEl = document.getElementById('connection');
    setupToolbar();
    setupCanvas();
    // A panel control being dragged is not rebuilt under the pointer by another client's state.
    document.getElementById('panel').addEventListener('pointerdown', () => { S.panelBusy = true; });
    window.addEventListener('pointerup', () => { S.panelBusy = false; }, true);
    window.addEventListener('resize', () => {
      layoutCanvas();
      for (const ed of editors.values()) ed.draw();
    });
    layoutCanvas();
    if (!token) setConnection('no token in the address', 'bad');
    connect();
  }

  if (document.readyState === 'loading') document.addEventListener('DOMContentLoaded', start);
  else start();
})();
