#!/usr/bin/env python3
"""An outside holder of the exercise key verifies a PDU captured from our C++ code.

Makes fresh random keys, has the capture program sign one Construct with each, then checks with
nothing but Python's standard hashlib (hmac for its constant-time compare) that the trailer's MAC
is keyed BLAKE2b-256 over the LCM bytes and the trailer fields under the MAC key derived from the
key file's bytes (BLAKE2b-512 personalised "dt-pdu-mac-key-1"), that the trailer's fields are the
documented big-endian layout, and that a changed byte or another key fails; for key files of
several lengths. With LCM's Python module it also decodes the authenticated bytes as they are:
LCM's decoder stops at the end of the PDU and ignores the trailer.
Exit 0: pass; 1: mismatch.
Usage: verify_mac_with_python.py <lcm-gen> <capture-program> <work-dir> <file.lcm>...
"""
import hashlib
import hmac  # compare_digest only
import json
import os
import struct
import subprocess
import sys

TRAILER = 64
SIGNED = 32
MAGIC = b"DTA2"
PERSON = b"dt-pdu-mac-key-1"


def mac_of(key_file_bytes, data):
    mac_key = hashlib.blake2b(key_file_bytes, digest_size=64, person=PERSON).digest()
    return hashlib.blake2b(data, key=mac_key, digest_size=32).digest()


def check_capture(capture, work, key_len, failures):
    """Signs a Construct under a fresh random key of key_len bytes; checks it. The capture."""
    key_path = os.path.join(work, f"exercise-{key_len}.key")
    key = os.urandom(key_len)
    with open(key_path, "wb") as f:
        f.write(key)
    prefix = os.path.join(work, f"signed-{key_len}")
    subprocess.run([capture, prefix, key_path], check=True)
    with open(prefix + ".bin", "rb") as f:
        data = f.read()
    with open(prefix + ".json") as f:
        want = json.load(f)
    where = f"({key_len}-byte key file)"

    if len(data) != want["lcm_bytes"] + TRAILER:
        failures.append(f"{len(data)} bytes, expected {want['lcm_bytes']} + {TRAILER} {where}")
        return None, want
    lcm_part, signed, mac = data[:-TRAILER], data[-TRAILER:-SIGNED], data[-SIGNED:]

    if not hmac.compare_digest(mac_of(key, lcm_part + signed), mac):
        failures.append(f"the MAC is not keyed BLAKE2b-256 of the LCM bytes + trailer fields {where}")

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

    # The check can fail: any changed byte, another key, or the key file's bytes used as the
    # MAC key without the derivation give another MAC.
    for at in (0, 20, len(lcm_part) - 1, len(lcm_part) + 10):
        changed = bytearray(data)
        changed[at] ^= 0x01
        if hmac.compare_digest(mac_of(key, bytes(changed[:-SIGNED])), mac):
            failures.append(f"a change at byte {at} kept the MAC valid {where}")
    if hmac.compare_digest(mac_of(os.urandom(key_len), lcm_part + signed), mac):
        failures.append(f"another key gave the same MAC {where}")
    if key_len <= 64 and hmac.compare_digest(
            hashlib.blake2b(lcm_part + signed, key=key, digest_size=32).digest(), mac):
        failures.append(f"the MAC is keyed with the raw key file bytes, not the derived key {where}")
    return data, want


def main():
    lcm_gen, capture, work = sys.argv[1:4]
    lcm_files = sys.argv[4:]
    os.makedirs(work, exist_ok=True)
    failures = []
    # The shortest key file, one whose bytes BLAKE2b could not take as its key, and the longest.
    for key_len in (32, 1000, 1024):
        data, want = check_capture(capture, work, key_len, failures)
        if data is None:
            print("FAIL: " + failures[-1])
            return 1
    lcm_part = data[:-TRAILER]
    _, site, host, incarnation, sequence, _ = struct.unpack(">4sHHQQQ", data[-TRAILER:-SIGNED])

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
    print(f"OK: Python's hashlib verified the {len(data)}-byte Construct ({len(lcm_part)} LCM bytes "
          f"+ {TRAILER}-byte trailer: sender {site}:{host}, incarnation {incarnation}, sequence "
          f"{sequence}), under key files of 32, 1000 and 1024 bytes{decoded}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
