#!/usr/bin/python3
"""Scene.show in Jupyter (issue 47): a notebook executed by `jupyter nbconvert --execute` shows a
scene; headless Chromium opens the view it serves and gets a converged frame equal to
scene.render() at that size (40 dB or better); a visibility click on the page reaches `scene`,
and scene.set(...) reaches the page; the HTML nbconvert writes holds the iframe and, for when
the kernel has gone, the scene's frame as a PNG.

  python/tests/check_notebook.py BUILD_DIR

Debian's /usr/bin/python3 with `scripts/install-deps --with-notebook` (jupyter-nbconvert,
python3-ipykernel) and chromium. Exits 77 (skipped) when Jupyter or Chromium is missing.
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
CDP = os.path.join(HERE, "..", "..", "tests", "viewer")

CELLS = [
    """
import base64, io, json, sys, time
sys.path.insert(0, CDP)
import numpy as np
import PIL.Image
import intermix
from cdp import Browser
scene = intermix.Scene.from_dict({
    "image": {"width": 96, "height": 64},
    "render": {"method": "mdvr", "spp": 1},
    "objects": [{"name": "ct", "type": "volume", "source": {"phantom": "ct-head", "size": 40},
                 "transfer_function": {"preset": "ct-bone"}}]})
view = scene.show(width=320, height=240)
view
""",
    """
def converged(b):
    b.wait_for("Boolean(window.viewerStats && viewerStats.connected && viewerStats.converged)",
               timeout=60, what="a converged frame")

def canvas(b):
    url = b.evaluate("document.getElementById('view').toDataURL('image/png')")
    return np.asarray(PIL.Image.open(io.BytesIO(base64.b64decode(url.split(',', 1)[1]))).convert('RGBA'))

def psnr(a, b):
    e = np.mean((a[..., :3].astype(float) - b[..., :3].astype(float)) ** 2)
    return 99.0 if e == 0 else 10 * np.log10(255 ** 2 / e)

browser = Browser().start()
browser.navigate(view.url, timeout=30)
converged(browser)
shown = canvas(browser)
rendered = scene.render(width=shown.shape[1], height=shown.shape[0]).to_uint8()
db = psnr(shown, rendered)
print(f"NOTEBOOK converged frame {shown.shape[1]}x{shown.shape[0]}: {db:.1f} dB against scene.render()")
assert db >= 40, db
""",
    """
box = json.dumps('.object[data-name="ct"] input.visible')
at = browser.evaluate(f"viewer.center({box})")
browser.click(at["x"], at["y"])
deadline = time.monotonic() + 20
while scene.to_dict()["objects"][0].get("visible", True) and time.monotonic() < deadline:
    time.sleep(0.05)
assert scene.to_dict()["objects"][0]["visible"] is False, "the page's click did not reach the scene"
print("NOTEBOOK page -> scene: visible", scene.to_dict()["objects"][0]["visible"])
scene.set("objects[0].visible", True)
browser.wait_for(f"document.querySelector({box}).checked", timeout=20,
                 what="the page to show the scene's edit")
print("NOTEBOOK scene -> page: checked", browser.evaluate(f"document.querySelector({box}).checked"))
""",
    """
browser.close()
view.close()
print("NOTEBOOK closed", view)
""",
]


def main():
    build = os.path.abspath(sys.argv[1])
    nbconvert = shutil.which("jupyter-nbconvert")
    if nbconvert is None or shutil.which("chromium") is None:
        print("check_notebook: skipped: needs jupyter-nbconvert and chromium "
              "(scripts/install-deps --with-notebook)")
        return 77
    try:
        import ipykernel  # noqa: F401
    except ImportError:
        print("check_notebook: skipped: needs python3-ipykernel (scripts/install-deps --with-notebook)")
        return 77
    notebook = {"nbformat": 4, "nbformat_minor": 5,
                "metadata": {"kernelspec": {"name": "python3", "display_name": "Python 3",
                                            "language": "python"}},
                "cells": [{"cell_type": "code", "metadata": {}, "execution_count": None,
                           "outputs": [], "id": f"cell{i}",
                           "source": cell.replace("CDP", repr(os.path.abspath(CDP))).strip()}
                          for i, cell in enumerate(CELLS)]}
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "show.ipynb")
        with open(path, "w") as f:
            json.dump(notebook, f)
        env = dict(os.environ, PYTHONPATH=os.path.join(build, "python"))
        run = subprocess.run([nbconvert, "--to", "html", "--execute",
                              "--ExecutePreprocessor.timeout=180", path, "--output-dir", folder],
                             env=env, capture_output=True, text=True, timeout=600)
        if run.returncode != 0:
            print(run.stdout[-4000:], run.stderr[-8000:])
            print("check_notebook: FAIL: the notebook did not run")
            return 1
        with open(os.path.join(folder, "show.html")) as f:
            html = f.read()
    # The cells' printed results (their sources, which hold the same words, are not in <pre>).
    printed = [line.strip().removeprefix("<pre>") for line in html.splitlines()
               if line.strip().removeprefix("<pre>").startswith("NOTEBOOK ")]
    for line in printed:
        print(line)
    checks = {"the view's iframe": '<iframe src="http://127.0.0.1:' in html,
              "the frame for a saved notebook": "data:image/png;base64," in html,
              "a converged frame": any(p.startswith("NOTEBOOK converged frame") for p in printed),
              "page -> scene": "NOTEBOOK page -&gt; scene: visible False" in printed,
              "scene -> page": "NOTEBOOK scene -&gt; page: checked True" in printed,
              "closed": any(p.startswith("NOTEBOOK closed") for p in printed)}
    for what, ok in checks.items():
        print(f"check_notebook: {'PASS' if ok else 'FAIL'}: {what}")
    return 0 if all(checks.values()) else 1


if __name__ == "__main__":
    sys.exit(main())
