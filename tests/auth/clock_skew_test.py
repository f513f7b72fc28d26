#!/usr/bin/env python3
"""A host whose clock is 45 s ahead is named, not silently cut off (docs/pdu.md "Authentication", clock skew).

Run inside tests/run_in_netns.sh (a private network namespace). dt_launch starts a server and two
nodes of an authenticated exercise (PDUs stamped with their send time, 30 s tolerance); node-2 runs
under `faketime -f +45s` (Debian's faketime, libfaketime), through a --node-bin wrapper. Then,
reading dt_launch's prefixed output line by line (readiness is a line read, never a sleep):
  a. the server and node-1 each log that PDUs from 1:2 (node-2) are stamped about 45 s ahead of
     their clock, and their `status` names 1:2 with an offset near 45 s;
  b. node-2 logs that its own clock is probably 45 s ahead of the exercise, and its `status` says
     own_clock_suspect 1;
  c. dt_launch gives up after its (short) ready timeout with an error that names node-2 and
     quotes node-2's clock line, and exits non-zero.
Everything is bounded in time; dt_launch (which stops its children by process group) is stopped
by PID if it still runs; the work directory is removed at the end.
With a last argument `lan` the same runs in hosts mode (dt_launch --hosts lan, docs/deploy.md):
each process on a network namespace of its own on one bridge, udpm at ttl=1, so node-2 is a host
of its own whose clock is off (root only; run under tests/drills/run_hosts_drill.sh).
Usage: clock_skew_test.py <dt_launch> <dt_node> <dt_server> <dt_ctl> <key file> <work dir> [lan]
Exit 0: pass; 1: fail; 77: skipped (no faketime, or it does not move this machine's clock).
"""
import os
import re
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "pylib"))
from launch_output import LaunchOutput  # noqa: E402

SKIP = 77
SKEW_S = 45
READY_TIMEOUT_S = 20  # dt_launch's --ready-timeout-s: node-2 never signs on
WAIT_S = 30  # every wait for a line gives up after this long
SKEWED = "node-2"
SKEWED_ADDRESS = "1:2"

EXERCISE = """\
[exercise]
name = "clock-skew"
id = 5
transport = "udpm://239.255.76.67:7667?ttl=0"
run_dir = "{run_dir}"
tick_hz = 30

[auth]
key_file = "{key}"

[terrain]
posts_per_side = 65
spacing_m = 10.0
relief_m = 20.0
seed = 42

[protocol]
max_feature_period_ms = 200
silence_ms = 1000
playback_retry_ms = 300
anti_entropy_period_ms = 500

[server]
name = "server"
site = 1
host = 100

[[node]]
name = "node-1"
site = 1
host = 1

[[node]]
name = "node-2"
site = 1
host = 2
"""

# dt_launch starts every node through this: node-2 under faketime, the others as they are.
# faketime preloads libfaketime ahead of a sanitized program's ASan runtime, which ASan refuses
# unless told the order does not matter (the asan-ubsan preset sets ASAN_OPTIONS).
WRAPPER = """\
#!/bin/sh
for a in "$@"; do
  if [ "$a" = "{skewed}" ]; then
    if [ -n "$ASAN_OPTIONS" ]; then
      ASAN_OPTIONS="$ASAN_OPTIONS:verify_asan_link_order=0"; export ASAN_OPTIONS
    fi
    exec faketime -f +{skew}s "{node}" "$@"
  fi
done
exec "{node}" "$@"
"""


class Failure(Exception):
    pass


def faketime_works():
    """True if faketime is installed and moves the clock of what it runs by SKEW_S."""
    if shutil.which("faketime") is None:
        print("SKIP: faketime is not installed (scripts/setup.sh installs it)")
        return False
    try:
        r = subprocess.run(["faketime", "-f", f"+{SKEW_S}s", "date", "+%s"], capture_output=True,
                           text=True, timeout=10)
        skew = int(r.stdout.strip()) - int(time.time())
    except (subprocess.SubprocessError, ValueError) as e:
        print(f"SKIP: faketime does not run here: {e}")
        return False
    if abs(skew - SKEW_S) > 2:
        print(f"SKIP: faketime moved the clock by {skew} s, not {SKEW_S} s")
        return False
    return True


def Launch(argv):
    """dt_launch of an exercise, its output read line by line under deadlines."""
    return LaunchOutput(argv, failure=Failure, wait_s=WAIT_S)


def status(ctl, config, name):
    """`status` of a process as a dict of its single lines, and its clock_suspect lines."""
    r = subprocess.run([ctl, "--config", config, "--name", name, "status"], capture_output=True,
                       text=True, timeout=10)
    if r.returncode != 0:
        raise Failure(f"dt_ctl --name {name} status: exit {r.returncode}: {r.stderr.strip()}")
    single, suspects = {}, []
    for line in r.stdout.splitlines():
        key, _, value = line.partition(" ")
        if key == "clock_suspect":
            suspects.append(value)
        else:
            single.setdefault(key, value)
    return single, suspects


def check_offset(who, seconds):
    if abs(seconds - SKEW_S) > 2:
        raise Failure(f"{who}: offset {seconds} s, not about {SKEW_S} s")


def run(launch_bin, node_bin, server_bin, ctl, key, work, hosts):
    config = os.path.join(work, "clock-skew.toml")
    with open(config, "w") as f:
        f.write(EXERCISE.format(key=os.path.abspath(key), run_dir=os.path.join(work, "run")))
    wrapper = os.path.join(work, "skewed-node")
    with open(wrapper, "w") as f:
        f.write(WRAPPER.format(skewed=SKEWED, skew=SKEW_S, node=os.path.abspath(node_bin)))
    os.chmod(wrapper, 0o755)

    launch = Launch([launch_bin, "--config", config, "--node-bin", wrapper, "--server-bin",
                     server_bin, "--ready-timeout-s", str(READY_TIMEOUT_S), "--grace-ms", "5000"]
                    + (["--hosts", hosts] if hosts else []))
    try:
        # a. Each other process names node-2, its address and its offset.
        for who in ("server", "node-1"):
            m = launch.wait_for(
                f"[{who}] naming {SKEWED}",
                re.compile(rf"^\[{who}\] .* warning \[{who}\] clock skew: PDUs from "
                           rf"{SKEWED_ADDRESS} \({SKEWED}\) are stamped ([0-9.]+) s ahead of this "
                           r"host's clock, beyond the exercise's 30 s tolerance"))
            check_offset(f"{who}'s log", float(m.group(1)))
            single, suspects = status(ctl, config, who)
            if single.get("clock_suspect_senders") != "1" or len(suspects) != 1:
                raise Failure(f"{who}'s status: clock_suspect_senders "
                              f"{single.get('clock_suspect_senders')}, lines {suspects}")
            m = re.fullmatch(rf"{SKEWED_ADDRESS} offset_ms=(-?\d+) stale=(\d+)", suspects[0])
            if not m:
                raise Failure(f"{who}'s status: clock_suspect {suspects[0]}")
            check_offset(f"{who}'s status", int(m.group(1)) / 1000)
            check_offset(f"{who}'s clock_worst_offset_ms",
                         int(single["clock_worst_offset_ms"]) / 1000)
            if single.get("own_clock_suspect") != "0":
                raise Failure(f"{who} suspects its own clock: {single}")
            print(f"PASS: {who} names {SKEWED_ADDRESS} ({SKEWED}) {m.group(1)} ms ahead")

        # b. node-2 blames its own clock.
        m = launch.wait_for(
            f"[{SKEWED}] blaming its own clock",
            re.compile(rf"^\[{SKEWED}\] .* warning \[{SKEWED}\] clock skew: every PDU received is "
                       r"stamped about (\d+) s behind this host's clock: this host's clock is "
                       r"probably (\d+) s ahead of the exercise"))
        check_offset(f"{SKEWED}'s log", float(m.group(2)))
        single, suspects = status(ctl, config, SKEWED)
        if single.get("own_clock_suspect") != "1" or len(suspects) != 2:
            raise Failure(f"{SKEWED}'s status: own_clock_suspect "
                          f"{single.get('own_clock_suspect')}, clock_suspect lines {suspects}")
        check_offset(f"{SKEWED}'s own_clock_offset_ms", int(single["own_clock_offset_ms"]) / 1000)
        print(f"PASS: {SKEWED} says its own clock is probably {m.group(2)} s ahead")

        # c. dt_launch's ready timeout names node-2 and quotes its clock line.
        m = launch.wait_for(
            "dt_launch's ready timeout",
            re.compile(r"^\[launch\] exercise failed to start: not ready after "
                       rf"{READY_TIMEOUT_S * 1000} ms: (.*)$"),
            timeout_s=READY_TIMEOUT_S + WAIT_S)
        reason = m.group(1)
        if not re.search(rf"(^|, ){SKEWED} \(its last word: \".* warning \[{SKEWED}\] clock "
                         r"skew: .*this host's clock is probably \d+ s ahead of the exercise",
                         reason):
            raise Failure(f"the timeout does not quote {SKEWED}'s clock line: {reason}")
        rc = launch.wait_exit()
        if rc == 0:
            raise Failure("dt_launch exited 0 although node-2 was never ready")
        print(f"PASS: dt_launch gave up quoting {SKEWED}'s clock line, exit {rc}")
    finally:
        launch.stop()
        if sys.exc_info()[0] is not None:
            print("dt_launch's output:\n" + "\n".join(launch.lines), file=sys.stderr)


def main():
    if len(sys.argv) not in (7, 8) or sys.argv[7:] not in ([], ["lan"]):
        print(__doc__, file=sys.stderr)
        return 2
    launch_bin, node_bin, server_bin, ctl, key, work = sys.argv[1:7]
    hosts = sys.argv[7] if len(sys.argv) == 8 else ""
    if not faketime_works():
        return SKIP
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    try:
        run(launch_bin, node_bin, server_bin, ctl, key, work, hosts)
    except Failure as e:
        print(f"FAIL: {e}")
        return 1
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print(f"clock_skew_test{' (hosts mode ' + hosts + ')' if hosts else ''}: pass")
    return 0


if __name__ == "__main__":
    sys.exit(main())
