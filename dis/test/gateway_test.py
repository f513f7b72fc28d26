#!/usr/bin/env python3
"""dt_dis with real processes and outside DIS peers, in a private network namespace.

Starts dt_server, two dt_node (node-1 drives a stationary tank) and dt_dis (each by PID, ready by
its READY line), then:
  (a) tshark captures on lo, UDP port 3000, and Wireshark's DIS dissector decodes the gateway's
      Entity State of the tank: entity ID, location and dead-reckoning algorithm equal what
      node-1 reports (dt_ctl vehicles; the location converted by opendis's own WGS-84 geodesy
      and the tangent plane at the exercise's origin, not by the gateway's code);
  (b) PyPI opendis encodes an Entity State and sends it to port 3000: both nodes list it as a
      remote vehicle owned by the gateway's address (dt_ctl vehicles) and draw it on their
      render where it is, against a render taken before it came; the gateway lists it as its
      own and the tank as node-1's;
  (c) bad DIS datagrams (short, foreign exercise, unknown PDU type) are counted in the
      gateway's status and change nothing.
With --import (an exercise whose [dis] says import_craters = true) it checks instead that an
outside Point Object State crater (dis_sample_tool's, sent as a DIS simulation's heartbeat would
be) becomes a crater feature of the gateway's own address on both nodes, and that its
deactivated state destroys it there.
Exits 77 (skipped) when tshark or opendis is not installed. Run inside tests/run_in_netns.sh.

  gateway_test.py <dt_server> <dt_node> <dt_dis> <dt_ctl> <exercise.toml> <run_dir>
                  [--import <dis_sample_tool>]
"""
import math
import os
import shutil
import signal
import socket
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../tests/pylib"))
from exercise_processes import ExerciseProcesses  # noqa: E402
from png_image import PngImage  # noqa: E402


def skip(why):
    print(f"SKIP: {why}")
    sys.exit(77)


TSHARK = shutil.which("tshark")
if TSHARK is None:
    skip("tshark is not installed (Debian package tshark; scripts/setup.sh installs it)")
try:
    from opendis.RangeCoordinates import GPS
    import opendis_pdus
except ImportError:
    skip("the opendis Python module is not installed (scripts/setup.sh installs it)")

ex = ExerciseProcesses(dict(zip(["dt_server", "dt_node", "dt_dis", "dt_ctl"], sys.argv[1:5])),
                       sys.argv[5], sys.argv[6])
ctl, status, poll, fail = ex.ctl, ex.status, ex.poll, ex.fail
# From dis-test.toml: its DIS exercise, origin, gateway address and terrain side (65 posts 10 m
# apart); a node's render is a 512-pixel map of the whole terrain (docs/rendering.md).
DIS_EXERCISE, ORIGIN = 3, (36.6, -121.9, 20.0)
GATEWAY = "1:60"
TERRAIN_M, RENDER_PX = 640.0, 512


def start_exercise():
    ex.start("server", "dt_server")
    ex.start("node-1", "dt_node")
    ex.start("node-2", "dt_node")
    ex.start("dis", "dt_dis")


def finish(failures, passed):
    """Stops every process (each must exit 0) and reports: the test's exit code."""
    for name, rc in ex.stop_all().items():
        if rc != 0:
            failures.append(f"{name} exited {rc}")
    for f in failures:
        print("FAIL:", f)
    if not failures:
        print(passed)
    return 1 if failures else 0


# The tangent plane at the origin (x east, y up, z north), from opendis's WGS-84 conversion.
lat, lon = math.radians(ORIGIN[0]), math.radians(ORIGIN[1])
# opendis 1.0: lla2ecef takes degrees (llarpy2ecef radians).
ORIGIN_ECEF = GPS().lla2ecef(ORIGIN)
EAST = (-math.sin(lon), math.cos(lon), 0.0)
NORTH = (-math.sin(lat) * math.cos(lon), -math.sin(lat) * math.sin(lon), math.cos(lat))
UP = (math.cos(lat) * math.cos(lon), math.cos(lat) * math.sin(lon), math.sin(lat))


def to_ecef(x, y, z):
    return tuple(ORIGIN_ECEF[i] + EAST[i] * x + NORTH[i] * z + UP[i] * y for i in range(3))


def vehicle_line(text, kind, entity):
    """The keys of the `vehicles` line of `entity` ("local <index> <id> <type> ..." or "remote
    <id> <type> ..."), with its id and type; None if it has none of that kind."""
    for line in text.splitlines():
        f = line.split()
        if len(f) > 3 and f[0] == kind and entity in f:
            type_name = f[3] if kind == "local" else f[2]
            return dict(kv.split("=", 1) for kv in f if "=" in kv) | {"id": entity,
                                                                      "type": type_name}
    return None


def render(name, tag):
    """Process `name`'s `render` (its own and remote vehicles, in their owners' colours)."""
    path = os.path.join(ex.run_dir, f"{name}-{tag}.png")
    ctl(name, "render", path)
    return PngImage.read(path)


def drawn_at(before, after, x_m, z_m, reach_px=8):
    """Where `after` differs from `before`: a failure text unless it does, only within reach of
    the map pixel of (x_m, z_m), around it (the centroid of the changed pixels within 2 px)."""
    mpp = TERRAIN_M / RENDER_PX
    column, row = x_m / mpp, (TERRAIN_M - z_m) / mpp  # north up, row 0 at the top
    if (after.width, after.height) != (RENDER_PX, RENDER_PX):
        return f"the render is {after.width} x {after.height} px, want {RENDER_PX}"
    near, far = [], 0
    for r in range(after.height):
        if before.rows[r] == after.rows[r]:
            continue
        for c in range(after.width):
            if before.pixel(c, r) != after.pixel(c, r):
                if abs(c + 0.5 - column) <= reach_px and abs(r + 0.5 - row) <= reach_px:
                    near.append((c + 0.5, r + 0.5))
                else:
                    far += 1
    print(f"  {len(near)} pixels changed within {reach_px} px of ({column:.1f}, {row:.1f}), "
          f"{far} farther away")
    if len(near) < 4:
        return f"{len(near)} pixels changed at ({column:.1f}, {row:.1f}): no vehicle drawn there"
    centre = (sum(c for c, _ in near) / len(near), sum(r for _, r in near) / len(near))
    if math.dist(centre, (column, row)) > 2.0:
        return f"the change is centred at {centre}, want ({column:.1f}, {row:.1f})"
    if far:
        return f"{far} pixels changed away from ({column:.1f}, {row:.1f})"
    return None


def import_craters(tool):
    start_exercise()
    path = os.path.join(ex.run_dir, "crater.bin")
    subprocess.run([tool, "crater", path], check=True, capture_output=True)
    crater = bytearray(open(path, "rb").read())
    crater[1] = DIS_EXERCISE  # the sample tool's exercise is another
    gone = bytearray(crater)
    gone[24:26] = (int.from_bytes(crater[24:26], "big") + 1).to_bytes(2, "big")  # update number
    gone[72] |= 0x08  # general appearance bit 11: deactivated
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)

    def features_after(datagram, name):
        # Sent again each poll as the outside simulation's heartbeat would: the gateway can make
        # features only once it has signed on.
        sock.sendto(bytes(datagram), ("127.0.0.1", 3000))
        return [f for f in ctl(name, "features").splitlines() if f.startswith(GATEWAY + ":")]

    made = {n: poll(f"{n} holding the imported crater", lambda: features_after(crater, n))
            for n in ("node-1", "node-2")}
    print(f"imported crater: {made}")
    failures = []
    if made["node-1"] != made["node-2"] or len(made["node-1"]) != 1:
        failures.append(f"the nodes hold {made}, want one and the same crater of {GATEWAY}")
    s = status("dis")
    if s.get("role") != "node" or s.get("dis_craters_imported") != "1":
        failures.append(f"gateway role {s.get('role')}, craters imported "
                        f"{s.get('dis_craters_imported')}; want node, 1")
    for n in ("node-1", "node-2"):
        poll(f"{n} dropping the deactivated crater", lambda: not features_after(gone, n))
    if status("dis").get("dis_craters_removed") != "1":
        failures.append("the gateway did not count the removal")
    return finish(failures, "an outside crater became the gateway's feature on both nodes, and "
                            "went with its deactivation")


def main():
    if len(sys.argv) > 8 and sys.argv[7] == "--import":
        return import_craters(sys.argv[8])
    start_exercise()

    # (a) tshark on lo, until the gateway has sent the tank's Entity State a few times.
    pcap = os.path.join(ex.run_dir, "gateway.pcap")
    cap = subprocess.Popen([TSHARK, "-i", "lo", "-f", "udp port 3000", "-a", "duration:20",
                            "-c", "400", "-w", pcap], stdout=subprocess.DEVNULL,
                           stderr=subprocess.PIPE, text=True)
    ex.procs["tshark"] = cap
    for line in cap.stderr:
        if "Capturing on" in line:
            break
    else:
        fail("tshark did not start capturing")
    before = int(status("dis").get("dis_entity_state_sent", "0"))
    poll("3 more Entity States from the gateway",
         lambda: int(status("dis")["dis_entity_state_sent"]) >= before + 3)
    node = vehicle_line(ctl("node-1", "vehicles"), "local", "1:1:1")
    if node is None:
        fail("node-1 does not list its tank 1:1:1")
    cap.send_signal(signal.SIGINT)  # tshark writes the file out and ends
    cap.wait(timeout=15)
    del ex.procs["tshark"]
    fields = ["dis.exer_id", "dis.pdu_type", "dis.entity_id_site", "dis.entity_id_application",
              "dis.entity_id_entity", "dis.entity_location.x", "dis.entity_location.y",
              "dis.entity_location.z", "dis.entity_marking_character_set"]
    cmd = [TSHARK, "-r", pcap, "-d", "udp.port==3000,dis", "-Y", "dis.pdu_type == 1",
           "-T", "fields", "-E", "separator=;", "-E", "occurrence=a", "-E", "aggregator=,"]
    for f in fields:
        cmd += ["-e", f]
    rows = [dict(zip(fields, line.split(";"))) for line in
            subprocess.run(cmd, check=True, capture_output=True, text=True).stdout.splitlines()]
    tank = [r for r in rows if (r["dis.entity_id_site"], r["dis.entity_id_application"],
                                r["dis.entity_id_entity"]) == ("1", "1", "1")]
    print(f"tshark decoded {len(rows)} Entity States, {len(tank)} of the tank")
    if not tank:
        fail("tshark decoded no Entity State of entity 1:1:1")
    es = tank[-1]
    failures = []
    if es["dis.exer_id"] != str(DIS_EXERCISE):
        failures.append(f"exercise ID {es['dis.exer_id']}, want {DIS_EXERCISE}")
    # tshark 4.0 gives the algorithm and the marking's character set under one field name.
    algorithm = es["dis.entity_marking_character_set"].split(",")[0]
    if algorithm != "2":
        failures.append(f"dead-reckoning algorithm {algorithm}, want 2 (FPW, dis-test.toml)")
    want = to_ecef(float(node["x_m"]), float(node["y_m"]), float(node["z_m"]))
    got = tuple(float(es[f"dis.entity_location.{a}"]) for a in "xyz")
    error_m = math.dist(want, got)
    print(f"node-1 reports {node['x_m']}, {node['y_m']}, {node['z_m']}; tshark {got}; "
          f"off by {error_m:.4f} m")
    if error_m > 0.02:  # dt_ctl prints centimetres
        failures.append(f"location {got} is {error_m:.3f} m from node-1's {want}")
    verbose = subprocess.run([TSHARK, "-r", pcap, "-d", "udp.port==3000,dis", "-V"],
                             check=True, capture_output=True, text=True).stdout
    if "Malformed" in verbose:
        failures.append("tshark calls a captured gateway datagram malformed")

    # (b) opendis sends an Entity State 30 m east of the tank; each node's render before it.
    before = {n: render(n, "before") for n in ("node-1", "node-2")}
    x, y, z = float(node["x_m"]) + 30.0, float(node["y_m"]), float(node["z_m"])
    # Upright and heading east, in DIS's Euler angles by opendis's own geodesy (its yaw a compass
    # heading): all zero would be an entity on its back, hidden in the ground on a render.
    _, _, _, psi, theta, phi = GPS().llarpy2ecef(lat, lon, ORIGIN[2], 0.0, 0.0, math.pi / 2)
    data = opendis_pdus.entity_state(DIS_EXERCISE, (31, 5, 777), to_ecef(x, y, z), 1,
                                     orientation=(psi, theta, phi))
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)

    def sent_and_seen(node_name):
        sock.sendto(data, ("127.0.0.1", 3000))
        return vehicle_line(ctl(node_name, "vehicles"), "remote", "31:5:777")

    for n in ("node-1", "node-2"):
        remote = poll(f"{n} listing the outside entity 31:5:777", lambda: sent_and_seen(n))
        print(f"{n}: remote 31:5:777 {remote}")
        if remote.get("owner") != GATEWAY:
            failures.append(f"{n}: outside entity owned by {remote.get('owner')}, want {GATEWAY}")
        if remote.get("type") != "truck":
            failures.append(f"{n}: outside entity of type {remote.get('type')}, want truck")
        off = math.hypot(float(remote["x_m"]) - x, float(remote["z_m"]) - z)
        if off > 0.05:
            failures.append(f"{n}: outside entity at {remote['x_m']}, {remote['z_m']}: {off} m off")
        if abs(math.remainder(float(remote["heading_deg"]), 360.0)) > 0.05:
            failures.append(f"{n}: outside entity heading {remote['heading_deg']} deg, want 0")
        # Drawn on the node's render (issue 12: "shows up on every node's render"), at its place
        # and nowhere else; drawn while its state is fresh, well inside the receivers' timeout.
        poll(f"{n} holding a fresh state of the outside entity",
             lambda: float((sent_and_seen(n) or {"age_s": "inf"})["age_s"]) < 0.5)
        print(f"{n}'s render against the one before the outside entity came:")
        if (why := drawn_at(before[n], render(n, "outside"), x, z)) is not None:
            failures.append(f"{n}'s render: {why}")

    # The gateway lists what it holds like a node: the outside entity as its own, the tank as
    # node-1's.
    held = ctl("dis", "vehicles")
    print(f"dis: vehicles\n{held}")
    outside = vehicle_line(held, "local", "31:5:777")
    tank = vehicle_line(held, "remote", "1:1:1")
    if outside is None or outside.get("owner") != GATEWAY or outside.get("type") != "truck":
        failures.append(f"the gateway lists the outside entity as {outside}, want its own truck")
    elif math.hypot(float(outside["x_m"]) - x, float(outside["z_m"]) - z) > 0.05:
        failures.append(f"the gateway has the outside entity at {outside['x_m']}, "
                        f"{outside['z_m']}, want {x:.2f}, {z:.2f}")
    if tank is None or tank.get("owner") != "1:1" or tank.get("type") != "tank":
        failures.append(f"the gateway lists the tank as {tank}, want node-1's (1:1) tank")
    elif math.hypot(float(tank["x_m"]) - float(node["x_m"]),
                    float(tank["z_m"]) - float(node["z_m"])) > 0.05:
        failures.append(f"the gateway has the tank at {tank['x_m']}, {tank['z_m']}, node-1 at "
                        f"{node['x_m']}, {node['z_m']}")

    # (c) Bad input: counted, and nothing of it reaches the exercise.
    before = status("dis")
    short = data[:10]
    foreign = data[:1] + bytes([DIS_EXERCISE + 1]) + data[2:]
    unknown = data[:2] + bytes([2]) + data[3:]  # a Fire PDU's type on an Entity State's bytes
    for d in (short, foreign, unknown):
        sock.sendto(d, ("127.0.0.1", 3000))

    def counted():
        s = status("dis")
        return all(int(s[k]) > int(before[k]) for k in
                   ("dis_in_rejected_too_short", "dis_in_rejected_foreign_exercise",
                    "dis_in_rejected_unsupported_pdu_type")) and s

    after = poll("the gateway counting the bad datagrams", counted)
    if int(after["dis_in_vehicles_published"]) - int(before["dis_in_vehicles_published"]) != 0:
        failures.append("a bad datagram was published as a vehicle")

    # (d) A datagram bundling PDUs (IEEE 1278.2): two opendis Entity States around one of an
    # unknown type; both entities reach the nodes, the bad one is counted.
    before = status("dis")
    pair = [opendis_pdus.entity_state(DIS_EXERCISE, (31, 5, n), to_ecef(x + dx, y, z), 1,
                                      orientation=(psi, theta, phi))
            for n, dx in ((778, 10.0), (779, 20.0))]
    bundle = pair[0] + unknown + pair[1]

    def bundle_seen(node_name):
        sock.sendto(bundle, ("127.0.0.1", 3000))
        text = ctl(node_name, "vehicles")
        return all(vehicle_line(text, "remote", f"31:5:{n}") for n in (778, 779))

    for n in ("node-1", "node-2"):
        poll(f"{n} listing both entities of a bundle", lambda: bundle_seen(n))
    after = status("dis")
    if int(after["dis_in_rejected_unsupported_pdu_type"]) <= int(
            before["dis_in_rejected_unsupported_pdu_type"]):
        failures.append("the bundle's bad PDU was not counted")
    return finish(failures, "tshark decoded the gateway's Entity State as node-1 reports it; "
                            "opendis's Entity State is a remote vehicle on both nodes; bad DIS "
                            "input was counted, not applied; a bundle's entities were all taken")


if __name__ == "__main__":
    sys.exit(main())
