#!/usr/bin/env python3
"""Wireshark's DIS dissector (tshark) decodes our Entity State from a pcap of one UDP/3000
datagram, and the checked fields (entity ID, location, dead-reckoning algorithm, ...) equal
what dis_sample_tool encoded. It also reads the headers of our Point and Linear Object State
PDUs (tshark 4.0 names them but does not decode their contents) without calling them malformed.
A datagram bundling PDUs (IEEE 1278.2) is read without a malformed-packet warning, its first PDU
right; tshark 4.0 dissects only that first PDU (the rest is not shown), so whatever more it
dissects must be ours in order.

    tshark_entity_state.py <dis_sample_tool> <work dir>

Exits 77 (skipped) when tshark is not installed (scripts/setup.sh installs it).
"""
import json
import os
import shutil
import subprocess
import sys

FIELDS = [
    "dis.proto_ver", "dis.exer_id", "dis.pdu_type",
    "dis.entity_id_site", "dis.entity_id_application", "dis.entity_id_entity",
    "dis.entity_location.x", "dis.entity_location.y", "dis.entity_location.z",
    "dis.entity_orientation.psi", "dis.entity_orientation.theta", "dis.entity_orientation.phi",
    # tshark 4.0 names the dead-reckoning algorithm and the marking's character set with one
    # field name: it yields two values, the algorithm first.
    "dis.entity_marking_character_set",
    "dis.entity_marking",
]


def main():
    tool, work = sys.argv[1], sys.argv[2]
    tshark = shutil.which("tshark")
    if tshark is None:
        print("tshark not found (scripts/setup.sh installs it): skipped")
        return 77
    os.makedirs(work, exist_ok=True)
    pcap = os.path.join(work, "entity_state.pcap")
    expected = json.loads(subprocess.run([tool, "pcap", pcap], check=True, capture_output=True,
                                         text=True).stdout)
    cmd = [tshark, "-r", pcap, "-d", "udp.port==3000,dis", "-T", "fields",
           "-E", "separator=;", "-E", "occurrence=a", "-E", "aggregator=,"]
    for f in FIELDS:
        cmd += ["-e", f]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout.strip()
    lines = out.splitlines()
    if len(lines) != 1:
        print(f"tshark saw {len(lines)} packets, expected 1: {out!r}")
        return 1
    values = dict(zip(FIELDS, lines[0].split(";")))
    print("tshark:", values)
    failures = []

    def check_int(field, want):
        got = values.get(field, "")
        if got != str(want):
            failures.append(f"{field}: tshark {got!r}, encoded {want}")

    def check_float(field, want, tolerance):
        got = values.get(field, "")
        try:
            if abs(float(got) - want) > tolerance:
                failures.append(f"{field}: tshark {got}, encoded {want!r}")
        except ValueError:
            failures.append(f"{field}: tshark {got!r} is not a number")

    check_int("dis.proto_ver", 7)
    check_int("dis.exer_id", expected["exercise"])
    check_int("dis.pdu_type", 1)
    check_int("dis.entity_id_site", expected["site"])
    check_int("dis.entity_id_application", expected["application"])
    check_int("dis.entity_id_entity", expected["entity"])
    # tshark prints 15 significant digits: about 1e-8 m at the Earth's radius.
    for axis in "xyz":
        check_float(f"dis.entity_location.{axis}", expected[axis], 1e-6)
    # ... and 6 for the angles.
    for name in ("psi", "theta", "phi"):
        check_float(f"dis.entity_orientation.{name}", expected[name], 1e-5)
    shared = values.get("dis.entity_marking_character_set", "").split(",")
    if shared != [str(expected["dead_reckoning"]), str(expected["marking_set"])]:
        failures.append(f"dead-reckoning algorithm, character set: tshark {shared}, encoded "
                        f"{expected['dead_reckoning']}, {expected['marking_set']}")
    if values.get("dis.entity_marking") != expected["marking"]:
        failures.append(f"marking: tshark {values.get('dis.entity_marking')!r}, encoded "
                        f"{expected['marking']!r}")
    # The whole dissection must be free of malformed-packet warnings.
    verbose = subprocess.run([tshark, "-r", pcap, "-V"], check=True, capture_output=True,
                             text=True).stdout
    if "Malformed" in verbose or "Expert Info (Error" in verbose:
        failures.append("tshark reports the packet malformed")
    # The algorithm by name and number, as the dissector's own enumeration spells it.
    if f"Dead Reckoning Algorithm: DRM(R, V, W) ({expected['dead_reckoning']})" not in verbose:
        failures.append("tshark does not name the dead-reckoning algorithm DRM(R, V, W) (4)")
    if f"PDU Length: {144}" not in verbose:
        failures.append("tshark does not read a PDU length of 144")

    # Features: the dissector's header fields for each Point / Linear Object State.
    features = os.path.join(work, "features.pcap")
    sent = [json.loads(line) for line in subprocess.run(
        [tool, "features-pcap", features], check=True, capture_output=True,
        text=True).stdout.splitlines()]
    out = subprocess.run([tshark, "-r", features, "-T", "fields", "-E", "separator=;",
                          "-e", "dis.proto_ver", "-e", "dis.pdu_type", "-e", "dis.pdu_length"],
                         check=True, capture_output=True, text=True).stdout.split()
    want = [f"7;{p['pdu_type']};{p['length']}" for p in sent]
    if out != want:
        failures.append(f"feature PDU headers: tshark {out}, sent {want}")
    verbose = subprocess.run([tshark, "-r", features, "-V"], check=True, capture_output=True,
                             text=True).stdout
    if "Malformed" in verbose or "Expert Info (Error" in verbose:
        failures.append("tshark reports a feature PDU malformed")
    for name in ("Point Object State PDU", "Linear Object State PDU"):
        if name not in verbose:
            failures.append(f"tshark does not name a {name}")

    # A bundle: one datagram holding an Entity State, a crater, a berm and an Entity State.
    bundle = os.path.join(work, "bundle.pcap")
    parts = [json.loads(line) for line in subprocess.run(
        [tool, "bundle-pcap", bundle], check=True, capture_output=True,
        text=True).stdout.splitlines()]
    out = subprocess.run([tshark, "-r", bundle, "-d", "udp.port==3000,dis", "-T", "fields",
                          "-E", "separator=;", "-E", "occurrence=a", "-E", "aggregator=,",
                          "-e", "dis.pdu_type", "-e", "dis.pdu_length"],
                         check=True, capture_output=True, text=True).stdout.strip().splitlines()
    if len(out) != 1:
        failures.append(f"bundle: tshark saw {len(out)} packets, expected 1")
    else:
        types, lengths = (column.split(",") for column in out[0].split(";"))
        want = [(str(p["pdu_type"]), str(p["length"])) for p in parts]
        dissected = list(zip(types, lengths))
        print(f"tshark dissected {len(dissected)} of the bundle's {len(parts)} PDUs: {dissected}")
        if not dissected or dissected != want[:len(dissected)]:
            failures.append(f"bundle: tshark read {dissected}, sent {want}")
    verbose = subprocess.run([tshark, "-r", bundle, "-V"], check=True, capture_output=True,
                             text=True).stdout
    if "Malformed" in verbose or "Expert Info (Error" in verbose:
        failures.append("tshark reports the bundle malformed")

    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
