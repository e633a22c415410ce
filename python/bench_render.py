#!/usr/bin/env python3
"""A render from Python against the CLI's render of the same scene, in one run.

For each scene and method: `intermix render SCENE --method M` (the render time it prints on
stderr, which excludes loading and writing) against `scene.render(method=M)` on a scene just
loaded with Scene.from_file (the wall time of the call: argument checks, the worker thread, the
render, and the numpy image, which takes over the engine's pixels without a copy). Both start
cold: the engine derives gradients, bricks and distance maps per volume on its first render and
keeps them while the volume lives, which a CLI process never sees twice. A second render of the
same scene ("warm") shows what a Python session gains from that. Interleaved over --rounds
rounds with the order alternating, after one warm-up each; medians and ratios.

    PYTHONPATH=build/python python3 python/bench_render.py [--rounds 7] [--method mdvr] [SCENE...]
"""

import argparse
import os
import re
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
# python/intermix is the package's source, without the extension module: use the built one.
sys.path = [p for p in sys.path if os.path.abspath(p or ".") != HERE]
import intermix  # noqa: E402
TIME = re.compile(r" in ([0-9.]+) s -> ")


def cli_seconds(cli, scene, method, extra):
    out = os.path.join(os.environ.get("TMPDIR", "/tmp"), f"bench_render_{os.getpid()}.png")
    run = subprocess.run([cli, "render", scene, "-o", out, "--method", method] + extra,
                         capture_output=True, text=True, check=True)
    os.remove(out)
    match = TIME.search(run.stderr)
    if not match:
        sys.exit(f"bench_render: no render time in the CLI's output: {run.stderr!r}")
    return float(match.group(1))


def python_seconds(path, method, kw):
    """A render of a freshly loaded scene (cold), and a second render of it (warm)."""
    scene = intermix.Scene.from_file(path)
    times = []
    for _ in range(2):
        start = time.perf_counter()
        scene.render(method=method, **kw)
        times.append(time.perf_counter() - start)
    return times


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", nargs="*", default=[os.path.join(ROOT, "examples", n)
                                                        for n in ("ct-head.json", "fusion.json")])
    parser.add_argument("--method", action="append", help="repeatable; default mdvr and zslab-hybrid")
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--size", type=int, help="image width and height (default: the scene's)")
    parser.add_argument("--cli", default=os.path.join(ROOT, "build", "intermix"))
    args = parser.parse_args()
    methods = args.method or ["mdvr", "zslab-hybrid"]
    extra, kw = [], {}
    if args.size:
        extra = ["--width", str(args.size), "--height", str(args.size)]
        kw = {"width": args.size, "height": args.size}

    print(f"{'scene':<14} {'method':<13} {'CLI ms':>9} {'Python ms':>10} {'ratio':>7} "
          f"{'warm ms':>9} {'ratio':>7}")
    for path in args.scenes:
        for method in methods:
            cli_seconds(args.cli, path, method, extra)  # warm-up: page cache, CPU clocks
            python_seconds(path, method, kw)
            cli, cold, warm = [], [], []

            def run_python():
                c, w = python_seconds(path, method, kw)
                cold.append(c)
                warm.append(w)

            for r in range(args.rounds):
                pair = [lambda: cli.append(cli_seconds(args.cli, path, method, extra)), run_python]
                for run in pair if r % 2 == 0 else reversed(pair):
                    run()
            c, p, w = (statistics.median(x) for x in (cli, cold, warm))
            name = os.path.basename(path)
            print(f"{name:<14} {method:<13} {c * 1e3:9.1f} {p * 1e3:10.1f} {p / c:7.3f} "
                  f"{w * 1e3:9.1f} {w / c:7.3f}", flush=True)


if __name__ == "__main__":
    main()
