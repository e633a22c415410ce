"""Runs the Python package's tests with pytest (ctest's Python.Package); arguments go to pytest.

Exits 77 (ctest: skipped) when pytest or numpy is not installed.
"""

import os
import sys

try:
    import numpy  # noqa: F401
    import pytest
except ImportError as e:
    print(f"python tests skipped: {e} (apt-get install python3-pytest python3-numpy)")
    sys.exit(77)

here = os.path.dirname(os.path.abspath(__file__))
# -p no:cacheprovider: no .pytest_cache in the source tree.
sys.exit(pytest.main(["-p", "no:cacheprovider", here] + sys.argv[1:]))
