"""ctest Python.PipInstall: `pip install --no-build-isolation .` into a fresh virtual environment.

    check_pip_install.py BUILD_DIR SOURCE_DIR
Makes a venv with --system-site-packages (Debian's numpy, setuptools and wheel) in a temporary
folder, installs the source tree into it offline (--no-index) with INTERMIX_BUILD_DIR=BUILD_DIR
(setup.py takes the extension module from that build instead of building its own), then imports
intermix from outside the tree and renders. Exits 77 (skipped) when venv or pip is missing.
"""

import os
import subprocess
import sys
import tempfile
import time

build, source = (os.path.abspath(p) for p in sys.argv[1:3])
start = time.monotonic()
with tempfile.TemporaryDirectory() as work:
    venv = os.path.join(work, "venv")
    made = subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", venv],
                          capture_output=True, text=True)
    if made.returncode != 0:
        print(f"SKIP: python3 -m venv failed (apt-get install python3-venv): {made.stderr.strip()}")
        sys.exit(77)
    python = os.path.join(venv, "bin", "python")
    if subprocess.run([python, "-m", "pip", "--version"], capture_output=True).returncode != 0:
        print("SKIP: no pip in the venv (apt-get install python3-pip)")
        sys.exit(77)
    env = dict(os.environ, INTERMIX_BUILD_DIR=build, PIP_NO_INDEX="1",
               PIP_DISABLE_PIP_VERSION_CHECK="1")
    env.pop("PYTHONPATH", None)
    subprocess.run([python, "-m", "pip", "install", "--no-build-isolation", "-q", source],
                   check=True, env=env, cwd=work)
    installed = time.monotonic()
    code = (
        "import intermix, os, sys\n"
        "assert os.path.realpath(intermix.__file__).startswith(os.path.realpath(sys.prefix)), "
        "intermix.__file__\n"
        "s = intermix.Scene.from_dict({'image': {'width': 16, 'height': 16}, 'camera': "
        "{'view': 'left'}, 'objects': [{'name': 'c', 'type': 'volume', 'source': "
        "intermix.phantom('cube', 16), 'transfer_function': {'points': [[0, 0, 0, 0, 0], "
        "[255, 1, 1, 1, 1]]}}]})\n"
        "image = s.render(method='mdvr')\n"
        "assert image.shape == (16, 16, 4) and image[..., 3].max() > 0.5\n"
        "print('imported', intermix.__version__, 'from', intermix.__file__)\n")
    subprocess.run([python, "-c", code], check=True, env=env, cwd=work)
    subprocess.run([python, "-m", "pip", "show", "-q", "intermix"], check=True, env=env,
                   cwd=work, stdout=subprocess.DEVNULL)
print(f"check_pip_install: ok (install {installed - start:.1f} s, all "
      f"{time.monotonic() - start:.1f} s)")
