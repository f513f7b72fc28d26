#!/usr/bin/env python3
"""A large world on one host: the server, three nodes, the view and the DIS gateway on an elevation
file of posts x posts posts, sharing its ground through the host's ground cache file
(docs/real-ground.md "Large worlds"). Prints, per process and for the host, the resident memory
(Rss) and the proportional share (Pss, from /proc/<pid>/smaps_rollup) and the ground cache
mapping's Rss and Pss (from /proc/<pid>/smaps), and each process's ground load time; checks that
every process came up and that the ground is held once on the host: the sum over the processes of
the cache mapping's Pss is at most 1.2 times the cache file (never once per process).

Run inside tests/run_in_netns.sh (a private network namespace). Readiness is each process's READY
line (tests/pylib/exercise_processes.py); processes are stopped by PID; the work directory is
removed at the end unless --keep.

The raster is made here: an analytic surface written with numpy as a raw float grid (EHdr) and
made a tiled GeoTIFF in UTM zone 33N by gdal_translate; nothing is committed or fetched.

Usage: large_world_test.py <bin dir> <key file> <work dir> [--posts N] [--spacing-m S]
       [--baseline-posts M] [--keep]
  <bin dir> holds dt_server, dt_node, dt_view, dt_dis and dt_ctl (build/<preset>/bin or the
  programs' folders: each is looked for as <bin dir>/<room>/<program> then <bin dir>/<program>).
  --baseline-posts M also runs the same processes on an M x M world first and prints the host's
  growth from it over the packed ground (the memory goal: at most 1.2, plus features).
Exit 0: pass; 1: fail.
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "pylib"))
from exercise_processes import ExerciseProcesses  # noqa: E402

E0, N0 = 500000.0, 4000000.0  # the raster's south-west corner, UTM 33N
PROGRAMS = {"dt_server": "server", "dt_node": "node", "dt_view": "view", "dt_dis": "dis",
            "dt_ctl": "node"}
PROCESSES = [("server", "dt_server"), ("node-1", "dt_node"), ("node-2", "dt_node"),
             ("node-3", "dt_node"), ("view", "dt_view"), ("dis", "dt_dis")]

EXERCISE = """\
[exercise]
name = "large"
id = 1
transport = "udpm://239.255.76.67:7667?ttl=0"
run_dir = "run"
tick_hz = 30

[auth]
key_file = "{key}"

[terrain]
elevation_file = "{raster}"
ground_cache_dir = "cache"

[server]
name = "server"
site = 1
host = 100

[[node]]
name = "node-1"
site = 1
host = 1
[[node.vehicle]]
type = "tank"
x_m = {x1}
z_m = {z1}
heading_deg = 0

[[node]]
name = "node-2"
site = 1
host = 2
[[node.vehicle]]
type = "truck"
x_m = {x2}
z_m = {z1}
heading_deg = 90

[[node]]
name = "node-3"
site = 1
host = 3

[view]
name = "view"
site = 1
host = 50
http_port = 8480

[dis]
name = "dis"
site = 1
host = 60
dis_exercise_id = 1
"""


def find_program(bin_dir, program):
    for path in (os.path.join(bin_dir, PROGRAMS[program], program), os.path.join(bin_dir, program)):
        if os.access(path, os.X_OK):
            return path
    sys.exit(f"FAIL: {program} not found under {bin_dir}")


def make_raster(work, posts, spacing_m):
    """A tiled GeoTIFF of posts x posts pixels `spacing_m` apart: ridges and a slope, written row
    block by row block so the script never holds the whole grid."""
    import numpy as np
    raw = os.path.join(work, f"area{posts}.bil")
    with open(raw, "wb") as f:
        x = np.arange(posts, dtype=np.float64) * spacing_m
        for r0 in range(0, posts, 256):
            rows = np.arange(r0, min(posts, r0 + 256), dtype=np.float64)
            n = (posts - 1 - rows)[:, None] * spacing_m  # row 0 is the north edge
            z = 200.0 + 0.01 * x[None, :] + 0.005 * n + 40.0 * np.sin(x[None, :] / 900.0) * \
                np.cos(n / 700.0)
            f.write(z.astype("<f4").tobytes())
    with open(os.path.join(work, f"area{posts}.hdr"), "w") as f:
        f.write(f"BYTEORDER I\nLAYOUT BIL\nNROWS {posts}\nNCOLS {posts}\nNBANDS 1\nNBITS 32\n"
                f"PIXELTYPE FLOAT\nULXMAP {E0}\nULYMAP {N0 + (posts - 1) * spacing_m}\n"
                f"XDIM {spacing_m}\nYDIM {spacing_m}\n")
    tif = os.path.join(work, f"area{posts}.tif")
    subprocess.run(["gdal_translate", "-q", "-of", "GTiff", "-co", "TILED=YES", "-a_srs",
                    "EPSG:32633", raw, tif], check=True)
    os.remove(raw)
    os.remove(os.path.join(work, f"area{posts}.hdr"))
    return tif


def smaps_rollup(pid):
    out = {}
    with open(f"/proc/{pid}/smaps_rollup") as f:
        for line in f:
            m = re.match(r"(\w+):\s+(\d+) kB", line)
            if m:
                out[m.group(1)] = int(m.group(2))
    return out


def mapping_of(pid, path):
    """Rss and Pss (kB) of the process's mappings of `path`."""
    rss = pss = 0
    inside = False
    with open(f"/proc/{pid}/smaps") as f:
        for line in f:
            if re.match(r"^[0-9a-f]+-[0-9a-f]+ ", line):
                inside = line.rstrip().endswith(path)
            elif inside and line.startswith("Rss:"):
                rss += int(line.split()[1])
            elif inside and line.startswith("Pss:"):
                pss += int(line.split()[1])
    return rss, pss


def run_world(args, programs, posts, work):
    """Starts the six processes on a posts x posts world; returns the figures."""
    os.makedirs(work, exist_ok=True)
    t0 = time.time()
    raster = make_raster(work, posts, args.spacing_m)
    print(f"raster {posts} x {posts} made in {time.time() - t0:.1f} s "
          f"({os.path.getsize(raster) >> 20} MB)")
    size_m = (posts - 1) * args.spacing_m
    exercise = os.path.join(work, "large.toml")
    with open(exercise, "w") as f:
        f.write(EXERCISE.format(key=args.key, raster=raster, x1=size_m * 0.3, z1=size_m * 0.3,
                                x2=size_m * 0.6))
    ex = ExerciseProcesses(programs, exercise, os.path.join(work, "run"))
    figures = {"posts": posts, "procs": {}}
    try:
        for name, program in PROCESSES:
            t = time.time()
            p = ex.start(name, program, ready_s=args.ready_s)
            figures["procs"][name] = {"pid": p.pid, "ready_s": time.time() - t}
        cache_files = [os.path.join(work, "cache", n) for n in os.listdir(os.path.join(work, "cache"))
                       if n.endswith(".dtg")]
        if len(cache_files) != 1:
            ex.fail(f"expected one ground cache file, found {cache_files}")
        cache = cache_files[0]
        figures["cache_mb"] = os.path.getsize(cache) / 2**20
        for name, _ in PROCESSES:
            pid = figures["procs"][name]["pid"]
            r = smaps_rollup(pid)
            rss, pss = mapping_of(pid, cache)
            log = open(os.path.join(work, "run", f"{name}.log"), errors="replace").read()
            m = re.search(r"terrain \d+ x \d+ posts .*?, (read into|mapped from) the ground cache"
                          r".*? in (\d+) ms", log)
            figures["procs"][name].update(rss_mb=r["Rss"] / 1024, pss_mb=r["Pss"] / 1024,
                                          cache_rss_mb=rss / 1024, cache_pss_mb=pss / 1024,
                                          load=(m.group(1), int(m.group(2))) if m else None)
    finally:
        # Every process stops within 10 s (the server's last digest no longer reads the ground
        # afresh): one that does not is killed and fails below.
        t0 = time.monotonic()
        codes = ex.stop_all(timeout_s=10)
        figures["stop_s"] = time.monotonic() - t0
    figures["codes"] = codes
    return figures


def report(f):
    print(f"{f['posts']} x {f['posts']} posts; ground cache file {f['cache_mb']:.1f} MB")
    print(f"{'process':8} {'Rss MB':>9} {'Pss MB':>9} {'cache Rss':>10} {'cache Pss':>10}  load")
    for name, p in f["procs"].items():
        load = f"{p['load'][0]} in {p['load'][1]} ms" if p["load"] else "?"
        print(f"{name:8} {p['rss_mb']:9.1f} {p['pss_mb']:9.1f} {p['cache_rss_mb']:10.1f} "
              f"{p['cache_pss_mb']:10.1f}  {load}")
    total = sum(p["pss_mb"] for p in f["procs"].values())
    cache_pss = sum(p["cache_pss_mb"] for p in f["procs"].values())
    print(f"host: Pss {total:.1f} MB, of it the ground cache {cache_pss:.1f} MB "
          f"({cache_pss / f['cache_mb']:.2f} x the file)")
    for name, p in f["procs"].items():
        if p["load"]:
            per = p["load"][1] / (f["posts"] ** 2 / 1e6)
            print(f"load {name}: {p['load'][0]} the cache, {per:.1f} ms per 10^6 posts")
    return total, cache_pss


def main():
    a = argparse.ArgumentParser()
    a.add_argument("bin_dir")
    a.add_argument("key")
    a.add_argument("work")
    a.add_argument("--posts", type=int, default=5001)
    a.add_argument("--spacing-m", type=float, default=10.0)
    a.add_argument("--baseline-posts", type=int, default=0)
    a.add_argument("--ready-s", type=float, default=600.0)
    a.add_argument("--keep", action="store_true")
    args = a.parse_args()
    args.key = os.path.abspath(args.key)
    args.bin_dir = os.path.abspath(args.bin_dir)
    programs = {p: find_program(args.bin_dir, p) for p in PROGRAMS}
    shutil.rmtree(args.work, ignore_errors=True)
    ok = True
    try:
        base_total = None
        if args.baseline_posts:
            base = run_world(args, programs, args.baseline_posts, os.path.join(args.work, "base"))
            base_total, _ = report(base)
        f = run_world(args, programs, args.posts, os.path.join(args.work, "large"))
        total, cache_pss = report(f)
        if base_total is not None:
            growth = total - base_total
            print(f"host growth over the {args.baseline_posts}^2 world: {growth:.1f} MB = "
                  f"{growth / f['cache_mb']:.2f} x the packed ground ({f['cache_mb']:.1f} MB)")
        if cache_pss > 1.2 * f["cache_mb"]:
            print(f"FAIL: the processes' ground cache Pss sum to {cache_pss:.1f} MB, more than "
                  f"1.2 x the {f['cache_mb']:.1f} MB file: the ground is not shared")
            ok = False
        for name in ("node-1", "node-2", "node-3"):
            p = f["procs"][name]
            if p["cache_rss_mb"] < 0.5 * f["cache_mb"] or p["cache_pss_mb"] > 0.5 * p["cache_rss_mb"]:
                print(f"FAIL: {name} maps {p['cache_rss_mb']:.1f} MB of the ground cache with "
                      f"Pss {p['cache_pss_mb']:.1f} MB: not mapped, or not shared")
                ok = False
        print(f"stopped, every process, in {f['stop_s']:.1f} s")
        bad = {n: c for n, c in f["codes"].items() if c not in (0, -15)}
        if bad:
            print(f"FAIL: processes exited with {bad}")
            ok = False
    finally:
        if not args.keep:
            shutil.rmtree(args.work, ignore_errors=True)
    print("PASS" if ok else "FAIL")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
