#!/usr/bin/env python3
"""An exercise starts on a saved terrain, and a node on another ground is refused, naming both
(docs/node.md "Starting from a saved terrain", docs/pdu.md "Ground identity").

Run inside tests/run_in_netns.sh (a private network namespace). Reading dt_launch's prefixed
output line by line (readiness is a line read, never a sleep):
  1. Exercise "field" on random ground: node-1 places a crater, the server `export`s the terrain
     to field.dtt: a prepared battlefield.
  2. Exercise "battle" names it as [terrain] ground_file. dt_launch starts its server, node-1 and
     node-2, but node-2 through a --node-bin wrapper that hands it the same exercise on random
     ground (seed 7) instead: another ground.
     a. node-2 logs that it loaded another ground than the exercise's, with both digests and its
        source; the server and node-1 log a refusal of 1:2 naming its digest and theirs;
     b. `status`: node-2 says ground_refused 1, its own digest and the exercise's, signed_on 0;
        the server and node-1 say ground_digest (the file's), ground_source (the file) and a
        ground_mismatch line naming 1:2 and node-2's digest. These dt_ctl calls run with
        field.dtt moved away (and back after): dt_ctl never reads the ground file;
     c. node-1 places a crater, and the server's export holds the file's crater as 0:0:1 (the
        ground's, renumbered under 0:0, which no member issues) beside node-1's new one;
     d. dt_launch's ready timeout names node-2 and quotes its ground line, and exits non-zero.
  3. dt_server of the random-ground file on the battle's database refuses to start (exit 2),
     naming both digests.
Everything is bounded in time; dt_launch (which stops its children by process group) is stopped
by PID if it still runs; the work directory is removed at the end.
Usage: ground_mismatch_test.py <dt_launch> <dt_node> <dt_server> <dt_ctl> <key file> <work dir>
Exit 0: pass; 1: fail.
"""
import os
import re
import select
import struct
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "pylib"))
from dt_ctl import ctl_answer  # noqa: E402
from launch_output import LaunchOutput  # noqa: E402

READY_TIMEOUT_S = 25  # dt_launch's --ready-timeout-s for the battle: node-2 never signs on
WAIT_S = 30  # every wait for a line or a state gives up after this long
ODD = "node-2"
ODD_ADDRESS = "1:2"
HEX = r"[0-9a-f]{32}"

EXERCISE = """\
[exercise]
name = "{name}"
id = {id}
transport = "udpm://239.255.76.67:7667?ttl=0"
run_dir = "{run_dir}"
tick_hz = 30

[auth]
key_file = "{key}"

[terrain]
{terrain}

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

RANDOM_GROUND = "posts_per_side = 65\nspacing_m = 10.0\nrelief_m = 20.0\nseed = {seed}"

# dt_launch starts every node through this: node-2 with the other file as its --config, the
# others as they are.
WRAPPER = """\
#!/bin/sh
odd=0
for a in "$@"; do
  if [ "$a" = "{odd}" ]; then odd=1; fi
done
if [ $odd = 1 ]; then
  prev=""
  for a in "$@"; do
    shift
    if [ "$prev" = "--config" ]; then a="{other}"; fi
    set -- "$@" "$a"
    prev="$a"
  done
fi
exec "{node}" "$@"
"""


class Failure(Exception):
    pass


def Launch(argv):
    """dt_launch of an exercise, its output read line by line under deadlines."""
    return LaunchOutput(argv, failure=Failure, wait_s=WAIT_S)


def ctl(ctl_bin, config, name, *args):
    return ctl_answer(ctl_bin, config, name, *args, failure=Failure)


def status(ctl_bin, config, name):
    """`status` as a dict of its single lines, and its ground_mismatch lines."""
    single, mismatches = {}, []
    for line in ctl(ctl_bin, config, name, "status").splitlines():
        key, _, value = line.partition(" ")
        if key == "ground_mismatch":
            mismatches.append(value)
        else:
            single.setdefault(key, value)
    return single, mismatches


def wait_features(ctl_bin, config, name, count):
    """Polls `status` until the process holds `count` live features (bounded)."""
    deadline = time.monotonic() + WAIT_S
    while time.monotonic() < deadline:
        single, _ = status(ctl_bin, config, name)
        if single.get("features") == str(count):
            return
        select.select([], [], [], 0.1)  # the pace of the poll, not a synchronisation
    raise Failure(f"{name} does not hold {count} features within {WAIT_S} s")


def feature_ids(path):
    """The feature IDs of a terrain file (docs/terrain-file-format.md), as "site:host:number"."""
    data = open(path, "rb").read()
    if data[:8] != b"\x89DTER\r\n\x1a":
        raise Failure(f"{path} is not a terrain file")
    ground_len, _ = struct.unpack_from("<QQ", data, 12)
    at = 28 + ground_len
    (count,) = struct.unpack_from("<I", data, at)
    at += 4
    ids = []
    for _ in range(count):
        site, host, number, length = struct.unpack_from("<HHII", data, at)
        ids.append(f"{site}:{host}:{number}")
        at += 12 + length
    return ids


def write(path, text):
    with open(path, "w") as f:
        f.write(text)


def make_field(launch_bin, node_bin, server_bin, ctl_bin, key, work):
    """Step 1: field.dtt, exported from a running exercise after node-1 placed a crater; returns
    the crater's ID."""
    config = os.path.join(work, "field.toml")
    write(config, EXERCISE.format(name="field", id=6, run_dir=os.path.join(work, "run-field"),
                                  key=key, terrain=RANDOM_GROUND.format(seed=42)))
    launch = Launch([launch_bin, "--config", config, "--node-bin", node_bin, "--server-bin",
                     server_bin, "--ready-timeout-s", str(WAIT_S), "--grace-ms", "5000"])
    try:
        launch.wait_for("READY field", re.compile(r"^READY field$"))
        crater = ctl(ctl_bin, config, "node-1", "crater", "300", "300", "12")
        if not re.fullmatch(r"1:1:\d+", crater):
            raise Failure(f"node-1's crater is {crater}, not one of node-1's")
        wait_features(ctl_bin, config, "server", 1)
        field = os.path.join(work, "grounds", "field.dtt")
        ctl(ctl_bin, config, "server", "export", field)
        if feature_ids(field) != [crater]:
            raise Failure(f"field.dtt holds {feature_ids(field)}, not {crater}")
        print(f"PASS: field.dtt exported with node-1's crater {crater}")
        return crater
    finally:
        launch.stop()
        if sys.exc_info()[0] is not None:
            print("dt_launch's output:\n" + "\n".join(launch.lines), file=sys.stderr)


def check_statuses(ctl_bin, config, field, odd_ground, field_ground):
    """Step 2b: node-2's status and the server's and node-1's name both grounds."""
    single, _ = status(ctl_bin, config, ODD)
    want = {"ground_refused": "1", "ground_digest": odd_ground,
            "exercise_ground_digest": field_ground, "signed_on": "0"}
    for k, v in want.items():
        if single.get(k) != v:
            raise Failure(f"{ODD}'s status: {k} {single.get(k)}, not {v}")
    for who in ("server", "node-1"):
        single, mismatches = status(ctl_bin, config, who)
        want = {"ground_refused": "0", "ground_digest": field_ground,
                "ground_source": f"ground_file {field}", "exercise_ground_digest": "-"}
        for k, v in want.items():
            if single.get(k) != v:
                raise Failure(f"{who}'s status: {k} {single.get(k)}, not {v}")
        if mismatches != [f"{ODD_ADDRESS} digest={odd_ground}"]:
            raise Failure(f"{who}'s status: ground_mismatch lines {mismatches}")
        if int(single.get("refused_ground", "0")) < 1:
            raise Failure(f"{who}'s status: refused_ground {single.get('refused_ground')}")


def battle(launch_bin, node_bin, server_bin, ctl_bin, key, work, field_crater):
    """Step 2; returns (battle config, other config, the file's ground, node-2's ground)."""
    run_dir = os.path.join(work, "run-battle")
    config = os.path.join(work, "battle.toml")
    other = os.path.join(work, "battle-random.toml")
    field = os.path.join(work, "grounds", "field.dtt")
    write(config, EXERCISE.format(name="battle", id=7, run_dir=run_dir, key=key,
                                  terrain='ground_file = "grounds/field.dtt"'))
    write(other, EXERCISE.format(name="battle", id=7, run_dir=run_dir, key=key,
                                 terrain=RANDOM_GROUND.format(seed=7)))
    wrapper = os.path.join(work, "other-ground-node")
    write(wrapper, WRAPPER.format(odd=ODD, node=node_bin, other=other))
    os.chmod(wrapper, 0o755)

    launch = Launch([launch_bin, "--config", config, "--node-bin", wrapper, "--server-bin",
                     server_bin, "--ready-timeout-s", str(READY_TIMEOUT_S), "--grace-ms", "5000"])
    try:
        # a. node-2 refuses itself; the others refuse it; each names both digests.
        m = launch.wait_for(
            f"[{ODD}] refusing itself",
            re.compile(rf"^\[{ODD}\] .* error \[{ODD}\] ground mismatch: node {ODD_ADDRESS} "
                       rf"loaded ground ({HEX}) from random seed 7 65x65 posts spacing 10 m "
                       rf"relief 20 m, but the exercise's ground \(server 1:100\) is ({HEX}): "
                       r"this process takes no part"))
        odd_ground, field_ground = m.group(1), m.group(2)
        if odd_ground == field_ground:
            raise Failure(f"both grounds are {odd_ground}")
        print(f"PASS: {ODD} refuses itself: its ground {odd_ground}, the exercise's {field_ground}")
        for who in ("server", "node-1"):
            launch.wait_for(
                f"[{who}] refusing {ODD}",
                re.compile(rf"^\[{who}\] .* warning \[{who}\] .*ground mismatch: node "
                           rf"{ODD_ADDRESS} is on ground {odd_ground}; this process's is "
                           rf"{field_ground} \(ground_file {re.escape(field)}\)"))
            print(f"PASS: {who} refuses {ODD_ADDRESS}, naming both grounds and the file")

        # b. Every status says the same, asked by dt_ctl with the ground file gone: it needs the
        # exercise file's names and addresses, never the ground (docs/node.md).
        os.rename(field, field + ".away")
        try:
            check_statuses(ctl_bin, config, field, odd_ground, field_ground)
        finally:
            os.rename(field + ".away", field)
        print("PASS: every status names both grounds, asked with the ground file moved away")

        # c. The file's crater is the ground's; node-1 signs on beside the refused node-2.
        launch.wait_for("[node-1] READY", re.compile(r"^\[node-1\] READY node-1$"))
        crater = ctl(ctl_bin, config, "node-1", "crater", "200", "400", "8")
        if not re.fullmatch(r"1:1:\d+", crater):
            raise Failure(f"node-1's crater on the battlefield is {crater}")
        wait_features(ctl_bin, config, "server", 1)
        exported = os.path.join(work, "battle.dtt")
        ctl(ctl_bin, config, "server", "export", exported)
        if feature_ids(exported) != ["0:0:1", crater]:
            raise Failure(f"the battle's terrain holds {feature_ids(exported)}")
        print(f"PASS: the battle started with the file's crater {field_crater} as 0:0:1, and "
              f"node-1 made {crater}")

        # d. dt_launch gives up on node-2, quoting its ground line.
        m = launch.wait_for(
            "dt_launch's ready timeout",
            re.compile(r"^\[launch\] exercise failed to start: not ready after "
                       rf"{READY_TIMEOUT_S * 1000} ms: (.*)$"),
            timeout_s=READY_TIMEOUT_S + WAIT_S)
        word = re.search(rf"(^|, ){ODD} \(its last word: \"(.*)", m.group(1))
        if (not word or "ground mismatch" not in word.group(2) or odd_ground not in word.group(2)
                or field_ground not in word.group(2)):
            raise Failure(f"the timeout does not quote {ODD}'s ground line: {m.group(1)}")
        rc = launch.wait_exit()
        if rc == 0:
            raise Failure(f"dt_launch exited 0 although {ODD} was never ready")
        print(f"PASS: dt_launch gave up quoting {ODD}'s ground line, exit {rc}")
    finally:
        launch.stop()
        if sys.exc_info()[0] is not None:
            print("dt_launch's output:\n" + "\n".join(launch.lines), file=sys.stderr)
    return config, other, field_ground, odd_ground


def server_refuses(server_bin, other, field_ground, odd_ground, work):
    """Step 3: the battle's database, opened on the random ground, is refused."""
    r = subprocess.run([server_bin, "--config", other, "--name", "server"], capture_output=True,
                       text=True, timeout=WAIT_S)
    db = os.path.join(work, "run-battle", "server.db")
    if r.returncode != 2:
        raise Failure(f"dt_server on another ground exited {r.returncode}, not 2: {r.stderr}")
    if not re.search(rf"{re.escape(db)}: holds an exercise on ground {field_ground} \(ground_file "
                     rf".*field.dtt\), but this server loaded ground {odd_ground} \(random seed 7",
                     r.stderr):
        raise Failure(f"dt_server's refusal does not name both grounds: {r.stderr}")
    print("PASS: dt_server refuses the battle's database on another ground")


def main():
    if len(sys.argv) != 7:
        print(__doc__, file=sys.stderr)
        return 2
    launch_bin, node_bin, server_bin, ctl_bin, key, work = sys.argv[1:]
    launch_bin, node_bin, server_bin, ctl_bin, key = (
        os.path.abspath(p) for p in (launch_bin, node_bin, server_bin, ctl_bin, key))
    work = os.path.abspath(work)
    subprocess.run(["rm", "-rf", work], check=True)
    os.makedirs(os.path.join(work, "grounds"))
    try:
        field_crater = make_field(launch_bin, node_bin, server_bin, ctl_bin, key, work)
        _, other, field_ground, odd_ground = battle(launch_bin, node_bin, server_bin, ctl_bin,
                                                    key, work, field_crater)
        server_refuses(server_bin, other, field_ground, odd_ground, work)
    except Failure as e:
        print(f"FAIL: {e}")
        return 1
    finally:
        subprocess.run(["rm", "-rf", work], check=True)
    print("ground_mismatch_test: pass")
    return 0


if __name__ == "__main__":
    sys.exit(main())
