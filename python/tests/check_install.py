"""ctest Python.Install: `cmake --install --component python` into a temporary prefix, then
import from there.

    check_install.py BUILD_DIR
Checks that the component installs the package alone (no program, headers or libraries), in the
folder install_dir.py names for the prefix, that a fresh interpreter imports it from there (not
from the build folder) and that it renders.
"""

import os
import subprocess
import sys
import tempfile

here = os.path.dirname(os.path.abspath(__file__))
build = sys.argv[1]
with tempfile.TemporaryDirectory() as prefix:
    subprocess.run(["cmake", "--install", build, "--prefix", prefix, "--component", "python"],
                   check=True, stdout=subprocess.DEVNULL)
    site = subprocess.run([sys.executable, os.path.join(here, "..", "install_dir.py"), prefix],
                          check=True, capture_output=True, text=True).stdout.strip()
    for name in ("__init__.py", "__init__.pyi", "py.typed", "_images.py", "_figures.py",
                 "_movies.py", "web/index.html"):  # web: the page Scene.show serves
        assert os.path.isfile(os.path.join(site, "intermix", name)), name
    everything = [os.path.relpath(os.path.join(d, f), prefix)
                  for d, _, files in os.walk(prefix) for f in files]
    strays = [f for f in everything if not os.path.realpath(os.path.join(prefix, f)).startswith(
        os.path.realpath(os.path.join(site, "intermix")))]
    assert not strays, f"the python component installed more than the package: {strays[:5]}"
    env = dict(os.environ, PYTHONPATH=site)
    code = ("import intermix, os, sys; "
            "assert os.path.realpath(intermix.__file__).startswith(sys.argv[1]), intermix.__file__; "
            "s = intermix.Scene.from_dict({'image': {'width': 8, 'height': 8}, 'objects': ["
            "{'name': 'c', 'type': 'volume', 'source': intermix.phantom('cube', 16), "
            "'transfer_function': {'points': [[0, 0, 0, 0, 0], [255, 1, 1, 1, 1]]}}]}); "
            "v = s.show(); assert 'iframe' in v._repr_html_(); v.close(); "
            "print(intermix.__file__, s.render(method='mdvr').shape)")
    subprocess.run([sys.executable, "-c", code, os.path.realpath(prefix)], check=True, env=env,
                   cwd=prefix)
print("check_install: ok")
