#!/usr/bin/env python3
"""Fails on any #include that runs sideways or upwards between rooms (docs/architecture.md).

Reads the floors table of docs/architecture.md (room, floor, the rooms it stands on), then every
.h/.cc/.in file of each room. An include of another room must name a room the table says it
stands on; tests, benchmarks and fuzzers may also include simulation/; nothing else may.
Usage: layering_test.py <source dir>
"""
import os
import re
import sys

TEST_PARTS = ("test", "bench", "fuzz")


def read_table(path):
    rooms = {}
    row = re.compile(r"^\| (\d+) \| `([a-z_]+)/` \| .* \| ([a-z_, —]+) \|$")
    for line in open(path, encoding="utf-8"):
        m = row.match(line.strip())
        if m:
            below = {r.strip() for r in m.group(3).split(",") if r.strip() not in ("", "—")}
            rooms[m.group(2)] = (int(m.group(1)), below)
    return rooms


def main():
    src = sys.argv[1]
    rooms = read_table(os.path.join(src, "docs", "architecture.md"))
    if len(rooms) < 10:
        print(f"layering_test: read only {len(rooms)} rooms from docs/architecture.md")
        return 1
    failures = []
    # The table itself must point downwards only.
    for room, (floor, below) in rooms.items():
        for other in below:
            if other not in rooms:
                failures.append(f"docs/architecture.md: {room} stands on unknown room {other}")
            elif rooms[other][0] >= floor:
                failures.append(f"docs/architecture.md: {room} (floor {floor}) stands on "
                                f"{other} (floor {rooms[other][0]}), not below it")
    include = re.compile(r'^\s*#\s*include\s+"([a-z_]+)/', re.M)
    files = 0
    for room, (floor, below) in rooms.items():
        for root, _, names in os.walk(os.path.join(src, room)):
            rel_root = os.path.relpath(root, src)
            is_test = any(part in TEST_PARTS for part in rel_root.split(os.sep))
            for name in names:
                if not name.endswith((".h", ".cc", ".in")):
                    continue
                files += 1
                path = os.path.join(rel_root, name)
                text = open(os.path.join(src, path), encoding="utf-8").read()
                for m in include.finditer(text):
                    other = m.group(1)
                    if other == room or other not in rooms:
                        continue
                    if other in below or (is_test and other == "simulation"):
                        continue
                    line = text.count("\n", 0, m.start()) + 1
                    failures.append(f"{path}:{line}: {room} (floor {floor}) includes {other}/ "
                                    f"(floor {rooms[other][0]}), which it does not stand on")
    for f in failures:
        print(f)
    print(f"layering_test: {len(rooms)} rooms, {files} files, {len(failures)} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
