#!/usr/bin/env python3
"""A DDS tool that knows nothing of dynterrain reads its topics by field name.

Runs inside a private network namespace (tests/run_in_netns.sh): starts dds_sample_publisher,
then `cyclonedds subscribe DT7_CONSTRUCT` (the PyPI `cyclonedds` package's CLI, which learns the
type over XTypes), and checks that a sample arrives printed with the PDU's named fields, its key
and the trailer in `auth`. Bounded: 60 s; every process it starts is stopped by its PID.
Exit 0: pass; 1: fail; 77: skipped (no `cyclonedds` CLI).
Usage: dds_python_subscribe.py <dds_sample_publisher> <cyclonedds.xml>
"""
import os
import re
import selectors
import shutil
import subprocess
import sys
import time

SKIP = 77
LIMIT_S = 60
# Fields that only a typed topic shows; values are the sample Construct's (pdu/test/sample_pdus.h).
WANT = [r"feature_number=3\b", r"origin=node_address_t\(site=1, host=2\)", r"change_seq=4\b",
        r"auth=\[165, 90, 1, 2\]"]


def main():
    publisher, config = sys.argv[1:3]
    cli = shutil.which("cyclonedds")
    if cli is None:
        print("SKIP: the `cyclonedds` command (PyPI cyclonedds, installed by scripts/setup.sh) "
              "is missing")
        return SKIP
    env = dict(os.environ, CYCLONEDDS_URI="file://" + config, COLUMNS="400", NO_COLOR="1",
               TERM="dumb")
    pub = subprocess.Popen([publisher, "dds://0?config=" + config], stdout=subprocess.PIPE,
                           text=True)
    sub = None
    deadline = time.monotonic() + LIMIT_S
    try:
        if pub.stdout.readline().strip() != "ready":
            print("FAIL: the publisher did not start")
            return 1
        sub = subprocess.Popen([cli, "subscribe", "DT7_CONSTRUCT", "--suppress-progress-bar",
                                "--color", "none"], stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, env=env)
        sel = selectors.DefaultSelector()
        sel.register(sub.stdout, selectors.EVENT_READ)
        text = ""
        while time.monotonic() < deadline:
            if not sel.select(timeout=max(0.0, deadline - time.monotonic())):
                break
            chunk = os.read(sub.stdout.fileno(), 65536)
            if not chunk:
                break
            text += chunk.decode(errors="replace")
            flat = re.sub(r"\s+", " ", text)
            if all(re.search(w, flat) for w in WANT):
                sample = flat[flat.find("construct_t("):][:600]
                print("cyclonedds subscribe printed:", sample)
                return 0
        print("FAIL: no sample with named fields within %d s; output was:\n%s" % (LIMIT_S, text))
        return 1
    finally:
        for p in (sub, pub):
            if p is not None and p.poll() is None:
                p.kill()
                p.wait()


if __name__ == "__main__":
    sys.exit(main())
