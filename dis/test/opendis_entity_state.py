#!/usr/bin/env python3
"""An independent DIS implementation (PyPI opendis) reads our Entity State, and writes one that
our decoder and mapping accept with the same field values; it also reads our crater's Point
Object State (its appearance as a float64 whose bits are our appearance record). Bundles
(IEEE 1278.2): opendis reads every PDU of our bundling datagram once it is split by each header's
length field (its createPdu reads one PDU, the first), and we read a bundle of its Entity States.

    opendis_entity_state.py <dis_sample_tool> <work dir>

Exits 77 (skipped) when the opendis module is not installed (scripts/setup.sh installs it).
The opendis 1.0 problems worked around here are listed in docs/dis.md "Outside peers".
"""
import json
import math
import os
import struct
import subprocess
import sys


def main():
    tool, work = sys.argv[1], sys.argv[2]
    try:
        from opendis.PduFactory import createPdu
        import opendis_pdus
    except ImportError:
        print("python module opendis not found (scripts/setup.sh installs it): skipped")
        return 77
    os.makedirs(work, exist_ok=True)
    failures = []

    def check(name, got, want, tolerance=None):
        ok = abs(got - want) <= tolerance if tolerance is not None else got == want
        if not ok:
            failures.append(f"{name}: opendis {got!r}, ours {want!r}")

    # 1. opendis reads what we encode.
    ours = os.path.join(work, "ours.bin")
    expected = json.loads(subprocess.run([tool, "encode", ours], check=True, capture_output=True,
                                         text=True).stdout)
    with open(ours, "rb") as f:
        pdu = createPdu(f.read())
    if type(pdu).__name__ != "EntityStatePdu":
        print(f"FAIL: opendis decoded a {type(pdu).__name__}")
        return 1
    check("PDU type", pdu.pduType, 1)
    check("length", pdu.length, 144)
    check("exercise", pdu.exerciseID, expected["exercise"])
    check("site", pdu.entityID.siteID, expected["site"])
    check("application", pdu.entityID.applicationID, expected["application"])
    check("entity", pdu.entityID.entityID, expected["entity"])
    check("force", pdu.forceId, expected["force"])
    for axis in "xyz":
        check(f"location {axis}", getattr(pdu.entityLocation, axis), expected[axis], 0.0)
    for name in ("psi", "theta", "phi"):
        check(name, getattr(pdu.entityOrientation, name), expected[name], 1e-6)
    check("dead-reckoning algorithm", pdu.deadReckoningParameters.deadReckoningAlgorithm,
          expected["dead_reckoning"])
    check("marking set", pdu.marking.characterSet, expected["marking_set"])
    marking = bytes(c for c in pdu.marking.characters if c != 0).decode("ascii")
    check("marking", marking, expected["marking"])
    check("entity kind", pdu.entityType.entityKind, expected["kind"])
    check("country", pdu.entityType.country, expected["country"])

    # 1b. opendis's own geodesy (RangeCoordinates.GPS, NED frames) gives our Euler angles for
    # the sample's attitude in the terrain's frame, the tangent plane at the origin: its yaw is a
    # compass heading (clockwise from north), ours counter-clockwise from east.
    from opendis.RangeCoordinates import GPS
    lat = math.radians(expected["origin_lat_deg"])
    lon = math.radians(expected["origin_lon_deg"])
    yaw = math.pi / 2 - expected["heading_rad"]
    _, _, _, psi, theta, phi = GPS().llarpy2ecef(lat, lon, expected["origin_h_m"],
                                                 expected["roll_rad"], expected["pitch_rad"], yaw)
    gps_origin = GPS().lla2ecef((expected["origin_lat_deg"], expected["origin_lon_deg"],
                                 expected["origin_h_m"]))
    for axis, theirs in zip("xyz", gps_origin):
        check(f"origin {axis} from opendis's lla2ecef", theirs, expected[f"origin_{axis}"], 1e-3)
    for name, theirs in (("psi", psi), ("theta", theta), ("phi", phi)):
        delta = math.remainder(theirs - expected[name], 2 * math.pi)
        check(f"{name} from opendis's llarpy2ecef", delta, 0.0, 1e-6)

    # 2. We read what opendis encodes.
    data = opendis_pdus.entity_state(7, (31, 5, 777), (-2706000.5, -4352000.25, 3784500.125), 2,
                                     orientation=(0.5, -0.75, 1.25), velocity=(3.5, -1.5, 0.0))
    check("opendis serialised size", len(data), 144)
    theirs = os.path.join(work, "theirs.bin")
    with open(theirs, "wb") as f:
        f.write(data)
    run = subprocess.run([tool, "decode", theirs], capture_output=True, text=True)
    if run.returncode != 0:
        failures.append(f"our decoder refused opendis's Entity State: {run.stderr.strip()}")
    else:
        got = json.loads(run.stdout)
        for key, want in (("site", 31), ("application", 5), ("entity", 777), ("force", 2),
                          ("dead_reckoning", 2), ("marking", "OUTSIDE"), ("country", 222),
                          ("x", -2706000.5), ("y", -4352000.25), ("z", 3784500.125)):
            check(f"decoded {key}", got[key], want)
        for key, want in (("psi", 0.5), ("theta", -0.75), ("phi", 1.25), ("vx", 3.5),
                          ("vy", -1.5)):
            check(f"decoded {key}", got[key], want, 1e-7)
    # 3. opendis reads our crater's Point Object State field for field; it takes the 64 bits of
    # object appearance (specific 32, general 16, padding 16) for one float64, whose bits must
    # be ours.
    crater = os.path.join(work, "crater.bin")
    sent = json.loads(subprocess.run([tool, "crater", crater], check=True, capture_output=True,
                                     text=True).stdout)
    with open(crater, "rb") as f:
        crater_bytes = f.read()
    point = createPdu(crater_bytes)
    if type(point).__name__ != "PointObjectStatePdu":
        failures.append(f"opendis decoded our Point Object State as a {type(point).__name__}")
    else:
        check("object site", point.objectID.siteID, sent["site"])
        check("object application", point.objectID.applicationID, sent["application"])
        check("object number", point.objectID.entityID, sent["object"])
        check("update number", point.updateNumber, sent["update"])
        check("object domain", point.objectType.domain, sent["domain"])
        check("object kind", point.objectType.objectKind, sent["kind"])
        check("object category", point.objectType.category, sent["category"])
        for axis in "xyz":
            check(f"object location {axis}", getattr(point.objectLocation, axis), sent[axis], 0.0)
        check("requester", (point.requesterID.site, point.requesterID.application),
              (sent["site"], sent["application"]))
        check("receiving", (point.receivingID.site, point.receivingID.application),
              (65535, 65535))
        appearance_bits = struct.pack(">d", point.objectAppearance)
        check("appearance bits", appearance_bits,
              struct.pack(">IHH", sent["specific"], sent["general"], 0))
    # 4. Bundles. opendis decodes one PDU per call (the first of a datagram); split by each
    # header's length field (bytes 8-9), it reads every PDU of ours.
    bundle = os.path.join(work, "bundle.bin")
    parts = [json.loads(line) for line in subprocess.run(
        [tool, "bundle", bundle], check=True, capture_output=True, text=True).stdout.splitlines()]
    with open(bundle, "rb") as f:
        datagram = f.read()
    check("bundle size", len(datagram), sum(p["length"] for p in parts))
    first = createPdu(datagram)
    check("createPdu on a bundle: the first PDU's type", first.pduType, parts[0]["pdu_type"])
    offset = 0
    for i, part in enumerate(parts):
        length = struct.unpack_from(">H", datagram, offset + 8)[0]
        check(f"bundled PDU {i} length", length, part["length"])
        piece = datagram[offset:offset + length]
        offset += length
        check(f"bundled PDU {i} type", piece[2], part["pdu_type"])
        if part["pdu_type"] in (1, 43):  # opendis 1.0 cannot build a Linear Object State
            pdu = createPdu(piece)
            check(f"bundled PDU {i} type by opendis", pdu.pduType, part["pdu_type"])
            check(f"bundled PDU {i} length by opendis", pdu.length, part["length"])
            if part["pdu_type"] == 1:
                check(f"bundled PDU {i} entity", pdu.entityID.entityID, part["entity"])
    check("bundle walked to its end", offset, len(datagram))
    # ... and we read a bundle of opendis's Entity States (opendis has no bundling of its own:
    # concatenated here, as 1278.2 bundles are).
    theirs_bundle = os.path.join(work, "theirs_bundle.bin")
    with open(theirs_bundle, "wb") as f:
        for entity in (801, 802, 803):
            f.write(opendis_pdus.entity_state(7, (31, 5, entity), (-2706000.5, -4352000.25,
                                                                   3784500.125), 2))
    run = subprocess.run([tool, "decode-bundle", theirs_bundle], capture_output=True, text=True)
    if run.returncode != 0:
        failures.append(f"our decoder refused opendis's bundle: {run.stderr.strip()}")
    else:
        got = [json.loads(line)["entity"] for line in run.stdout.splitlines()]
        check("entities of opendis's bundle", got, [801, 802, 803])

    for f in failures:
        print("FAIL:", f)
    if not failures:
        print("opendis read our Entity State and Point Object State, and we read its Entity State")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
