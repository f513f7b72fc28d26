#!/usr/bin/env python3
"""Cross-language check: LCM's own Python module reads a PDU captured from our C++ code.

Generates the Python bindings with lcm-gen -p, loops the captured bytes through an lcm.LCM
memq instance (LCM's Python module, PyPI package `lcm`), decodes them with the generated
dtpdu.construct_t and compares every checked field with the values the capture wrote; checks that
the captured fingerprint names construct_t alone among the generated types (as a tool that picks
the type by fingerprint, like lcm-spy, would look it up). Then decodes a captured Batch as
docs/pdu.md "Batch" tells an LCM user to: batch_t, each member rebuilt if it came as a delta,
then decoded by its pdu_type.
Exit 0: pass; 1: mismatch; 77: skipped (no `lcm` Python module).
Usage: decode_with_python.py <lcm-gen> <capture-program> <work-dir> <file.lcm>...
"""
import json
import os
import subprocess
import sys

SKIP = 77


def main():
    lcm_gen, capture, work = sys.argv[1:4]
    lcm_files = sys.argv[4:]
    try:
        import lcm  # noqa: F401  (LCM's own Python module)
    except ImportError:
        print("SKIP: the `lcm` Python module is not installed (scripts/setup.sh installs it "
              "with pip); cannot check that other tools read our PDUs")
        return SKIP

    os.makedirs(work, exist_ok=True)
    prefix = os.path.join(work, "construct")
    subprocess.run([capture, prefix], check=True)
    py_dir = os.path.join(work, "python")
    subprocess.run([lcm_gen, "-p", "--ppath", py_dir] + lcm_files, check=True)
    sys.path.insert(0, py_dir)
    import dtpdu  # generated above

    with open(prefix + ".bin", "rb") as f:
        captured = f.read()
    with open(prefix + ".json") as f:
        want = json.load(f)

    # Through LCM's Python transport, as a tool listening to our traffic would get it.
    received = []
    lc = lcm.LCM("memq://")
    lc.subscribe("DT7_CONSTRUCT", lambda channel, data: received.append(data))
    lc.publish("DT7_CONSTRUCT", captured)
    lc.handle_timeout(1000)
    if received != [captured]:
        print("FAIL: LCM's Python module did not hand back the captured bytes")
        return 1

    # A tool that picks the type by fingerprint (as lcm-spy does) must find exactly one type.
    by_fingerprint = {}
    for name in dir(dtpdu):
        cls = getattr(dtpdu, name)
        if isinstance(cls, type) and hasattr(cls, "_get_packed_fingerprint"):
            by_fingerprint.setdefault(cls._get_packed_fingerprint(), []).append(cls.__name__)
    shared = [names for names in by_fingerprint.values() if len(names) > 1]
    if shared:
        print(f"FAIL: LCM types share a fingerprint: {shared}")
        return 1
    if by_fingerprint.get(captured[:8]) != ["construct_t"]:
        print(f"FAIL: the captured fingerprint names {by_fingerprint.get(captured[:8])}, "
              "not construct_t")
        return 1

    msg = dtpdu.construct_t.decode(received[0])
    got = {
        "fingerprint": dtpdu.construct_t._get_packed_fingerprint().hex(),
        "exercise_id": msg.header.exercise_id,
        "pdu_type": msg.header.pdu_type,
        "timestamp_dis": msg.header.timestamp_dis,
        "sender": [msg.sender.site, msg.sender.host],
        "sender_seq": msg.sender_seq,
        "origin": [msg.origin.site, msg.origin.host],
        "feature_number": msg.feature_number,
        "feature_type": msg.feature_type,
        "position_m": list(msg.position_m),
        "length_m0": msg.length_m[0],
        "material": msg.material,
        "vertex_edits": [[e.spoke, e.ring, e.offset_m] for e in msg.vertex_edits],
    }
    bad = {k: (got[k], want[k]) for k in want if got[k] != want[k]}
    if bad:
        for k, (g, w) in bad.items():
            print(f"FAIL: {k}: Python decoded {g!r}, C++ sent {w!r}")
        return 1
    # Re-encoding in Python gives the C++ bytes back.
    if msg.encode() != captured:
        print("FAIL: Python re-encodes different bytes")
        return 1
    print(f"OK: LCM's Python module decoded a {len(captured)}-byte Construct PDU; "
          f"{len(want)} fields match")
    return check_batch(dtpdu, prefix + "_batch.bin", msg)


def rebuild(previous, delta):
    """A member sent as a delta (encoding 1), as docs/pdu.md "Member deltas" gives it."""
    n = int.from_bytes(delta[:2], "big", signed=True)
    out = bytearray(previous[:n].ljust(n, b"\0"))
    at, cursor = 2, 0
    while at < len(delta):
        skip, count = delta[at], delta[at + 1]
        cursor += skip
        out[cursor:cursor + count] = delta[at + 2:at + 2 + count]
        cursor += count
        at += 2 + count
    return bytes(out)


def member_bytes(batch):
    """Each member's bytes as it would travel alone, in order."""
    previous = b""
    for m in batch.members:
        data = bytes(m.bytes) if m.encoding == 0 else rebuild(previous, bytes(m.bytes))
        yield data
        previous = data


def check_batch(dtpdu, path, construct):
    """The recipe of docs/pdu.md "Batch": batch_t, each member rebuilt if a delta, then decoded
    with the type it names."""
    types = {220: dtpdu.construct_t, 221: dtpdu.update_t, 222: dtpdu.destruct_t,
             223: dtpdu.max_feature_t, 224: dtpdu.playback_t, 225: dtpdu.anti_entropy_t,
             226: dtpdu.earth_move_t, 230: dtpdu.vehicle_state_t}
    with open(path, "rb") as f:
        data = f.read()
    batch = dtpdu.batch_t.decode(data)
    if batch.header.pdu_type != 231 or [m.pdu_type for m in batch.members] != [220, 221]:
        print(f"FAIL: batch of type {batch.header.pdu_type} with members "
              f"{[m.pdu_type for m in batch.members]}, not 231 with [220, 221]")
        return 1
    if [m.encoding for m in batch.members] != [0, 1]:
        print(f"FAIL: member encodings {[m.encoding for m in batch.members]}, not [0, 1] "
              "(the Update as a delta against the Construct before it)")
        return 1
    whole = list(member_bytes(batch))
    members = [types[m.pdu_type].decode(data) for m, data in zip(batch.members, whole)]
    if [p.sender_seq for p in members] != [construct.sender_seq + 1, construct.sender_seq + 2]:
        print(f"FAIL: member sender_seq {[p.sender_seq for p in members]}")
        return 1
    if members[0].feature_number != construct.feature_number or \
            list(members[0].position_m) != list(construct.position_m):
        print("FAIL: the batched Construct's fields differ from the lone one's")
        return 1
    if any(p.encode() != data for p, data in zip(members, whole)):
        print("FAIL: a member re-encodes different bytes")
        return 1
    print(f"OK: decoded a {len(data)}-byte batch of {len(members)} PDUs member by member")
    return 0


if __name__ == "__main__":
    sys.exit(main())
