#!/usr/bin/env python3
"""An outside holder of the exercise key verifies a PDU captured from our C++ code.

Makes a fresh random key, has the capture program sign one Construct with it, then checks with
nothing but Python's standard hmac and hashlib that the trailer's MAC is HMAC-SHA-512 truncated to
32 bytes (libsodium's crypto_auth, HMAC-SHA512-256) over the LCM bytes and the trailer fields, that
the trailer's fields are the documented big-endian layout, and that a changed byte or another key
fails. With LCM's Python module it also decodes the authenticated bytes as they are: LCM's decoder
stops at the end of the PDU and ignores the trailer.
Exit 0: pass; 1: mismatch.
Usage: verify_mac_with_python.py <lcm-gen> <capture-program> <work-dir> <file.lcm>...
"""
import hashlib
import hmac
import json
import os
import struct
import subprocess
import sys

TRAILER = 64
SIGNED = 32
MAGIC = b"DTA1"


def mac_of(key, data):
    return hmac.new(key, data, hashlib.sha512).digest()[:32]


def main():
    lcm_gen, capture, work = sys.argv[1:4]
    lcm_files = sys.argv[4:]
    os.makedirs(work, exist_ok=True)
    key_path = os.path.join(work, "exercise.key")
    key = os.urandom(32)
    with open(key_path, "wb") as f:
        f.write(key)
    prefix = os.path.join(work, "signed")
    subprocess.run([capture, prefix, key_path], check=True)
    with open(prefix + ".bin", "rb") as f:
        data = f.read()
    with open(prefix + ".json") as f:
        want = json.load(f)

    failures = []
    if len(data) != want["lcm_bytes"] + TRAILER:
        print(f"FAIL: {len(data)} bytes, expected {want['lcm_bytes']} + {TRAILER}")
        return 1
    lcm_part, signed, mac = data[:-TRAILER], data[-TRAILER:-SIGNED], data[-SIGNED:]

    if not hmac.compare_digest(mac_of(key, lcm_part + signed), mac):
        failures.append("the MAC is not HMAC-SHA-512/256 of the LCM bytes + trailer fields")

    magic, site, host, incarnation, sequence, send_ms = struct.unpack(">4sHHQQQ", signed)
    t = want["trailer"]
    got_t = {"sender": [site, host], "incarnation": incarnation, "sequence": sequence,
             "send_time_ms": send_ms}
    if magic != MAGIC:
        failures.append(f"magic {magic!r}, expected {MAGIC!r}")
    for k in t:
        if got_t[k] != t[k]:
            failures.append(f"trailer {k}: read {got_t[k]!r}, C++ sent {t[k]!r}")
    # The PDU's own sender field (bytes 15..18, big-endian) is the trailer's sender.
    pdu_sender = list(struct.unpack(">HH", lcm_part[15:19]))
    if pdu_sender != [site, host]:
        failures.append(f"PDU sender {pdu_sender} != trailer sender {[site, host]}")

    # The check can fail: any changed byte, or another key, gives another MAC.
    for at in (0, 20, len(lcm_part) - 1, len(lcm_part) + 10):
        changed = bytearray(data)
        changed[at] ^= 0x01
        if hmac.compare_digest(mac_of(key, bytes(changed[:-SIGNED])), mac):
            failures.append(f"a change at byte {at} kept the MAC valid")
    if hmac.compare_digest(mac_of(os.urandom(32), lcm_part + signed), mac):
        failures.append("another key gave the same MAC")

    # LCM's Python decoder reads the authenticated bytes, trailer and all.
    try:
        import lcm  # noqa: F401  (only to know the generated code can run)
        py_dir = os.path.join(work, "python")
        subprocess.run([lcm_gen, "-p", "--ppath", py_dir] + lcm_files, check=True)
        sys.path.insert(0, py_dir)
        import dtpdu  # generated above
        msg = dtpdu.construct_t.decode(data)
        if [msg.sender.site, msg.sender.host] != want["sender"]:
            failures.append("LCM's Python decoder read another sender from the signed bytes")
        if msg.feature_number != want["feature_number"] or list(msg.position_m) != want["position_m"]:
            failures.append("LCM's Python decoder read other fields from the signed bytes")
        if msg.encode() != lcm_part:
            failures.append("the decoded PDU re-encodes to other bytes than the LCM part")
        decoded = "; LCM's Python module decodes the signed bytes"
    except ImportError:
        decoded = "; LCM's Python module is not installed, decoding not checked"

    if failures:
        for f in failures:
            print("FAIL: " + f)
        return 1
    print(f"OK: Python's hmac verified the {len(data)}-byte Construct ({len(lcm_part)} LCM bytes "
          f"+ {TRAILER}-byte trailer: sender {site}:{host}, incarnation {incarnation}, sequence "
          f"{sequence}){decoded}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
