"""A small Chrome DevTools Protocol client for headless Chromium (websocket-client + stdlib).

    with Browser() as b:                 # starts chromium --headless=new on a free port
        b.navigate('http://127.0.0.1:8080/')
        b.evaluate('document.title')
        b.drag(100, 100, 300, 100, steps=40, duration=2.0)
        b.screenshot('/tmp/page.png')

Every wait has a deadline and fails with CdpError naming what it waited for. Chromium runs in
its own process group, killed (TERM, then KILL) by close(); its output goes to a log file whose
tail is quoted when it fails to start.
"""

import base64
import collections
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

try:
    import websocket  # Debian: python3-websocket (websocket-client)
except ImportError:  # a python3 outside Debian's (pyenv, venv) can still use Debian's copy
    _dist = '/usr/lib/python3/dist-packages'
    if os.path.isdir(os.path.join(_dist, 'websocket')) and _dist not in sys.path:
        sys.path.append(_dist)
    try:
        import websocket
    except ImportError:
        websocket = None

CHROMIUM = '/usr/bin/chromium'


class CdpError(Exception):
    pass


def find_chromium(path=None):
    """The browser: `path` when given (else None), else $CHROMIUM, /usr/bin/chromium or one on
    the PATH."""
    candidates = [path] if path else [os.environ.get('CHROMIUM', ''), CHROMIUM,
                                      shutil.which('chromium') or '',
                                      shutil.which('chromium-browser') or '']
    for p in candidates:
        if p and os.path.isfile(p) and os.access(p, os.X_OK):
            return p
    return None


def kill_group(proc, term_timeout=5.0):
    """Ends a process started with start_new_session=True and everything in its group."""
    if proc is None:
        return None
    for sig, wait in ((signal.SIGTERM, term_timeout), (signal.SIGKILL, 5.0)):
        if proc.poll() is not None:
            break
        try:
            os.killpg(proc.pid, sig)
        except (ProcessLookupError, PermissionError):
            pass
        try:
            proc.wait(timeout=wait)
        except subprocess.TimeoutExpired:
            continue
    # children left in the group after the leader exited
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass
    return proc.poll()


def _tail(path, n=2000):
    try:
        with open(path, 'rb') as f:
            f.seek(0, 2)
            size = f.tell()
            f.seek(max(0, size - n))
            return f.read().decode('utf-8', 'replace')
    except OSError:
        return ''


class Browser:
    def __init__(self, chromium=None, window=(1280, 900), log_path=None, extra_args=()):
        if websocket is None:
            raise CdpError('the websocket module is missing (apt-get install python3-websocket)')
        self.chromium = find_chromium(chromium)
        if not self.chromium:
            raise CdpError('chromium not found (apt-get install chromium)')
        self.window = window
        self.extra_args = list(extra_args)
        self.proc = None
        self.ws = None
        self.session = None
        self.next_id = 1
        self.events = collections.deque(maxlen=20000)
        self.page_errors = []   # uncaught exceptions and console.error lines of the page
        self.tmp = tempfile.mkdtemp(prefix='imx-chromium-')
        self.log_path = log_path or os.path.join(self.tmp, 'chromium.log')
        self._log = None

    # ------------------------------------------------------------ start and stop
    def start(self, timeout=30.0):
        profile = os.path.join(self.tmp, 'profile')
        os.makedirs(profile, exist_ok=True)
        args = [self.chromium, '--headless=new', '--no-sandbox', '--disable-gpu',
                '--remote-debugging-port=0', f'--user-data-dir={profile}',
                f'--window-size={self.window[0]},{self.window[1]}',
                '--no-first-run', '--no-default-browser-check', '--disable-extensions',
                '--disable-background-networking', '--disable-sync', '--mute-audio',
                '--disable-dev-shm-usage', '--disable-background-timer-throttling',
                '--disable-renderer-backgrounding', '--disable-backgrounding-occluded-windows',
                '--disable-crash-reporter', '--disable-breakpad',
                '--force-device-scale-factor=1', '--hide-scrollbars',
                *self.extra_args, 'about:blank']
        self._log = open(self.log_path, 'wb')
        self.proc = subprocess.Popen(args, stdin=subprocess.DEVNULL, stdout=self._log,
                                     stderr=subprocess.STDOUT, start_new_session=True)
        port_file = os.path.join(profile, 'DevToolsActivePort')
        deadline = time.monotonic() + timeout
        browser_path = None
        while time.monotonic() < deadline:
            if self.proc.poll() is not None:
                raise CdpError(f'chromium exited with status {self.proc.returncode} before '
                               f'listening; its log ends:\n{_tail(self.log_path)}')
            try:
                with open(port_file) as f:
                    lines = f.read().split('\n')
                if len(lines) >= 2 and lines[0].strip().isdigit() and lines[1].strip():
                    port, browser_path = int(lines[0]), lines[1].strip()
                    break
            except OSError:
                pass
            time.sleep(0.05)
        if not browser_path:
            raise CdpError(f'chromium wrote no DevToolsActivePort within {timeout:.0f} s; '
                           f'its log ends:\n{_tail(self.log_path)}')
        self.port = port
        url = f'ws://127.0.0.1:{port}{browser_path}'
        remaining = max(1.0, deadline - time.monotonic())
        try:
            self.ws = websocket.create_connection(url, timeout=remaining, suppress_origin=True,
                                                  enable_multithread=False)
        except Exception as e:  # noqa: BLE001 - any connection failure is fatal here
            raise CdpError(f'cannot connect to chromium at {url}: {e}') from e
        # One page target, attached with a flat session.
        targets = self.send('Target.getTargets', timeout=10)['targetInfos']
        pages = [t for t in targets if t.get('type') == 'page']
        if pages:
            target_id = pages[0]['targetId']
        else:
            target_id = self.send('Target.createTarget', {'url': 'about:blank'})['targetId']
        self.target_id = target_id
        self.session = self.send('Target.attachToTarget',
                                 {'targetId': target_id, 'flatten': True},
                                 session=None)['sessionId']
        try:  # downloads (the viewer's saved scene, screenshots) are not written anywhere
            self.send('Browser.setDownloadBehavior', {'behavior': 'deny'}, session=None)
        except CdpError:
            pass
        for domain in ('Page', 'Runtime', 'Log'):
            self.send(f'{domain}.enable')
        self.send('Emulation.setDeviceMetricsOverride',
                  {'width': self.window[0], 'height': self.window[1], 'deviceScaleFactor': 1,
                   'mobile': False})
        self.send('Emulation.setFocusEmulationEnabled', {'enabled': True})
        return self

    def close(self):
        if self.ws is not None:
            try:
                self.ws.settimeout(2)
                self._send_raw('Browser.close', {}, None)
            except Exception:  # noqa: BLE001 - the process group is killed below anyway
                pass
            try:
                self.ws.close(timeout=1)
            except Exception:  # noqa: BLE001
                pass
            self.ws = None
        if self.proc is not None:
            try:
                self.proc.wait(timeout=3)
            except subprocess.TimeoutExpired:
                pass
            kill_group(self.proc)
            self.proc = None
        if self._log:
            self._log.close()
            self._log = None
        shutil.rmtree(self.tmp, ignore_errors=True)

    def __enter__(self):
        return self.start()

    def __exit__(self, *exc):
        self.close()
        return False

    # ------------------------------------------------------------ protocol
    def _send_raw(self, method, params, session):
        msg_id = self.next_id
        self.next_id += 1
        msg = {'id': msg_id, 'method': method, 'params': params or {}}
        if session:
            msg['sessionId'] = session
        self.ws.send(json.dumps(msg))
        return msg_id

    def _recv(self, deadline):
        """One message, or None when the deadline passed first."""
        remaining = deadline - time.monotonic()
        if remaining <= 0:
            return None
        self.ws.settimeout(remaining)
        try:
            raw = self.ws.recv()
        except websocket.WebSocketTimeoutException:
            return None
        except (websocket.WebSocketConnectionClosedException, ConnectionError, OSError) as e:
            raise CdpError(f'the DevTools connection closed: {e}') from e
        msg = json.loads(raw)
        if 'method' in msg:
            self._on_event(msg)
        return msg

    def _on_event(self, msg):
        self.events.append(msg)
        m, p = msg['method'], msg.get('params', {})
        if m == 'Runtime.exceptionThrown':
            d = p.get('exceptionDetails', {})
            text = d.get('exception', {}).get('description') or d.get('text', '')
            self.page_errors.append(f'exception: {text}')
        elif m == 'Runtime.consoleAPICalled' and p.get('type') == 'error':
            args = ' '.join(str(a.get('value', a.get('description', ''))) for a in p.get('args', []))
            self.page_errors.append(f'console.error: {args}')
        elif m == 'Log.entryAdded' and p.get('entry', {}).get('level') == 'error':
            e = p['entry']
            self.page_errors.append(f"log: {e.get('text', '')} {e.get('url', '')}".strip())

    def send(self, method, params=None, timeout=30.0, session='page'):
        """Sends a command and returns its result; CdpError on an error reply or timeout."""
        if self.ws is None:
            raise CdpError(f'{method}: not connected')
        sess = self.session if session == 'page' else session
        msg_id = self._send_raw(method, params, sess)
        deadline = time.monotonic() + timeout
        while True:
            msg = self._recv(deadline)
            if msg is None:
                raise CdpError(f'{method}: no reply within {timeout:.1f} s')
            if msg.get('id') == msg_id:
                if 'error' in msg:
                    raise CdpError(f"{method}: {msg['error'].get('message')} "
                                   f"{msg['error'].get('data', '')}".strip())
                return msg.get('result', {})

    def pump_events(self, seconds=0.0):
        """Reads the events that arrive within the given time (none: only those waiting)."""
        deadline = time.monotonic() + max(seconds, 0.001)
        while self._recv(deadline) is not None:
            pass

    def wait_event(self, method, timeout=30.0, predicate=None, since=0):
        """The first event `method` (matching predicate) among those from index `since` of
        self.events on, reading more until the deadline."""
        deadline = time.monotonic() + timeout
        checked = since
        while True:
            evs = list(self.events)
            for ev in evs[checked:]:
                if ev['method'] == method and (predicate is None or predicate(ev['params'])):
                    return ev['params']
            checked = len(evs)
            if self._recv(deadline) is None and time.monotonic() >= deadline:
                raise CdpError(f'no {method} event within {timeout:.1f} s')

    # ------------------------------------------------------------ page helpers
    def navigate(self, url, timeout=30.0):
        self.events.clear()  # the load event looked for is one of this navigation's
        res = self.send('Page.navigate', {'url': url}, timeout=timeout)
        if res.get('errorText'):
            raise CdpError(f'navigating to {url}: {res["errorText"]}')
        self.wait_event('Page.loadEventFired', timeout=timeout)
        return res

    def evaluate(self, expr, timeout=30.0, await_promise=True):
        """Evaluates a JavaScript expression in the page; returns its value (JSON-able)."""
        res = self.send('Runtime.evaluate',
                        {'expression': expr, 'returnByValue': True,
                         'awaitPromise': await_promise, 'userGesture': True,
                         'timeout': int(timeout * 1000)}, timeout=timeout + 5)
        if 'exceptionDetails' in res:
            d = res['exceptionDetails']
            text = d.get('exception', {}).get('description') or d.get('text', '')
            raise CdpError(f'JavaScript error in {expr[:120]!r}: {text}')
        r = res.get('result', {})
        if r.get('type') == 'undefined':
            return None
        if 'value' in r:
            return r['value']
        if r.get('unserializableValue') is not None:  # Infinity, -Infinity, NaN, -0, 12n
            u = r['unserializableValue']
            try:
                return float(u.replace('Infinity', 'inf'))
            except ValueError:
                return int(u[:-1]) if u.endswith('n') else u
        return None

    def wait_for(self, expr, timeout=30.0, interval=0.05, what=None):
        """Polls a JavaScript expression until it is truthy; returns its value."""
        deadline = time.monotonic() + timeout
        while True:
            v = self.evaluate(expr, timeout=max(1.0, min(10.0, deadline - time.monotonic())))
            if v:
                return v
            if time.monotonic() >= deadline:
                raise CdpError(f'timed out after {timeout:.1f} s waiting for {what or expr}')
            self.pump_events(interval)

    # ------------------------------------------------------------ input
    def mouse(self, kind, x, y, button='none', buttons=0, click_count=0, modifiers=0):
        self.send('Input.dispatchMouseEvent',
                  {'type': kind, 'x': float(x), 'y': float(y), 'button': button,
                   'buttons': buttons, 'clickCount': click_count, 'modifiers': modifiers},
                  timeout=15)

    # modifiers (CDP's bit mask, as on the DOM events): ALT 1, CTRL 2, META 4, SHIFT 8.
    ALT, CTRL, META, SHIFT = 1, 2, 4, 8

    def key(self, key, modifiers=0):
        """Presses and releases one key (`key` as KeyboardEvent.key names it, a letter or
        'Home', ...) with `modifiers` held."""
        code = ('Key' + key.upper()) if len(key) == 1 and key.isalpha() else key
        vk = ord(key.upper()) if len(key) == 1 else 0
        for kind in ('keyDown', 'keyUp'):
            self.send('Input.dispatchKeyEvent',
                      {'type': kind, 'key': key, 'code': code, 'modifiers': modifiers,
                       'windowsVirtualKeyCode': vk}, timeout=15)

    def press(self, x, y, button='left', modifiers=0):
        self.mouse('mouseMoved', x, y, modifiers=modifiers)
        self.mouse('mousePressed', x, y, button=button, buttons=_BUTTONS[button], click_count=1,
                   modifiers=modifiers)

    def release(self, x, y, button='left', modifiers=0):
        self.mouse('mouseReleased', x, y, button=button, buttons=0, click_count=1,
                   modifiers=modifiers)

    def drag(self, x0, y0, x1, y1, steps=40, duration=2.0, button='left', release=True,
             on_step=None, modifiers=0):
        """Presses at (x0, y0), moves in `steps` even steps to (x1, y1) spread over `duration`
        seconds, and releases (unless release=False); every event carries `modifiers` (held
        keys, e.g. Browser.CTRL). on_step(i) runs after move i (1-based).
        Returns (t_press, t_last_move) in time.monotonic() seconds."""
        self.press(x0, y0, button, modifiers)
        t0 = time.monotonic()
        for i in range(1, steps + 1):
            f = i / steps
            self.mouse('mouseMoved', x0 + (x1 - x0) * f, y0 + (y1 - y0) * f, button=button,
                       buttons=_BUTTONS[button], modifiers=modifiers)
            if on_step:
                on_step(i)
            wait = t0 + duration * i / steps - time.monotonic()
            if wait > 0:
                time.sleep(wait)
        t1 = time.monotonic()
        if release:
            self.release(x1, y1, button, modifiers)
        return t0, t1

    def click(self, x, y, button='left', modifiers=0):
        self.press(x, y, button, modifiers)
        self.release(x, y, button, modifiers)

    # ------------------------------------------------------------ output
    def screenshot(self, path, timeout=30.0):
        res = self.send('Page.captureScreenshot', {'format': 'png'}, timeout=timeout)
        data = base64.b64decode(res['data'])
        with open(path, 'wb') as f:
            f.write(data)
        return len(data)


_BUTTONS = {'none': 0, 'left': 1, 'right': 2, 'middle': 4}
