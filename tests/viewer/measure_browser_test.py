#!/usr/bin/python3
"""Headless-Chromium test of the viewer's measurements (docs/viewer.md, "Measurements").

    tests/viewer/measure_browser_test.py --intermix build/intermix [--out DIR]

Writes a volume of known values (NRRD, 33 x 33 x 9 voxels of 0.7 x 0.9 x 2.5 mm, value
i + 10 j + 100 k) and a scene of it, serves it, and with real clicks in the axial view checks:
a ruler between two voxel centres reads their distance within 0.1 mm; an angle between three
reads theirs within 0.5 degrees; a polygon ROI around a block of voxels gives their count, mean
and SD, an ellipse ROI those of the voxel centres inside it; the 3-D view's overlay draws them;
undo and redo take one back and forth; the copied link holds them; the 3-D ruler picks two
points on the 3-D view; hostile `annotations` messages (a NaN, 300 polygon corners, an unknown
kind, parallel axes) each get one error and lose nothing; a polygon ROI over the same values on a
grid turned 20 degrees (a second, hidden volume, asked over the WebSocket) gives those of the
voxels its plane cuts; and the annotations survive save -> reload (a second server on the saved
scene shows the same measurements) -> render (`intermix render` draws the ruler where it
projects; `intermix info --annotations` gives the same numbers). Exit 0: all passed, 1: a check
failed, 77: skipped (no chromium or websocket module).

    tests/viewer/measure_browser_test.py --latency DATA... [--rounds N]

measures the latency of ROI statistics requests instead (docs/viewer.md, "Measurements").
"""

import argparse
import json
import math
import os
import signal
import struct
import subprocess
import sys
import time
import urllib.parse
import zlib

sys.dont_write_bytecode = True  # no __pycache__ beside the sources
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cdp import CdpError, websocket  # noqa: E402
from viewer_browser_test import (Checks, Failure, Watcher, alarm_after, finish, log,
                                 start_browser, start_server,
                                 output_folder, preflight,  # noqa: E402
                                 wait_converged)

DIMS = (33, 33, 9)
SPACING = (0.7, 0.9, 2.5)
ORIGIN = (-10.0, -12.0, -8.0)
LAYER = 4  # the middle layer: the axial view's first plane (the volume box's centre)


def value(i, j, k):
    return i + 10 * j + 100 * k


def world(i, j, k=LAYER):
    return [ORIGIN[0] + i * SPACING[0], ORIGIN[1] + j * SPACING[1], ORIGIN[2] + k * SPACING[2]]


# The same values on a grid turned 20 degrees about x: its columns (world mm per index step).
TILT = math.radians(20)
TILTED = [(SPACING[0], 0.0, 0.0),
          (0.0, SPACING[1] * math.cos(TILT), SPACING[1] * math.sin(TILT)),
          (0.0, -SPACING[2] * math.sin(TILT), SPACING[2] * math.cos(TILT))]


def write_volume(path, columns=None):
    """A float NRRD in LPS of the known values, i fastest; axis-aligned unless `columns`."""
    columns = columns or [(SPACING[0], 0, 0), (0, SPACING[1], 0), (0, 0, SPACING[2])]
    directions = ' '.join('(' + ','.join(repr(float(x)) for x in c) + ')' for c in columns)
    header = ('NRRD0004\ntype: float\ndimension: 3\nspace: left-posterior-superior\n'
              f'sizes: {DIMS[0]} {DIMS[1]} {DIMS[2]}\n'
              f'space directions: {directions}\n'
              'kinds: domain domain domain\nendian: little\nencoding: raw\n'
              f'space origin: ({ORIGIN[0]},{ORIGIN[1]},{ORIGIN[2]})\n\n')
    data = struct.pack(f'<{DIMS[0] * DIMS[1] * DIMS[2]}f',
                       *[value(i, j, k) for k in range(DIMS[2]) for j in range(DIMS[1])
                         for i in range(DIMS[0])])
    with open(path, 'wb') as f:
        f.write(header.encode() + data)


def write_scene(folder):
    write_volume(os.path.join(folder, 'known.nrrd'))
    write_volume(os.path.join(folder, 'tilted.nrrd'), TILTED)
    scene = {'camera': {'eye': [0, -300, 0], 'target': [1.2, 2.4, 2.0], 'up': [0, 0, 1]},
             'image': {'width': 256, 'height': 256},
             'objects': [{'name': 'known', 'type': 'volume', 'source': {'file': 'known.nrrd'},
                          'window': [400, 800],
                          'transfer_function': {'points': [[0, 1, 1, 1, 0],
                                                           [900, 1, 1, 1, 0.2]]}},
                         {'name': 'tilted', 'type': 'volume', 'visible': False,
                          'source': {'file': 'tilted.nrrd'}}]}
    path = os.path.join(folder, 'known.json')
    with open(path, 'w') as f:
        json.dump(scene, f)
    return path


def stats(values):
    n = len(values)
    mean = sum(values) / n
    return n, mean, math.sqrt(sum((v - mean) ** 2 for v in values) / n)


def tilted_roi(corners):
    """The known values of the tilted grid's voxels inside an axial polygon, by the rule of
    src/measure/roi_statistics.hpp worked out here: the plane passes through the voxel's box
    (|d| within half its extent along z, the lower bound closed) and its centre lies inside."""
    z = corners[0][2]
    h = 0.5 * sum(abs(c[2]) for c in TILTED)
    inside = []
    for k in range(DIMS[2]):
        for j in range(DIMS[1]):
            for i in range(DIMS[0]):
                w = [ORIGIN[a] + i * TILTED[0][a] + j * TILTED[1][a] + k * TILTED[2][a]
                     for a in range(3)]
                if not -h <= w[2] - z < h:
                    continue
                crossings = 0
                for (ax, ay, _), (bx, by, _) in zip(corners, corners[1:] + corners[:1]):
                    if (ay > w[1]) != (by > w[1]) and \
                            w[0] < ax + (w[1] - ay) * (bx - ax) / (by - ay):
                        crossings += 1
                if crossings % 2:
                    inside.append(value(i, j, k))
    return inside


def close(a, b, rel=1e-9):
    return a is not None and abs(a - b) <= rel * max(1.0, abs(b))


# ---------------------------------------------------------------- PNG (8-bit RGB/RGBA) reading
def read_png(path):
    """(width, height, channels, rows of bytes) of a non-interlaced 8-bit RGB or RGBA PNG."""
    with open(path, 'rb') as f:
        data = f.read()
    pos, idat, width = 8, b'', 0
    while pos < len(data):
        n, kind = struct.unpack('>I4s', data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b'IHDR':
            width, height, depth, colour = struct.unpack('>IIBB', body[:10])
            if depth != 8 or colour not in (2, 6):
                raise Failure(f'{path}: a PNG of depth {depth}, colour type {colour}')
            channels = 3 if colour == 2 else 4
        elif kind == b'IDAT':
            idat += body
        pos += 12 + n
    raw, stride, rows = zlib.decompress(idat), width * channels, []
    prev = bytearray(stride)
    for y in range(height):
        start = y * (stride + 1)
        f, line = raw[start], bytearray(raw[start + 1:start + 1 + stride])
        for x in range(stride):
            a = line[x - channels] if x >= channels else 0
            b, c = prev[x], prev[x - channels] if x >= channels else 0
            p = a + b - c
            pred = [0, a, b, (a + b) // 2,
                    a if abs(p - a) <= abs(p - b) and abs(p - a) <= abs(p - c)
                    else b if abs(p - b) <= abs(p - c) else c][f]
            line[x] = (line[x] + pred) & 0xFF
        rows.append(bytes(line))
        prev = line
    return width, height, channels, rows


def project(camera, width, height, p):
    """A world point's image position through a perspective scene camera (CameraModel's)."""
    sub = [p[i] - camera['eye'][i] for i in range(3)]
    fwd = [camera['target'][i] - camera['eye'][i] for i in range(3)]
    n = math.sqrt(sum(x * x for x in fwd))
    fwd = [x / n for x in fwd]
    up = camera['up']
    right = [fwd[1] * up[2] - fwd[2] * up[1], fwd[2] * up[0] - fwd[0] * up[2],
             fwd[0] * up[1] - fwd[1] * up[0]]
    n = math.sqrt(sum(x * x for x in right))
    right = [x / n for x in right]
    up = [right[1] * fwd[2] - right[2] * fwd[1], right[2] * fwd[0] - right[0] * fwd[2],
          right[0] * fwd[1] - right[1] * fwd[0]]
    dot = lambda a, b: sum(x * y for x, y in zip(a, b))  # noqa: E731
    z = dot(sub, fwd)
    t = math.tan(math.radians(camera.get('fov_deg', 30)) / 2)
    return (width / 2 + dot(sub, right) / z / t * height / 2,
            height / 2 - dot(sub, up) / z / t * height / 2)


# ---------------------------------------------------------------- the page
def start_page(args, scene, out, name, cleanup, browser):
    server = start_server(args, scene, ['--port', '0', '--bind', '127.0.0.1', '--method', 'zslab',
                                        '--spp', '1', '--max-image-side', '256'],
                          out, cleanup, log=f'{name}.log')
    url = server.wait_url(60)
    browser.navigate(url, timeout=20)
    browser.wait_for('Boolean(window.viewerStats && viewerStats.connected)', timeout=10,
                     what='the page to connect its WebSocket')
    wait_converged(browser, 30, f'{name} after load')
    browser.evaluate("viewer.setLayout('2x2')")
    browser.wait_for('viewer.slicesDrawn() >= 3 && viewer.slicesSettled()', timeout=15,
                     what='the three 2-D views')
    return server, url


def click_world(browser, p, axis='axial'):
    xy = browser.evaluate(f'viewer.pagePixelOf({json.dumps(axis)}, {json.dumps(p)})')
    if not xy:
        raise Failure(f'no {axis} view to click in')
    browser.click(xy[0], xy[1])


def wait_measured(browser, count, what):
    return browser.wait_for(
        f'(() => {{ const m = viewer.measurements(); return m.length === {count} && '
        'm.every((x) => x.measurement) ? m : null; })()', timeout=15, what=what)


def run(args, out, checks, cleanup):
    scene = write_scene(out)
    browser = start_browser(args, out, cleanup)
    server, url = start_page(args, scene, out, 'server', cleanup, browser)
    u = urllib.parse.urlsplit(url)
    token = urllib.parse.parse_qs(u.query).get('token', [''])[0]
    ws_url = f'ws://{u.netloc}/ws?token={token}'
    point = browser.evaluate('viewer.slicePoint()')
    checks.check('the axial view shows the middle layer of voxel centres',
                 close(point[2], world(0, 0)[2]), f'z = {point[2]} mm')

    # a ruler between two voxel centres
    browser.evaluate("viewer.setMeasureTool('ruler')")
    a, b = world(4, 5), world(20, 27)
    click_world(browser, a)
    click_world(browser, b)
    m = wait_measured(browser, 1, 'the ruler measured')[0]
    want = math.dist(a, b)
    got = m['measurement']['length_mm']
    checks.check('a ruler between two voxel centres reads their distance within 0.1 mm',
                 abs(got - want) <= 0.1, f'{got:.4f} mm', f'voxel centres {want:.4f} mm apart')

    # an angle at a voxel centre
    browser.evaluate("viewer.setMeasureTool('angle')")
    p, q, r = world(26, 6), world(10, 8), world(12, 28)
    for x in (p, q, r):
        click_world(browser, x)
    m = wait_measured(browser, 2, 'the angle measured')[1]
    u1, u2 = [p[i] - q[i] for i in range(3)], [r[i] - q[i] for i in range(3)]
    want = math.degrees(math.acos(sum(x * y for x, y in zip(u1, u2)) /
                                  (math.hypot(*u1) * math.hypot(*u2))))
    got = m['measurement']['angle_deg']
    checks.check('an angle between three voxel centres reads theirs within 0.5 degrees',
                 abs(got - want) <= 0.5, f'{got:.3f} deg', f'{want:.3f} deg')

    # a polygon ROI around voxels i 8..15, j 10..18 (its edges half a voxel outside them)
    browser.evaluate("viewer.setMeasureTool('polygon')")
    corners = [world(7.5, 9.5), world(15.5, 9.5), world(15.5, 18.5), world(7.5, 18.5)]
    for c in corners + corners[:1]:  # the first corner again closes it
        click_world(browser, c)
    m = wait_measured(browser, 3, 'the polygon measured')[2]['measurement']
    n, mean, sd = stats([value(i, j, LAYER) for j in range(10, 19) for i in range(8, 16)])
    checks.check('a polygon ROI over a block of known values gives their count, mean and SD',
                 m.get('voxels') == n and close(m.get('mean'), mean) and close(m.get('sd'), sd) and
                 m.get('min') == value(8, 10, LAYER) and m.get('max') == value(15, 18, LAYER),
                 f"{m.get('voxels')} voxels, mean {m.get('mean')}, SD {m.get('sd')}, "
                 f"min {m.get('min')}, max {m.get('max')}",
                 f'{n} voxels, mean {mean}, SD {sd:.6f}; area {m.get("area_mm2"):.2f} mm²')

    # an ellipse ROI: the voxel centres inside it, from the points the page placed
    browser.evaluate("viewer.setMeasureTool('ellipse')")
    click_world(browser, world(24, 16))
    click_world(browser, world(27.3, 19.6))
    listed = wait_measured(browser, 4, 'the ellipse measured')
    e = listed[3]
    c, pa, pb = e['annotation']['points']
    ax, by = abs(pa[0] - c[0]), abs(pb[1] - c[1])
    inside = [value(i, j, LAYER) for j in range(DIMS[1]) for i in range(DIMS[0])
              if ((world(i, j)[0] - c[0]) / ax) ** 2 + ((world(i, j)[1] - c[1]) / by) ** 2 <= 1]
    n, mean, sd = stats(inside)
    m = e['measurement']
    checks.check('an ellipse ROI gives the count, mean and SD of the voxel centres inside it',
                 m.get('voxels') == n and close(m.get('mean'), mean) and close(m.get('sd'), sd) and
                 close(m.get('area_mm2'), math.pi * ax * by),
                 f"{m.get('voxels')} voxels, mean {m.get('mean')}, SD {m.get('sd')}",
                 f'{n} voxels, mean {mean}, SD {sd:.6f}')

    browser.screenshot(os.path.join(out, 'measurements.png'))
    # The 3-D view's overlay draws them too, through the camera, in the annotations' orange.
    orange = browser.evaluate("""(() => {
      const c = document.getElementById('colorbars');
      const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
      let n = 0;
      for (let i = 0; i < d.length; i += 4)
        n += d[i] > 200 && d[i + 1] > 120 && d[i + 1] < 200 && d[i + 2] < 90 && d[i + 3] > 200;
      return n;
    })()""")
    checks.check("the 3-D view's overlay draws the measurements", orange > 50,
                 f'{orange} orange pixels')

    # a triangle closed with Enter, every edge a voxel's half diagonal or half side clear of the
    # voxel centres: its area and the centres inside
    browser.evaluate("viewer.setMeasureTool('polygon')")
    triangle = [world(2.5, 2.5), world(12, 2.5), world(2.5, 12)]
    for c in triangle:
        click_world(browser, c)
    browser.key('Enter')
    t = wait_measured(browser, 5, 'the triangle closed with Enter')[4]['measurement']
    inside = [(i, j) for j in range(DIMS[1]) for i in range(DIMS[0])
              if i > 2.5 and j > 2.5 and i + j < 14.5]
    area = 0.5 * 9.5 * SPACING[0] * 9.5 * SPACING[1]
    checks.check('Enter closes a polygon: its area and voxels are the triangle\'s',
                 t.get('voxels') == len(inside) and abs(t.get('area_mm2', 0) - area) < 0.05,
                 f"{t.get('voxels')} voxels, {t.get('area_mm2', 0):.3f} mm²",
                 f'{len(inside)} voxel centres inside, {area:.3f} mm²')

    # undo, redo, link
    browser.evaluate("viewer.setMeasureTool('none')")
    browser.click(*[browser.evaluate("viewer.center('#undo')")[k] for k in ('x', 'y')])
    after_undo = browser.wait_for('viewer.measurements().length === 4', timeout=5,
                                  what='undo to take the triangle back')
    browser.click(*[browser.evaluate("viewer.center('#redo')")[k] for k in ('x', 'y')])
    after_redo = browser.wait_for('viewer.measurements().length === 5', timeout=5,
                                  what='redo to put it back')
    link = browser.evaluate('viewer.viewLink()')
    view = json.loads(urllib.parse.unquote(link.split('#view=', 1)[1]))
    checks.check('undo takes the last measurement back, redo puts it back, the link holds them',
                 after_undo and after_redo and len(view.get('annotations', [])) == 5,
                 f"{len(view.get('annotations', []))} annotations in the link")

    # the 3-D ruler: two picks on the 3-D view
    browser.evaluate("viewer.setMeasureTool('ruler3d')")
    cell = browser.evaluate("viewer.center('#view')")
    picks = []
    for dx in (-0.04, 0.04):
        browser.evaluate('window.__pick = viewer.lastPick()')
        browser.click(cell['x'] + dx * cell['w'], cell['y'])
        picks.append(browser.wait_for('viewer.lastPick() !== window.__pick && viewer.lastPick()',
                                      timeout=15, what='a pick'))
    listed = wait_measured(browser, 6, 'the 3-D ruler measured')
    pa, pb = picks[0].get('point'), picks[1].get('point')
    got = listed[5]['measurement']['length_mm']
    checks.check('the 3-D ruler measures between two picked points in the volume',
                 pa and pb and close(got, math.dist(pa, pb), 1e-6) and got > 0,
                 f'{got:.3f} mm', f'picks {pa} and {pb}')
    browser.evaluate("viewer.setMeasureTool('none')")
    before = browser.evaluate('viewer.measurements()')

    # hostile annotations messages: one error each, nothing lost
    watcher = Watcher(ws_url)
    cleanup.append(watcher.close)
    watcher.wait(lambda t, m: m.get('type') == 'hello', 10)
    ruler = {'kind': 'ruler', 'points': [a, b]}
    bad = [
        ('a NaN point', '{"type": "annotations", "annotations": [{"kind": "ruler", '
                        '"points": [[0, 0, 0], [NaN, 0, 0]]}]}', 'invalid'),
        ('300 polygon corners', json.dumps({'type': 'annotations', 'annotations': [ruler, {
            'kind': 'polygon', 'points': [[math.cos(i / 50), math.sin(i / 50), 2.0]
                                          for i in range(300)]}]}),
         'annotations[1].points: a polygon has 3 to 256 points, not 300'),
        ('an unknown kind', json.dumps({'type': 'annotations', 'annotations': [
            {'kind': 'circle', 'points': [a, b]}]}), 'annotations[0].kind'),
        ('parallel axes', json.dumps({'type': 'annotations', 'annotations': [
            {'kind': 'ellipse', 'points': [a, b, [2 * b[i] - a[i] for i in range(3)]]}]}),
         "an ellipse's semi-axes"),
    ]
    for what, text, expected in bad:
        t0 = time.monotonic()
        watcher.ws.send(text)
        err = watcher.wait(lambda t, m: t >= t0 and m.get('type') == 'error', 5)
        time.sleep(0.3)
        errors = watcher.of_type('error', t0)
        fresh = Watcher(ws_url)
        hello = fresh.wait(lambda t, m: m.get('type') == 'hello', 10) or {}
        fresh.close()
        kept = [x['annotation'] for x in before] == hello.get('annotations')
        checks.check(f'a hostile annotations message ({what}) gets one error and loses nothing',
                     err and len(errors) == 1 and expected in err.get('message', '') and kept,
                     (err or {}).get('message', 'no error'),
                     f'{len(hello.get("annotations", []))} annotations kept')

    # an ROI over the grid turned 20 degrees: the voxels its plane cuts, in world space
    corners = [[-6.3, -5.1, 2.0], [6.2, -4.3, 2.0], [4.1, 7.7, 2.0], [-5.7, 6.2, 2.0]]
    t0 = time.monotonic()
    watcher.send({'type': 'measure', 'seq': 1, 'annotations': [
        {'kind': 'polygon', 'volume': 'tilted', 'points': corners}]})
    got = watcher.wait(lambda t, m: t >= t0 and m.get('type') == 'measure', 10)
    m = got['measurements'][0] if got else {}
    n, mean, sd = stats(tilted_roi(corners))
    checks.check('a polygon ROI over a grid turned 20 degrees gives the count, mean and SD of '
                 'the voxels its plane cuts',
                 m.get('voxels') == n and close(m.get('mean'), mean) and close(m.get('sd'), sd),
                 f"{m.get('voxels')} voxels, mean {m.get('mean')}, SD {m.get('sd')}",
                 f'{n} voxels, mean {mean}, SD {sd:.6f}')

    # save -> reload -> render
    browser.evaluate('viewerStats.saved = null')
    browser.click(*[browser.evaluate("viewer.center('#save')")[k] for k in ('x', 'y')])
    saved = browser.wait_for('viewerStats.saved', timeout=10, what='the saved message')
    saved_path = os.path.join(out, saved['file'])
    with open(saved_path) as f:
        document = json.load(f)
    checks.check('the saved scene holds the annotations',
                 document.get('annotations') == [x['annotation'] for x in before],
                 f"{len(document.get('annotations', []))} annotations in {saved['file']}")
    server.stop()
    start_page(args, saved_path, out, 'reloaded', cleanup, browser)
    again = wait_measured(browser, len(before), 'the reloaded scene measured')
    same = all(x['annotation'] == y['annotation'] and
               json.dumps(x['measurement'], sort_keys=True) ==
               json.dumps(y['measurement'], sort_keys=True) for x, y in zip(again, before))
    checks.check('a second server on the saved scene shows the same measurements', same,
                 f'{len(again)} measurements')

    with_png, without_png = os.path.join(out, 'with.png'), os.path.join(out, 'without.png')
    for extra, png in (([], with_png), (['--no-annotations'], without_png)):
        r = subprocess.run([args.intermix, 'render', saved_path, '-o', png, '--method', 'mdvr',
                            '--spp', '1'] + extra, capture_output=True, text=True, timeout=120)
        if r.returncode != 0:
            raise Failure(f'intermix render {saved_path}: {r.stderr.strip()}')
    w, h, ch, rows_with = read_png(with_png)
    _, _, _, rows_without = read_png(without_png)
    camera = document['camera']
    mid = [(a[i] + b[i]) / 2 for i in range(3)]
    x, y = project(camera, w, h, mid)
    near = [(xx, yy) for yy in range(int(y) - 2, int(y) + 3) for xx in range(int(x) - 2, int(x) + 3)
            if 0 <= xx < w and 0 <= yy < h and
            rows_with[yy][xx * ch:xx * ch + 3] != rows_without[yy][xx * ch:xx * ch + 3]]
    far_changed = sum(rows_with[yy][xx * ch:xx * ch + 3] != rows_without[yy][xx * ch:xx * ch + 3]
                      for yy in range(0, h, 4) for xx in range(0, w, 4)
                      if math.hypot(xx - x, yy - y) > 0.45 * w)
    checks.check('intermix render draws the ruler where it projects, and only the annotations',
                 len(near) >= 3, f'{len(near)} of 25 pixels changed about ({x:.1f}, {y:.1f})',
                 f'{far_changed} sampled pixels changed far from it')
    r = subprocess.run([args.intermix, 'info', saved_path, '--annotations', '--json'],
                       capture_output=True, text=True, timeout=120)
    listed = json.loads(r.stdout)['annotations'] if r.returncode == 0 else []
    ok = len(listed) == len(before) and all(
        close(x.get('length_mm', 0), y['measurement'].get('length_mm', 0), 1e-12) and
        close(x.get('mean', 0), y['measurement'].get('mean', 0), 1e-12)
        for x, y in zip(listed, before))
    checks.check('intermix info --annotations gives the page\'s numbers', ok,
                 f'{len(listed)} measurements', r.stderr.strip()[:200])
    errors = browser.evaluate('viewerStats.errors')
    checks.check('the page got no error of its own', not errors, str(errors))


def answer(watcher, seq, timeout):
    """The watcher's `measure` answer to `seq`, polled every 0.2 ms (Watcher.wait's 50 ms steps
    would hide the latency)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        with watcher.lock:
            for _, m in reversed(watcher.messages):
                if m.get('type') == 'measure' and m.get('seq') == seq:
                    return m
        time.sleep(0.0002)
    return None


def roi_latency(args, out, cleanup):
    """ROI statistics request latency: each file's server, interleaved round by round; an axial
    ellipse over 80% of the volume's box and an oblique (30 degree) hexagon of the same size,
    timed from send to answer and by the server (`ms`). JSON on stdout."""
    sessions = []
    for k, data in enumerate(args.latency):
        server = start_server(args, data, ['--port', '0', '--bind', '127.0.0.1', '--spp', '1',
                                           '--max-image-side', '64'],
                              out, cleanup, log=f'latency-{k}.log')
        u = urllib.parse.urlsplit(server.wait_url(300))
        token = urllib.parse.parse_qs(u.query).get('token', [''])[0]
        watcher = Watcher(f'ws://{u.netloc}/ws?token={token}')
        cleanup.append(watcher.close)
        hello = watcher.wait(lambda t, m: m.get('type') == 'hello', 300)
        volume = next(o for o in hello['objects'] if o.get('kind') == 'volume')
        lo, hi = volume['bounds']
        c = [(lo[i] + hi[i]) / 2 for i in range(3)]
        rx, ry = 0.4 * (hi[0] - lo[0]), 0.4 * (hi[1] - lo[1])
        ellipse = {'kind': 'ellipse', 'volume': volume['name'],
                   'points': [c, [c[0] + rx, c[1], c[2]], [c[0], c[1] + ry, c[2]]]}
        t = math.radians(30)
        hexagon = {'kind': 'polygon', 'volume': volume['name'], 'points': [
            [c[0] + rx * math.cos(a), c[1] + ry * math.sin(a) * math.cos(t),
             c[2] + ry * math.sin(a) * math.sin(t)] for a in [i * math.pi / 3 for i in range(6)]]}
        sessions.append({'data': data, 'watcher': watcher, 'rois': [ellipse, hexagon],
                         'times': {'ellipse': [], 'polygon': []},
                         'server_ms': {'ellipse': [], 'polygon': []}, 'voxels': {}})
    seq = 1
    for _ in range(args.rounds):
        for s in sessions:
            for roi in s['rois']:
                t0 = time.monotonic()
                s['watcher'].send({'type': 'measure', 'seq': seq, 'annotations': [roi]})
                m = answer(s['watcher'], seq, 60)
                if not m:
                    raise Failure(f"{s['data']}: no measure answer in 60 s")
                s['times'][roi['kind']].append(1000 * (time.monotonic() - t0))
                s['server_ms'][roi['kind']].append(m['ms'])
                s['voxels'][roi['kind']] = m['measurements'][0]['voxels']
                seq += 1
    med = lambda xs: sorted(xs)[len(xs) // 2]  # noqa: E731
    report = [{'data': s['data'], 'voxels': s['voxels'],
               'round_trip_ms_median': {k: round(med(v), 2) for k, v in s['times'].items()},
               'round_trip_ms_max': {k: round(max(v), 2) for k, v in s['times'].items()},
               'server_ms_median': {k: med(v) for k, v in s['server_ms'].items()}}
              for s in sessions]
    print(json.dumps(report, indent=1))
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    ap.add_argument('--intermix', default='build/intermix', help='the intermix program')
    ap.add_argument('--out', help='folder for the scene, logs and images (default: a new '
                                  'temporary folder, kept)')
    ap.add_argument('--chromium', help='the browser (default /usr/bin/chromium)')
    ap.add_argument('--timeout', type=float, default=240, help='overall limit in seconds')
    ap.add_argument('--latency', nargs='+', metavar='DATA',
                    help='measure ROI statistics latency on these scenes or data files instead')
    ap.add_argument('--rounds', type=int, default=20, help='with --latency: requests per ROI')
    args = ap.parse_args()
    status = preflight(args, browser=not args.latency)
    if status is not None:
        return status
    out = output_folder(args, 'imx-measure-test-')
    alarm_after(args.timeout)
    checks, cleanup, t0 = Checks(), [], time.monotonic()
    if args.latency:
        cleanup = []
        try:
            return roi_latency(args, out, cleanup)
        finally:
            signal.alarm(0)
            for fn in reversed(cleanup):
                fn()
    log(f'measure browser test, output in {out}')
    try:
        run(args, out, checks, cleanup)
    except (Failure, CdpError, OSError, subprocess.SubprocessError,
            websocket.WebSocketException, KeyError, TypeError, ValueError) as e:
        checks.check('run completed', False, type(e).__name__, str(e))
    finally:
        finish(cleanup)
    failed = checks.failed()
    with open(os.path.join(out, 'results.json'), 'w') as f:
        json.dump(checks.results, f, indent=1)
    log(f'{len(checks.results) - len(failed)} of {len(checks.results)} checks passed in '
        f'{time.monotonic() - t0:.1f} s; output in {out}')
    return 1 if failed else 0


if __name__ == '__main__':
    sys.exit(main())
