"""A stand-in for dt_view at exercise scale: serves the page's files (view/web) and one WebSocket,
/ws, that sends a snapshot and then deltas at the view's tick rate, in dt_view's message format
(docs/view.md "Messages"), for N vehicles of three owners wandering on circles and M features.

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
import threading
import time

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
            round(cz + r * math.sin(a), 2), round(a + math.pi / 2, 3), 6.0, i % 10 != 9]


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
    def __init__(self, vehicles, features):
        self.n = vehicles
        per_side = max(1, math.ceil(math.sqrt(features)))
        self.features = [_feature(i, per_side) for i in range(features)]
        self.bodies = []
        for k in range(PERIOD_TICKS):
            moved = [_vehicle(i, k) for i in range(k % MOVED_PER_TICK, vehicles, MOVED_PER_TICK)]
            self.bodies.append(json.dumps(moved, separators=(",", ":")))
        self.seq = 0
        self.tick = 0
        self.sent_bytes = 0

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
                           "vehicles": [_vehicle(i, 0) for i in range(self.n)], "relief": -1},
                          separators=(",", ":"))

    def delta(self):
        self.seq += 1
        self.tick += 1
        body = self.bodies[self.tick % PERIOD_TICKS]
        return (f'{{"type":"delta","seq":{self.seq},"t_ms":{int(time.time() * 1000)},'
                f'"vehicles":{body}}}')



def serve(port, web_dir, vehicles, features):
    """Serves on 127.0.0.1:port in a thread of its own; returns the server (shutdown() stops it)."""
    feed_lock = threading.Lock()
    feeds = {}

    class Handler(http.server.SimpleHTTPRequestHandler):
        def __init__(self, *args, **kwargs):
            super().__init__(*args, directory=web_dir, **kwargs)

        def log_message(self, *args):
            pass

        def do_GET(self):
            path, _, query = self.path.partition("?")
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
                    feeds["feed"] = Feed(vehicles, features)
                feed = feeds["feed"]
            try:
                sock = self.connection
                sock.sendall(websocket_upgrade.frame(feed.snapshot()))
                next_at = time.monotonic()
                while True:
                    next_at += 1.0 / TICK_HZ
                    text = feed.delta()
                    sock.sendall(websocket_upgrade.frame(text))
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
