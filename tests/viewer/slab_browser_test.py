#!/usr/bin/python3
"""Headless-Chromium test of the viewer's thick slabs and oblique reading views (docs/viewer.md,
"Thick slabs and oblique views").

    tests/viewer/slab_browser_test.py --intermix build/intermix [--out DIR]
    tests/viewer/slab_browser_test.py --intermix build/intermix --scene ct.json --measure 20

Test mode writes a 33 x 33 x 25 volume of 1 mm voxels whose values vary without order, serves
it (2x2 layout) and checks in numbers, against the voxels as this script reads them:
- the axial view's MIP and MinIP slab of 5 mm, set with the view's own controls, equal the
  maximum and minimum over the slab's samples (voxel layers z - 2 .. z + 2, bilinear in plane)
  at every checked pixel, within one 8-bit step, and differ from the thin plane; the slab is
  written to the scene (the second client's `state`: the volume's `slabs`);
- an alt+drag in the axial view turns the crosshair: the coronal and sagittal views turn about
  the axial normal, the axial view stays; their orientation letters are the nearest patient
  directions; a click in the oblique coronal view puts the crosshair on that plane and the
  readout is the trilinear sample there (to 1e-6), and the oblique image's pixels are trilinear
  samples at their world points.
Exit 0: all passed, 1: a check failed, 77: skipped (no chromium or websocket module).

Measure mode (--measure N) serves --scene as it is (2x2 layout) and, N times over the three
views, sets a view's slab (10 or 20 mm MIP) and steps a slice with the slab on, printing the
input-to-frame latency of each kind (median, 95th percentile) as JSON.
"""

import argparse
import json
import math
import os
import struct
import subprocess
import sys
import time
import urllib.parse

sys.dont_write_bytecode = True  # no __pycache__ beside the sources
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cdp import CdpError, websocket  # noqa: E402
from viewer_browser_test import (Checks, Failure, Watcher, alarm_after, finish, log,
                                 start_browser, start_server,
                                 output_folder, preflight, percentile,  # noqa: E402
                                 rnd, slice_views_settled, wait_converged, wheel)

DIMS = (33, 33, 25)  # odd: the box's centre, where the crosshair starts, is a voxel centre
WINDOW = (500.0, 1000.0)  # [centre, width]: a byte b shows the value b / 255 * 1000


def value_of(i, j, k):
    return float((i * 73 + j * 151 + k * 337 + i * j * k * 17) % 997)


def write_volume(path):
    nx, ny, nz = DIMS
    header = ('NRRD0004\ntype: float\ndimension: 3\nspace: left-posterior-superior\n'
              f'sizes: {nx} {ny} {nz}\nspace directions: (1,0,0) (0,1,0) (0,0,1)\n'
              'kinds: domain domain domain\nendian: little\nencoding: raw\n'
              'space origin: (0,0,0)\n\n')
    data = struct.pack(f'<{nx * ny * nz}f', *(value_of(i, j, k) for k in range(nz)
                                             for j in range(ny) for i in range(nx)))
    with open(path, 'wb') as f:
        f.write(header.encode() + data)


def trilinear(p):
    """The volume at world point p (voxel (i, j, k) at (i, j, k) mm) as the views sample it:
    None outside the voxels' extent, clamped to the outer voxel centres within it."""
    if any(x < -0.5 or x > d - 0.5 for x, d in zip(p, DIMS)):
        return None
    q = [min(max(x, 0.0), d - 1.0) for x, d in zip(p, DIMS)]
    i0 = [min(int(math.floor(x)), max(d - 2, 0)) for x, d in zip(q, DIMS)]
    f = [x - i for x, i in zip(q, i0)]
    total = 0.0
    for c in range(8):
        o = [(c >> a) & 1 for a in range(3)]
        w = 1.0
        for a in range(3):
            w *= f[a] if o[a] else 1.0 - f[a]
        if w:
            total += w * value_of(*(min(i0[a] + o[a], DIMS[a] - 1) for a in range(3)))
    return total


def pixel_world(v, x, y):
    """The world point of a view's backing pixel (x, y)'s centre, by its last image's geometry."""
    mm = v['mm_per_pixel']
    return [v['point'][a] + (x + 0.5 - v['width'] / 2) * mm * v['right'][a] +
            (y + 0.5 - v['height'] / 2) * mm * v['down'][a] for a in range(3)]


def view_bytes(browser, axis, pixels):
    """The red bytes of a view's image at backing pixels [(x, y), ...]."""
    return browser.evaluate(f"""(() => {{
      const c = document.querySelector('.slice-cell[data-axis={axis}] .slice');
      const g = c.getContext('2d');
      return {json.dumps(pixels)}.map(([x, y]) => g.getImageData(x, y, 1, 1).data[0]); }})()""")


def set_slab(browser, axis, thickness, mode):
    """Sets a view's slab controls as the user does (mode, then the thickness typed)."""
    ok = browser.evaluate(f"""(() => {{
      const box = document.querySelector('.slice-cell[data-axis={axis}] .slab-control');
      if (!box) return false;
      const m = box.querySelector('.slab-mode'), t = box.querySelector('.slab-thickness');
      m.value = {json.dumps(mode)};
      t.value = {json.dumps(str(thickness))};
      t.dispatchEvent(new Event('input', {{bubbles: true}}));
      t.dispatchEvent(new Event('change', {{bubbles: true}}));
      return true; }})()""")
    if not ok:
        raise Failure(f'no slab control in the {axis} view')


def letter(v):
    i = max(range(3), key=lambda a: abs(v[a]))
    return ('LPS' if v[i] > 0 else 'RAI')[i]


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def check_slab(checks, browser, mode):
    set_slab(browser, 'axial', 5, mode)
    views = slice_views_settled(browser, f'the axial {mode} slab',
                                f"v.axial.thick_slab && v.axial.thick_slab.thickness === 5 && "
                                f"v.axial.thick_slab.mode === '{mode}' && "
                                "v.axial.format === 'png'")
    v = views['axial']
    z = v['point'][2]
    pick = max if mode == 'mip' else min
    pixels, want, plane = [], [], []
    for gy in range(12):
        for gx in range(12):
            x, y = int((gx + 0.5) * v['width'] / 12), int((gy + 0.5) * v['height'] / 12)
            p = pixel_world(v, x, y)
            samples = [trilinear([p[0], p[1], z + dz]) for dz in (-2, -1, 0, 1, 2)]
            if any(s is None for s in samples):
                continue
            pixels.append([x, y])
            want.append(pick(samples))
            plane.append(samples[2])
    got = [b * WINDOW[1] / 255 for b in view_bytes(browser, 'axial', pixels)]
    worst = max((abs(g - w) for g, w in zip(got, want)), default=math.inf)
    differs = sum(abs(w - p) > 20 for w, p in zip(want, plane))
    step = WINDOW[1] / 255
    checks.check(f'a. the axial {mode.upper()} slab of 5 mm is the {pick.__name__} over the '
                 'slab computed from the voxels',
                 len(pixels) >= 40 and worst <= step and differs >= len(pixels) // 3,
                 f'largest gap {worst:.2f} over {len(pixels)} pixels (one 8-bit step '
                 f'{step:.2f})', f'{differs} pixels differ from the thin plane by > 20')


def run_test(args, out, checks, cleanup):
    write_volume(os.path.join(out, 'slab.nrrd'))
    scene = os.path.join(out, 'slab.json')
    with open(scene, 'w') as f:
        json.dump({'objects': [{'name': 'vol', 'type': 'volume', 'source': {'file': 'slab.nrrd'},
                                'window': list(WINDOW),
                                'transfer_function': {'points': [[0, 1, 1, 1, 0],
                                                                 [1000, 1, 1, 1, 0.05]]}}]}, f)
    server = start_server(args, scene, ['--port', '0', '--bind', '127.0.0.1', '--method', 'zslab',
                                        '--spp', '1', '--max-image-side', '256'],
                          out, cleanup, cwd=out)
    url = server.wait_url(60)
    token = url.split('token=')[1].split('&')[0]
    watcher = Watcher(f"ws://{url.split('//')[1].split('/')[0]}/ws?token={token}")
    cleanup.append(watcher.close)
    browser = start_browser(args, out, cleanup)
    browser.navigate(url, timeout=30)
    wait_converged(browser, 60, 'after load')
    browser.evaluate("viewer.setLayout('2x2')")
    slice_views_settled(browser, 'the three 2-D views')
    point = browser.evaluate('viewer.slicePoint()')
    centre = [(d - 1) / 2 for d in DIMS]
    if point != centre:
        raise Failure(f'the crosshair starts at {point}, not the voxel centre {centre}')

    # a. thick slabs through the view's own controls, and kept in the scene
    t0 = time.monotonic()
    check_slab(checks, browser, 'minip')
    check_slab(checks, browser, 'mip')
    state = watcher.wait(lambda t, m: t >= t0 and m.get('type') == 'state' and any(
        (o.get('slabs') or {}).get('axial') == {'thickness': 5, 'mode': 'mip'}
        for o in m.get('objects', [])), 10)
    checks.check("a. the axial slab is written to the scene (the volume's `slabs`)",
                 state is not None, 'seen by a second client' if state else 'not seen')
    set_slab(browser, 'axial', 0, 'mip')
    slice_views_settled(browser, 'the axial view without a slab',
                        'v.axial.thick_slab && v.axial.thick_slab.thickness === 0')

    # b. an alt+drag in the axial view turns the crosshair about the axial normal
    before = slice_views_settled(browser, 'the square views')
    a = before['axial']
    r = browser.evaluate("viewer.center('.slice-cell[data-axis=axial] .slice')")
    css = a['mm_per_css_px']
    # the crosshair's page position: its offset from the view's centre point, in CSS pixels
    d = [p - q for p, q in zip(browser.evaluate('viewer.slicePoint()'), a['point'])]
    cx = r['x'] + dot(d, a['right']) / css[0]
    cy = r['y'] + dot(d, a['down']) / css[1]
    turn = math.radians(60)
    browser.drag(cx + 80, cy, cx + 80 * math.cos(turn), cy + 80 * math.sin(turn), steps=12,
                 duration=0.5, modifiers=browser.ALT)
    views = slice_views_settled(browser, 'the oblique views',
                                'Math.abs(v.coronal.normal[0]) > 0.5')
    cor, sag, ax = views['coronal'], views['sagittal'], views['axial']
    # Turned by +60 degrees on the screen (y down) about right x down = +z: P goes to
    # (-sin, cos, 0), L to (cos, sin, 0).
    want_cor = [-math.sin(turn), math.cos(turn), 0.0]
    want_sag = [math.cos(turn), math.sin(turn), 0.0]
    gap = max(max(abs(x - y) for x, y in zip(cor['normal'], want_cor)),
              max(abs(x - y) for x, y in zip(sag['normal'], want_sag)))
    checks.check('b. alt+drag of 60 degrees in the axial view turns the coronal and sagittal '
                 'planes by 60 degrees about the axial normal; the axial view stays',
                 gap < 0.03 and ax['normal'] == [0, 0, 1] and ax['right'] == [1, 0, 0],
                 f'normals off by {gap:.4f}', f"coronal {[rnd(x, 3) for x in cor['normal']]}, "
                 f"sagittal {[rnd(x, 3) for x in sag['normal']]}")
    letters = {k: [letter([-x for x in w['down']]), letter(w['down']),
                   letter([-x for x in w['right']]), letter(w['right'])]
               for k, w in views.items()}
    checks.check('b. the orientation letters are the nearest patient directions of the turned '
                 'views', all(views[k]['letters'] == letters[k] for k in views) and
                 letters['coronal'][2:] == ['A', 'P'],
                 ' '.join(f"{k} {''.join(w['letters'])}" for k, w in views.items()),
                 f'want {letters}')

    # c. a click in the oblique coronal view: the crosshair on that plane, the readout the
    # trilinear sample there, the image's pixels trilinear samples at their world points
    r = browser.evaluate("viewer.center('.slice-cell[data-axis=coronal] .slice')")
    browser.click(r['x'] + 0.13 * r['w'], r['y'] - 0.07 * r['h'])
    browser.wait_for('viewer.readout() && JSON.stringify(viewer.readout().point) === '
                     'JSON.stringify(viewer.slicePoint())', timeout=10, what='the readout')
    views = slice_views_settled(browser, 'the views through the clicked point',
                                "Object.values(v).every((x) => x.format === 'png')")
    point = browser.evaluate('viewer.slicePoint()')
    readout = browser.evaluate('viewer.readout()')['values'][0]
    cor = views['coronal']
    off = abs(dot([p - q for p, q in zip(point, cor['point'])], cor['normal']))
    want = trilinear(point)
    got = readout.get('sample')
    checks.check("c. the oblique coronal view's readout at the crosshair is the trilinear "
                 'sample there',
                 got is not None and want is not None and abs(got - want) < 1e-6 and off < 1e-6,
                 f'{got} (want {want})', f'{off:.2g} mm off the plane; point '
                 f'{[rnd(x, 3) for x in point]}')
    pixels, want = [], []
    for gy in range(10):
        for gx in range(10):
            x, y = int((gx + 0.5) * cor['width'] / 10), int((gy + 0.5) * cor['height'] / 10)
            s = trilinear(pixel_world(cor, x, y))
            if s is not None:
                pixels.append([x, y])
                want.append(s)
    got = [b * WINDOW[1] / 255 for b in view_bytes(browser, 'coronal', pixels)]
    worst = max((abs(g - w) for g, w in zip(got, want)), default=math.inf)
    checks.check("c. the oblique coronal image's pixels are trilinear samples at their world "
                 'points', len(pixels) >= 20 and worst <= WINDOW[1] / 255,
                 f'largest gap {worst:.2f} over {len(pixels)} pixels')
    # d. copy link keeps the turn: its rotation's P column is the coronal view's normal
    link = browser.evaluate('viewer.viewLink()')
    view = json.loads(urllib.parse.unquote(link.split('#view=')[1]))
    rot = view.get('rotation') or [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    gap = max(abs(rot[i][1] - cor['normal'][i]) for i in range(3))
    checks.check("d. copy link carries the crosshair's turn", gap < 1e-9,
                 f'P column off the coronal normal by {gap:.2g}')
    errors = [m for _, m in watcher.of_type('error')]
    checks.check('no error from the server and no page error',
                 not errors and not browser.page_errors, f'{len(errors)} errors',
                 str(errors[:2] + browser.page_errors[:2]))
    code, _ = server.stop()
    checks.check('the server exits 0 on SIGINT', code == 0, f'exit {code}')


def run_measure(args, out, cleanup):
    server = start_server(args, os.path.abspath(args.scene),
                          ['--port', '0', '--bind', '127.0.0.1', '--max-image-side', '512'],
                          out, cleanup)
    browser = start_browser(args, out, cleanup)
    browser.navigate(server.wait_url(120), timeout=30)
    wait_converged(browser, 180, 'after load')
    browser.evaluate("viewer.setLayout('2x2')")
    slice_views_settled(browser, 'the three 2-D views')
    for i in range(args.measure):
        axis = ('axial', 'coronal', 'sagittal')[i % 3]
        set_slab(browser, axis, 10 if i % 2 == 0 else 20, 'mip')
        slice_views_settled(browser, 'a slab change')
        wheel(browser, axis, -100 if i % 2 == 0 else 100)
        browser.wait_for('viewer.slicesSettled()', timeout=15, what='a slice step')
        slice_views_settled(browser, 'a slice step with slabs')
        time.sleep(0.4)  # the slab views' full PNG after the step
        slice_views_settled(browser, "the slab views' PNG",
                            "Object.values(v).every((x) => x.format === 'png')")
    slab = browser.evaluate("viewer.inputLatencies('slab')")
    slab_set = browser.evaluate("viewer.inputLatencies('slab-set')")
    steps = browser.evaluate('viewer.sliceLatencies()')
    timings = browser.evaluate('viewer.sliceTimings()')
    views = browser.evaluate('viewer.sliceViews()')
    png = [t for t in timings if t['format'] == 'png']
    jpeg = [t for t in timings if t['format'] == 'jpeg']
    result = {'scene': args.scene,
              'views': {a: [v['width'], v['height']] for a, v in views.items()},
              'slab_change': {'n': len(slab), 'median_ms': rnd(percentile(slab, 0.5)),
                              'p95_ms': rnd(percentile(slab, 0.95))},
              'slab_set_png': {'n': len(slab_set), 'median_ms': rnd(percentile(slab_set, 0.5)),
                               'p95_ms': rnd(percentile(slab_set, 0.95))},
              'step_with_slabs': {'n': len(steps), 'median_ms': rnd(percentile(steps, 0.5)),
                                  'p95_ms': rnd(percentile(steps, 0.95))},
              'png_render_encode_ms': [rnd(percentile([t['render_ms'] for t in png], 0.5)),
                                       rnd(percentile([t['encode_ms'] for t in png], 0.5))],
              'jpeg_render_encode_ms': [rnd(percentile([t['render_ms'] for t in jpeg], 0.5)),
                                        rnd(percentile([t['encode_ms'] for t in jpeg], 0.5))],
              'load': os.getloadavg()[0]}
    print(json.dumps(result))
    with open(os.path.join(out, 'measure-slab.json'), 'w') as f:
        json.dump(result, f, indent=1)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    ap.add_argument('--intermix', default='build/intermix', help='the intermix program')
    ap.add_argument('--out', help='folder for logs (default: a new temporary folder, kept)')
    ap.add_argument('--scene', help='measure mode: the scene to serve')
    ap.add_argument('--measure', type=int, default=0, metavar='N',
                    help='measure mode: N slab changes and N slice steps with slabs')
    ap.add_argument('--chromium', help='the browser (default /usr/bin/chromium)')
    ap.add_argument('--timeout', type=float, default=180, help='overall limit in seconds')
    args = ap.parse_args()
    status = preflight(args)
    if status is not None:
        return status
    if args.measure and not args.scene:
        print('error: --measure needs --scene', file=sys.stderr)
        return 2
    out = output_folder(args, 'imx-slab-test-')
    alarm_after(args.timeout)
    checks, cleanup, status, t0 = Checks(), [], 0, time.monotonic()
    try:
        if args.measure:
            run_measure(args, out, cleanup)
        else:
            log(f'slab browser test, output in {out}')
            run_test(args, out, checks, cleanup)
    except (Failure, CdpError, OSError, subprocess.SubprocessError,
            websocket.WebSocketException) as e:
        checks.check('run completed', False, type(e).__name__, str(e))
        status = 1
    finally:
        finish(cleanup)
    if args.measure:
        return status
    failed = checks.failed()
    log(f'{len(checks.results) - len(failed)} of {len(checks.results)} checks passed in '
        f'{time.monotonic() - t0:.1f} s; output in {out}')
    return 1 if failed or status else 0


if __name__ == '__main__':
    sys.exit(main())
