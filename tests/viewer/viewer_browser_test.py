#!/usr/bin/python3
"""Headless-Chromium test of the viewer (`intermix serve` + web/), docs/viewer.md.

    tests/viewer/viewer_browser_test.py --intermix build/intermix --scene examples/fusion.json
    tests/viewer/viewer_browser_test.py --intermix build/intermix --scene examples/ct-head.json \\
        --measure 50 --out out/viewer

Test mode (default) serves the scene at 256x256 with zslab and checks, printing each check's
measured number and PASS/FAIL: the page loads and converges; HTTP and WebSocket refuse a missing
or wrong token; a canvas drag orbits at >= 10 frames/s; dragging a TF control point changes the
image and re-runs only the edited volume's stage; toggling an object's visibility changes the
image; a second (plain WebSocket) client gets `state` messages after the page's edits; the saved
scene renders (intermix render) to the converged canvas within 40 dB PSNR. Then, in the same
browser, a second server on examples/mpr.json (--mpr-scene; a CT with three MPR planes):
ctrl+drag sets a plane's window and re-runs only part of the stages; a plane's position slider
moves it; "add clip plane" then alt+drag moves that clip; "reset view" after an orbit restores
the initial camera. Screenshots go to --out. Exit 0: all passed, 1: a check failed, 77: skipped
(no chromium or websocket module).

Measure mode (--measure N) serves the scene as it is and does N short drags, reporting
input-to-frame latency (median, 95th percentile), frames per second while moving and the time
from release to 40 dB of the converged frame, as JSON on stdout and in DIR/measure.json.

Needs only Debian's python3-websocket and chromium besides the standard library.
"""

import argparse
import base64
import copy
import glob
import http.client
import json
import math
import os
import re
import select
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
import urllib.error
import urllib.parse
import urllib.request

sys.dont_write_bytecode = True  # no __pycache__ beside the sources
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cdp  # noqa: E402
from cdp import CdpError, kill_group, websocket  # noqa: E402

SKIP = 77
TEST_SIZE = 256
REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


class Failure(Exception):
    pass


def log(msg):
    print(msg, flush=True)


# ---------------------------------------------------------------- results
class Checks:
    def __init__(self):
        self.results = []

    def check(self, name, ok, measured, detail=''):
        self.results.append({'check': name, 'pass': bool(ok), 'measured': measured,
                             'detail': detail})
        log(f"{'PASS' if ok else 'FAIL'}  {name}: {measured}" + (f'  ({detail})' if detail else ''))
        return ok

    def failed(self):
        return [r for r in self.results if not r['pass']]


# ---------------------------------------------------------------- the server
class Server:
    URL_RE = re.compile(r'intermix serve: (http://\S+)')

    def __init__(self, intermix, scene, args, log_path, cwd):
        self.cmd = [intermix, 'serve', scene] + args
        self.log_path = log_path
        self.cwd = cwd
        self.proc = None
        self.url = None
        self._log = None
        self._stdout = []

    def start(self):
        self._log = open(self.log_path, 'wb')
        self.proc = subprocess.Popen(self.cmd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                     stderr=self._log, cwd=self.cwd, start_new_session=True)

    def wait_url(self, timeout=60.0):
        """Reads stdout until the URL line; fails when the server exits or the deadline passes."""
        deadline = time.monotonic() + timeout
        buf = b''
        fd = self.proc.stdout.fileno()
        while time.monotonic() < deadline:
            ready, _, _ = select.select([fd], [], [], 0.2)
            if ready:
                chunk = os.read(fd, 4096)
                if not chunk:  # stdout closed: the server is gone or closed it
                    break
                buf += chunk
                m = self.URL_RE.search(buf.decode('utf-8', 'replace'))
                if m and b'\n' in buf[buf.find(b'intermix serve:'):]:
                    self.url = m.group(1)
                    self._stdout.append(buf)
                    threading.Thread(target=self._drain, daemon=True).start()
                    return self.url
            elif self.proc.poll() is not None:
                break
        status = self.proc.poll()
        raise Failure(f"`{' '.join(self.cmd)}` printed no URL line within {timeout:.0f} s "
                      f"(exit status {status}; stdout {buf[-500:]!r}); its stderr ends:\n"
                      f"{tail(self.log_path)}")

    def _drain(self):
        try:
            while True:
                chunk = self.proc.stdout.read(4096)
                if not chunk:
                    return
                self._stdout.append(chunk)
        except (OSError, ValueError):
            return

    def stop(self, timeout=10.0):
        """SIGINT, then waits; returns (exit status, seconds) or (None, timeout) if it hung."""
        if self.proc is None or self.proc.poll() is not None:
            return (self.proc.returncode if self.proc else None), 0.0
        t0 = time.monotonic()
        try:
            self.proc.send_signal(signal.SIGINT)
            self.proc.wait(timeout=timeout)
            return self.proc.returncode, time.monotonic() - t0
        except subprocess.TimeoutExpired:
            return None, timeout

    def kill(self):
        if self.proc is not None:
            kill_group(self.proc, term_timeout=3)
        if self._log:
            self._log.close()
            self._log = None


def tail(path, n=1500):
    try:
        with open(path, 'rb') as f:
            f.seek(0, 2)
            f.seek(max(0, f.tell() - n))
            return f.read().decode('utf-8', 'replace')
    except OSError:
        return ''


# ---------------------------------------------------------------- a second client
class Watcher:
    """A plain WebSocket client: records every message the server sends it."""

    def __init__(self, ws_url):
        self.ws = websocket.create_connection(ws_url, timeout=10, suppress_origin=True)
        self.messages = []       # (monotonic time, parsed text message)
        self.binaries = 0
        self.violations = []     # protocol order problems
        self.expect_binary = False
        self.error = None
        self.lock = threading.Lock()
        self.stop_flag = threading.Event()
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self):
        sock = self.ws.sock
        try:
            while not self.stop_flag.is_set():
                r, _, _ = select.select([sock], [], [], 0.2)
                if not r:
                    continue
                self.ws.settimeout(10)
                opcode, data = self.ws.recv_data()
                now = time.monotonic()
                if opcode == websocket.ABNF.OPCODE_TEXT:
                    m = json.loads(data.decode('utf-8'))
                    with self.lock:
                        if self.expect_binary:
                            self.violations.append(f"{m.get('type')} text where a binary "
                                                   'image was expected')
                        if not self.messages and m.get('type') != 'hello':
                            self.violations.append(f"first message is {m.get('type')}, "
                                                   'not hello')
                        self.expect_binary = m.get('type') in ('frame', 'screenshot')
                        self.messages.append((now, m))
                elif opcode == websocket.ABNF.OPCODE_BINARY:
                    with self.lock:
                        if not self.expect_binary:
                            self.violations.append('a binary message without its frame text')
                        self.expect_binary = False
                        self.binaries += 1
                elif opcode == websocket.ABNF.OPCODE_CLOSE:
                    return
        except Exception as e:  # noqa: BLE001 - reported by the check that reads it
            if not self.stop_flag.is_set():
                self.error = f'{type(e).__name__}: {e}'

    def send(self, message):
        self.ws.send(json.dumps(message))

    def of_type(self, kind, since=0.0):
        with self.lock:
            return [(t, m) for t, m in self.messages if m.get('type') == kind and t >= since]

    def wait(self, pred, timeout):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            with self.lock:
                msgs = list(self.messages)
            for t, m in msgs:
                if pred(t, m):
                    return m
            time.sleep(0.05)
        return None

    def close(self):
        self.stop_flag.set()
        self.thread.join(timeout=3)
        try:
            self.ws.close(timeout=1)
        except Exception:  # noqa: BLE001
            pass


# ---------------------------------------------------------------- page helpers (JavaScript)
JS_SNAP = """(() => {
  const c = document.getElementById('view');
  const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
  window.__imxSnaps = window.__imxSnaps || {};
  window.__imxSnaps[%s] = new Uint8ClampedArray(d);
  return [c.width, c.height];
})()"""

JS_DIFF = """((a, b) => {
  let se = 0, changed = 0;
  const n = a.length / 4;
  for (let i = 0; i < a.length; i += 4) {
    let m = 0;
    for (let k = 0; k < 3; k++) {
      const d = a[i + k] - b[i + k];
      se += d * d;
      m = Math.max(m, Math.abs(d));
    }
    if (m > 8) changed++;
  }
  return {psnr_db: se ? 10 * Math.log10(255 * 255 / (se / (3 * n))) : 999,
          changed: changed / n};
})(window.__imxSnaps[%s], window.__imxSnaps[%s])"""


# The page's modules (index.html's import map) and whether each was fetched with status 200.
JS_MODULES = """(() => {
  const map = document.querySelector('script[type="importmap"]');
  const listed = map ? Object.values(JSON.parse(map.textContent).imports)
                           .map((u) => new URL(u, location.href).href) : [];
  const status = new Map(performance.getEntriesByType('resource')
                             .map((r) => [r.name, r.responseStatus]));
  return {listed: listed.length,
          missing: listed.filter((u) => status.get(u) !== 200).map((u) => new URL(u).pathname)};
})()"""


def snap(b, name):
    return b.evaluate(JS_SNAP % json.dumps(name))


def diff(b, a, c):
    return b.evaluate(JS_DIFF % (json.dumps(a), json.dumps(c)))


def wait_converged(b, timeout, what):
    # 'disconnected' only after the socket was once open: before, it is still connecting.
    v = b.wait_for("!window.viewerStats ? '' : viewerStats.converged ? 'converged' : "
                   "(window.imxWasConnected = window.imxWasConnected || viewerStats.connected, "
                   "viewerStats.connected || !window.imxWasConnected) ? '' : 'disconnected'",
                   timeout=timeout,
                   interval=0.03, what=f'a converged frame ({what})')
    if v == 'disconnected':
        raise Failure(f'the page lost its WebSocket connection while waiting for a converged '
                      f'frame ({what})')


def page_now(b):
    return b.evaluate('viewer.now()')


def frames_between(b, t0, t1=None):
    cond = 'f.drawn_at >= %r' % t0 + ('' if t1 is None else ' && f.drawn_at <= %r' % t1)
    return b.evaluate(f'viewerStats.frames.filter((f) => {cond})')


def objects_on_page(b):
    return b.evaluate("""[...document.querySelectorAll('.object')].map((e) => ({
      name: e.dataset.name, kind: (e.querySelector('.kind') || {}).textContent,
      visible: (e.querySelector('input.visible') || {}).checked}))""")


def canvas_png(b, path):
    url = b.evaluate("document.getElementById('view').toDataURL('image/png')")
    prefix = 'data:image/png;base64,'
    if not url or not url.startswith(prefix):
        raise Failure(f'canvas.toDataURL gave {str(url)[:60]!r}')
    with open(path, 'wb') as f:
        f.write(base64.b64decode(url[len(prefix):]))


def percentile(xs, q):
    if not xs:
        return None
    s = sorted(xs)
    pos = (len(s) - 1) * q
    lo = math.floor(pos)
    hi = min(lo + 1, len(s) - 1)
    return s[lo] + (s[hi] - s[lo]) * (pos - lo)


def rnd(x, d=1):
    return None if x is None else round(x, d)


# ---------------------------------------------------------------- HTTP and WebSocket access
def http_status(url, timeout=10):
    try:
        with urllib.request.urlopen(url, timeout=timeout) as r:
            return r.status, r.read(200000)
    except urllib.error.HTTPError as e:
        return e.code, e.read(2000)
    except (urllib.error.URLError, OSError) as e:
        return f'error: {e}', b''


def raw_http_status(host, port, target, timeout=10):
    """GET with the request target sent exactly as given (urllib would normalize some)."""
    c = http.client.HTTPConnection(host, port, timeout=timeout)
    try:
        c.request('GET', target)
        r = c.getresponse()
        return r.status, r.read(200000)
    except OSError as e:
        return f'error: {e}', b''
    finally:
        c.close()


def ws_status(url, timeout=10):
    """'open' when the upgrade succeeded, else the HTTP status of the refusal."""
    try:
        ws = websocket.create_connection(url, timeout=timeout, suppress_origin=True)
    except websocket.WebSocketBadStatusException as e:
        return e.status_code
    except Exception as e:  # noqa: BLE001
        return f'error: {type(e).__name__}: {e}'
    ws.close()
    return 'open'


def check_access(checks, base, token):
    u = urllib.parse.urlsplit(base)
    host, port = u.hostname, u.port
    ws_base = f'ws://{host}:{port}'
    ok_status, body = http_status(f'{base}/?token={token}')
    checks.check('b. GET /?token=T serves the page', ok_status == 200 and b'js/main.js' in body,
                 ok_status)
    for path, needle in (('index.html', b'js/main.js'), ('js/main.js', b'viewerStats'),
                         ('viewer.css', b'{')):
        st, body = http_status(f'{base}/{path}?token={token}')
        checks.check(f'b. GET /{path}?token=T', st == 200 and needle in body, st)
    flipped = token[:-1] + ('0' if token[-1:] != '0' else '1')
    for what, url in (('GET / without token', f'{base}/'),
                      ('GET / with a wrong token', f'{base}/?token=0{token[1:]}wrong'),
                      ('GET / with a wrong token of the same length', f'{base}/?token={flipped}'),
                      ('GET / with the token plus a character', f'{base}/?token={token}0'),
                      ('GET / with the token minus its last character',
                       f'{base}/?token={token[:-1]}'),
                      ('GET /js/main.js without token', f'{base}/js/main.js'),
                      ('GET /index.html with an empty token', f'{base}/index.html?token=')):
        status, _ = http_status(url)
        checks.check(f'b. {what} -> 403', status == 403, status)
    for what, target in (('GET /../README.md?token=T', f'/../README.md?token={token}'),
                         ('GET /%2e%2e/README.md?token=T', f'/%2e%2e/README.md?token={token}'),
                         ('GET /..%2fREADME.md?token=T', f'/..%2fREADME.md?token={token}')):
        status, body = raw_http_status(host, port, target)
        checks.check(f'b. {what} serves nothing outside web/',
                     status != 200 or b'intermix renders scenes' not in body, status)
    for what, url in (('WebSocket /ws without token', f'{ws_base}/ws'),
                      ('WebSocket /ws with a wrong token', f'{ws_base}/ws?token=x{token}')):
        status = ws_status(url)
        checks.check(f'b. {what} is refused (403)', status == 403, status)


# ---------------------------------------------------------------- test mode
def run_test(args, out, checks, cleanup):
    scene = os.path.abspath(args.scene)
    # The server saves beside the scene as NAME.viewer-N.json: the test moves its own saves away.
    saves = os.path.join(os.path.dirname(scene),
                         os.path.splitext(os.path.basename(scene))[0] + '.viewer-*.json')
    saves_before = set(glob.glob(saves))

    def move_saves():
        for f in set(glob.glob(saves)) - saves_before:
            shutil.move(f, os.path.join(out, 'saved-' + os.path.basename(f)))
    cleanup.append(move_saves)

    sargs = ['--port', '0', '--bind', '127.0.0.1', '--method', args.method or 'zslab',
             '--set', f'image.width={TEST_SIZE}', '--set', f'image.height={TEST_SIZE}',
             '--max-image-side', str(TEST_SIZE)]
    if args.spp:
        sargs += ['--spp', str(args.spp)]
    for s in args.set:
        sargs += ['--set', s]
    t_start = time.monotonic()
    server = start_server(args, scene, sargs, out, cleanup)
    browser = start_browser(args, out, cleanup)
    url = server.wait_url(60)
    log(f'server: {url}  (log: {out}/server.log; started in '
        f'{time.monotonic() - t_start:.1f} s with chromium)')
    u = urllib.parse.urlsplit(url)
    token = urllib.parse.parse_qs(u.query).get('token', [''])[0]
    base = f'{u.scheme}://{u.netloc}'
    checks.check('server prints its URL with a token', bool(token), url)

    # b. access control
    check_access(checks, base, token)

    # f. a second client watches the whole session
    watcher = Watcher(f'ws://{u.netloc}/ws?token={token}')
    cleanup.append(watcher.close)
    hello = watcher.wait(lambda t, m: m.get('type') == 'hello', 10)
    checks.check('f. second client gets hello', hello is not None,
                 'hello' if hello else 'nothing in 10 s',
                 f"objects {[o.get('name') for o in hello.get('objects', [])]}, method "
                 f"{hello.get('method')}, spp {hello.get('spp')}, image {hello.get('image')}"
                 if hello else '')

    # a. load and converge
    t0 = time.monotonic()
    browser.navigate(url, timeout=20)
    browser.wait_for('Boolean(window.viewerStats && viewerStats.connected)', timeout=10,
                     what='the page to connect its WebSocket')
    wait_converged(browser, 30, 'after load')
    load_s = time.monotonic() - t0
    last = browser.evaluate('viewerStats.lastFrame')
    checks.check('a. page loads and converges', last and last.get('final'),
                 f'{load_s:.2f} s',
                 f"{last.get('width')}x{last.get('height')} {last.get('format')} "
                 f"{last.get('samples')}/{last.get('spp')} spp, "
                 f"{browser.evaluate('viewerStats.framesDrawn')} frames drawn")
    # Still frames come at the view's device pixels, scaled down to --max-image-side.
    vp = browser.evaluate('viewer.viewport()') or [0, 0]
    shrink = min(1.0, TEST_SIZE / max(vp[0], vp[1], 1))
    want = [max(16, math.floor(x * shrink + 0.5)) for x in vp]
    checks.check('a. converged frame is PNG at the view\'s size (CSS x devicePixelRatio, bounded)',
                 last.get('format') == 'png' and [last.get('width'), last.get('height')] == want
                 and last.get('scale') == 1 and min(vp) > 0,
                 f"{last.get('format')} {last.get('width')}x{last.get('height')} "
                 f"scale {last.get('scale')}", f'viewport {vp}, expected {want}')
    modules = browser.evaluate(JS_MODULES)
    checks.check('a. every ES module of the import map was fetched with the token (200)',
                 modules['listed'] > 0 and not modules['missing'],
                 f"{modules['listed'] - len(modules['missing'])} of {modules['listed']}",
                 f"not loaded: {modules['missing']}" if modules['missing'] else '')
    href = browser.evaluate('location.href')
    checks.check('a. the token leaves the address bar once the page has loaded',
                 'token' not in href, href.replace(token, '<token>'))
    bars = browser.evaluate('viewer.colorBars()')
    shown = [o['name'] for o in (hello or {}).get('objects', [])
             if o.get('kind') == 'volume' and o.get('visible', True)]
    checks.check('a. a colour bar for every visible volume', bars == shown, str(bars),
                 f'visible volumes {shown}')
    # Each bar whole inside the view (its caption and labels too), over its visible range within
    # the data's (the hello's histogram ranges), never the preset's whole span.
    layout = browser.evaluate('viewer.colorBarLayout()') or []
    ranges = {name: h.get('range') for name, h in ((hello or {}).get('histograms') or {}).items()}
    inside = all(0 <= b['left'] and b['right'] <= b['width'] for b in layout)
    within = all(ranges.get(b['name']) is None or
                 (b['lo'] >= ranges[b['name']][0] - 1e-6 and b['hi'] <= ranges[b['name']][1] + 1e-6)
                 for b in layout)
    checks.check('a. colour bars lie inside the view, over the data\'s range',
                 len(layout) == len(bars) and inside and within,
                 '; '.join(f"{b['name']} [{b['lo']:g}, {b['hi']:g}] at {b['left']:.0f}-"
                           f"{b['right']:.0f} of {b['width']}" for b in layout),
                 f'data ranges {ranges}')
    browser.screenshot(os.path.join(out, 'viewer-loaded.png'))
    objects = objects_on_page(browser)
    log(f'      objects on the page: {objects}')

    # c. orbit
    view = browser.evaluate("viewer.center('#view')")
    cam0 = browser.evaluate('viewer.camera()')
    lat0 = browser.evaluate('viewerStats.latencies.length')
    t_orbit0 = time.monotonic()
    p0 = page_now(browser)
    x0, x1 = view['x'] - 0.3 * view['w'], view['x'] + 0.3 * view['w']
    browser.drag(x0, view['y'] + 10, x1, view['y'] - 10, steps=40, duration=2.0, release=False)
    p1 = page_now(browser)
    browser.release(x1, view['y'] - 10)
    wait_converged(browser, 20, 'after the orbit')
    cam1 = browser.evaluate('viewer.camera()')
    during = frames_between(browser, p0, p1)
    fps = len(during) / max(1e-9, (p1 - p0) / 1000)
    lats = browser.evaluate(f'viewerStats.latencies.slice({lat0})')
    checks.check('c. orbit drag: frames per second while moving >= 10', fps >= 10,
                 f'{fps:.1f} fps',
                 f'{len(during)} frames in {(p1 - p0) / 1000:.2f} s; scales '
                 f"{sorted(set(f['scale'] for f in during))}, formats "
                 f"{sorted(set(f['format'] for f in during))}; latency median "
                 f'{rnd(percentile(lats, 0.5))} ms, p95 {rnd(percentile(lats, 0.95))} ms')
    moved = math.dist(cam0['eye'], cam1['eye'])
    checks.check('c. orbit changed the camera', moved > 1e-3, f'eye moved {moved:.1f} mm')
    after = frames_between(browser, p0)
    full = [f for f in after if f['stages_run'] != f['stages']]
    checks.check('c. every orbit frame re-ran all stages (camera changed)', not full and after,
                 f'{len(after)} frames', f'(run, stages): {[(f["stages_run"], f["stages"]) for f in full]}')
    checks.check('c. frames during the drag are JPEG, after release PNG',
                 all(f['format'] == 'jpeg' for f in during if not f['final']) and
                 browser.evaluate('viewerStats.lastFrame.format') == 'png',
                 f"{sum(f['format'] == 'jpeg' for f in during)} jpeg of {len(during)}")

    # c2. a second window that has not seen the orbit zooms from the camera it last saw: the
    # server adds its move to the orbit, and the page takes the result once it is idle
    stale = copy.deepcopy(cam0)
    zoomed = copy.deepcopy(cam0)
    zoomed['eye'] = [t + (e - t) * 0.8 for e, t in zip(cam0['eye'], cam0['target'])]
    watcher.send(dict(zoomed, type='camera', seq=1, moving=False, **{'from': stale}))
    deadline = time.monotonic() + 10
    cam2 = cam1
    while time.monotonic() < deadline:
        browser.pump_events(0.1)
        cam2 = browser.evaluate('viewer.camera()')
        if abs(math.dist(cam2['eye'], cam2['target']) -
               0.8 * math.dist(cam1['eye'], cam1['target'])) < 1e-3:
            break

    def direction(c):
        d = [e - t for e, t in zip(c['eye'], c['target'])]
        n = math.sqrt(sum(x * x for x in d))
        return [x / n for x in d]
    turn_kept = math.dist(direction(cam2), direction(cam1))
    zoom_kept = math.dist(cam2['eye'], cam2['target']) / math.dist(cam1['eye'], cam1['target'])
    checks.check("c2. a stale window's move adds to this window's orbit (neither is lost)",
                 turn_kept < 1e-6 and abs(zoom_kept - 0.8) < 1e-6,
                 f'direction off by {turn_kept:.2g}, distance x{zoom_kept:.4f} (want 0.8)')
    wait_converged(browser, 20, 'after the second window\'s move')

    # m. the reading views: 2x2 layout, a click in the axial view moves the other crosshairs,
    # the readout reads the voxel there, the wheel steps one slice
    run_reading_views(args, checks, browser)
    # n. the 2-D views' window/level, zoom and pan, linked views, a preset's window shown
    run_reading_interaction(checks, browser, watcher)

    # d. transfer-function edit
    tfs = {o['name']: browser.evaluate(f"viewer.tfPoints({json.dumps(o['name'])})")
           for o in objects if o['kind'] == 'volume'}
    tfs = {k: v for k, v in tfs.items() if v}
    if not tfs:
        raise Failure(f'the scene has no volume with a transfer function: {objects}')
    vol, idx, score = pick_tf_point(tfs, (hello or {}).get('histograms') or {}, args.tf_volume)
    log(f'      TF point to drag: {vol} point {idx} {tfs[vol][idx]} (weight {score:.3g})')
    alpha0 = tfs[vol][idx][4]
    sel = f'.object[data-name="{vol}"] canvas.tf-editor'
    ed = browser.evaluate(f'viewer.center({json.dumps(sel)})')
    if not ed:
        raise Failure(f'no TF editor canvas for {vol} ({sel})')
    pt = browser.evaluate(f'viewer.tfPoint({json.dumps(vol)}, {idx})')
    # hovering a point shows its value
    browser.mouse('mouseMoved', pt['x'], pt['y'])
    browser.pump_events(0.2)
    hovered = browser.evaluate(f'viewer.tfHoverValue({json.dumps(vol)})')
    checks.check('d. hovering a TF point shows its value', hovered == tfs[vol][idx][0],
                 f'{hovered} (the point: {tfs[vol][idx][0]})')
    snap(browser, 'before_tf')
    p_tf = page_now(browser)
    t_tf = time.monotonic()
    dy = 0.45 * ed['h']
    shots = []

    def mid_shot(i):
        if i == 10:
            path = os.path.join(out, 'viewer-tf-edit.png')
            browser.screenshot(path)
            shots.append(path)
    browser.drag(pt['x'], pt['y'], pt['x'], pt['y'] + dy, steps=20, duration=1.0,
                 on_step=mid_shot)
    wait_converged(browser, 20, 'after the TF edit')
    snap(browser, 'after_tf')
    alpha1 = browser.evaluate(f'viewer.tfPoints({json.dumps(vol)})')[idx][4]
    checks.check('d. TF drag moved the control point', alpha1 < alpha0 - 1e-6,
                 f'{vol} point {idx}: alpha {alpha0:.3f} -> {alpha1:.3f}')
    d_tf = diff(browser, 'before_tf', 'after_tf')
    checks.check('d. TF edit changed the image', d_tf['changed'] > 0.001,
                 f"{100 * d_tf['changed']:.2f} % of pixels changed",
                 f"PSNR before/after {d_tf['psnr_db']:.1f} dB")
    fr = frames_between(browser, p_tf)
    stages = sorted(set(f['stages'] for f in fr))
    runs = [(f['stages_run'], f['stages'], f['scale'], f['samples']) for f in fr]
    ok_set = all(f['stages_run'] in (1, f['stages']) for f in fr)
    n_one = sum(1 for f in fr if f['stages_run'] == 1 and f['stages'] > 1)
    checks.check('d. TF-edit frames have stages_run in {1, stages}', ok_set and bool(fr),
                 f'{len(fr)} frames', f'stages {stages}; (run, stages, scale, samples): {runs}')
    one_ms = [f['render_ms'] for f in fr if f['stages_run'] == 1 and f['stages'] > 1]
    all_ms = [f['render_ms'] for f in fr if f['stages_run'] == f['stages'] and f['scale'] < 1]
    checks.check('d. some TF-edit frame re-ran only the edited volume (stages_run 1 < stages)',
                 n_one >= 1, f'{n_one} frames with stages_run 1',
                 f'median render {rnd(percentile(one_ms, 0.5))} ms with one stage, '
                 f'{rnd(percentile(all_ms, 0.5))} ms with all (moving frames)')

    # e. visibility
    target = next((o for o in objects if o['kind'] == 'mesh'), None) or \
        next((o for o in objects if o['name'] != vol), objects[0])
    vis_name = target['name']
    cb_sel = json.dumps(f'.object[data-name="{vis_name}"] input.visible')
    cb = browser.evaluate(f'viewer.center({cb_sel})')
    snap(browser, 'before_vis')
    t_vis = time.monotonic()
    browser.click(cb['x'], cb['y'])
    checked = browser.evaluate(f'document.querySelector({cb_sel}).checked')
    wait_converged(browser, 20, 'after the visibility toggle')
    snap(browser, 'after_vis')
    d_vis = diff(browser, 'before_vis', 'after_vis')
    checks.check(f'e. hiding {vis_name} changed the image',
                 checked is False and d_vis['changed'] > 0.001,
                 f"{100 * d_vis['changed']:.2f} % of pixels changed",
                 f"checkbox now {checked}; PSNR before/after {d_vis['psnr_db']:.1f} dB")
    browser.screenshot(os.path.join(out, 'viewer-edited.png'))

    # f. the second client saw the edits
    cam_page = browser.evaluate('viewer.camera()')
    st_orbit = [x for x in watcher.of_type('state', t_orbit0) if x[0] < t_tf]
    st_tf = watcher.wait(lambda t, m: t >= t_tf and m.get('type') == 'state' and any(
        o.get('name') == vol and _tf_alpha(o, idx) is not None and
        abs(_tf_alpha(o, idx) - alpha1) < 1e-6 for o in m.get('objects', [])), 5)
    st_vis = watcher.wait(lambda t, m: t >= t_vis and m.get('type') == 'state' and any(
        o.get('name') == vis_name and o.get('visible') is False for o in m.get('objects', [])), 5)
    states = watcher.of_type('state')
    last_state = states[-1][1] if states else {}
    cam_state = last_state.get('camera') or {}
    cam_gap = math.dist(cam_state['eye'], cam_page['eye']) if cam_state.get('eye') else None
    checks.check('f. second client got state messages after the page\'s edits',
                 len(st_orbit) >= 1 and st_tf is not None and st_vis is not None,
                 f'{len(states)} state messages',
                 f'during/after the orbit: {len(st_orbit)}; TF alpha {alpha1:.3f} seen: {st_tf is not None}; '
                 f'{vis_name} hidden seen: {st_vis is not None}')
    checks.check('f. second client\'s last state has the page\'s camera',
                 cam_gap is not None and cam_gap < 1e-3, f'eye gap {rnd(cam_gap, 6)} mm')
    frames_w = watcher.of_type('frame')
    checks.check('f. second client gets frames, each followed by its image',
                 len(frames_w) >= 1 and not watcher.violations and watcher.error is None,
                 f'{len(frames_w)} frames, {watcher.binaries} binaries',
                 '; '.join(watcher.violations[:3]) + (watcher.error or ''))

    # g. save, render the saved scene, compare with the canvas
    wait_converged(browser, 20, 'before save')
    sv = browser.evaluate("viewer.center('#save')")
    browser.click(sv['x'], sv['y'])
    saved = browser.wait_for('viewerStats.saved', timeout=10, what='the saved message')
    name = saved.get('file') or ''
    path = os.path.join(os.path.dirname(scene), name) if name else ''
    exists = bool(name) and os.sep not in name and os.path.isfile(path)
    checks.check('g. save writes a numbered scene file, named without a server path', exists,
                 name)
    if exists:
        with open(path) as f:
            doc = json.load(f)
        render = doc.get('render', {})
        log(f"      saved scene: image {doc.get('image', {}).get('width')}x"
            f"{doc.get('image', {}).get('height')}, render {render}")
        shutil.copy2(path, os.path.join(out, 'saved-scene.json'))
        ref = os.path.join(out, 'ref.png')
        canvas_file = os.path.join(out, 'canvas.png')
        canvas_png(browser, canvas_file)
        t0 = time.monotonic()
        size = browser.evaluate('[viewerStats.lastFrame.width, viewerStats.lastFrame.height]')
        r = subprocess.run([args.intermix, 'render', path, '-o', ref, '--width', str(size[0]),
                            '--height', str(size[1])], capture_output=True, text=True,
                           timeout=120)
        render_s = time.monotonic() - t0
        if r.returncode != 0:
            checks.check('g. intermix render of the saved scene', False, f'exit {r.returncode}',
                         (r.stderr or r.stdout).strip()[-500:])
        else:
            c = subprocess.run([args.intermix, 'compare', ref, canvas_file, '--json'],
                               capture_output=True, text=True, timeout=60)
            try:
                cj = json.loads(c.stdout)
                p = cj['psnr_db']
                p = math.inf if p == 'inf' else float(p)
            except (ValueError, KeyError) as e:
                p, cj = None, {'error': f'{e}: {c.stdout.strip()} {c.stderr.strip()}'}
            checks.check('g. canvas matches intermix render of the saved scene: PSNR >= 40 dB',
                         p is not None and p >= 40,
                         f'{p:.2f} dB' if p is not None else str(cj),
                         f"SSIM {cj.get('ssim')}, render {render_s:.1f} s; {ref} vs "
                         f'{canvas_file}')

    # page health
    errs = browser.evaluate('viewerStats.errors')
    browser.pump_events(0.05)
    checks.check('no server error messages and no page errors', not errs and
                 not browser.page_errors, len(errs) + len(browser.page_errors),
                 '; '.join((errs or []) + browser.page_errors)[:500])
    log(f'      screenshots: {out}/viewer-loaded.png, {out}/viewer-tf-edit.png, '
        f'{out}/viewer-edited.png')

    # the address without the token still works after a reload: the page's cookie carries it
    browser.evaluate('window.imxOldPage = true, location.reload()')
    reloaded = True
    try:
        browser.wait_for('!window.imxOldPage && Boolean(window.viewerStats && '
                         'viewerStats.connected)', timeout=10, what='the reloaded page to connect')
    except Failure:
        reloaded = False
    checks.check('a. a reload without the token in the address connects (cookie)', reloaded,
                 browser.evaluate('location.href').replace(token, '<token>'))

    # clean shutdown
    watcher.close()
    status, secs = server.stop(10)
    checks.check('server exits 0 on SIGINT', status == 0, f'status {status} after {secs:.2f} s')

    # h.-k. the MPR scene, in the same browser
    if args.mpr_scene:
        run_mpr(args, out, checks, cleanup, browser)
    # l. a multi-frame volume's frame slider and play/pause (needs ../shared/data)
    if os.path.isdir(ASL_SERIES):
        run_frames(args, out, checks, cleanup, browser)
    else:
        log(f'l. skipped: no {ASL_SERIES}')
    run_labels(args, out, checks, cleanup, browser)
    run_streamlines(args, out, checks, cleanup, browser)
    browser.close()


def run_streamlines_only(args, out, checks, cleanup):
    browser = start_browser(args, out, cleanup)
    run_streamlines(args, out, checks, cleanup, browser)
    browser.close()


def run_reading_views(args, checks, browser):
    browser.evaluate("viewer.setLayout('2x2')")
    browser.wait_for('viewer.slicesDrawn() >= 3 && viewer.readout() !== null', timeout=15,
                     what='the three 2-D views and the readout')
    drawn = browser.evaluate('viewer.slicesDrawn()')
    r = browser.evaluate("viewer.center('.slice-cell[data-axis=axial] .slice')")
    browser.click(r['x'] - 0.2 * r['w'], r['y'] - 0.15 * r['h'])
    browser.wait_for(f'viewer.slicesDrawn() >= {drawn + 2} && viewer.readout() && '
                     'JSON.stringify(viewer.readout().point) === '
                     'JSON.stringify(viewer.slicePoint()) && '
                     'Object.keys(viewer.crosshairs()).length === 3', timeout=15,
                     what='the coronal and sagittal views and the readout after the click')
    point = browser.evaluate('viewer.slicePoint()')
    marks = browser.evaluate('viewer.crosshairs()')
    readout = browser.evaluate('viewer.readout()')
    ct = readout['values'][0]
    # The CT as Python reads it (the same phantom the scene names): its voxel pitch and the
    # voxel holding the point.
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(args.intermix)), 'python'))
    import intermix  # noqa: E402 - the build's own module
    import numpy as np  # noqa: E402
    volume = intermix.phantom('ct-head', 256)
    affine = np.array(volume.lps_affine)
    pitch = [affine[a][a] for a in range(3)]
    gaps = {axis: max(abs(m[a] - point[a]) / pitch[a] for a in range(3))
            for axis, m in marks.items()}
    checks.check('m. a click in the axial view moves the coronal and sagittal crosshairs to the '
                 'same point (within half a voxel)',
                 set(marks) == {'axial', 'coronal', 'sagittal'} and
                 max(gaps.values()) <= 0.5,
                 ', '.join(f'{a} {g:.3f} voxel' for a, g in gaps.items()),
                 f'point {[round(x, 2) for x in point]}')
    index = np.rint(np.linalg.solve(affine, np.array(point + [1.0]))[:3]).astype(int).tolist()
    want = float(volume.array[index[2], index[1], index[0]])
    checks.check("m. the readout's CT value is the voxel's value there",
                 ct.get('index') == index and ct.get('value') == want,
                 f"{ct.get('value')} {ct.get('units')} at {ct.get('index')}",
                 f'Python reads {want} at {index}')
    bars = browser.evaluate('viewer.scaleBars()')
    widths = browser.evaluate("[...document.querySelectorAll('.slice-cell')].map((c) => "
                              "c.clientWidth * (window.devicePixelRatio || 1))")
    checks.check('m. each 2-D view has a scale bar of 1, 2 or 5 x 10^k mm',
                 set(bars) == {'axial', 'coronal', 'sagittal'} and
                 all(str(int(v)).strip('0') in ('1', '2', '5') for v in bars.values()),
                 str(bars), f'view widths {widths}')
    z0 = point[2]
    browser.evaluate("document.querySelector('.slice-cell[data-axis=axial] .slice')"
                     ".dispatchEvent(new WheelEvent('wheel', {deltaY: -100, bubbles: true, "
                     "cancelable: true}))")
    browser.wait_for(f'viewer.slicePoint()[2] !== {z0}', timeout=5, what='a slice step')
    z1 = browser.evaluate('viewer.slicePoint()')[2]
    checks.check('m. a wheel step in the axial view moves one slice', abs(z1 - z0 - pitch[2]) < 1e-9,
                 f'{z1 - z0:.4f} mm (the slice pitch is {pitch[2]} mm)')
    # Cine: the axial slices go by at the rate set (10 a second, for 2 s), wrapping at the end.
    browser.evaluate("viewer.cine('axial', 10)")
    time.sleep(2.0)
    cine = browser.evaluate('viewer.cineState()') or {}
    browser.evaluate('viewer.cine(null)')
    rate = cine.get('steps', 0) / max(cine.get('ms', 1) / 1000, 1e-3)
    moved = browser.evaluate('viewer.slicePoint()')[2] != z1
    checks.check('m. cine steps the axial slices at the rate set (within 10%)',
                 abs(rate - 10) <= 1.0 and moved and browser.evaluate('viewer.cineState()') is None,
                 f"{cine.get('steps')} slices in {cine.get('ms', 0) / 1000:.2f} s: {rate:.2f} a second",
                 'asked 10')
    # latency of 2-D interactions (input to the last view showing it): 10 clicks, 10 steps
    browser.wait_for('viewer.slicesSettled()', timeout=10, what='the views to show the step')
    lat0 = len(browser.evaluate('viewer.sliceLatencies()'))
    for i in range(10):
        browser.click(r['x'] + (0.03 * i - 0.15) * r['w'], r['y'] + (0.02 * i - 0.1) * r['h'])
        browser.wait_for('viewer.slicesSettled()', timeout=10, what='a crosshair move')
        browser.evaluate("document.querySelector('.slice-cell[data-axis=coronal] .slice')"
                         ".dispatchEvent(new WheelEvent('wheel', {deltaY: 100, bubbles: true, "
                         "cancelable: true}))")
        browser.wait_for('viewer.slicesSettled()', timeout=10, what='a slice step')
    lats = browser.evaluate('viewer.sliceLatencies()')[lat0:]
    checks.check('m. 2-D view interactions (crosshair, slice step): median latency measured',
                 len(lats) == 20, f'median {rnd(percentile(lats, 0.5))} ms, p95 '
                 f'{rnd(percentile(lats, 0.95))} ms over {len(lats)}')
    browser.evaluate("viewer.setLayout('1x1')")

    # the snap buttons: each turns the 3-D camera to look from that side of the patient (LPS)
    wanted = {'A': [0, -1, 0], 'P': [0, 1, 0], 'L': [1, 0, 0], 'R': [-1, 0, 0], 'S': [0, 0, 1],
              'I': [0, 0, -1]}
    got = {}
    for name, d in wanted.items():
        b = browser.evaluate(f"viewer.center('#snap button[data-view={name}]')")
        browser.click(b['x'], b['y'])
        browser.wait_for(f"(() => {{ const c = viewer.camera(); const v = c.eye.map((e, i) => "
                         f"e - c.target[i]); const n = Math.hypot(...v); return "
                         f"v.every((x, i) => Math.abs(x / n - {d}[i]) < 1e-6); }})()",
                         timeout=5, what=f'the {name} view')
        c = browser.evaluate('viewer.camera()')
        n = math.dist(c['eye'], c['target'])
        got[name] = [round((e - t) / n, 6) for e, t in zip(c['eye'], c['target'])]
    checks.check('m. the six snap buttons look from A, P, L, R, S and I',
                 all(got[k] == [float(x) for x in v] for k, v in wanted.items()), str(got))
    wait_converged(browser, 20, 'after the snap views')

    # copy link: the address of this view without the token; opened, it shows the same view
    browser.evaluate("viewer.setLayout('2x2')")
    link = browser.evaluate('viewer.viewLink()')
    cam = browser.evaluate('viewer.camera()')
    # (the link differs from the address only by its fragment: load it anew)
    browser.evaluate(f'window.imxOldPage = true, location.href = {json.dumps(link)}, '
                     'location.reload()')
    browser.wait_for("!window.imxOldPage && window.viewerStats && viewerStats.connected && "
                     "document.getElementById('layout').value === '2x2'", timeout=10,
                     what='the linked view')
    browser.wait_for('viewer.camera() !== null', timeout=5, what='the camera')
    cam2 = browser.evaluate('viewer.camera()')
    checks.check('m. copy link: no token in it, and opened it shows the same camera and layout',
                 'token' not in link and math.dist(cam['eye'], cam2['eye']) < 1e-6,
                 f"eye moved {math.dist(cam['eye'], cam2['eye']):.2g} mm", link[:80] + '...')
    browser.evaluate("viewer.setLayout('1x1')")
    wait_converged(browser, 20, 'after the linked view')


# The page's rules (web/js/slices.js): W/L drags scale the width by exp(0.005) per CSS pixel
# right and move the centre by width / 256 per pixel down; ctrl+wheel zooms by exp(0.0015) per
# pixel of deltaY (up: in).
WL_WIDTH_RATE, WL_LEVEL_STEPS, WHEEL_ZOOM_RATE = 0.005, 256, 0.0015


def dragged_window(w0, dx, dy):
    return [w0[0] + dy * max(abs(w0[1]), 1e-3) / WL_LEVEL_STEPS,
            max(1e-6, w0[1] * math.exp(dx * WL_WIDTH_RATE))]


def slice_views_settled(browser, what, cond='true'):
    """Each shown 2-D view's last image, once none waits for one and `cond` (JavaScript over
    `v`, the views) holds."""
    browser.wait_for("(() => { const v = viewer.sliceViews(); return Object.keys(v).length === 3 "
                     f"&& Object.values(v).every((x) => !x.pending) && ({cond}); }})()",
                     timeout=15, what=what)
    return browser.evaluate('viewer.sliceViews()')


def wheel(browser, axis, delta_y, **mods):
    flags = ', '.join(f'{k}: true' for k in mods)
    browser.evaluate(f"""(() => {{ const el = document.querySelector(
      '.slice-cell[data-axis={axis}] .slice'); const r = el.getBoundingClientRect();
      el.dispatchEvent(new WheelEvent('wheel', {{deltaY: {delta_y}, clientX: r.left + r.width / 2,
        clientY: r.top + r.height / 2, bubbles: true, cancelable: true, {flags}}})); }})()""")


def close_to(a, b, rel=1e-9):
    return a is not None and b is not None and len(a) == len(b) and \
        all(abs(x - y) <= rel * max(1.0, abs(y)) for x, y in zip(a, b))


def panel_window(browser, volume):
    """The 2-D window the panel shows in a volume's box."""
    sel = json.dumps(f'.object[data-name="{volume}"] .slice-window')
    return browser.evaluate(f'(document.querySelector({sel}) || {{}}).textContent')


def run_reading_interaction(checks, browser, watcher):
    browser.evaluate("viewer.setLayout('2x2')")
    v0 = slice_views_settled(browser, 'the three 2-D views')
    base = browser.evaluate('viewer.sliceWindow()')
    point0 = browser.evaluate('viewer.slicePoint()')
    cells = {a: browser.evaluate(f"viewer.center('.slice-cell[data-axis={a}] .slice')")
             for a in ('axial', 'coronal', 'sagittal')}
    checks.check('n. the 2-D views start at the base volume\'s window (the initial-window rule)',
                 base and base['window'] and
                 all(close_to(v['window'], base['window']) for v in v0.values()),
                 f"{base and base['name']}: {base and [rnd(x, 1) for x in base['window']]}",
                 (base or {}).get('note') or 'no note')

    # n1. window/level: a right drag in the axial view, a ctrl+drag in the coronal view, a drag
    # in W/L mode in the sagittal view; each changes the window by the page's rule, in every
    # view and in the scene's state, and leaves the crosshair where it was.
    lat0 = len(browser.evaluate("viewer.inputLatencies('wl')"))
    drags = [('axial', 'right', 0, False, 60, -30), ('coronal', 'left', browser.CTRL, False, -40, 25),
             ('sagittal', 'left', 0, True, 30, 40)]
    for axis, button, mods, mode, dx, dy in drags:
        w0 = browser.evaluate('viewer.sliceWindow()')['window']
        want = dragged_window(w0, dx, dy)
        if mode:
            browser.key('w')
        c = cells[axis]
        t0 = time.monotonic()
        browser.drag(c['x'], c['y'], c['x'] + dx, c['y'] + dy, steps=12, duration=0.4,
                     button=button, modifiers=mods)
        if mode:
            browser.key('w')
        views = slice_views_settled(
            browser, f'the W/L drag in the {axis} view',
            f"Object.values(v).every((x) => x.window && Math.abs(x.window[1] - {want[1]}) < "
            f"1e-6 * {want[1]})")
        st = settled_state(watcher, t0)
        doc = (state_object(st, base['name']) or {}).get('window')
        label = panel_window(browser, base['name'])
        point = browser.evaluate('viewer.slicePoint()')
        how = {'right': 'right drag', 'left': 'ctrl+drag' if mods else 'W/L mode drag'}[button]
        checks.check(f'n. a {how} in the {axis} view sets the 2-D window by the drag '
                     f'({dx:+d}, {dy:+d}) px, in every view and the scene; no crosshair move',
                     all(close_to(v['window'], want) for v in views.values()) and
                     close_to(doc, want) and point == point0 and
                     label == f'2-D window · W {want[1]:.0f} / L {want[0]:.0f}',
                     f'{[rnd(x, 2) for x in w0]} -> {[rnd(x, 2) for x in views[axis]["window"]]} '
                     f'(want {[rnd(x, 2) for x in want]})',
                     f'scene {doc}; panel {label!r}; crosshair moved '
                     f'{math.dist(point, point0):.3g} mm')
    wl_lat = browser.evaluate("viewer.inputLatencies('wl')")[lat0:]

    # n2. zoom: ctrl+wheel up in the axial view by 200 px zooms it in by exp(0.3), alone;
    # shift+wheel down by 100 in the coronal view zooms it out by exp(-0.15)
    lat0 = len(browser.evaluate("viewer.inputLatencies('zoom')"))
    before = slice_views_settled(browser, 'the views before zooming')
    wheel(browser, 'axial', -200, ctrlKey=True)
    after = slice_views_settled(browser, 'the zoomed axial view',
                                f"v.axial.mm_per_pixel !== {before['axial']['mm_per_pixel']}")
    ratio = {a: before[a]['mm_per_pixel'] / after[a]['mm_per_pixel'] for a in after}
    checks.check('n. ctrl+wheel (deltaY -200) zooms the axial view in by exp(0.3), alone',
                 abs(ratio['axial'] - math.exp(0.3)) < 1e-9 and ratio['coronal'] == 1 and
                 ratio['sagittal'] == 1,
                 f"mm per pixel x1/{ratio['axial']:.6f} (want {math.exp(0.3):.6f})",
                 f'the others x{ratio["coronal"]}, x{ratio["sagittal"]}')
    before = after
    wheel(browser, 'coronal', 100, shiftKey=True)
    after = slice_views_settled(browser, 'the zoomed coronal view',
                                f"v.coronal.mm_per_pixel !== {before['coronal']['mm_per_pixel']}")
    r = after['coronal']['mm_per_pixel'] / before['coronal']['mm_per_pixel']
    checks.check('n. shift+wheel (deltaY +100) zooms the coronal view out by exp(0.15)',
                 abs(r - math.exp(0.15)) < 1e-9, f'mm per pixel x{r:.6f}',
                 f'want {math.exp(0.15):.6f}')
    zoom_lat = browser.evaluate("viewer.inputLatencies('zoom')")[lat0:]

    # n3. pan: a middle drag in the axial view moves its image with the pointer: the view's
    # centre moves by minus the drag in mm (right is +x, down is +y in LPS), its zoom kept.
    before = after
    c, dx, dy = cells['axial'], 50, -20
    mm = before['axial']['mm_per_css_px']
    want = [-dx * mm[0], -dy * mm[1], 0.0]
    browser.drag(c['x'], c['y'], c['x'] + dx, c['y'] + dy, steps=10, duration=0.3,
                 button='middle')
    x_want = before['axial']['point'][0] + want[0]
    try:  # the release's image (a loaded machine may still be drawing the last move's)
        slice_views_settled(browser, 'the panned axial view',
                            f'Math.abs(v.axial.point[0] - {x_want}) < 1e-6')
    except Failure:
        pass
    after = browser.evaluate('viewer.sliceViews()')
    moved = [a - b for a, b in zip(after['axial']['point'], before['axial']['point'])]
    checks.check('n. a middle drag pans the axial view by the dragged amount',
                 all(abs(m - w) < 1e-6 for m, w in zip(moved, want)) and
                 after['axial']['mm_per_pixel'] == before['axial']['mm_per_pixel'],
                 f'centre moved {[rnd(x, 3) for x in moved]} mm',
                 f'want {[rnd(x, 3) for x in want]} ({dx}, {dy}) px at {rnd(mm[0], 4)}, '
                 f'{rnd(mm[1], 4)} mm/px')

    # n3b. a two-finger pinch (touch events) in the sagittal view: the fingers from 40 to 80 px
    # apart about a fixed midpoint zoom it in by 2
    before = slice_views_settled(browser, 'the views before the pinch')
    browser.send('Emulation.setTouchEmulationEnabled', {'enabled': True, 'maxTouchPoints': 5})
    c = cells['sagittal']

    def touch(kind, half):
        points = [] if kind == 'touchEnd' else [{'x': c['x'] - half, 'y': c['y'], 'id': 1},
                                                {'x': c['x'] + half, 'y': c['y'], 'id': 2}]
        browser.send('Input.dispatchTouchEvent', {'type': kind, 'touchPoints': points})
    touch('touchStart', 20)
    for k in range(1, 11):
        touch('touchMove', 20 + 2 * k)
        time.sleep(0.03)
    touch('touchEnd', 40)
    browser.send('Emulation.setTouchEmulationEnabled', {'enabled': False})
    after = slice_views_settled(browser, 'the pinched sagittal view',
                                f"v.sagittal.zoom !== {before['sagittal']['zoom']}")
    r = before['sagittal']['mm_per_pixel'] / after['sagittal']['mm_per_pixel']
    # (touch points land on whole pixels: the midpoint may be half a pixel off the centre)
    shift = math.dist(after['sagittal']['point'], before['sagittal']['point'])
    checks.check('n. a pinch from 40 to 80 px zooms the sagittal view in by 2 about its midpoint',
                 abs(r - 2) < 1e-9 and shift <= max(before['sagittal']['mm_per_css_px']),
                 f'mm per pixel x1/{r:.6f}', f'the centre moved {shift:.3g} mm')
    before = after

    # n4. linked: the three views take the last zoomed or panned one's (the sagittal) zoom, and
    # zoom together
    b = browser.evaluate("viewer.center('#link-views')")
    browser.click(b['x'], b['y'])
    zoom_a = after['sagittal']['zoom']  # the view zoomed last
    linked = slice_views_settled(browser, 'the linked views',
                                 f'Object.values(v).every((x) => x.zoom === {zoom_a})')
    wheel(browser, 'sagittal', -100, ctrlKey=True)
    both = slice_views_settled(browser, 'the linked zoom', 'Object.values(v).every((x, i, a) => '
                               f"x.zoom !== {zoom_a})")
    ratios = {a: linked[a]['mm_per_pixel'] / both[a]['mm_per_pixel'] for a in both}
    checks.check('n. linked views: a ctrl+wheel in one zooms all three by exp(0.15)',
                 all(abs(x - math.exp(0.15)) < 1e-9 for x in ratios.values()),
                 ', '.join(f'{a} x{x:.6f}' for a, x in ratios.items()))
    browser.click(b['x'], b['y'])
    rb = browser.evaluate("viewer.center('#reset-view')")
    browser.click(rb['x'], rb['y'])
    reset = slice_views_settled(browser, 'the views reset',
                                'Object.values(v).every((x) => x.zoom === 1)')
    checks.check('n. "reset view" fits the 2-D views again',
                 all(abs(reset[a]['mm_per_pixel'] - v0[a]['mm_per_pixel']) < 1e-12 and
                     close_to(reset[a]['point'], v0[a]['point']) for a in reset),
                 str({a: rnd(x['mm_per_pixel'], 4) for a, x in reset.items()}))

    # n5. a W/L preset: the views, the scene and the panel show the preset's window
    t0 = time.monotonic()
    browser.evaluate("(() => { const s = document.getElementById('wl-preset'); s.value = 'bone'; "
                     "s.dispatchEvent(new Event('change')); })()")
    views = slice_views_settled(browser, 'the bone preset',
                                'Object.values(v).every((x) => x.window[1] === 1800)')
    doc = (state_object(settled_state(watcher, t0), base['name']) or {}).get('window')
    label = panel_window(browser, base['name'])
    checks.check('n. the bone preset: the views, the scene and the panel show W 1800 / L 400',
                 all(v['window'] == [400, 1800] for v in views.values()) and
                 doc == [400, 1800] and label == '2-D window · W 1800 / L 400',
                 f'panel {label!r}', f'scene {doc}')
    # n6. screenshots as shown: the layout at the display's pixel ratio, the axial view at 2x
    dpr = browser.evaluate('window.devicePixelRatio || 1')
    area = browser.evaluate("viewer.center('#view-area')")
    cell = browser.evaluate("viewer.center('.slice-cell[data-axis=axial]')")
    shot = browser.evaluate("viewer.capture('layout')")
    one = browser.evaluate("viewer.capture('axial', 2)")
    want_l = [round(area['w'] * dpr), round(area['h'] * dpr)]
    want_a = [round(cell['w'] * 2), round(cell['h'] * 2)]
    checks.check("n. a layout screenshot has the layout's size (x the pixel ratio), a 2x one of "
                 'the axial view twice its size, both drawn',
                 shot and one and [shot['width'], shot['height']] == want_l and
                 [one['width'], one['height']] == want_a and shot['lit'] > 0.05 and
                 one['lit'] > 0.05,
                 f"layout {shot and [shot['width'], shot['height']]} (want {want_l}), axial "
                 f"{one and [one['width'], one['height']]} (want {want_a})",
                 f"lit {shot and rnd(shot['lit'], 3)}, {one and rnd(one['lit'], 3)}")
    checks.check('n. 2-D W/L and zoom latency (input to the last view showing it) measured',
                 len(wl_lat) >= 3 and len(zoom_lat) >= 2,
                 f'W/L median {rnd(percentile(wl_lat, 0.5))} ms, p95 '
                 f'{rnd(percentile(wl_lat, 0.95))} ms over {len(wl_lat)}; zoom '
                 f'{[rnd(x) for x in zoom_lat]} ms')
    browser.evaluate("viewer.setLayout('1x1')")
    wait_converged(browser, 20, 'after the 2-D interactions')


# ---------------------------------------------------------------- test mode: streamlines
def write_tck(path, count=200):
    """A tractogram of `count` straight streamlines along y (RAS mm, MRtrix .tck), over x in
    [-30, 30] at z = 0, each from y = -30 to 30 in 31 points: green when coloured by direction."""
    import struct
    header = f'mrtrix tracks\ndatatype: Float32LE\ncount: {count}\nfile: . '
    offset = len(header) + 16
    header = (header + f'{offset}\nEND\n').ljust(offset, '\0')
    with open(path, 'wb') as f:
        f.write(header.encode())
        for i in range(count):
            x = -30 + 60 * i / (count - 1)
            for k in range(31):
                f.write(struct.pack('<3f', x, -30 + 2 * k, 0))
            f.write(struct.pack('<3f', math.nan, math.nan, math.nan))
        f.write(struct.pack('<3f', math.inf, math.inf, math.inf))


# Of the 3-D canvas (or a 2-D view's canvas, by selector): pixels mostly red, mostly green, any
# drawn (brighter than the background), and their mean brightness.
JS_TINTS = """((sel) => {
  const c = document.querySelector(sel);
  const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
  let red = 0, green = 0, drawn = 0, sum = 0;
  for (let i = 0; i < d.length; i += 4) {
    const r = d[i], g = d[i + 1], b = d[i + 2];
    if (r + g + b < 40) continue;
    drawn++;
    sum += r + g + b;
    if (r > g + 50 && r > b + 50) red++;  // highlights make it pink, not white
    if (g > r + 50 && g > b + 50) green++;
  }
  return {red, green, drawn, mean: drawn ? sum / drawn / 3 : 0};
})(%s)"""


def tints(b, sel='#view'):
    return b.evaluate(JS_TINTS % json.dumps(sel))


def set_control(b, name, cls, value, events=('input', 'change')):
    """Sets a panel control of object `name` (a select, colour or range input) as the user does,
    firing its events."""
    sel = json.dumps(f'.object[data-name="{name}"] .{cls}')
    ok = b.evaluate(f"""(() => {{ const e = document.querySelector({sel}); if (!e) return false;
      if (e.type === 'checkbox') e.checked = {json.dumps(bool(value))};
      else e.value = {json.dumps(value)};
      for (const t of {json.dumps(list(events))}) e.dispatchEvent(new Event(t, {{bubbles: true}}));
      return true; }})()""")
    if not ok:
        raise Failure(f'no control .{cls} for {name} in the panel')


def run_streamlines(args, out, checks, cleanup, browser):
    """s. A tractogram over a volume whose transfer function shows nothing (the 2-D views' base):
    the panel's colour mode and colour make the tubes red; an axial view through the streamlines'
    plane shows them in red, a slice 8 mm away does not; the panel's stride and opacity thin and
    darken the tubes; its sphere region at the crosshair keeps only the streamlines through it."""
    write_tck(os.path.join(out, 'lines.tck'))
    write_label_nrrd(os.path.join(out, 'base.nrrd'))
    scene = os.path.join(out, 'streamlines.json')
    with open(scene, 'w') as f:
        json.dump({'camera': {'eye': [0, 0, 160], 'target': [0, 0, 0], 'up': [0, -1, 0]},
                   'image': {'width': 128, 'height': 128, 'background': [0, 0, 0, 1]},
                   'objects': [{'name': 'base', 'type': 'volume', 'source': {'file': 'base.nrrd'},
                                'transfer_function': {'points': [[0, 0, 0, 0, 0],
                                                                 [7, 0, 0, 0, 0]]}},
                               {'name': 'lines', 'type': 'streamlines',
                                'source': {'file': 'lines.tck'}, 'radius': 0.6}]}, f)
    _, url, watcher, hello = serve_small(args, scene, os.path.join(out, 'server-streamlines.log'),
                                         cleanup)
    lines = state_object(hello or {}, 'lines') or {}
    checks.check('s. hello describes the streamlines (count, colour mode, stride)',
                 lines.get('count') == 200 and lines.get('color_by') == 'direction' and
                 lines.get('stride') == 1, json.dumps({k: lines.get(k) for k in
                                                       ('count', 'color_by', 'stride')}))
    browser.navigate(url, timeout=20)
    browser.wait_for('Boolean(window.viewerStats && viewerStats.connected)', timeout=10,
                     what='the streamlines page to connect its WebSocket')
    wait_converged(browser, 30, 'streamlines scene after load')
    before = tints(browser)
    snap(browser, 'sl_direction')
    set_control(browser, 'lines', 'sl-color-by', 'fixed', ('change',))
    browser.wait_for("Boolean(document.querySelector('.object[data-name=\"lines\"] .sl-color'))",
                     timeout=5, what='the colour control of fixed colouring')
    t0 = time.monotonic()  # before the change: the watcher may get its final frame first
    set_control(browser, 'lines', 'sl-color', '#ff0000', ('input',))
    wait_converged(browser, 20, 'after fixed red')
    st = settled_state(watcher, t0)
    red = tints(browser)
    o = state_object(st, 'lines') or {}
    checks.check('s. colour mode "fixed" and a red colour from the panel make the tract red '
                 '(it was green by direction)',
                 o.get('color_by') == 'fixed' and o.get('color') == [1, 0, 0] and
                 before['green'] > 0.8 * before['drawn'] and red['red'] > 0.8 * red['drawn'] and red['drawn'] > 200,
                 f"red {red['red']} of {red['drawn']} drawn pixels",
                 f"before: green {before['green']} of {before['drawn']}; state {o.get('color_by')} "
                 f"{o.get('color')}")
    snap(browser, 'sl_red')
    canvas_png(browser, os.path.join(out, 'streamlines-red.png'))
    browser.screenshot(os.path.join(out, 'viewer-streamlines.png'))
    # The 2-D views: the crosshair starts at the base volume's centre, z = 0: the lines' plane.
    browser.evaluate("viewer.setLayout('2x2')")
    browser.wait_for('viewer.slicesDrawn() >= 3', timeout=15, what='the three 2-D views')
    browser.wait_for('viewer.slicesSettled()', timeout=10, what='the 2-D views')
    axial = '.slice-cell[data-axis=axial] .slice'
    browser.pump_events(0.5)
    at_plane = tints(browser, axial)
    point = browser.evaluate('viewer.slicePoint()')
    drawn = browser.evaluate('viewer.slicesDrawn()')
    for _ in range(2):  # two 4 mm slice steps: 8 mm from the lines, beyond the 2 mm slab
        browser.evaluate(f"document.querySelector({json.dumps(axial)})"
                         ".dispatchEvent(new WheelEvent('wheel', {deltaY: -100, bubbles: true, "
                         "cancelable: true}))")
        browser.wait_for('viewer.slicesSettled()', timeout=10, what='a slice step')
    browser.wait_for(f'viewer.slicesDrawn() >= {drawn + 2}', timeout=10, what='the stepped views')
    browser.pump_events(0.5)
    away = tints(browser, axial)
    point2 = browser.evaluate('viewer.slicePoint()')
    browser.screenshot(os.path.join(out, 'viewer-streamlines-slices.png'))
    checks.check('s. the axial view through the streamlines shows them in their colour (red); '
                 '8 mm away it shows none',
                 point and abs(point[2]) < 1e-6 and at_plane['red'] > 100 and away['red'] == 0 and
                 abs(point2[2]) >= 7.9,
                 f"red pixels {at_plane['red']} at z = {point[2] if point else None}, "
                 f"{away['red']} at z = {point2[2] if point2 else None}")
    browser.evaluate("viewer.setLayout('1x1')")
    wait_converged(browser, 20, 'back to the 3-D view alone')
    t0 = time.monotonic()
    set_control(browser, 'lines', 'sl-stride', '10')
    wait_converged(browser, 20, 'after stride 10')
    st = settled_state(watcher, t0)
    strided = tints(browser)
    o = state_object(st, 'lines') or {}
    checks.check('s. stride 10 from the panel draws about a tenth of the streamlines',
                 o.get('stride') == 10 and strided['drawn'] < 0.5 * red['drawn'],
                 f"{strided['drawn']} drawn pixels (was {red['drawn']})",
                 f"state stride {o.get('stride')}")
    opacity_sel = '.object[data-name="lines"] .row input[type=range]'  # the first: opacity
    t0 = time.monotonic()
    ok = browser.evaluate(f"""(() => {{ const e = document.querySelector({json.dumps(opacity_sel)});
      if (!e) return false; e.value = '0.3';
      for (const t of ['input', 'change']) e.dispatchEvent(new Event(t, {{bubbles: true}}));
      return true; }})()""")
    if not ok:
        raise Failure('no opacity slider for the streamlines')
    wait_converged(browser, 20, 'after opacity 0.3')
    st = settled_state(watcher, t0)
    faint = tints(browser)
    o = state_object(st, 'lines') or {}
    checks.check('s. opacity 0.3 from the panel darkens the tubes over the black background',
                 o.get('opacity') == 0.3 and faint['mean'] < 0.75 * strided['mean'],
                 f"mean brightness {faint['mean']:.1f} (was {strided['mean']:.1f})",
                 f"state opacity {o.get('opacity')}")
    snap(browser, 'sl_faint')
    # A sphere region at the crosshair (8 mm above the lines' centre, 10 mm radius): only the
    # streamlines within 6 mm of x = 0 pass through it.
    t0 = time.monotonic()
    set_control(browser, 'lines', 'sl-region-on', True, ('change',))
    wait_converged(browser, 20, 'after the sphere region')
    st = settled_state(watcher, t0)
    regions = (state_object(st, 'lines') or {}).get('regions') or []
    passing = tints(browser)
    checks.check('s. a sphere region at the crosshair from the panel keeps only the streamlines '
                 'through it',
                 len(regions) == 1 and regions[0].get('shape') == 'sphere' and
                 regions[0].get('radius') == 10 and passing['drawn'] < 0.5 * faint['drawn'] and
                 passing['drawn'] > 0,
                 f"{passing['drawn']} drawn pixels (was {faint['drawn']})", json.dumps(regions))
    browser.evaluate("viewer.setLayout('1x1')")
    watcher.close()


# ---------------------------------------------------------------- test mode: MPR planes and clips
def settled_state(watcher, since, timeout=30.0):
    """The watcher's last `state` once it has a final frame received after `since` (the server
    broadcasts the state of an input before any frame that shows it, so that state is in).
    30 s: under the whole suite's load (-j2 on two cores) a still frame with covered tube
    silhouettes took more than the 10 s this waited before."""
    f = watcher.wait(lambda t, m: t >= since and m.get('type') == 'frame' and m.get('final'),
                     timeout)
    if f is None:
        raise Failure(f'the second client got no final frame within {timeout:.0f} s')
    states = watcher.of_type('state')
    return states[-1][1] if states else {}


def state_object(state, name):
    return next((o for o in (state or {}).get('objects', []) if o.get('name') == name), None)


def camera_gap(a, b):
    """The largest difference of any coordinate of eye, target and up, and of fov_deg."""
    if not a or not b:
        return math.inf
    g = abs(a['fov_deg'] - b['fov_deg'])
    for k in ('eye', 'target', 'up'):
        g = max(g, max(abs(x - y) for x, y in zip(a[k], b[k])))
    return g


ASL_SERIES = os.path.join(os.path.dirname(REPO), 'shared', 'data', 'dicom4d', 'xa30-asl-25')


def serve_small(args, scene, log_path, cleanup):
    """Starts intermix serve on a small scene (zslab, 1 spp, frames of at most TEST_SIZE) and a
    watching WebSocket; returns the server, the page's address, the watcher and its hello."""
    server = Server(args.intermix, scene, ['--port', '0', '--bind', '127.0.0.1', '--method',
                                           'zslab', '--spp', '1', '--max-image-side',
                                           str(TEST_SIZE)], log_path, os.getcwd())
    server.start()
    cleanup.append(server.kill)
    url = server.wait_url(60)
    u = urllib.parse.urlsplit(url)
    token = urllib.parse.parse_qs(u.query).get('token', [''])[0]
    watcher = Watcher(f'ws://{u.netloc}/ws?token={token}')
    cleanup.append(watcher.close)
    return server, url, watcher, watcher.wait(lambda t, m: m.get('type') == 'hello', 10)


def run_frames(args, out, checks, cleanup, browser):
    """A 7-frame ASL series (MIP) beside a phantom: play steps through the frames, each change
    re-runs only the ASL volume's stage, pause stops it."""
    scene = os.path.join(out, 'frames.json')
    with open(scene, 'w') as f:
        json.dump({'camera': {'eye': [0, 600, 40], 'target': [0, 0, 40], 'up': [0, 0, 1]},
                   'image': {'width': 128, 'height': 128},
                   'objects': [{'name': 'asl', 'type': 'volume', 'source': {'file': ASL_SERIES},
                                'style': 'mip',
                                'transfer_function': {'points': [[0, 0, 0, 0, 0],
                                                                 [1500, 1, 1, 1, 1]]}},
                               {'name': 'head', 'type': 'volume',
                                'source': {'phantom': 'ct-head', 'size': 48},
                                'transfer_function': {'preset': 'ct-bone'}}]}, f)
    server, url, watcher, hello = serve_small(args, scene, os.path.join(out, 'server-frames.log'),
                                              cleanup)
    asl = state_object(hello or {}, 'asl') or {}
    checks.check('l. hello gives the ASL volume its 7 frames', asl.get('frames') == 7,
                 f"frames {asl.get('frames')}, frame {asl.get('frame')}")
    browser.navigate(url, timeout=20)
    browser.wait_for('Boolean(window.viewerStats && viewerStats.connected)', timeout=10,
                     what='the frames page to connect its WebSocket')
    wait_converged(browser, 30, 'frames scene after load')
    snap(browser, 'frames_before_play')
    play_sel = json.dumps('.object[data-name="asl"] .frame-play')
    play = browser.evaluate(f'viewer.center({play_sel})')
    if not play:
        raise Failure('no play button for the multi-frame volume asl')
    p0 = page_now(browser)
    t0 = time.monotonic()
    browser.click(play['x'], play['y'])
    browser.pump_events(2.5)
    browser.click(play['x'], play['y'])  # pause
    wait_converged(browser, 20, 'after play and pause')
    snap(browser, 'frames_after_play')
    seen = sorted({(state_object(m, 'asl') or {}).get('frame') for t, m in
                   watcher.of_type('state', t0)} - {None})
    checks.check('l. play steps the frame (state messages with 2 or more frames)', len(seen) >= 2,
                 f'frames seen {seen}')
    fr = frames_between(browser, p0)
    partial = [f for f in fr if f['stages_run'] < f['stages']]
    checks.check('l. a frame change re-runs only that volume\'s stage (stages_run < stages)',
                 bool(partial), f'{len(partial)} of {len(fr)} frames',
                 f"(run, stages): {[(f['stages_run'], f['stages']) for f in fr][:12]}")
    d = diff(browser, 'frames_before_play', 'frames_after_play')
    checks.check('l. another frame changed the image', d['changed'] > 0.0005,
                 f"{100 * d['changed']:.2f} % of pixels changed")
    t_paused = time.monotonic()
    states = watcher.of_type('state')
    after = (state_object(states[-1][1], 'asl') or {}).get('frame') if states else None
    browser.pump_events(1.0)
    still = [(state_object(m, 'asl') or {}).get('frame')
             for t, m in watcher.of_type('state', t_paused)]
    checks.check('l. pause stops the frames', all(f in (None, after) for f in still),
                 f'frame {after} after pause; later states {still}')
    watcher.close()
    status, secs = server.stop(10)
    checks.check('frames server exits 0 on SIGINT', status == 0, f'status {status}')


def write_label_nrrd(path):
    """A 24^3 label volume (4 mm voxels): background 0, a block of label 2 beside one of 7."""
    n = 24
    data = bytearray(n * n * n)
    for z in range(6, 18):
        for y in range(6, 18):
            for x in range(4, 20):
                data[(z * n + y) * n + x] = 2 if x < 12 else 7
    with open(path, 'wb') as f:
        f.write(f'NRRD0004\ntype: uint8\ndimension: 3\nspace: left-posterior-superior\n'
                f'sizes: {n} {n} {n}\nspace directions: (4,0,0) (0,4,0) (0,0,4)\n'
                f'space origin: (-46,-46,-46)\nencoding: raw\n\n'.encode())
        f.write(bytes(data))


def run_labels(args, out, checks, cleanup, browser):
    """m2. A label volume beside a phantom: the panel lists the labels its voxels hold with the
    table's names; unticking one hides it in the state and the image, re-running only that
    volume's stage."""
    write_label_nrrd(os.path.join(out, 'seg.nrrd'))
    scene = os.path.join(out, 'labels.json')
    with open(scene, 'w') as f:
        json.dump({'camera': {'eye': [0, -400, 0], 'target': [0, 0, 0], 'up': [0, 0, 1]},
                   'image': {'width': 128, 'height': 128},
                   'objects': [{'name': 'seg', 'type': 'volume', 'source': {'file': 'seg.nrrd'},
                                'style': 'labels',
                                'labels': {'table': [{'value': 2, 'name': 'liver',
                                                      'color': [0.8, 0.3, 0.2]},
                                                     {'value': 7, 'name': 'spleen',
                                                      'color': [0.2, 0.4, 0.9]}]}},
                               {'name': 'head', 'type': 'volume',
                                'source': {'phantom': 'ct-head', 'size': 32},
                                'transfer_function': {'preset': 'ct-bone'},
                                'transform': {'translate': [0, 150, 0]}}]}, f)
    _, url, watcher, hello = serve_small(args, scene, os.path.join(out, 'server-labels.log'),
                                         cleanup)
    listed = [(x['value'], x['name'], x['visible'])
              for x in (state_object(hello or {}, 'seg') or {}).get('labels') or []]
    checks.check('m2. hello lists the labels the voxels hold, named by the table',
                 listed == [(0, 'label 0', False), (2, 'liver', True), (7, 'spleen', True)],
                 str(listed))
    browser.navigate(url, timeout=20)
    browser.wait_for('Boolean(window.viewerStats && viewerStats.connected)', timeout=10,
                     what='the labels page to connect its WebSocket')
    wait_converged(browser, 30, 'labels scene after load')
    snap(browser, 'labels_before')
    box = json.dumps('.object[data-name="seg"] .row.label[data-value="7"] input[type=checkbox]')
    at = browser.evaluate(f'viewer.center({box})')
    if not at:
        raise Failure('no checkbox for label 7 in the panel')
    p0 = page_now(browser)
    t0 = time.monotonic()
    browser.click(at['x'], at['y'])
    wait_converged(browser, 20, 'after hiding a label')
    snap(browser, 'labels_after')
    st = settled_state(watcher, t0)
    shown = {x['value']: x['visible'] for x in (state_object(st, 'seg') or {}).get('labels') or []}
    fr = frames_between(browser, p0)
    d = diff(browser, 'labels_before', 'labels_after')
    checks.check('m2. unticking a label hides it (state), changes the image and re-runs only the '
                 'label volume\'s stage',
                 shown.get(7) is False and shown.get(2) is True and d['changed'] > 0.001 and
                 any(f['stages_run'] < f['stages'] for f in fr),
                 f"{100 * d['changed']:.2f} % of pixels changed",
                 f"labels {shown}; (run, stages): {[(f['stages_run'], f['stages']) for f in fr]}")
    watcher.close()


def run_mpr(args, out, checks, cleanup, browser):
    """The MPR scene (a CT with three planes) at 256x256, zslab: window/level by ctrl+drag, a
    plane's position slider, a clip plane added and moved by alt+drag, reset view."""
    scene = os.path.abspath(args.mpr_scene)
    sargs = ['--port', '0', '--bind', '127.0.0.1', '--method', 'zslab',
             '--set', f'image.width={TEST_SIZE}', '--set', f'image.height={TEST_SIZE}',
             '--max-image-side', str(TEST_SIZE)]
    if args.spp:
        sargs += ['--spp', str(args.spp)]
    t_start = time.monotonic()
    server = start_server(args, scene, sargs, out, cleanup, log='server-mpr.log')
    url = server.wait_url(60)
    log(f'mpr server: {url}  (log: {out}/server-mpr.log; started in '
        f'{time.monotonic() - t_start:.1f} s)')
    u = urllib.parse.urlsplit(url)
    token = urllib.parse.parse_qs(u.query).get('token', [''])[0]
    watcher = Watcher(f'ws://{u.netloc}/ws?token={token}')
    cleanup.append(watcher.close)
    hello = watcher.wait(lambda t, m: m.get('type') == 'hello', 10)
    if hello is None:
        raise Failure('the second client of the MPR server got no hello in 10 s')
    # MPR planes: planes that sample a volume (a plain colored plane has no window to set)
    planes = [o for o in hello.get('objects', []) if o.get('kind') == 'plane' and o.get('volume')]
    if not planes:
        raise Failure(f'{args.mpr_scene} has no plane of a volume: '
                      f'{[o.get("name") for o in hello.get("objects", [])]}')

    errors_before = len(browser.page_errors)
    t0 = time.monotonic()
    browser.navigate(url, timeout=20)
    browser.wait_for('Boolean(window.viewerStats && viewerStats.connected)', timeout=10,
                     what='the MPR page to connect its WebSocket')
    wait_converged(browser, 30, 'MPR scene after load')
    last = browser.evaluate('viewerStats.lastFrame')
    checks.check('h. MPR page loads and converges', last and last.get('final'),
                 f'{time.monotonic() - t0:.2f} s',
                 f"{args.mpr_scene}: {last.get('width')}x{last.get('height')}, "
                 f"{last.get('stages')} stages, planes {[p['name'] for p in planes]}")
    view = browser.evaluate("viewer.center('#view')")

    # h. window/level: click the last MPR plane's radio (the default is the first plane's),
    # ctrl+drag right
    wl = planes[-1]
    radio_sel = json.dumps(f'.object[data-name="{wl["name"]}"] input[type=radio]')
    rb = browser.evaluate(f'viewer.center({radio_sel})')
    if not rb:
        raise Failure(f'no W/L radio button for plane {wl["name"]}')
    browser.click(rb['x'], rb['y'])
    radio_on = browser.evaluate(f'document.querySelector({radio_sel}).checked')
    snap(browser, 'mpr_before_wl')
    win0 = list(wl['window'])
    dx = 0.18 * view['w']
    x0, y = view['x'] - 0.3 * view['w'], view['y'] + 0.1 * view['h']
    p_wl = page_now(browser)
    t_wl0 = time.monotonic()
    browser.drag(x0, y, x0 + dx, y, steps=20, duration=0.8, modifiers=browser.CTRL)
    t_wl1 = time.monotonic()
    wait_converged(browser, 20, 'after the W/L drag')
    snap(browser, 'mpr_after_wl')
    st = settled_state(watcher, t_wl1)
    win1 = (state_object(st, wl['name']) or {}).get('window')
    label_sel = json.dumps(f'.object[data-name="{wl["name"]}"] .wl-label')
    label = browser.evaluate(f'(document.querySelector({label_sel}) || {{}}).textContent')
    # the page: width * exp(0.005 per pixel right), centre + (pixels down) * width / 256
    want = win0[1] * math.exp(0.005 * dx)
    wl_states = [m for t, m in watcher.of_type('state', t_wl0)
                 if (state_object(m, wl['name']) or {}).get('window') not in (None, win0)]
    checks.check(f'h. ctrl+drag set {wl["name"]}\'s window width (W/L)',
                 radio_on is True and win1 is not None and abs(win1[0] - win0[0]) < 1e-6 and
                 abs(win1[1] - want) < 0.02 * want,
                 f'window {win0} -> {[rnd(v, 1) for v in win1] if win1 else None}',
                 f'radio checked {radio_on}; expected width {want:.1f} for {dx:.0f} px; '
                 f'{len(wl_states)} state messages with a changed window; page: {label!r}')
    d = diff(browser, 'mpr_before_wl', 'mpr_after_wl')
    checks.check('h. W/L drag changed the image', d['changed'] > 0.001,
                 f"{100 * d['changed']:.2f} % of pixels changed",
                 f"PSNR before/after {d['psnr_db']:.1f} dB")
    fr = frames_between(browser, p_wl)
    one = [f for f in fr if f['stages_run'] < f['stages']]
    checks.check('h. some W/L frame re-ran only part of the stages (stages_run < stages)',
                 len(one) >= 1, f'{len(one)} of {len(fr)} frames',
                 f"(run, stages, scale): "
                 f"{[(f['stages_run'], f['stages'], f['scale']) for f in fr]}")

    # h2. the bone preset: the selected plane's window, and its label in the panel at once
    t_pre = time.monotonic()
    browser.evaluate("(() => { const s = document.getElementById('wl-preset'); s.value = 'bone'; "
                     "s.dispatchEvent(new Event('change')); })()")
    label = browser.evaluate(f'(document.querySelector({label_sel}) || {{}}).textContent')
    wait_converged(browser, 20, 'after the bone preset')
    win2 = (state_object(settled_state(watcher, t_pre), wl['name']) or {}).get('window')
    checks.check(f"h. the bone preset sets {wl['name']}'s window and its label shows it",
                 win2 == [400, 1800] and label == 'W/L target · W 1800 / L 400',
                 f'panel {label!r}', f'window {win2}')

    # i. the first MPR plane's position slider: drag its thumb left
    pl = planes[0]
    slider_sel = json.dumps(f'.object[data-name="{pl["name"]}"] > .row[data-control="position"] > '
                            'input[type=range]')
    sl = browser.evaluate(f'viewer.center({slider_sel})')
    if not sl:
        raise Failure(f'no position slider for plane {pl["name"]}')
    c0 = list((state_object(st, pl['name']) or pl)['center'])
    normal = pl['normal']
    nlen = math.sqrt(sum(v * v for v in normal)) or 1.0
    normal = [v / nlen for v in normal]
    # The thumb sits at the slider's value (0 = the middle, as the scene placed the plane).
    v0 = float(browser.evaluate(f'document.querySelector({slider_sel}).value'))
    snap(browser, 'mpr_before_pos')
    t_pos0 = time.monotonic()
    browser.drag(sl['x'], sl['y'], sl['x'] - 0.15 * sl['w'], sl['y'], steps=12, duration=0.6)
    t_pos1 = time.monotonic()
    v1 = float(browser.evaluate(f'document.querySelector({slider_sel}).value'))
    wait_converged(browser, 20, 'after the position slider')
    snap(browser, 'mpr_after_pos')
    st = settled_state(watcher, t_pos1)
    c1 = (state_object(st, pl['name']) or {}).get('center')
    moved = [a - b for a, b in zip(c1, c0)] if c1 else None
    along = sum(m * n for m, n in zip(moved, normal)) if moved else None
    off_normal = math.dist(moved, [along * n for n in normal]) if moved else None
    pos_states = [m for t, m in watcher.of_type('state', t_pos0)
                  if (state_object(m, pl['name']) or {}).get('center') not in (None, c0)]
    checks.check(f'i. position slider moved {pl["name"]} along its normal',
                 moved is not None and abs(along) > 1.0 and off_normal < 1e-6 and
                 abs(along - (v1 - v0)) < 1e-6,
                 f'center {c0} -> {[rnd(v, 2) for v in c1] if c1 else None}',
                 f'{rnd(along, 2)} mm along the normal, slider {v0:g} -> {v1:.3f}; '
                 f'{len(pos_states)} state messages with a moved center')
    d = diff(browser, 'mpr_before_pos', 'mpr_after_pos')
    checks.check('i. position slider changed the image', d['changed'] > 0.001,
                 f"{100 * d['changed']:.2f} % of pixels changed",
                 f"PSNR before/after {d['psnr_db']:.1f} dB")

    # j. a clip plane: "add clip plane" in the plane's volume's box, then alt+drag down (the
    # clip, through the target facing the view, moves toward the eye)
    vol = pl['volume']
    clips_before = list((state_object(st, vol) or {}).get('clip_planes') or [])
    # the last row of a volume's box
    add_sel = json.dumps(f'.object[data-name="{vol}"] > .row:last-child > button')
    add = browser.evaluate(f'viewer.center({add_sel})')
    add_text = browser.evaluate(f'(document.querySelector({add_sel}) || {{}}).textContent')
    if add_text != 'add clip plane':
        add = None
    if not add:
        raise Failure(f'no "add clip plane" button for volume {vol}')
    t_add = time.monotonic()
    browser.click(add['x'], add['y'])
    wait_converged(browser, 20, 'after adding a clip plane')
    st = settled_state(watcher, t_add)
    clips0 = list((state_object(st, vol) or {}).get('clip_planes') or [])
    snap(browser, 'mpr_before_clip')
    p_clip = page_now(browser)
    dy = 0.12 * view['h']
    cx, cy = view['x'] + 0.05 * view['w'], view['y']
    browser.drag(cx, cy, cx, cy + dy, steps=12, duration=0.6, modifiers=browser.ALT)
    t_clip1 = time.monotonic()
    wait_converged(browser, 20, 'after the clip drag')
    snap(browser, 'mpr_after_clip')
    st = settled_state(watcher, t_clip1)
    clips1 = list((state_object(st, vol) or {}).get('clip_planes') or [])
    moved_clips = [(a, b) for a, b in zip(clips0, clips1)
                   if math.dist(a['point'], b['point']) > 1e-6]
    same_normals = all(math.dist(a['normal'], b['normal']) < 1e-9 for a, b in zip(clips0, clips1))
    # The page moves the clip along its normal by -(pixels down) * mm per pixel at the target.
    cam = browser.evaluate('viewer.camera()')
    mm_px = (2 * math.dist(cam['eye'], cam['target']) *
             math.tan(math.radians(cam['fov_deg']) / 2) / view['h'])
    want = -dy * mm_px
    along = off_normal = None
    if len(moved_clips) == 1:
        a, b = moved_clips[0]
        n = a['normal']
        nn = math.sqrt(sum(v * v for v in n)) or 1.0
        mv = [q - p for p, q in zip(a['point'], b['point'])]
        along = sum(m * v / nn for m, v in zip(mv, n))
        off_normal = math.dist(mv, [along * v / nn for v in n])
    checks.check(f'j. "add clip plane" then alt+drag moved one clip plane of {vol}',
                 len(clips0) == len(clips_before) + 1 and len(clips1) == len(clips0) and
                 along is not None and abs(along - want) < 0.02 * abs(want) and
                 off_normal < 1e-6 and same_normals,
                 f'moved {rnd(along, 2)} mm along its normal' if along is not None else
                 f'{len(moved_clips)} planes moved',
                 f'expected {want:.2f} mm for {dy:.0f} px; clip planes {len(clips_before)} -> '
                 f'{len(clips0)} (added) -> {len(clips1)}; point moved: '
                 f'{[[[rnd(v, 2) for v in c["point"]] for c in ab] for ab in moved_clips][:2]}')
    d = diff(browser, 'mpr_before_clip', 'mpr_after_clip')
    fr = frames_between(browser, p_clip)
    checks.check('j. clip drag changed the image', d['changed'] > 0.001,
                 f"{100 * d['changed']:.2f} % of pixels changed",
                 f"PSNR before/after {d['psnr_db']:.1f} dB; (run, stages) of its frames: "
                 f"{sorted(set((f['stages_run'], f['stages']) for f in fr))}")
    browser.screenshot(os.path.join(out, 'viewer-mpr-edited.png'))
    run_clip_handles(browser, watcher, checks, vol)

    # k. orbit, then "reset view"
    init = hello.get('initial_camera') or hello.get('camera')
    cam_a = browser.evaluate('viewer.camera()')
    browser.drag(view['x'] - 0.2 * view['w'], view['y'], view['x'] + 0.1 * view['w'],
                 view['y'] - 0.1 * view['h'], steps=6, duration=0.3)
    t_orbit1 = time.monotonic()
    wait_converged(browser, 20, 'after the orbit')
    cam_b = browser.evaluate('viewer.camera()')
    settled_state(watcher, t_orbit1)  # the orbit's final frame is in before reset is clicked
    rv = browser.evaluate("viewer.center('#reset-view')")
    t_reset = time.monotonic()
    browser.click(rv['x'], rv['y'])
    wait_converged(browser, 20, 'after reset view')
    cam_c = browser.evaluate('viewer.camera()')
    st = settled_state(watcher, t_reset)
    gap_page = camera_gap(cam_c, init)
    gap_state = camera_gap(st.get('camera'), init)
    checks.check('k. "reset view" after an orbit restores the initial camera (1e-6)',
                 math.dist(cam_a['eye'], cam_b['eye']) > 1.0 and gap_page <= 1e-6 and
                 gap_state <= 1e-6,
                 f'gap {gap_page:.3g} (page), {gap_state:.3g} (state)',
                 f"the orbit moved the eye {math.dist(cam_a['eye'], cam_b['eye']):.1f} mm; "
                 f"gap of the camera at load {camera_gap(cam_a, init):.3g}")

    errs = browser.evaluate('viewerStats.errors')
    browser.pump_events(0.05)
    page_errs = browser.page_errors[errors_before:]
    checks.check('MPR: no server error messages and no page errors',
                 not errs and not page_errs and not watcher.violations and
                 watcher.error is None,
                 len(errs) + len(page_errs) + len(watcher.violations),
                 '; '.join((errs or []) + page_errs + watcher.violations)[:500] +
                 (watcher.error or ''))
    watcher.close()
    status, secs = server.stop(10)
    checks.check('MPR server exits 0 on SIGINT', status == 0,
                 f'status {status} after {secs:.2f} s')


def pick_tf_point(tfs, histograms, only=None):
    """The control point whose alpha weighs on the most voxels: alpha times the voxels under
    its tent (the histogram's counts weighted by the point's interpolation weight). Without a
    histogram, the most opaque point."""
    best = (None, None, -1.0)
    for name, pts in tfs.items():
        if only and name != only:
            continue
        h = histograms.get(name) or {}
        counts, rng = h.get('counts') or [], h.get('range') or [0, 0]
        for i, p in enumerate(pts):
            if p[4] <= 0:
                continue
            lo = pts[i - 1][0] if i > 0 else p[0]
            hi = pts[i + 1][0] if i + 1 < len(pts) else p[0]
            w = 0.0
            if counts and rng[1] > rng[0]:
                bw = (rng[1] - rng[0]) / len(counts)
                for k, n in enumerate(counts):
                    v = rng[0] + (k + 0.5) * bw
                    if lo < v <= p[0] and p[0] > lo:
                        w += n * (v - lo) / (p[0] - lo)
                    elif p[0] < v < hi:
                        w += n * (hi - v) / (hi - p[0])
                    elif v == p[0]:
                        w += n
            else:
                w = 1.0
            score = p[4] * w
            if score > best[2]:
                best = (name, i, score)
    if best[0] is None:
        raise Failure(f'no transfer-function point with alpha > 0 in {sorted(tfs)}')
    return best


def _tf_alpha(o, idx):
    tf = o.get('transfer_function')
    pts = tf.get('points') if isinstance(tf, dict) else tf
    try:
        return float(pts[idx][4])
    except (TypeError, IndexError, ValueError):
        return None


def clip_offset_change(before, after):
    """How far the one clip plane that moved went along its normal, mm (None unless one did)."""
    moved = [(a, b) for a, b in zip(before, after) if math.dist(a['point'], b['point']) > 1e-6]
    if len(moved) != 1 or len(before) != len(after):
        return None
    a, b = moved[0]
    return sum((q - p) * n for p, q, n in zip(a['point'], b['point'], a['normal']))


def run_clip_handles(browser, watcher, checks, vol):
    """j2/j3. The clip plane's outline has a handle in the 3-D view and in each 2-D view it
    crosses; dragging a handle moves the plane along its normal by the drag's distance."""
    handles = browser.evaluate('viewer.clipHandles()')
    h3 = [h for h in handles['view3d'] if h['volume'] == vol]
    st = settled_state(watcher, time.monotonic() - 60)
    clips0 = list((state_object(st, vol) or {}).get('clip_planes') or [])
    if not h3:
        checks.check('j2. the clip plane has a handle in the 3-D view', False, 'none drawn')
        return
    h = h3[-1]
    cam = browser.evaluate('viewer.camera()')
    view = browser.evaluate("viewer.center('#view')")
    # The plane faces the camera (added so), so the handle takes the vertical drag: down moves
    # it toward the viewer by the mm a pixel spans at the handle's depth.
    fwd = [t - e for t, e in zip(cam['target'], cam['eye'])]
    fn = math.sqrt(sum(v * v for v in fwd))
    depth = sum((p - e) * f / fn for p, e, f in zip(h['point'], cam['eye'], fwd))
    mm_px = 2 * depth * math.tan(math.radians(cam['fov_deg']) / 2) / view['h']
    dy = 25
    t0 = time.monotonic()
    browser.drag(h['x'], h['y'], h['x'], h['y'] + dy, steps=8, duration=0.4)
    wait_converged(browser, 20, 'after the 3-D handle drag')
    clips1 = list((state_object(settled_state(watcher, t0), vol) or {}).get('clip_planes') or [])
    along = clip_offset_change(clips0, clips1)
    want = -dy * mm_px
    checks.check('j2. dragging the clip plane\'s 3-D handle moves it along its normal',
                 along is not None and abs(along - want) < 0.03 * abs(want) + 0.05,
                 f'{rnd(along, 2)} mm', f'expected {want:.2f} mm for {dy} px at depth '
                 f'{depth:.0f} mm; handles {len(h3)}')

    browser.evaluate("viewer.setLayout('2x2')")
    browser.wait_for("Object.keys(viewer.clipHandles().slices).length === 3 && "
                     "Object.values(viewer.clipHandles().slices).some((v) => v.handles.length)",
                     timeout=10, what='the 2-D views with the clip plane\'s lines')
    slices = browser.evaluate('viewer.clipHandles().slices')
    crossing = {a: v for a, v in slices.items() if v['handles']}
    axis, v = next(iter(crossing.items()))
    hh = v['handles'][0]
    frame = {'axial': ([1, 0, 0], [0, 1, 0]), 'coronal': ([1, 0, 0], [0, 0, -1]),
             'sagittal': ([0, 1, 0], [0, 0, -1])}[axis]
    normal = clips1[hh['index']]['normal']
    dx, dy = 12, 18
    want = sum((dx * r + dy * d) * n for r, d, n in zip(frame[0], frame[1], normal)) * v['mm_per_px']
    t0 = time.monotonic()
    browser.drag(hh['x'], hh['y'], hh['x'] + dx, hh['y'] + dy, steps=8, duration=0.4)
    wait_converged(browser, 20, 'after the 2-D handle drag')
    clips2 = list((state_object(settled_state(watcher, t0), vol) or {}).get('clip_planes') or [])
    along = clip_offset_change(clips1, clips2)
    # The plane facing the camera's view is parallel to one 2-D view (no line there) and crosses
    # the other two.
    checks.check('j3. each 2-D view the clip plane crosses draws its line with a handle; '
                 'dragging it moves the plane by the drag\'s part along its normal',
                 len(crossing) >= 1 and along is not None and abs(along - want) < 0.03 * abs(want) + 0.05
                 and abs(want) > 0.5,
                 f'{rnd(along, 2)} mm in the {axis} view',
                 f'expected {want:.2f} mm; views with a line: {sorted(crossing)}; handle {hh}, '
                 f'{v["mm_per_px"]:.3f} mm/px, normal {[rnd(x, 3) for x in normal]}')
    browser.evaluate("viewer.setLayout('1x1')")
    wait_converged(browser, 20, 'back to the 3-D layout')

    # j4. undo and redo (Ctrl+Z, Ctrl+Shift+Z): the 2-D drag is one step, back and forth, and
    # the server ends where the page is.
    def clips_after(keys, modifiers):
        t0 = time.monotonic()
        browser.key(keys, modifiers)
        wait_converged(browser, 20, f'after {keys}')
        return list((state_object(settled_state(watcher, t0), vol) or {}).get('clip_planes')
                    or [])
    depth = browser.evaluate('viewer.historyDepth()')
    undone = clips_after('z', browser.CTRL)
    redone = clips_after('z', browser.CTRL | browser.SHIFT)
    same = lambda a, b: len(a) == len(b) and all(
        math.dist(x['point'], y['point']) < 1e-6 for x, y in zip(a, b))
    checks.check('j4. Ctrl+Z undoes the last edit (the 2-D handle drag) in one step and '
                 'Ctrl+Shift+Z redoes it; the server agrees',
                 depth['undo'] >= 3 and same(undone, clips1) and same(redone, clips2),
                 f"history {depth['undo']} steps",
                 f'undo gave {[rnd(c["point"][0], 2) for c in undone]}, expected '
                 f'{[rnd(c["point"][0], 2) for c in clips1]}; redo gave '
                 f'{[rnd(c["point"][0], 2) for c in redone]}, expected '
                 f'{[rnd(c["point"][0], 2) for c in clips2]}')


# ---------------------------------------------------------------- measure mode
def run_measure(args, out, cleanup):
    scene = os.path.abspath(args.scene)
    sargs = ['--port', '0', '--bind', '127.0.0.1', '--max-image-side', str(args.max_image_side)]
    if args.method:
        sargs += ['--method', args.method]
    if args.spp:
        sargs += ['--spp', str(args.spp)]
    for s in args.set:
        sargs += ['--set', s]
    server = start_server(args, scene, sargs, out, cleanup)
    browser = start_browser(args, out, cleanup)
    url = server.wait_url(60)
    print(f'server: {url}', file=sys.stderr, flush=True)
    browser.navigate(url, timeout=30)
    wait_converged(browser, 120, 'after load')
    first = browser.evaluate('viewerStats.lastFrame')
    view = browser.evaluate("viewer.center('#view')")
    per = []
    all_lat, moving_frames, moving_s, moving_meta = [], 0, 0.0, []
    moving_lat, release_lat, release_meta = [], [], []
    for i in range(args.measure):
        sign = 1 if i % 2 == 0 else -1
        cx, cy = view['x'], view['y'] + (i % 5 - 2) * 0.05 * view['h']
        xa, xb = cx - sign * 0.08 * view['w'], cx + sign * 0.08 * view['w']
        lat0 = browser.evaluate('viewerStats.latencies.length')
        p0 = page_now(browser)
        browser.drag(xa, cy, xb, cy, steps=8, duration=0.3, release=False)
        p1 = browser.evaluate('(viewer.startRecording(viewer.now()), viewer.now())')
        browser.release(xb, cy)
        t_rel = time.monotonic()
        converged = False
        while time.monotonic() < t_rel + args.settle:
            if browser.evaluate('viewerStats.converged'):
                converged = True
                break
            time.sleep(0.02)
        settled_in = converged
        if not converged:  # keep recording until it converges, so the times hold for every drag
            try:
                wait_converged(browser, 30, f'after drag {i}')
                converged = True
            except CdpError:
                pass
        rec = browser.evaluate("""viewer.finishRecording().map((r) => Object.assign(r,
            {psnr_db: Number.isFinite(r.psnr_db) ? r.psnr_db : 999}))""")
        lats = browser.evaluate(f'viewerStats.latencies.slice({lat0})')
        mf = frames_between(browser, p0, p1)
        still = [f for f in frames_between(browser, p1) if f.get('format') == 'png']
        if still:  # the release's frame: where its latency goes
            release_meta.append((still[0]['render_ms'], still[0]['encode_ms'],
                                 still[0]['drawn_at'] - p1))
        n_moving = len(mf)
        moving_meta += [(f['scale'], f['render_ms'], f['encode_ms']) for f in mf]
        # The psnr of a recorded frame is against the last one recorded: the converged frame
        # when it converged (and the recording, at most 256 frames, did not fill up).
        valid = converged and len(rec) < 256 and rec and rec[-1]['final']
        t40 = next((r['t_ms'] for r in rec if r['psnr_db'] >= 40), None) if valid else None
        t_final = next((r['t_ms'] for r in rec if r['final']), None) if valid else None
        per.append({'drag': i, 'converged': bool(converged),
                    'converged_within_settle': settled_in, 'moving_frames': n_moving,
                    'moving_ms': rnd(p1 - p0), 'latencies_ms': [rnd(x) for x in lats],
                    'time_to_40db_ms': rnd(t40), 'time_to_final_ms': rnd(t_final),
                    'frames_after_release': len(rec)})
        all_lat += lats
        # The last latency of a drag is the release's (the first full-resolution frame); the
        # others are of inputs sent while moving.
        moving_lat += lats[:-1]
        release_lat += lats[-1:]
        moving_frames += n_moving
        moving_s += (p1 - p0) / 1000
    t40s = [p['time_to_40db_ms'] for p in per if p['time_to_40db_ms'] is not None]
    finals = [p['time_to_final_ms'] for p in per if p['time_to_final_ms'] is not None]
    fps_each = [p['moving_frames'] / (p['moving_ms'] / 1000) for p in per if p['moving_ms']]
    summary = {
        'scene': args.scene, 'method': first.get('method') or args.method,
        'image': [first.get('width'), first.get('height')], 'spp': first.get('spp'),
        'drags': args.measure, 'drag': '8 moves over 300 ms, then release',
        'settle_s': args.settle,
        'converged_within_settle': sum(p['converged_within_settle'] for p in per),
        'converged_drags': sum(p['converged'] for p in per),
        'latency_ms': {'median': rnd(percentile(all_lat, 0.5)),
                       'p95': rnd(percentile(all_lat, 0.95)), 'n': len(all_lat)},
        'moving_latency_ms': {'median': rnd(percentile(moving_lat, 0.5)),
                              'p95': rnd(percentile(moving_lat, 0.95)), 'n': len(moving_lat)},
        'release_latency_ms': {'median': rnd(percentile(release_lat, 0.5)),
                               'p95': rnd(percentile(release_lat, 0.95)),
                               'n': len(release_lat)},
        'release_frame': {
            'render_ms_median': rnd(percentile([m[0] for m in release_meta], 0.5)),
            'encode_ms_median': rnd(percentile([m[1] for m in release_meta], 0.5)),
            'drawn_after_release_ms_median': rnd(percentile([m[2] for m in release_meta], 0.5))},
        'moving_fps': {'overall': rnd(moving_frames / moving_s if moving_s else None),
                       'median_per_drag': rnd(percentile(fps_each, 0.5))},
        'moving_frame': {'scale_median': rnd(percentile([m[0] for m in moving_meta], 0.5), 3),
                         'render_ms_median': rnd(percentile([m[1] for m in moving_meta], 0.5)),
                         'encode_ms_median': rnd(percentile([m[2] for m in moving_meta], 0.5))},
        'time_to_40db_ms': {'median': rnd(percentile(t40s, 0.5)),
                            'p95': rnd(percentile(t40s, 0.95)), 'n': len(t40s)},
        'time_to_final_ms': {'median': rnd(percentile(finals, 0.5)),
                             'p95': rnd(percentile(finals, 0.95)), 'n': len(finals)},
        'cores': os.cpu_count(),
        'per_drag': per,
    }
    method = browser.evaluate("document.getElementById('method').value")
    summary['method'] = method or summary['method']
    browser.close()
    server.stop(10)
    text = json.dumps(summary, indent=1)
    with open(os.path.join(out, 'measure.json'), 'w') as f:
        f.write(text + '\n')
    short = {k: v for k, v in summary.items() if k != 'per_drag'}
    print(json.dumps(short, indent=1), flush=True)
    return 0


JS_DIAGNOSIS = """({
  url: location.href, readyState: document.readyState,
  connection: (document.getElementById('connection') || {}).textContent,
  status: (document.getElementById('status') || {}).textContent,
  stats: window.viewerStats ? Object.assign({}, viewerStats, {frames: viewerStats.frames.length,
                                                             latencies: viewerStats.latencies.length})
                            : null,
  resources: performance.getEntriesByType('resource').map((r) => [r.name.replace(/token=\\w+/, 'token=T'),
                                                                  Math.round(r.duration), r.responseStatus]),
})"""


def run_measure_2d(args, out, cleanup):
    """The 2-D views' latency (input event to the last view drawn showing it) on the scene as it
    is, 2x2 layout: N right drags of 10 moves over 0.5 s (window/level) and N ctrl+wheel steps
    (zoom), alternating directions and views."""
    sargs = ['--port', '0', '--bind', '127.0.0.1', '--max-image-side', str(args.max_image_side)]
    for s in args.set:
        sargs += ['--set', s]
    server = start_server(args, os.path.abspath(args.scene), sargs, out, cleanup)
    browser = start_browser(args, out, cleanup)
    url = server.wait_url(120)
    print(f'server: {url}', file=sys.stderr, flush=True)
    browser.navigate(url, timeout=30)
    wait_converged(browser, 120, 'after load')
    browser.evaluate("viewer.setLayout('2x2')")
    slice_views_settled(browser, 'the three 2-D views')
    sizes = {a: browser.evaluate(f"viewer.center('.slice-cell[data-axis={a}] .slice')")
             for a in ('axial', 'coronal', 'sagittal')}
    for i in range(args.measure_2d):
        axis = ('axial', 'coronal', 'sagittal')[i % 3]
        c, sign = sizes[axis], 1 if i % 2 == 0 else -1
        browser.drag(c['x'], c['y'], c['x'] + sign * 40, c['y'] + sign * 20, steps=10,
                     duration=0.5, button='right')
        slice_views_settled(browser, 'a W/L drag')
        wheel(browser, axis, -sign * 100, ctrlKey=True)
        slice_views_settled(browser, 'a zoom step')
    wl, zoom = (browser.evaluate(f"viewer.inputLatencies('{k}')") for k in ('wl', 'zoom'))
    views = browser.evaluate('viewer.sliceViews()')
    timings = browser.evaluate('viewer.sliceTimings()')
    parts = {f'{fmt}_{k}': rnd(percentile([t[k] for t in timings if t['format'] == fmt], 0.5))
             for fmt in ('png', 'jpeg')
             for k in ('render_ms', 'encode_ms', 'round_trip_ms', 'decode_ms')}
    result = {'per_image_median': parts, 'scene': args.scene, 'views': {a: [round(sizes[a]['w']), round(sizes[a]['h'])]
                                             for a in sizes},
              'dpr': browser.evaluate('window.devicePixelRatio'),
              'wl': {'n': len(wl), 'median_ms': rnd(percentile(wl, 0.5)),
                     'p95_ms': rnd(percentile(wl, 0.95))},
              'zoom': {'n': len(zoom), 'median_ms': rnd(percentile(zoom, 0.5)),
                       'p95_ms': rnd(percentile(zoom, 0.95))},
              'mm_per_pixel': {a: rnd(v['mm_per_pixel'], 4) for a, v in views.items()},
              'load': os.getloadavg()[0]}
    print(json.dumps(result))
    with open(os.path.join(out, 'measure-2d.json'), 'w') as f:
        json.dump(result, f, indent=1)
    return 0


def diagnose(cleanup, out):
    """After a failure: what the page shows, and a screenshot of it."""
    owners = [getattr(fn, '__self__', None) for fn in cleanup]
    server = next((o for o in reversed(owners) if isinstance(o, Server)), None)
    if server and server.proc:
        status = server.proc.poll()
        log(f"      server: {'running' if status is None else f'exited with status {status}'}; "
            f'its log ends:\n{tail(server.log_path, 600)}')
    browser = next((o for o in owners if isinstance(o, cdp.Browser)), None)
    if browser is None or browser.ws is None:
        return
    try:
        signal.alarm(20)
        log(f'      page state: {json.dumps(browser.evaluate(JS_DIAGNOSIS, timeout=5))}')
        if browser.page_errors:
            log(f'      page errors: {browser.page_errors[:5]}')
        browser.screenshot(os.path.join(out, 'failure.png'), timeout=5)
        log(f'      screenshot of the failure: {out}/failure.png')
    except Exception as e:  # noqa: BLE001 - a diagnosis must not hide the failure
        log(f'      (no page diagnosis: {type(e).__name__}: {e})')
    finally:
        signal.alarm(0)


# ---------------------------------------------------------------- main
def start_server(args, scene, server_args, out, cleanup, log='server.log', cwd=None):
    """`intermix serve SCENE` with `server_args`, logging to OUT/LOG, killed at the run's end."""
    server = Server(args.intermix, scene, server_args, os.path.join(out, log), cwd or os.getcwd())
    server.start()
    cleanup.append(server.kill)
    return server


def start_browser(args, out, cleanup):
    """Headless Chromium logging to OUT/chromium.log, closed at the run's end."""
    browser = cdp.Browser(chromium=args.chromium, log_path=os.path.join(out, 'chromium.log'))
    cleanup.append(browser.close)
    browser.start()
    return browser


def preflight(args, browser=True):
    """What every browser test checks before it starts: websocket-client, Chromium (unless
    `browser` is false) and args.intermix, made absolute. None to go on, else the exit status
    (SKIP when a Debian package is missing)."""
    if websocket is None:
        print('SKIP: the python websocket module is missing (apt-get install python3-websocket)')
        return SKIP
    if browser and not cdp.find_chromium(args.chromium):
        print('SKIP: chromium is not installed (apt-get install chromium)')
        return SKIP
    if not (os.path.isfile(args.intermix) and os.access(args.intermix, os.X_OK)):
        print(f'error: {args.intermix} is not an executable program', file=sys.stderr)
        return 2
    args.intermix = os.path.abspath(args.intermix)
    return None


def output_folder(args, prefix):
    """args.out made absolute and created, or a new temporary folder (kept)."""
    out = os.path.abspath(args.out) if args.out else tempfile.mkdtemp(prefix=prefix)
    os.makedirs(out, exist_ok=True)
    return out


def finish(cleanup):
    """Ends a run: the alarm off, then each cleanup step, last first, whatever the others do."""
    signal.alarm(0)
    for fn in reversed(cleanup):
        try:
            fn()
        except Exception as e:  # noqa: BLE001 - cleanup goes on
            print(f'cleanup: {type(e).__name__}: {e}', file=sys.stderr)


def alarm_after(seconds):
    """Raises Failure in the main thread once the whole run has taken `seconds`."""
    def on_alarm(signum, frame):
        raise Failure(f'the whole run took longer than {seconds:.0f} s')
    signal.signal(signal.SIGALRM, on_alarm)
    signal.alarm(int(seconds))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    ap.add_argument('--intermix', default='build/intermix', help='the intermix program')
    ap.add_argument('--scene', default='examples/fusion.json',
                    help='a scene file, or a data file or DICOM folder (intermix serve DATA)')
    ap.add_argument('--out', help='folder for screenshots, logs and measure.json '
                                  '(default: a new temporary folder, kept)')
    ap.add_argument('--measure', type=int, default=0, metavar='N',
                    help='measure mode: N short drags on the scene at its own size')
    ap.add_argument('--measure-2d', type=int, default=0, metavar='N',
                    help='measure the 2-D views: N window/level drags and N zoom steps')
    ap.add_argument('--method', help='rendering method (test mode default: zslab)')
    ap.add_argument('--spp', type=int, help='samples per pixel the viewer converges to')
    ap.add_argument('--max-image-side', type=int, default=512,
                    help='measure mode: the largest side of a frame (the page asks for its '
                         'view\'s size)')
    ap.add_argument('--set', action='append', default=[], metavar='KEY=VALUE',
                    help='scene override passed to intermix serve (repeatable)')
    ap.add_argument('--mpr-scene', default=os.path.join(REPO, 'examples', 'mpr.json'),
                    help='test mode: the scene with MPR planes for checks h-k, served after '
                         "--scene ('' skips them)")
    ap.add_argument('--tf-volume', help='the volume whose TF is edited (default: the one with '
                                        'the most opaque control point)')
    ap.add_argument('--settle', type=float, default=3.0,
                    help='measure mode: seconds to wait for convergence after each drag')
    ap.add_argument('--chromium', help='the browser (default /usr/bin/chromium)')
    ap.add_argument('--only', choices=['streamlines'],
                    help='test mode: run only this part (s: the streamline controls and views)')
    ap.add_argument('--timeout', type=float, help='overall limit in seconds '
                    '(default 180 in test mode, 120 + 8 per drag in measure mode)')
    args = ap.parse_args()

    status = preflight(args)
    if status is not None:
        return status
    if not os.path.exists(args.scene):  # a scene file, or data intermix serve opens (a folder)
        print(f'error: no scene file or data {args.scene}', file=sys.stderr)
        return 2
    if args.mpr_scene and not args.measure and not os.path.isfile(args.mpr_scene):
        print(f'error: no scene file {args.mpr_scene}', file=sys.stderr)
        return 2
    out = output_folder(args, 'imx-viewer-test-')

    limit = args.timeout or (120 + 8 * args.measure if args.measure else
                             180 + 5 * args.measure_2d if args.measure_2d else 180)

    def on_term(signum, frame):
        raise SystemExit(f'stopped by signal {signum}')
    signal.signal(signal.SIGTERM, on_term)
    alarm_after(limit)

    checks = Checks()
    cleanup = []
    t0 = time.monotonic()
    status = 0
    try:
        if args.measure_2d:
            status = run_measure_2d(args, out, cleanup)
        elif args.measure:
            status = run_measure(args, out, cleanup)
        else:
            log(f'viewer browser test: {args.scene}, output in {out}')
            if args.only == 'streamlines':
                run_streamlines_only(args, out, checks, cleanup)
            else:
                run_test(args, out, checks, cleanup)
    except (Failure, CdpError, OSError, subprocess.SubprocessError,
            websocket.WebSocketException) as e:
        checks.check('run completed', False, type(e).__name__, str(e))
        diagnose(cleanup, out)
        status = 1
    except KeyboardInterrupt:
        checks.check('run completed', False, 'interrupted')
        status = 1
    finally:
        finish(cleanup)
    if args.measure or args.measure_2d:
        return status
    failed = checks.failed()
    with open(os.path.join(out, 'results.json'), 'w') as f:
        json.dump(checks.results, f, indent=1)
    log(f"{len(checks.results) - len(failed)} of {len(checks.results)} checks passed in "
        f'{time.monotonic() - t0:.1f} s; output in {out}')
    return 1 if failed or status else 0


if __name__ == '__main__':
    sys.exit(main())
