#!/usr/bin/env python3
"""Tests transport/idl/lcm_to_idl.py: the IDL it writes has every LCM struct with the same members in
the same order (plus `auth` on the PDU types, keys on the feature and vehicle types); a member added to one
.lcm file (as a fingerprint change would) reaches that type's IDL and conversions only; what the
generator cannot map is refused naming the file and line.
Usage: lcm_to_idl_test.py <lcm_to_idl.py> <file.lcm>...
"""
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

FAILURES = []


def check(condition, message):
    if not condition:
        FAILURES.append(message)


def lcm_members(path):
    text = re.sub(r"//[^\n]*", "", Path(path).read_text())
    body = re.search(r"struct\s+(\w+)\s*\{(.*?)\}", text, re.S)
    names = [re.match(r"\s*\w+\s+(\w+)", d).group(1)
             for d in body.group(2).split(";") if d.strip()]
    return body.group(1), names


def idl_structs(idl):
    structs = {}
    for name, body in re.findall(r"struct\s+(\w+)\s*\{(.*?)\};", idl, re.S):
        members, keys = [], []
        for line in body.split("\n"):
            line = re.sub(r"//.*", "", line).strip().rstrip(";")
            if not line:
                continue
            m = re.search(r"(\w+)(\[\d+\])?$", line)
            members.append(m.group(1))
            if line.startswith("@key"):
                keys.append(m.group(1))
        structs[name] = (members, keys)
    return structs


def generate(script, out, files):
    return subprocess.run([sys.executable, script, str(out)] + [str(f) for f in files],
                          capture_output=True, text=True)


def main():
    script, files = sys.argv[1], sys.argv[2:]
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        r = generate(script, tmp / "real", files)
        check(r.returncode == 0, f"generator failed on the real files: {r.stderr}")
        idl = idl_structs((tmp / "real" / "dt_pdu_dds.idl").read_text())
        for f in files:
            name, members = lcm_members(f)
            got, keys = idl.get(name, ([], []))
            pdu = bool(members) and members[0] == "header"  # a PDU type opens with its header
            want = members + (["auth"] if pdu else [])
            check(got == want, f"{name}: IDL members {got} != LCM members {want}")
            if name in ("construct_t", "update_t", "destruct_t", "earth_move_t"):
                check(keys == ["origin", "feature_number"], f"{name}: keys {keys}")
            elif name == "vehicle_state_t":  # one DDS instance per vehicle
                check(keys == ["entity_id"], f"{name}: keys {keys}")
            else:
                check(keys == [], f"{name}: unexpected keys {keys}")

        # A member added to update_t only, as a fingerprint change would add.
        changed = tmp / "changed_lcm"
        changed.mkdir()
        for f in files:
            shutil.copy(f, changed)
        update = changed / "update_t.lcm"
        update.write_text(update.read_text().replace(
            "int64_t lamport;", "int64_t lamport;\n    int32_t added_member_for_test;"))
        r = generate(script, tmp / "changed", sorted(changed.glob("*.lcm")))
        check(r.returncode == 0, f"generator failed on a changed update_t: {r.stderr}")
        idl = idl_structs((tmp / "changed" / "dt_pdu_dds.idl").read_text())
        check("added_member_for_test" in idl["update_t"][0], "the added member is not in update_t")
        check("added_member_for_test" not in idl["construct_t"][0],
              "the added member leaked into construct_t")
        codec = (tmp / "changed" / "dt_pdu_dds_codec.cc").read_text()
        lines = [ln for ln in codec.split("\n") if "added_member_for_test" in ln]
        check(len(lines) == 2, f"the added member should be converted once each way: {lines}")

        # Unsupported: a string member.
        bad = changed / "update_t.lcm"
        bad.write_text(bad.read_text().replace("int32_t added_member_for_test;", "string name;"))
        r = generate(script, tmp / "bad", sorted(changed.glob("*.lcm")))
        check(r.returncode != 0 and re.search(r"update_t\.lcm:\d+: 'string' is not supported",
                                              r.stderr), f"string not refused: {r.stderr!r}")
    for f in FAILURES:
        print("FAIL:", f)
    print(f"{'0' if FAILURES else '1'} passed, {len(FAILURES)} failed")
    return 1 if FAILURES else 0


if __name__ == "__main__":
    sys.exit(main())
