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

With --features N, once the memory is measured, node-1's and node-2's vehicles drive (their
scenarios) and the server imports N craters spread over the world: the test exports the server's
terrain (`export`, the ground past 4097 posts a side), writes the same ground with N crater records
(docs/terrain-file-format.md; the checksum through libxxhash) and has the server `import` it, which
issues every crater as an Update. It then checks the promises: every process (server, nodes, view,
gateway) holds the N craters and the same digest, and the DIS gateway's Point Object State of
sampled craters (decoded here from the gateway's UDP port) lies within 1 m of the crater's place by
the raster's georeference (the PDU's geocentric point taken back to UTM 33N by gdaltransform).

With --ground-file the world is a saved terrain instead ([terrain] ground_file, docs/node.md
"Starting from a saved terrain"): the same surface written here as a terrain file
(docs/terrain-file-format.md; the checksum through libxxhash), no raster and no georeference (so
not with --features). The same sharing checks hold; the test also times dt_ctl's `status` against
the exercise (dt_ctl reads no ground), and that of --ctl-compare <dt_ctl> if given.

With --page DIR the live view's page is opened in headless chromium (Playwright, as the browser
tests): the test waits for the whole world's relief to be complete and for both vehicles on the
map, then zooms to a 1 km window around node-1's vehicle and waits for the finer level the page
picks there; it checks that the relief tiles shown have the ground's shading (not one flat colour)
and that the page raised no error, prints how long each picture took, and leaves
DIR/page-whole.png and DIR/page-zoomed.png.

Usage: large_world_test.py <bin dir> <key file> <work dir> [--posts N] [--spacing-m S]
       [--baseline-posts M] [--features F] [--ground-file [--ctl-compare P]] [--page DIR] [--keep]
  <bin dir> holds dt_server, dt_node, dt_view, dt_dis and dt_ctl (build/<preset>/bin or the
  programs' folders: each is looked for as <bin dir>/<room>/<program> then <bin dir>/<program>).
  --baseline-posts M also runs the same processes on an M x M world first and prints the host's
  growth from it over the packed ground (the memory goal: at most 1.2, plus features).
Exit 0: pass; 1: fail.
"""
import argparse
import ctypes
import ctypes.util
import math
import os
import re
import shutil
import signal
import socket
import struct
import subprocess
import sys
import threading
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
{terrain}
ground_cache_dir = "cache"

[server]
name = "server"
site = 1
host = 100

[[node]]
name = "node-1"
site = 1
host = 1
scenario = "drive.toml"
[[node.vehicle]]
type = "tank"
x_m = {x1}
z_m = {z1}
heading_deg = 0

[[node]]
name = "node-2"
site = 1
host = 2
scenario = "drive.toml"
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


# The vehicles circle slowly for the whole run (docs/node.md "Scenario files").
DRIVE = """\
[[step]]
action = "drive"
vehicle = 0
speed_mps = 6
heading_rate_deg_s = 1
"""

FEATURE_ORIGIN = (2, 1)  # site:host of the imported craters: no member's, so no member numbers them
DIS_PORT = 3000
MAX_DIS_NUMBER = 65533  # features numbered above have no DIS number (docs/dis.md)


def find_program(bin_dir, program):
    for path in (os.path.join(bin_dir, PROGRAMS[program], program), os.path.join(bin_dir, program)):
        if os.access(path, os.X_OK):
            return path
    sys.exit(f"FAIL: {program} not found under {bin_dir}")


def make_raster(work, posts, spacing_m):
    """A tiled GeoTIFF of posts x posts pixels `spacing_m` apart: ridges and a slope, written row
    block by row block so the script never holds the whole grid."""
    raw = os.path.join(work, f"area{posts}.bil")
    with open(raw, "wb") as f:
        for r0 in range(0, posts, 256):
            f.write(surface_rows(posts, spacing_m, r0, min(posts, r0 + 256), north_up=True).tobytes())
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


def surface_rows(posts, spacing_m, r0, r1, north_up):
    """Rows r0 .. r1 - 1 of the analytic surface as float32; row 0 is the north edge when
    north_up (a raster's order), else the south edge (a terrain file's, z northwards)."""
    import numpy as np
    x = np.arange(posts, dtype=np.float64) * spacing_m
    rows = np.arange(r0, r1, dtype=np.float64)
    n = ((posts - 1 - rows) if north_up else rows)[:, None] * spacing_m
    z = 200.0 + 0.01 * x[None, :] + 0.005 * n + 40.0 * np.sin(x[None, :] / 900.0) * \
        np.cos(n / 700.0)
    return z.astype("<f4")


def make_ground_file(work, posts, spacing_m):
    """A terrain file (version 3, square) of the same surface, grass soils, no features, written a
    block of rows at a time."""
    path = os.path.join(work, f"area{posts}.dtt")
    ground_bytes = 4 + 8 + 4 * posts * posts + 2 * 2 * (posts - 1) ** 2
    h = Xxh3()
    with open(path, "wb") as out:
        def put(data):
            h.update(data)
            out.write(data)
        put(struct.pack("<8sIQQ", b"\x89DTER\r\n\x1a", 3, ground_bytes, 4))
        put(struct.pack("<Id", posts, spacing_m))
        for r0 in range(0, posts, 256):
            put(surface_rows(posts, spacing_m, r0, min(posts, r0 + 256), north_up=False).tobytes())
        row_soils = struct.pack("<H", 1) * (2 * (posts - 1))  # grass
        for r0 in range(0, posts - 1, 256):
            put(row_soils * (min(posts - 1, r0 + 256) - r0))
        put(struct.pack("<I", 0))
        out.write(struct.pack("<Q", h.digest()))
    return path


def time_ctl(ctl, exercise, run_dir, repeats=5):
    """The median wall times, seconds, of `dt_ctl ... --name server status` and of dt_ctl's start
    alone: reading the exercise file, then refusing a name it does not hold (exit 2)."""
    def median(name, command, code):
        times = []
        for _ in range(repeats):
            t = time.monotonic()
            r = subprocess.run([ctl, "--config", exercise, "--run-dir", run_dir, "--name", name,
                                command], capture_output=True, timeout=60)
            times.append(time.monotonic() - t)
            if r.returncode != code:
                raise RuntimeError(f"dt_ctl --name {name} {command}: exit {r.returncode}: "
                                   f"{r.stderr.decode(errors='replace')}")
        return sorted(times)[len(times) // 2]
    return median("server", "status", 0), median("no-such-process", "status", 2)


class Xxh3:
    """XXH3-64 (seed 0) through the system's libxxhash, streamed (the file's checksum)."""

    def __init__(self):
        lib = ctypes.CDLL(ctypes.util.find_library("xxhash") or "libxxhash.so.0")
        lib.XXH3_createState.restype = ctypes.c_void_p
        lib.XXH3_64bits_reset.argtypes = [ctypes.c_void_p]
        lib.XXH3_64bits_update.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_size_t]
        lib.XXH3_64bits_digest.argtypes = [ctypes.c_void_p]
        lib.XXH3_64bits_digest.restype = ctypes.c_uint64
        lib.XXH3_freeState.argtypes = [ctypes.c_void_p]
        self.lib = lib
        self.state = lib.XXH3_createState()
        lib.XXH3_64bits_reset(self.state)

    def update(self, data):
        self.lib.XXH3_64bits_update(self.state, data, len(data))

    def digest(self):
        d = self.lib.XXH3_64bits_digest(self.state)
        self.lib.XXH3_freeState(self.state)
        return d


def crater_places(count, size_m):
    """`count` craters on a square pattern over the world, away from its edges: (x_m, z_m)."""
    side = math.ceil(math.sqrt(count))
    step = (size_m - 40.0) / side
    return [(20.0 + step * (k % side + 0.5), 20.0 + step * (k // side + 0.5)) for k in range(count)]


def write_with_craters(exported, out_path, places):
    """The exported terrain file's ground with one crater (radius 3 m) per place, numbered 1, 2, ...
    under FEATURE_ORIGIN (docs/terrain-file-format.md), read and written a piece at a time."""
    site, host = FEATURE_ORIGIN
    with open(exported, "rb") as f:
        head = f.read(28)
        magic, version, ground_bytes, _ = struct.unpack("<8sIQQ", head)
        if magic != b"\x89DTER\r\n\x1a":
            raise RuntimeError(f"{exported}: not a terrain file")
        params = 82
        feature_bytes = 4 + len(places) * (12 + params)
        h = Xxh3()
        with open(out_path, "wb") as out:
            def put(data):
                h.update(data)
                out.write(data)
            put(struct.pack("<8sIQQ", magic, version, ground_bytes, feature_bytes))
            left = ground_bytes
            while left:
                piece = f.read(min(left, 1 << 20))
                if not piece:
                    raise RuntimeError(f"{exported}: ends inside its ground section")
                put(piece)
                left -= len(piece)
            put(struct.pack("<I", len(places)))
            batch = []
            for number, (x, z) in enumerate(places, start=1):
                # type crater, x, z, direction, height[2], length[3] (radius first), width,
                # material dirt, status, no vertex edits
                batch.append(struct.pack("<HHII", site, host, number, params) +
                             struct.pack("<HdddddddddHiH", 1, x, z, 0.0, 0.0, 0.0, 3.0, 0.0,
                                         0.0, 0.0, 2, 0, 0))
                if len(batch) == 10000:
                    put(b"".join(batch))
                    batch = []
            put(b"".join(batch))
            put(struct.pack("<Q", h.digest()))


class DisListener:
    """Reads the gateway's DIS datagrams (broadcast to DIS_PORT on this namespace's loopback) on
    a thread: the location of each Point Object State (type 43) by object ID, and the Entity
    State (type 1) IDs seen."""

    def __init__(self):
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEPORT, 1)
        self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 8 << 20)
        self.sock.bind(("0.0.0.0", DIS_PORT))
        self.sock.settimeout(0.2)
        self.objects = {}
        self.entities = set()
        self.lock = threading.Lock()
        self.running = True
        self.thread = threading.Thread(target=self.run, daemon=True)
        self.thread.start()

    def run(self):
        while self.running:
            try:
                data = self.sock.recv(65536)
            except socket.timeout:
                continue
            at = 0
            while at + 12 <= len(data):  # one PDU, or a bundle of them
                length = struct.unpack_from(">H", data, at + 8)[0]
                if length < 12 or at + length > len(data):
                    break
                kind = data[at + 2]
                with self.lock:
                    if kind == 43 and length >= 56:
                        oid = struct.unpack_from(">HHH", data, at + 12)
                        self.objects[oid] = struct.unpack_from(">ddd", data, at + 32)
                    elif kind == 1 and length >= 18:
                        self.entities.add(struct.unpack_from(">HHH", data, at + 12))
                at += length

    def location(self, oid):
        with self.lock:
            return self.objects.get(oid)

    def close(self):
        self.running = False
        self.thread.join()
        self.sock.close()


def utm_of_geocentric(points):
    """UTM 33N easting, northing and height of geocentric points, by gdaltransform (PROJ)."""
    text = "".join(f"{x!r} {y!r} {z!r}\n" for x, y, z in points)
    r = subprocess.run(["gdaltransform", "-s_srs", "EPSG:4978", "-t_srs", "EPSG:32633"],
                       input=text, capture_output=True, text=True, check=True)
    return [tuple(float(v) for v in line.split()[:3]) for line in r.stdout.splitlines()]


def ctl_long(ex, name, *command, timeout_s):
    """dt_ctl with a long answer time (an import of 10^6 features runs in the server's loop)."""
    r = subprocess.run([ex.programs["dt_ctl"], "--config", ex.exercise, "--run-dir", ex.run_dir,
                        "--name", name, "--timeout-ms", str(int(timeout_s * 1000)), *command],
                       capture_output=True, text=True, timeout=timeout_s + 30)
    if r.returncode != 0:
        ex.fail(f"dt_ctl {name} {' '.join(command)}: {r.stderr.strip()}")
    return r.stdout.strip()


def check_features(args, ex, work, size_m, dis, figures):
    """Imports args.features craters through the server and checks the promises (module doc)."""
    t0 = time.time()
    exported = os.path.join(work, "exported.dtt")
    ctl_long(ex, "server", "export", exported, timeout_s=300)
    places = crater_places(args.features, size_m)
    craters = os.path.join(work, "craters.dtt")
    write_with_craters(exported, craters, places)
    os.remove(exported)
    print(f"terrain file with {args.features} craters written in {time.time() - t0:.1f} s "
          f"({os.path.getsize(craters) >> 20} MB)")
    t1 = time.time()
    ctl_long(ex, "server", "import", craters, timeout_s=600)
    figures["import_s"] = time.time() - t1
    print(f"server imported them in {figures['import_s']:.1f} s")
    names = [name for name, _ in PROCESSES]

    def status(name):
        """`status` as a dict, or None while the process is too busy to answer (it applies
        10^6 changes in its loop); a process that exited fails the test."""
        if ex.procs[name].poll() is not None:
            ex.fail(f"{name} exited ({ex.procs[name].returncode}) while the craters spread")
        r = subprocess.run([ex.programs["dt_ctl"], "--config", ex.exercise, "--run-dir",
                            ex.run_dir, "--name", name, "--timeout-ms", "30000", "status"],
                           capture_output=True, text=True, timeout=60)
        if r.returncode != 0:
            return None
        return dict(line.split(" ", 1) for line in r.stdout.splitlines() if " " in line)

    last = {}

    def converged():
        for n in names:
            st = status(n)
            if st is None:
                return None
            last[n] = (st.get("features"), st.get("digest"))
        counts = {n: int(f or -1) for n, (f, _) in last.items()}
        digests = {n: d for n, (_, d) in last.items()}
        if any(c != args.features for c in counts.values()) or len(set(digests.values())) != 1:
            return None
        return digests

    deadline = time.time() + args.converge_s
    digests = None
    while digests is None and time.time() < deadline:
        digests = converged()
        if digests is None:
            time.sleep(2.0)  # polling the processes' status, bounded by the deadline
    if digests is None:
        ex.fail(f"the six processes did not all hold the {args.features} craters with one digest "
                f"within {args.converge_s:.0f} s: (features, digest) {last}")
    figures["converge_s"] = time.time() - t1
    print(f"every process holds the {args.features} craters with digest "
          f"{next(iter(digests.values()))}, {figures['converge_s']:.1f} s after the import began")
    # DIS: sampled craters with a DIS number, each within 1 m of its place by the georeference.
    mapped = min(args.features, MAX_DIS_NUMBER)
    samples = sorted({1, mapped, mapped // 2, mapped // 3 + 1, max(1, mapped - 7)})
    site, host = FEATURE_ORIGIN
    oids = {n: (site, host, n) for n in samples}
    got = ex.poll("the gateway's Point Object State of every sampled crater",
                  lambda: all(dis.location(o) for o in oids.values()) and
                  {n: dis.location(o) for n, o in oids.items()}, timeout_s=60, period_s=0.5)
    utm = utm_of_geocentric([got[n] for n in samples])
    worst = 0.0
    for n, (e, north, _) in zip(samples, utm):
        x, z = places[n - 1]
        off = math.hypot(e - (E0 + x), north - (N0 + z))
        worst = max(worst, off)
        if off > 1.0:
            ex.fail(f"DIS crater {site}:{host}:{n} at UTM ({e:.2f}, {north:.2f}) lies {off:.2f} m "
                    f"from its place ({E0 + x:.2f}, {N0 + z:.2f})")
    figures["dis_worst_m"] = worst
    # Both driving vehicles: waited for, as the craters are (the import may end before the
    # gateway has heard a node's first vehicle state).
    def entities():
        with dis.lock:
            return set(dis.entities)
    ex.poll("the gateway's Entity States of the two driving vehicles",
            lambda: len(entities()) >= 2, timeout_s=30, period_s=0.2)
    print(f"DIS: {len(samples)} sampled craters within {worst:.3f} m of their places; entity IDs "
          f"seen: {sorted(entities())}")


def check_page(args, ex, size_m, figures):
    """Opens the view's page: the whole world's relief, then 1 km around node-1's vehicle at the
    finer level the page picks (module doc, --page)."""
    from browser_prerequisites import CHROMIUM, require_browser
    from relief_tile_pixels import tile_pixels
    sync_playwright = require_browser()
    os.makedirs(args.page, exist_ok=True)
    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=CHROMIUM, headless=True, args=["--no-sandbox"])
        errors = []
        page = browser.new_page(viewport={"width": 1600, "height": 1000})
        page.on("pageerror", lambda e: errors.append(str(e)))
        t0 = time.time()
        page.goto("http://127.0.0.1:8480/")
        page.wait_for_function("window.dtView.relief && window.dtView.relief.complete",
                               timeout=180000)
        whole_s = time.time() - t0
        levels = page.evaluate("window.dtView.relief.info.levels")
        whole_level = page.evaluate("window.dtView.relief.level")
        # Both vehicles on the map: a newcomer learns of one at its next Entity State.
        page.wait_for_function("window.dtView.state.vehicles.size >= 2", timeout=30000)
        page.screenshot(path=os.path.join(args.page, "page-whole.png"))
        x, z = size_m * 0.3, size_m * 0.3  # node-1's vehicle's start
        t0 = time.time()
        page.evaluate(f"() => {{ state.view = {{x: {x - 500}, y: {size_m - z - 500}, w: 1000, "
                      f"h: 1000}}; applyView(); }}")
        # The level the page picks for 1 km (its pixel no wider than the screen's, or the finest):
        # finer than the whole world's, unless that was the finest already (a small world).
        page.wait_for_function("window.dtView.relief.complete && (window.dtView.relief.level > "
                               f"{whole_level} || window.dtView.relief.level === {levels - 1})",
                               timeout=180000)
        zoomed_s = time.time() - t0
        zoomed_level = page.evaluate("window.dtView.relief.level")
        need = page.evaluate("window.dtView.relief.need")
        page.screenshot(path=os.path.join(args.page, "page-zoomed.png"))
        tiles = {k: tile_pixels(page, f"/relief/{k}.png") for k in need}
        # Each tile's size and the spread of its green channel.
        spreads = {k: (t.shape[1], t.shape[0], int(t[:, :, 1].min()), int(t[:, :, 1].max()))
                   for k, t in tiles.items()}
        browser.close()
    figures["page"] = dict(levels=levels, whole_s=whole_s, zoomed_s=zoomed_s, tiles=spreads)
    print(f"the page: {levels} levels; the whole world's relief (level {whole_level}) complete "
          f"{whole_s:.1f} s after opening; 1 km around node-1's vehicle at level {zoomed_level} "
          f"{zoomed_s:.1f} s after zooming (tiles {sorted(need)})")
    print("relief tiles shown, green channel: " +
          ", ".join(f"{k} {lo}..{hi}" for k, (_, _, lo, hi) in sorted(spreads.items())))
    if errors:
        ex.fail(f"the page raised {errors}")
    # The whole world's tile spans the surface's ridges; a fine tile (a few hundred metres) only
    # gentle slopes, 2 or 3 levels of green: a blank or one-colour tile has none.
    for key, (w, h, lo, hi) in spreads.items():
        if (w, h) != (256, 256) or hi - lo < (16 if key == "0/0/0" else 1):
            ex.fail(f"relief tile {key}: {w} x {h} px, green {lo}..{hi}: not the ground's shading")


def stop_timed(ex, timeout_s):
    """SIGTERM to every process at once, then each one's exit code and seconds to exit (polled
    every 10 ms); one still running after timeout_s is killed (its code then tells)."""
    t0 = time.monotonic()
    for p in ex.procs.values():
        if p.poll() is None:
            p.send_signal(signal.SIGTERM)
    seconds = {}
    while len(seconds) < len(ex.procs) and time.monotonic() - t0 < timeout_s:
        for name, p in ex.procs.items():
            if name not in seconds and p.poll() is not None:
                seconds[name] = time.monotonic() - t0
        time.sleep(0.01)  # polling the processes' exits, bounded by timeout_s
    codes = {}
    for name, p in ex.procs.items():
        if p.poll() is None:
            p.kill()
        codes[name] = p.wait()
    return codes, seconds


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


def run_world(args, programs, posts, work, features=0):
    """Starts the six processes on a posts x posts world; returns the figures."""
    os.makedirs(work, exist_ok=True)
    t0 = time.time()
    if args.ground_file:
        source = make_ground_file(work, posts, args.spacing_m)
        terrain = f'ground_file = "{source}"'
    else:
        source = make_raster(work, posts, args.spacing_m)
        terrain = f'elevation_file = "{source}"'
    print(f"{os.path.basename(source)}: {posts} x {posts} made in {time.time() - t0:.1f} s "
          f"({os.path.getsize(source) >> 20} MB)")
    size_m = (posts - 1) * args.spacing_m
    exercise = os.path.join(work, "large.toml")
    with open(exercise, "w") as f:
        f.write(EXERCISE.format(key=args.key, terrain=terrain, x1=size_m * 0.3, z1=size_m * 0.3,
                                x2=size_m * 0.6))
    with open(os.path.join(work, "drive.toml"), "w") as f:
        f.write(DRIVE)
    ex = ExerciseProcesses(programs, exercise, os.path.join(work, "run"))
    figures = {"posts": posts, "procs": {}}
    dis = DisListener() if features else None
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
        if args.ground_file:
            run_dir = os.path.join(work, "run")
            figures["ctl_s"] = time_ctl(programs["dt_ctl"], exercise, run_dir)
            if args.ctl_compare:
                figures["ctl_compare_s"] = time_ctl(args.ctl_compare, exercise, run_dir)
        if features:
            check_features(args, ex, work, size_m, dis, figures)
        if args.page and posts == args.posts:
            check_page(args, ex, size_m, figures)
    finally:
        if dis:
            dis.close()
        # Every process stops within 10 s (the server's last digest no longer reads the ground
        # afresh): one that does not is killed and fails below.
        codes, figures["stop_each_s"] = stop_timed(ex, timeout_s=10)
        figures["stop_s"] = max(figures["stop_each_s"].values(), default=10.0)
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
    for key, what in (("ctl_s", "dt_ctl"), ("ctl_compare_s", "--ctl-compare")):
        if key in f:
            print(f"{what}: status {f[key][0]:.3f} s, start alone {f[key][1]:.3f} s "
                  "(medians of 5)")
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
    a.add_argument("--features", type=int, default=0)
    a.add_argument("--converge-s", type=float, default=600.0)
    a.add_argument("--ground-file", action="store_true")
    a.add_argument("--ctl-compare", default="")
    a.add_argument("--page", default="")
    a.add_argument("--keep", action="store_true")
    args = a.parse_args()
    if args.ground_file and args.features:
        a.error("--features needs the raster's georeference: not with --ground-file")
    args.key = os.path.abspath(args.key)
    args.bin_dir = os.path.abspath(args.bin_dir)
    if args.page:
        args.page = os.path.abspath(args.page)
    programs = {p: find_program(args.bin_dir, p) for p in PROGRAMS}
    shutil.rmtree(args.work, ignore_errors=True)
    ok = True
    try:
        base_total = None
        if args.baseline_posts:
            base = run_world(args, programs, args.baseline_posts, os.path.join(args.work, "base"))
            base_total, _ = report(base)
        f = run_world(args, programs, args.posts, os.path.join(args.work, "large"),
                      features=args.features)
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
        print(f"stopped, every process, in {f['stop_s']:.1f} s: " +
              ", ".join(f"{n} {t:.2f} s" for n, t in f["stop_each_s"].items()))
        slow = [n for n, _ in PROCESSES if n not in f["stop_each_s"]]
        if slow:
            print(f"FAIL: {slow} did not stop within 10 s of SIGTERM")
            ok = False
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
