#!/usr/bin/python3
"""intermix render --distributed under a real mpirun (Open MPI), oversubscribed on this machine.

  1. fusion, ct-implant, two-volumes and shells-volumes on 1, 2 and 4 ranks, partitioned by
     objects and by bricks: each image within 0.5 dB of the single-process zslab image, both
     measured against the reference.
  2. ct-head cut into 4 bricks against the unsplit zslab image: 50 dB or better.
  3. A fault on one rank (its brick lies in the truncated part of a raw NRRD): every rank ends
     with the same error naming the file, mpirun exits non-zero, all within 10 s.
  4. Peak memory per rank on a 512^3 volume in bricks mode: each rank holds at most 1/R of the
     voxels plus aprons, and its peak is at most those voxels (5% more for the skipping
     structures) plus the fixed cost measured on a 64^3 volume of the same scene.

Usage: mpi_render_test.py INTERMIX EXAMPLES_DIR [--only N] [--scenes a,b] [--ranks 1,2,4]
                          [--size 96] [--head-size N]
--ranks and --size apply to part 1: the rank counts tried and the image side; --head-size to
part 2: the side of ct-head's phantom (the example's 256 by default).
"""
import json
import os
import re
import subprocess
import sys
import tempfile
import time

SIZE = 96  # image side: small, so the reference renders in seconds (part 1 takes --size)
SCENES = ["fusion", "ct-implant", "two-volumes", "shells-volumes"]
RANKS = [1, 2, 4]


def mpirun(ranks):
    cmd = ["mpirun", "--oversubscribe", "-np", str(ranks)]
    if os.geteuid() == 0:
        cmd.append("--allow-run-as-root")  # CI runs as root; Open MPI refuses it otherwise
    return cmd


def environment(ranks_of_mpirun):
    env = dict(os.environ)
    # Containers often forbid the cross-memory attach Open MPI's shared-memory transport tries.
    env.setdefault("OMPI_MCA_btl_vader_single_copy_mechanism", "none")
    # Under the sanitizers (scripts/test --sanitize) leak checking is off in mpirun's ranks: Open
    # MPI 4.1 keeps registries until exit in plugins it unloads first, so the reports name no
    # module a suppression could match. ASan and UBSan still check every access; the compositing
    # code's leaks are checked in test_dist, which runs the same merge and resolve in one process.
    if ranks_of_mpirun and "ASAN_OPTIONS" in env:
        env["ASAN_OPTIONS"] += ":detect_leaks=0"
    return env


def run(cmd, timeout=600):
    started = time.monotonic()
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout,
                       env=environment(cmd[0] == "mpirun"))
    return p, time.monotonic() - started


def check(cmd, timeout=600):
    p, _ = run(cmd, timeout)
    if p.returncode != 0:
        raise AssertionError(f"{' '.join(cmd)} exited {p.returncode}:\n{p.stderr[-3000:]}")
    return p


def psnr(intermix, a, b):
    out = check([intermix, "compare", a, b, "--json"]).stdout
    value = json.loads(out)["psnr_db"]
    return float("inf") if value == "inf" else float(value)


def render(intermix, scene, out, extra=(), size=SIZE):
    check([intermix, "render", scene, "-o", out, "--width", str(size), "--height", str(size),
           *extra])


def distributed(intermix, ranks, scene, out, partition, report=None, size=SIZE, extra=()):
    cmd = mpirun(ranks) + [intermix, "render", scene, "-o", out, "--distributed",
                           "--partition", partition, "--width", str(size), "--height", str(size),
                           *extra]
    if report:
        cmd += ["--report", report]
    return check(cmd)


def scenes_match_single_process(intermix, examples, tmp, failures, scenes, ranks_tried, size):
    for name in scenes:
        scene = os.path.join(examples, name + ".json")
        ref, single = f"{tmp}/{name}-ref.png", f"{tmp}/{name}-zslab.png"
        render(intermix, scene, ref, ["--method", "reference"], size)
        render(intermix, scene, single, ["--method", "zslab"], size)
        base = psnr(intermix, single, ref)
        for partition in ("objects", "bricks"):
            for ranks in ranks_tried:
                out = f"{tmp}/{name}-{partition}-{ranks}.png"
                distributed(intermix, ranks, scene, out, partition, size=size)
                got = psnr(intermix, out, ref)
                same = psnr(intermix, out, single)
                line = (f"{name:15s} {partition:7s} R={ranks}: {got:6.2f} dB vs reference "
                        f"(zslab {base:6.2f} dB), {same:6.2f} dB vs zslab")
                print(line, flush=True)
                if abs(got - base) > 0.5:
                    failures.append(line + ": more than 0.5 dB from zslab")


def split_equals_unsplit(intermix, examples, tmp, failures, head_size=None):
    scene = os.path.join(examples, "ct-head.json")
    single, split = f"{tmp}/head-zslab.png", f"{tmp}/head-4-bricks.png"
    sized = ["--set", f"objects.ct.source.size={head_size}"] if head_size else []
    render(intermix, scene, single, ["--method", "zslab", *sized])
    report = f"{tmp}/head-4-bricks.json"
    distributed(intermix, 4, scene, split, "bricks", report, extra=sized)
    bricks = sum(1 for r in json.load(open(report))["per_rank"] if "ct[" in r["part"])
    value = psnr(intermix, split, single)
    print(f"ct-head in {bricks} bricks vs unsplit: {value:.2f} dB", flush=True)
    if bricks != 4 or value < 50.0:
        failures.append(f"ct-head in {bricks} bricks: {value:.2f} dB against unsplit (need 4, 50)")


def fault_ends_every_rank(intermix, tmp, failures):
    volume = f"{tmp}/cut.nrrd"
    check([intermix, "phantom", "ct-head", "-o", volume, "--size", "96", "--raw"])
    size = os.path.getsize(volume)
    with open(volume, "r+b") as f:  # the last third of the slices is gone
        f.truncate(size - size // 3)
    scene = f"{tmp}/cut.json"
    json.dump({"camera": {"eye": [0, -500, 0], "target": [0, 0, 0], "up": [0, 0, 1]},
               "image": {"width": 64, "height": 64},
               "objects": [{"name": "ct", "type": "volume", "source": {"file": "cut.nrrd"},
                            "transfer_function": {"points": [[-1000, 0, 0, 0, 0],
                                                             [1000, 1, 1, 1, 0.5]]}}]},
              open(scene, "w"))
    for partition in ("bricks", "objects"):
        p, seconds = run(mpirun(4) + [intermix, "render", scene, "-o", f"{tmp}/cut.png",
                                      "--distributed", "--partition", partition], timeout=60)
        errors = [l for l in p.stderr.splitlines() if "error:" in l]
        print(f"fault ({partition}): exit {p.returncode} after {seconds:.1f} s, "
              f"{len(errors)} error lines: {errors[:1]}", flush=True)
        if p.returncode == 0 or seconds > 10.0:
            failures.append(f"fault ({partition}): exit {p.returncode} after {seconds:.1f} s")
        if len(errors) != 4 or len(set(errors)) != 1 or "cut.nrrd" not in errors[0]:
            failures.append(f"fault ({partition}): expected the same error naming cut.nrrd from "
                            f"4 ranks, got {errors}")
        if os.path.exists(f"{tmp}/cut.png"):
            failures.append(f"fault ({partition}): an image was written")


def memory_per_rank(intermix, tmp, failures):
    results = {}
    for side in (64, 512):
        volume = f"{tmp}/cube{side}.nrrd"
        check([intermix, "phantom", "cube", "-o", volume, "--size", str(side), "--raw"])
        scene = f"{tmp}/cube{side}.json"
        pitch = 256.0 / side  # the same 256 mm cube at both sizes
        json.dump({"camera": {"eye": [300, -500, 250], "target": [128, 128, 128], "up": [0, 0, 1]},
                   "image": {"width": 128, "height": 128},
                   "objects": [{"name": "cube", "type": "volume", "source": {"file": f"cube{side}.nrrd"},
                                "transform": {"scale": [pitch, pitch, pitch]},
                                "transfer_function": {"points": [[0, 1, 0.5, 0.2, 0],
                                                                 [255, 1, 0.5, 0.2, 0.5]]},
                                "shading": {"enabled": False}}]},
                  open(scene, "w"))
        for ranks in (2, 4):
            report = f"{tmp}/cube{side}-{ranks}.json"
            distributed(intermix, ranks, scene, f"{tmp}/cube{side}-{ranks}.png", "bricks",
                        report, size=128)
            results[(side, ranks)] = json.load(open(report))["per_rank"]
        os.remove(volume)
    whole = 512 ** 3  # uint8 voxels: one byte each
    # Per voxel held, 5% more: the skipping structures of its 8^3 bricks and the allocator's
    # rounding (measured: 2.5% on 2 ranks, 2.8% on 4).
    per_voxel = 1.05
    for ranks in (2, 4):
        fixed = max(r["peak_rss_bytes"] for r in results[(64, ranks)])
        for k, r in enumerate(results[(512, ranks)]):
            # Beyond 1/R: at each of its cuts (at most 2 for R <= 4) the shared boundary layer,
            # the apron layer and a layer of rounding where R does not divide the grid.
            apron = 2 * 3 * 512 * 512
            line = (f"512^3 in {ranks} bricks, rank {k}: peak {r['peak_rss_bytes'] / 2**20:.1f} MiB,"
                    f" {r['voxels'] / 2**20:.2f} Mi voxels (1/R {whole / ranks / 2**20:.0f} + apron"
                    f" {apron / 2**20:.1f}), fixed {fixed / 2**20:.1f} MiB")
            print(line, flush=True)
            if r["voxels"] > whole / ranks + apron:
                failures.append(line + ": holds more than 1/R of the voxels plus aprons")
            if r["peak_rss_bytes"] > fixed + per_voxel * r["voxels"]:
                failures.append(line + f": peak over fixed + {per_voxel} B per voxel held")


def main():
    intermix, examples = sys.argv[1], sys.argv[2]
    only = sys.argv[sys.argv.index("--only") + 1] if "--only" in sys.argv else None
    scenes = sys.argv[sys.argv.index("--scenes") + 1].split(",") if "--scenes" in sys.argv else SCENES
    ranks = ([int(r) for r in sys.argv[sys.argv.index("--ranks") + 1].split(",")]
             if "--ranks" in sys.argv else RANKS)
    size = int(sys.argv[sys.argv.index("--size") + 1]) if "--size" in sys.argv else SIZE
    head_size = (int(sys.argv[sys.argv.index("--head-size") + 1]) if "--head-size" in sys.argv
                 else None)
    failures = []
    with tempfile.TemporaryDirectory(prefix="imx-mpi-") as tmp:
        parts = {"1": lambda: scenes_match_single_process(intermix, examples, tmp, failures, scenes,
                                                          ranks, size),
                 "2": lambda: split_equals_unsplit(intermix, examples, tmp, failures, head_size),
                 "3": lambda: fault_ends_every_rank(intermix, tmp, failures),
                 "4": lambda: memory_per_rank(intermix, tmp, failures)}
        for key, part in parts.items():
            if only is None or only == key:
                part()
    for f in failures:
        print("FAIL:", f)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
