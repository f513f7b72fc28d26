"""A fixed scene for the 3D view's browser test: what dt_view's GET /terrain3d answers (docs/view.md
"The 3D view"), for a terrain given as a function (rolling ground with a crater, a berm, a ditch,
an intact and a destroyed bridge), sampled as dt_view samples its grid (whole post spacings, or a
power-of-two fraction of one close up, on the step's lattice, at most the posts asked for a side),
plus the page's vehicles standing
still. The server answers the page's files, /terrain3d and /ws (one snapshot, then nothing), so the
picture depends on the camera alone.

  scene3d.serve(port, web_dir, size_m, spacing_m) -> server (shutdown() stops it)
"""
import http.server
import json
import math
import socketserver
import threading
import urllib.parse

import numpy as np

import websocket_upgrade

OWNERS = ["node-1", "node-2", "node-3"]
DECK_THICKNESS_M = 0.5
PIER_WIDTH_M = 1.0
RUBBLE_HEIGHT_M = 1.0


def ground(x, z):
    return 20.0 + 8.0 * np.sin(x / 150.0) * np.cos(z / 190.0) + 0.004 * x


CRATER = (420.0, 520.0, 30.0, 5.0)  # x, z, radius, depth
BERM = (560.0, 470.0, 0.3, 90.0, 18.0, 3.5)  # x, z, direction, length, width, height
DITCH = ((330.0, 420.0), (500.0, 390.0), 9.0, 2.5)  # from, to, half width, depth
# x, z, direction, width, ramp, span, ramp, height, destroyed
BRIDGES = [(500.0, 610.0, 0.25, 10.0, 30.0, 40.0, 30.0, 7.0, False),
           (380.0, 660.0, -0.5, 10.0, 25.0, 35.0, 25.0, 6.0, True)]


def earthworks(x, z):
    """The earthworks' part of the surface: a crater bowl with its rim, a berm, a ditch."""
    cx, cz, r, depth = CRATER
    d = np.hypot(x - cx, z - cz) / r
    out = np.where(d < 1.0, -depth * (1.0 - d * d), 0.0)
    out += np.where((d >= 0.8) & (d < 1.4), 1.2 * np.cos((d - 1.1) / 0.3 * math.pi / 2), 0.0)
    bx, bz, bdir, blen, bw, bh = BERM
    a = (x - bx) * math.cos(bdir) + (z - bz) * math.sin(bdir)
    s = (x - bx) * math.sin(bdir) - (z - bz) * math.cos(bdir)
    out += np.where((np.abs(a) < blen / 2) & (np.abs(s) < bw / 2),
                    bh * np.cos(s / (bw / 2) * math.pi / 2), 0.0)
    (x0, z0), (x1, z1), hw, dd = DITCH
    ux, uz = x1 - x0, z1 - z0
    ln = math.hypot(ux, uz)
    a = ((x - x0) * ux + (z - z0) * uz) / ln
    s = np.abs((x - x0) * uz - (z - z0) * ux) / ln
    out += np.where((a > 0) & (a < ln) & (s < hw), -dd * np.cos(s / hw * math.pi / 2), 0.0)
    return out


def bridge_solids(b):
    """The solids of vehicle/bridge_solids.h for one bridge: ramp, span (or rubble), ramp, piers."""
    x, z, direction, width, l1, span, l2, height, destroyed = b
    ux, uz = math.cos(direction), math.sin(direction)
    g = float(ground(x, z))
    top = g + height
    w = width / 2

    def solid(kind, a0, a1, r0, r1, b0, b1, t0, t1):
        return {"bridge": "1:1:9", "kind": kind, "o": [x, z], "u": [ux, uz], "a": [a0, a1],
                "r": [r0, r1], "bottom": [b0, b1], "top": [t0, t1]}

    out = [solid("deck", 0, l1, -w, w, g - DECK_THICKNESS_M, top - DECK_THICKNESS_M, g, top)]
    if not destroyed:
        out.append(solid("deck", l1, l1 + span, -w, w, top - DECK_THICKNESS_M,
                         top - DECK_THICKNESS_M, top, top))
    out.append(solid("deck", l1 + span, l1 + span + l2, -w, w, top - DECK_THICKNESS_M,
                     g - DECK_THICKNESS_M, top, g))
    for a in (l1, l1 + span):
        for r in (-w, w - PIER_WIDTH_M):
            out.append(solid("pier", a - PIER_WIDTH_M / 2, a + PIER_WIDTH_M / 2, r,
                             r + PIER_WIDTH_M, g - 1, g - 1, top - DECK_THICKNESS_M,
                             top - DECK_THICKNESS_M))
    if destroyed:
        out.append(solid("rubble", l1, l1 + span, -w, w, g, g, g + RUBBLE_HEIGHT_M,
                         g + RUBBLE_HEIGHT_M))
    return out


def window(query, size_m, spacing_m):
    """GET /terrain3d's answer, sampled as view/terrain_window.cc samples."""
    q = {k: float(v[0]) for k, v in urllib.parse.parse_qs(query).items()}
    want = int(q.get("posts", 129))
    lo_x, hi_x = (min(max(q["x"] + s * q["half"], 0.0), size_m) for s in (-1, 1))
    lo_z, hi_z = (min(max(q["z"] + s * q["half"], 0.0), size_m) for s in (-1, 1))
    wanted = max(hi_x - lo_x, hi_z - lo_z) / (want - 1)
    step = spacing_m
    if wanted > spacing_m:
        step = spacing_m * math.ceil(wanted / spacing_m - 1e-9)
    else:
        while step / 2 >= wanted and step > spacing_m / 8 * 1.5:
            step /= 2

    def first(lo):
        return math.floor(lo / step + 1e-9)

    def count(k0, hi):
        n = 1 + math.ceil((hi - k0 * step) / step - 1e-9)
        return int(max(1, min(n, want, math.floor(size_m / step + 1e-9) - k0 + 1)))

    i0, j0 = first(lo_x), first(lo_z)
    nx, nz = count(i0, hi_x), count(j0, hi_z)
    xs = np.minimum((i0 + np.arange(nx)) * step, size_m)
    zs = np.minimum((j0 + np.arange(nz)) * step, size_m)
    X, Z = np.meshgrid(xs, zs)
    bare, works = ground(X, Z), earthworks(X, Z)
    solids = []
    for b in BRIDGES:
        if abs(b[0] - q["x"]) < q["half"] + 120 and abs(b[1] - q["z"]) < q["half"] + 120:
            solids += bridge_solids(b)
    return {"x0": i0 * step, "z0": j0 * step, "step": step, "nx": nx, "nz": nz,
            "spacing": spacing_m, "size_x": size_m, "size_z": size_m,
            "h": np.round(bare + works, 2).ravel().tolist(),
            "d": np.round(works, 2).ravel().tolist(), "solids": solids}


def vehicles():
    """Twelve vehicles of three owners on a line past the crater, one on the intact deck, one dead."""
    out = []
    for k in range(12):
        owner = OWNERS[k % 3]
        out.append([f"{owner}/{k}", owner, "tank", 360.0 + 22.0 * k, 470.0 + 6.0 * k,
                    0.3 + 0.25 * k, 0.0, k != 7])
    bx, bz, bdir = BRIDGES[0][:3]
    out.append(["node-1/99", "node-1", "truck", bx + 50 * math.cos(bdir), bz + 50 * math.sin(bdir),
                bdir, 0.0, True])
    return out



def snapshot(size_m):
    import time
    return json.dumps({"type": "snapshot", "seq": 1, "t_ms": int(time.time() * 1000),
                       "exercise": {"name": "scene3d", "size_x_m": size_m, "size_z_m": size_m,
                                    "silence_ms": 2000, "view": "view", "commands": False,
                                    "nodes": OWNERS},
                       "features": [], "events": [], "processes": [], "vehicles": vehicles(),
                       "relief": -1})


def serve(port, web_dir, size_m, spacing_m):
    class Handler(http.server.SimpleHTTPRequestHandler):
        def __init__(self, *args, **kwargs):
            super().__init__(*args, directory=web_dir, **kwargs)

        def log_message(self, *args):
            pass

        def do_GET(self):
            path, _, query = self.path.partition("?")
            if path == "/terrain3d":
                body = json.dumps(window(query, size_m, spacing_m)).encode()
                self.send_response(200)
                self.send_header("Content-Type", "application/json")
                self.send_header("Content-Length", str(len(body)))
                self.end_headers()
                self.wfile.write(body)
                return
            if path != "/ws":
                return super().do_GET()
            websocket_upgrade.accept(self)
            try:
                self.connection.sendall(websocket_upgrade.frame(snapshot(size_m)))
                while self.connection.recv(4096):  # until the page goes
                    pass
            except OSError:
                return

    class Server(socketserver.ThreadingMixIn, http.server.HTTPServer):
        daemon_threads = True
        allow_reuse_address = True

    server = Server(("127.0.0.1", port), Handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    return server
