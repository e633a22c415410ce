"""Prints the folder `cmake --install` puts the intermix package into, for the prefix given.

The folder on this interpreter's own search path (sys.path and the user site) that lies under
the prefix as PREFIX/lib.../dist-packages or site-packages: Debian's python3 searches
/usr/local/lib/python3.X/dist-packages and ~/.local/lib/python3.X/site-packages. Otherwise the
standard platlib for that prefix (PREFIX/lib/python3.X/site-packages), which PYTHONPATH must name.
"""

import os
import site
import sys
import sysconfig


def main() -> None:
    prefix = os.path.realpath(os.path.expanduser(sys.argv[1]))
    candidates = list(sys.path)
    try:
        candidates.append(site.getusersitepackages())
    except AttributeError:  # a virtual environment without user site
        pass
    for path in candidates:
        if not path or not os.path.basename(path) in ("dist-packages", "site-packages"):
            continue
        real = os.path.realpath(path)
        if os.path.commonpath([real, prefix]) != prefix:
            continue
        # PREFIX/lib/...: for the prefix /usr, /usr/local/lib/... is another prefix's folder.
        if os.path.relpath(real, prefix).split(os.sep)[0] in ("lib", "lib64"):
            print(path)
            return
    print(sysconfig.get_path("platlib", "posix_prefix", vars={"base": prefix, "platbase": prefix}))


if __name__ == "__main__":
    main()
