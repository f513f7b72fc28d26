#!/usr/bin/env python3
"""A host whose clock is 45 s off is named, not silently cut off; one 10 s off is not cut off at all
(docs/pdu.md "Authentication", clock skew; docs/deploy.md "Clocks").

Loopback (no mode argument), run inside tests/run_in_netns.sh (a private network namespace):
dt_launch starts a server and two nodes of an authenticated exercise (PDUs stamped with their send
time, 30 s tolerance); node-2 runs under `faketime -f +45s` (Debian's faketime, libfaketime),
through a --node-bin wrapper. Then, reading dt_launch's prefixed output line by line (readiness is
a line read, never a sleep):
  a. the server and node-1 each log that PDUs from 1:2 (node-2) are stamped about 45 s ahead of
     their clock, and their `status` names 1:2 with an offset near 45 s;
  b. node-2 logs that its own clock is probably 45 s ahead of the exercise, and its `status` says
     own_clock_suspect 1;
  c. dt_launch gives up after its (short) ready timeout with an error that names node-2 and
     quotes node-2's clock line, and exits non-zero.

Hosts mode (`lan <udpm|dds> <ahead|behind>`, run under tests/drills/run_hosts_drill.sh, root
only): dt_launch --hosts lan puts each process on a network namespace of its own on one bridge
(udpm at ttl=1, or Cyclone DDS on the hosts' interfaces). Four processes: the server, node-1 on
time, node-2 45 s off and node-3 10 s off the other way (ahead: node-2 +45 s, node-3 -10 s;
behind: node-2 -45 s, node-3 +10 s), each under libfaketime (LD_PRELOAD, so the wrapper knows the
node's own PID). Then:
  a. the server and node-1 name node-2 (and only node-2) with an offset near 45 s in its
     direction, in their log and `status`; node-3, 10 s off and inside the tolerance, names only
     node-2 too (55 s from its own clock), signs on (READY) and suspects no clock of its own;
  b. node-2 says its own clock is probably off in its direction, and its `status` says so;
  c. node-2's clock is corrected and the host restarted: its node is SIGKILLed by PID and starts
     again on the true clock; it signs on (READY), dt_launch reports the exercise READY, a crater
     made on node-2 and one on node-3 reach every process, and all four hold one digest, caught
     up, with no clock suspect left anywhere.
Everything is bounded in time; dt_launch (which stops its children by process group) is stopped
by PID if it still runs; the work directory is removed at the end.
Usage: clock_skew_test.py <dt_launch> <dt_node> <dt_server> <dt_ctl> <key file> <work dir>
                          [lan <udpm|dds> <ahead|behind>]
Exit 0: pass; 1: fail; 77: skipped (no faketime, or it does not move this machine's clock).
"""
import os
import re
import shutil
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "pylib"))
from dt_ctl import ctl_answer  # noqa: E402
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


def run(launch_bin, node_bin, server_bin, ctl, key, work):
    config = os.path.join(work, "clock-skew.toml")
    with open(config, "w") as f:
        f.write(EXERCISE.format(key=os.path.abspath(key), run_dir=os.path.join(work, "run")))
    wrapper = os.path.join(work, "skewed-node")
    with open(wrapper, "w") as f:
        f.write(WRAPPER.format(skewed=SKEWED, skew=SKEW_S, node=os.path.abspath(node_bin)))
    os.chmod(wrapper, 0o755)

    launch = Launch([launch_bin, "--config", config, "--node-bin", wrapper, "--server-bin",
                     server_bin, "--ready-timeout-s", str(READY_TIMEOUT_S), "--grace-ms", "5000"])
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


# Hosts mode: node-2 45 s off and node-3 10 s off the other way; node-2's clock then corrected.
HOSTS_SKEW_S = {"node-2": 45, "node-3": -10}  # "ahead"; "behind" negates both
HOSTS_READY_TIMEOUT_S = 120  # node-2 signs on only after its restart
LIBFAKETIME = "/usr/lib/x86_64-linux-gnu/faketime/libfaketime.so.1"
ADDRESSES = {"server": "1:100", "node-1": "1:1", "node-2": "1:2", "node-3": "1:3"}

HOSTS_EXERCISE_TAIL = """
[[node]]
name = "node-3"
site = 1
host = 3
"""

# node-2 and node-3 run under libfaketime by LD_PRELOAD (not `faketime`, which forks: the wrapper
# must know the node's own PID). node-2's wrapper waits for its node; once the test has written
# the `corrected` file and SIGKILLed that node (a host restarted with its clock set right), it
# starts the node again on the true clock, in its place.
HOSTS_WRAPPER = """\
#!/bin/sh
skew=""
for a in "$@"; do
  case "$a" in
    node-2) skew="{skew2}"; name=node-2 ;;
    node-3) skew="{skew3}"; name=node-3 ;;
  esac
done
if [ -z "$skew" ]; then exec "{node}" "$@"; fi
if [ -n "$ASAN_OPTIONS" ]; then
  ASAN_OPTIONS="$ASAN_OPTIONS:verify_asan_link_order=0"; export ASAN_OPTIONS
fi
if [ "$name" = node-3 ]; then
  LD_PRELOAD="{lib}" FAKETIME="$skew" exec "{node}" "$@"
fi
LD_PRELOAD="{lib}" FAKETIME="$skew" "{node}" "$@" &
echo $! > "{pid_file}"
wait $!
if [ -e "{corrected}" ]; then exec "{node}" "$@"; fi
exit 1
"""


def skew_text(seconds):
    return f"{seconds:+d}s"


def direction_word(seconds):
    """As the log words an offset: "ahead of" or "behind"."""
    return "ahead of" if seconds > 0 else "behind"


def check_signed_offset(who, seconds, expected_s, slack_s=2):
    if abs(seconds - expected_s) > slack_s:
        raise Failure(f"{who}: offset {seconds} s, not about {expected_s} s")


def check_suspects(ctl, config, who, expected_offset_s):
    """`who` names node-2, and only node-2, with about expected_offset_s (signed), and does not
    suspect its own clock."""
    single, suspects = status(ctl, config, who)
    if single.get("clock_suspect_senders") != "1" or len(suspects) != 1:
        raise Failure(f"{who}'s status: clock_suspect_senders "
                      f"{single.get('clock_suspect_senders')}, lines {suspects} (only node-2, "
                      "1:2, should be named; node-3 is 10 s off, inside the 30 s tolerance)")
    m = re.fullmatch(r"1:2 offset_ms=(-?\d+) stale=(\d+)", suspects[0])
    if not m:
        raise Failure(f"{who}'s status: clock_suspect {suspects[0]}")
    check_signed_offset(f"{who}'s status", int(m.group(1)) / 1000, expected_offset_s)
    if single.get("own_clock_suspect") != "0":
        raise Failure(f"{who} suspects its own clock: {single}")
    return int(m.group(1))


def converged(ctl, config, names):
    """True when every process is signed on, caught up, holds the same digest and two features,
    and names no clock, its own or another's."""
    digests = set()
    for name in names:
        single, suspects = status(ctl, config, name)
        if (single.get("signed_on") != "1" or single.get("caught_up") != "1"
                or single.get("features") != "2" or suspects
                or single.get("clock_suspect_senders") != "0"
                or single.get("own_clock_suspect") != "0"):
            return False
        digests.add(single.get("digest"))
    return len(digests) == 1


def ctl_line(ctl_bin, config, name, *words):
    return ctl_answer(ctl_bin, config, name, *words, failure=Failure)


def run_hosts(launch_bin, node_bin, server_bin, ctl, key, work, carrier, direction):
    sign = 1 if direction == "ahead" else -1
    skew = {name: sign * s for name, s in HOSTS_SKEW_S.items()}
    if carrier == "udpm":
        transport = "udpm://239.255.76.67:7667?ttl=0"
    else:  # the hosts mode writes its own Cyclone configuration for the hosts' interface
        transport = "dds://0?config=" + os.path.join(
            os.path.dirname(os.path.abspath(__file__)), "..", "..", "configs",
            "cyclonedds-loopback.xml")
    config = os.path.join(work, "clock-skew.toml")
    with open(config, "w") as f:
        f.write(EXERCISE.format(key=os.path.abspath(key), run_dir=os.path.join(work, "run"))
                .replace('transport = "udpm://239.255.76.67:7667?ttl=0"',
                         f'transport = "{transport}"') + HOSTS_EXERCISE_TAIL)
    pid_file = os.path.join(work, "node-2.pid")
    corrected = os.path.join(work, "corrected")
    wrapper = os.path.join(work, "skewed-node")
    with open(wrapper, "w") as f:
        f.write(HOSTS_WRAPPER.format(skew2=skew_text(skew["node-2"]),
                                     skew3=skew_text(skew["node-3"]), lib=LIBFAKETIME,
                                     node=os.path.abspath(node_bin), pid_file=pid_file,
                                     corrected=corrected))
    os.chmod(wrapper, 0o755)

    launch = Launch([launch_bin, "--config", config, "--node-bin", wrapper, "--server-bin",
                     server_bin, "--ready-timeout-s", str(HOSTS_READY_TIMEOUT_S), "--grace-ms",
                     "5000", "--hosts", "lan"])
    n2, n3 = skew["node-2"], skew["node-3"]
    try:
        # a. The server and node-1 name node-2 about 45 s off; node-3 names it 55 s off, signs on
        # and blames no clock of its own.
        for who, expected in (("server", n2), ("node-1", n2), ("node-3", n2 - n3)):
            m = launch.wait_for(
                f"[{who}] naming node-2",
                re.compile(rf"^\[{who}\] .* warning \[{who}\] clock skew: PDUs from 1:2 "
                           rf"\(node-2\) are stamped ([0-9.]+) s {direction_word(expected)} "
                           r"this host's clock, beyond the exercise's 30 s tolerance"))
            check_signed_offset(f"{who}'s log", abs(float(m.group(1))), abs(expected))
            offset_ms = check_suspects(ctl, config, who, expected)
            print(f"PASS: {who} names 1:2 (node-2) {offset_ms} ms off")
        launch.wait_for("node-3's READY", re.compile(r"^\[node-3\] READY node-3$"))
        print(f"PASS: node-3, {n3:+d} s off, signed on")

        # b. node-2 blames its own clock (the others are 45 and 55 s away from it: the mean).
        m = launch.wait_for(
            "[node-2] blaming its own clock",
            re.compile(r"^\[node-2\] .* warning \[node-2\] clock skew: every PDU received is "
                       rf"stamped about (\d+) s {'behind' if n2 > 0 else 'ahead of'} this "
                       rf"host's clock: this host's clock is probably (\d+) s "
                       rf"{direction_word(n2)} the exercise"))
        own = int(m.group(2))
        if not abs(n2) - 2 <= own <= abs(n2 - n3) + 2:
            raise Failure(f"node-2 blames its clock by {own} s, not {abs(n2)}..{abs(n2 - n3)} s")
        single, _ = status(ctl, config, "node-2")
        if single.get("own_clock_suspect") != "1" or \
                int(single["own_clock_offset_ms"]) * sign < (abs(n2) - 2) * 1000:
            raise Failure(f"node-2's status: own_clock_suspect {single.get('own_clock_suspect')}"
                          f", own_clock_offset_ms {single.get('own_clock_offset_ms')}")
        print(f"PASS: node-2 says its own clock is probably {own} s {direction_word(n2)} the "
              "exercise")

        # c. node-2's clock corrected, its host restarted: it signs on and the exercise converges.
        with open(corrected, "w") as f:
            f.write("clock corrected\n")
        with open(pid_file) as f:
            skewed_pid = int(f.read().strip())
        os.kill(skewed_pid, signal.SIGKILL)
        launch.wait_for("node-2's READY after the restart",
                        re.compile(r"^\[node-2\] READY node-2$"), timeout_s=60)
        launch.wait_for("the exercise's READY", re.compile(r"^READY clock-skew$|"
                                                           r"^\[launch\] READY clock-skew$"))
        for name in ("node-2", "node-3"):
            ctl_line(ctl, config, name, "crater", "200" if name == "node-2" else "400", "300",
                     "5")
        names = list(ADDRESSES)
        deadline = time.monotonic() + WAIT_S
        while not converged(ctl, config, names):
            if time.monotonic() > deadline:
                report = {n: status(ctl, config, n) for n in names}
                raise Failure(f"not converged within {WAIT_S} s of the restart: {report}")
            time.sleep(0.2)  # polling the processes' status, as dt_drill's digest marks do
        print("PASS: node-2 restarted on the true clock, signed on; every process converged, "
              "no clock named")
    finally:
        launch.stop()
        if sys.exc_info()[0] is not None:
            print("dt_launch's output:\n" + "\n".join(launch.lines), file=sys.stderr)


def main():
    hosts = sys.argv[7:]
    if len(sys.argv) < 7 or not (hosts == [] or (
            len(hosts) == 3 and hosts[0] == "lan" and hosts[1] in ("udpm", "dds")
            and hosts[2] in ("ahead", "behind"))):
        print(__doc__, file=sys.stderr)
        return 2
    launch_bin, node_bin, server_bin, ctl, key, work = sys.argv[1:7]
    if not faketime_works():
        return SKIP
    if hosts and not os.path.exists(LIBFAKETIME):
        print(f"SKIP: {LIBFAKETIME} is not here (scripts/setup.sh installs faketime)")
        return SKIP
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    try:
        if hosts:
            run_hosts(launch_bin, node_bin, server_bin, ctl, key, work, hosts[1], hosts[2])
        else:
            run(launch_bin, node_bin, server_bin, ctl, key, work)
    except Failure as e:
        print(f"FAIL: {e}")
        return 1
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print(f"clock_skew_test{' (hosts mode ' + ' '.join(hosts) + ')' if hosts else ''}: pass")
    return 0


if __name__ == "__main__":
    sys.exit(main())
