"""A stand-in for dt_view at exercise scale: serves the page's files (view/web) and one WebSocket,
/ws, that sends a snapshot and then deltas at the view's tick rate, in dt_view's message format
(docs/view.md "Messages"), for N vehicles of three owners wandering on circles and M features: the
vehicles' moves as dt_view sends them, in the binary vehicle message (docs/view.md "The binary
vehicle message"), or as JSON rows with json_vehicles (the format before it, for comparison).
/relief.png is a shaded picture of scene3d.py's ground, so the map shows terrain under the vehicles.

GET /terrain3d answers scene3d.py's ground over the same 1000 m, so the 3D view can be timed with
the same vehicles. Used by view_scale_test.py to load the page with 9000 or 30 000 vehicles without running the
nodes that would drive them. The deltas of one period of the vehicles' motion are built once and
sent in a loop, each with a fresh seq and t_ms, so the feed itself costs little CPU and the page's
measured frame rate and lag are the page's.
"""
import http.server
import json
import math
import os
import random
import socket
import socketserver
import struct
import threading
import time
import zlib

import numpy as np

import scene3d
import websocket_upgrade

OWNERS = ["node-1", "node-2", "node-3"]
TYPES = ["tank", "truck", "jeep"]
SIZE_M = 1000.0
TICK_HZ = 30
PERIOD_TICKS = 90  # the motion repeats every 3 s
MOVED_PER_TICK = 3  # a third of the vehicles change each tick (their owners' updates interleave)


_circles = {}


def _vehicle(i, k):
    """Vehicle i at tick k: on a circle of its own, every tenth one dead."""
    if i not in _circles:
        rnd = random.Random(i)
        _circles[i] = (rnd.uniform(30, SIZE_M - 30), rnd.uniform(30, SIZE_M - 30),
                       rnd.uniform(5, 25), rnd.uniform(0, 2 * math.pi))
    cx, cz, r, phase = _circles[i]
    a = phase + 2 * math.pi * k / PERIOD_TICKS
    owner = OWNERS[i % len(OWNERS)]
    return [f"{owner}/{i // len(OWNERS)}", owner, TYPES[i % 3], round(cx + r * math.cos(a), 2),
            round(cz + r * math.sin(a), 2), round(a + math.pi / 2, 3), 6.0, i % 10 != 9, i]


def _record(row):
    """A vehicle's 16 bytes in the binary vehicle message (view/vehicle_frame.h)."""
    slot = row[8] | (0 if row[7] else 0x80000000)
    heading = math.remainder(row[5], 2 * math.pi)
    return struct.pack("<Iffhh", slot, row[3], row[4], round(heading * 10000), round(row[6] * 100))


def relief_png(size_px=256):
    """scene3d.py's ground and earthworks, shaded from the north-west, north up, as a PNG."""
    m = np.linspace(0, SIZE_M, size_px)
    X, Z = np.meshgrid(m, m[::-1])
    h = scene3d.ground(X, Z) + scene3d.earthworks(X, Z)
    gz, gx = np.gradient(h, SIZE_M / size_px)
    shade = np.clip(0.6 + 0.35 * (-gx * 0.7 - gz * 0.7) / np.sqrt(1 + gx * gx + gz * gz), 0, 1)
    t = (h - h.min()) / max(float(np.ptp(h)), 1.0)
    rgb = np.stack([(70 + 90 * t) * shade, (100 + 70 * t) * shade, (60 + 40 * t) * shade], -1)
    raw = b"".join(b"\0" + row.tobytes() for row in np.clip(rgb, 0, 255).astype(np.uint8))

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))
    return (b"\x89PNG\r\n\x1a\n" +
            chunk(b"IHDR", struct.pack(">IIBBBBB", size_px, size_px, 8, 2, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


def _feature(i, per_side):
    x = 15.0 + (SIZE_M - 30) * (i % per_side) / per_side
    z = 15.0 + (SIZE_M - 30) * (i // per_side) / per_side
    fid = f"1:1:{i + 1}"
    history = [{"t_ms": 0, "kind": "create", "by": "node-1", "feature": fid, "change_seq": i + 1}]
    if i % 10 == 9:
        return {"id": fid, "type": "berm", "x": x, "z": z, "placed": True, "dir": 0.7,
                "length": 3.0, "width": 1.0, "height": 1.0, "history": history}
    return {"id": fid, "type": "crater", "x": x, "z": z, "placed": True, "radius": 1.0,
            "history": history}


class Feed:
    def __init__(self, vehicles, features, json_vehicles=False):
        self.n = vehicles
        self.json_vehicles = json_vehicles
        per_side = max(1, math.ceil(math.sqrt(features)))
        self.features = [_feature(i, per_side) for i in range(features)]
        self.bodies = []
        for k in range(PERIOD_TICKS):
            moved = [_vehicle(i, k) for i in range(k % MOVED_PER_TICK, vehicles, MOVED_PER_TICK)]
            if json_vehicles:
                self.bodies.append((len(moved), json.dumps(moved, separators=(",", ":"))))
            else:
                self.bodies.append((len(moved), b"".join(_record(v) for v in moved)))
        self.seq = 0
        self.tick = 0
        self.sent_bytes = 0
        self.max_send_s = 0.0

    def snapshot(self):
        self.seq += 1
        exercise = {"name": "scale", "size_x_m": SIZE_M, "size_z_m": SIZE_M, "silence_ms": 1000,
                    "view": "view", "commands": False, "nodes": OWNERS}
        processes = [{"name": n, "role": "node", "address": f"1:{j + 1}", "reachable": True,
                      "signed_on": True, "caught_up": True, "diverged": False, "silent": False,
                      "digest": "0123456789abcdef", "features": len(self.features),
                      "counters": {}, "last_heard_ago_ms": 0} for j, n in enumerate(OWNERS)]
        return json.dumps({"type": "snapshot", "seq": self.seq, "t_ms": int(time.time() * 1000),
                           "exercise": exercise, "features": self.features, "events": [],
                           "processes": processes,
                           "vehicles": [_vehicle(i, 0) for i in range(self.n)], "relief": 0},
                          separators=(",", ":"))

    def delta(self):
        """The tick's message: the moves in binary (or a JSON delta with json_vehicles)."""
        self.seq += 1
        self.tick += 1
        count, body = self.bodies[self.tick % PERIOD_TICKS]
        t_ms = int(time.time() * 1000)
        if self.json_vehicles:
            return f'{{"type":"delta","seq":{self.seq},"t_ms":{t_ms},"vehicles":{body}}}'
        return struct.pack("<4sIdII", b"DTV1", self.seq, float(t_ms), count, 0) + body



def serve(port, web_dir, vehicles, features, json_vehicles=False):
    """Serves on 127.0.0.1:port in a thread of its own; returns the server (shutdown() stops it)."""
    feed_lock = threading.Lock()
    feeds = {}
    relief = relief_png()

    class Handler(http.server.SimpleHTTPRequestHandler):
        def __init__(self, *args, **kwargs):
            super().__init__(*args, directory=web_dir, **kwargs)

        def log_message(self, *args):
            pass

        def do_GET(self):
            path, _, query = self.path.partition("?")
            if path == "/relief.png":
                self.send_response(200)
                self.send_header("Content-Type", "image/png")
                self.send_header("Content-Length", str(len(relief)))
                self.end_headers()
                self.wfile.write(relief)
                return
            if path == "/terrain3d":  # the 3D view's window: scene3d's ground, 129 posts a side
                body = json.dumps(scene3d.window(query, SIZE_M, SIZE_M / 128)).encode()
                self.send_response(200)
                self.send_header("Content-Type", "application/json")
                self.send_header("Content-Length", str(len(body)))
                self.end_headers()
                self.wfile.write(body)
                return
            if self.path != "/ws":
                return super().do_GET()
            websocket_upgrade.accept(self)
            with feed_lock:
                if "feed" not in feeds:
                    feeds["feed"] = Feed(vehicles, features, json_vehicles)
                feed = feeds["feed"]
            try:
                sock = self.connection
                sock.sendall(websocket_upgrade.frame(feed.snapshot()))
                next_at = time.monotonic()
                while True:
                    next_at += 1.0 / TICK_HZ
                    text = feed.delta()
                    stamped = time.monotonic()
                    sock.sendall(websocket_upgrade.frame(text))
                    # A send that waits is a page (or a browser) not reading: part of its lag.
                    feed.max_send_s = max(feed.max_send_s, time.monotonic() - stamped)
                    feed.sent_bytes += len(text)
                    time.sleep(max(0.0, next_at - time.monotonic()))
            except (BrokenPipeError, ConnectionResetError, socket.timeout, OSError):
                return

    class Server(socketserver.ThreadingMixIn, http.server.HTTPServer):
        daemon_threads = True
        allow_reuse_address = True

    server = Server(("127.0.0.1", port), Handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    server.feeds = feeds
    return server


if __name__ == "__main__":
    import sys
    here = os.path.dirname(os.path.abspath(__file__))
    srv = serve(int(sys.argv[1]), os.path.join(here, "../web"), int(sys.argv[2]), int(sys.argv[3]))
    print(f"serving http://127.0.0.1:{sys.argv[1]}/", flush=True)
    threading.Event().wait()
