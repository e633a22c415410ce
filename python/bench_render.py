#!/usr/bin/env python3
"""A render from Python against the CLI's render of the same scene, in one run.

For each scene and method: `intermix render SCENE --method M` (its render time, which it prints
on stderr, excludes loading and writing, as Scene.render excludes loading) and
`scene.render(method=M)` (wall time of the call: argument checks, the worker thread, the
render and the numpy image, which owns the engine's pixels without a copy), interleaved over
--rounds rounds with the order alternating, after one warm-up each; medians and their ratio.

    PYTHONPATH=build/python python3 python/bench_render.py [--rounds 7] [--method mdvr] [SCENE...]
"""

import argparse
import os
import re
import statistics
import subprocess
import sys
import time

import intermix

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
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


def python_seconds(scene, method, kw):
    start = time.perf_counter()
    scene.render(method=method, **kw)
    return time.perf_counter() - start


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

    print(f"{'scene':<14} {'method':<13} {'CLI ms':>9} {'Python ms':>10} {'ratio':>7}")
    for path in args.scenes:
        scene = intermix.Scene.from_file(path)
        for method in methods:
            cli_seconds(args.cli, path, method, extra)  # warm-up: page cache, CPU clocks
            python_seconds(scene, method, kw)
            cli, py = [], []
            for r in range(args.rounds):
                pair = [lambda: cli.append(cli_seconds(args.cli, path, method, extra)),
                        lambda: py.append(python_seconds(scene, method, kw))]
                for run in pair if r % 2 == 0 else reversed(pair):
                    run()
            c, p = statistics.median(cli), statistics.median(py)
            name = os.path.basename(path)
            print(f"{name:<14} {method:<13} {c * 1e3:9.1f} {p * 1e3:10.1f} {p / c:7.3f}", flush=True)


if __name__ == "__main__":
    main()
