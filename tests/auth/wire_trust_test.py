#!/usr/bin/env python3
"""Trust on the wire: strangers and old logs cannot change a running, authenticated exercise.

Run inside tests/run_in_netns.sh (a private network namespace). Drives real processes:
dt_launch starts the exercise (server + nodes, PDUs authenticated with the exercise key),
dt_ctl reads each process's `status`, /usr/bin/lcm-logger records the exercise's traffic and
/usr/bin/lcm-logplayer replays it. Forged PDUs come from this program through LCM's Python
module, with bindings generated from pdu/lcm/*.lcm.

  1. Run 1: lcm-logger records while node-2 and node-1 each create a crater.
  2. A stranger without the key sends a Construct of its own (from 9:9) and a Destruct of
     node-2's crater (claiming to be node-1): once without a trailer, once signed with another
     key; and the Construct signed with the exercise key in the former trailer version ("DTA1",
     HMAC-SHA512-256). Every process counts them (rejected_unauthenticated, rejected_bad_mac)
     and nothing changes: features, digest, counters.
  3. Control: the same Construct signed with the exercise key (Python's hashlib, as any holder
     of the key could) passes authentication everywhere, so the forgeries were refused for want
     of the key (or of the current trailer version).
  4. The log is replayed into run 1: every process counts every replayed PDU of the others
     (rejected_replayed or rejected_stale; its own it drops as echoes before authenticating) and
     no state moves.
  5. Run 2, a fresh exercise (no stored state): the log of run 1 is replayed into it; every
     replayed PDU is refused, no process gains a feature, and node-1's and node-2's own counters
     (own_change_seq, acknowledged_change_seq, max_feature) stay at zero.
Everything is bounded in time; processes are stopped by PID.
Usage: wire_trust_test.py <dt_launch> <dt_ctl> <lcm-gen> <exercise.toml> <work-dir> <file.lcm>...
Exit 0: pass; 1: fail; 77: skipped (no `lcm` Python module).
"""
import hashlib
import hmac
import os
import shutil
import signal
import struct
import subprocess
import sys
import threading
import time
import tomllib

SKIP = 77
LOGGER = "/usr/bin/lcm-logger"
PLAYER = "/usr/bin/lcm-logplayer"
STRANGER = (9, 9)
WAIT_S = 30  # every wait for a condition gives up after this long


class Failure(Exception):
    pass


def check(cond, what):
    if not cond:
        raise Failure(what)


class Exercise:
    """One dt_launch of the exercise file, its output read on a thread."""

    def __init__(self, launch, ctl, config, run_dir):
        self.ctl, self.config, self.run_dir = ctl, config, run_dir
        shutil.rmtree(run_dir, ignore_errors=True)
        os.makedirs(run_dir)
        with open(config, "rb") as f:
            ex = tomllib.load(f)
        self.name = ex["exercise"]["name"]
        self.processes = [ex["server"]["name"]] + [n["name"] for n in ex["node"]]
        if "standby" in ex:
            self.processes.insert(1, ex["standby"]["name"])
        self.lines = []
        self.ready = threading.Event()
        self.proc = subprocess.Popen(
            [launch, "--config", config, "--run-dir", run_dir, "--ready-timeout-s", "60"],
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()
        if not self.ready.wait(90):
            self.stop()
            raise Failure(f"dt_launch never printed READY {self.name}:\n" + "\n".join(self.lines))

    def _read(self):
        for line in self.proc.stdout:
            line = line.rstrip("\n")
            self.lines.append(line)
            if line == f"READY {self.name}":
                self.ready.set()

    def call(self, name, *words):
        r = subprocess.run([self.ctl, "--config", self.config, "--run-dir", self.run_dir,
                            "--name", name] + list(words), capture_output=True, text=True,
                           timeout=20)
        if r.returncode != 0:
            raise Failure(f"dt_ctl {name} {' '.join(words)}: exit {r.returncode}: {r.stderr}")
        return r.stdout.strip()

    def status(self, name):
        """`status` as a dict: the first value of each key, every max_feature line in a list.
        runtime/status_report.h is the format's one definition; this reads only what the test
        needs and must agree with it."""
        out = {"max_feature": []}
        for line in self.call(name, "status").splitlines():
            key, _, value = line.partition(" ")
            if key == "max_feature":
                out["max_feature"].append(value)
            elif key not in out:
                out[key] = value
        return out

    def statuses(self):
        return {n: self.status(n) for n in self.processes}

    def wait_for(self, what, cond):
        """Polls every process's status until cond(statuses) holds; the bounded wait of a drill."""
        deadline = time.monotonic() + WAIT_S
        while True:
            s = self.statuses()
            if cond(s):
                return s
            if time.monotonic() > deadline:
                raise Failure(f"timed out waiting for {what}; last status: {s}")
            time.sleep(0.05)

    def stop(self):
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
        try:
            self.proc.wait(60)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        self.reader.join(10)
        return self.proc.returncode


def others(statuses, senders):
    """Per process, how many of the logged PDUs another process sent and it listens to: only
    nodes subscribe to VehicleState (the server holds no vehicles), so only they count those."""
    return {p: sum(1 for a, channel in senders
                   if a != s["address"] and (s["role"] == "node" or
                                             not channel.endswith("_VEHICLESTATE")))
            for p, s in statuses.items()}


def settled(procs, nodes):
    """Every process tracks every sender and all agree on every node's maxima (nothing still in
    flight between them), so a snapshot is taken of a quiet exercise."""
    def cond(s):
        first = s[procs[0]]["max_feature"]
        return len(first) >= nodes and all(
            int(s[p]["auth_senders"]) >= len(procs) - 1 and s[p]["max_feature"] == first and
            s[p]["digest"] == s[procs[0]]["digest"] for p in procs)
    return cond


def refused(s):
    return int(s["rejected_replayed"]) + int(s["rejected_stale"])


# What must not move when PDUs are refused.
STATE_KEYS = ("features", "digest", "own_feature_number", "own_change_seq",
              "acknowledged_change_seq", "max_feature", "applied")


def state(statuses):
    return {n: {k: s[k] for k in STATE_KEYS} for n, s in statuses.items()}


class Wire:
    """This program's own LCM endpoint on the exercise's group, and the PDU bindings."""

    def __init__(self, lcm, dtpdu, url, exercise_id, key):
        self.lc = lcm.LCM(url)
        self.dtpdu = dtpdu
        self.id = exercise_id
        self.key = key

    def channel(self, kind):
        return f"DT{self.id}_{kind}"

    def header(self, pdu_type):
        h = self.dtpdu.header_t()
        h.protocol_version, h.exercise_id, h.pdu_type, h.timestamp_dis = 3, self.id, pdu_type, 1
        return h

    @staticmethod
    def address(dtpdu, site, host):
        a = dtpdu.node_address_t()
        a.site, a.host = site, host
        return a

    @staticmethod
    def trailer(lcm_bytes, key, sender, incarnation, sequence):
        """The authentication trailer (docs/pdu.md), computed with the standard library alone:
        keyed BLAKE2b-256 under the MAC key derived from the key file's bytes."""
        signed = struct.pack(">4sHHQQQ", b"DTA2", sender[0], sender[1], incarnation, sequence,
                             int(time.time() * 1000))
        mac_key = hashlib.blake2b(key, digest_size=64, person=b"dt-pdu-mac-key-1").digest()
        mac = hashlib.blake2b(lcm_bytes + signed, key=mac_key, digest_size=32).digest()
        return signed + mac

    @staticmethod
    def former_trailer(lcm_bytes, key, sender, incarnation, sequence):
        """The trailer as its former version was: "DTA1", HMAC-SHA512-256 under the raw key."""
        signed = struct.pack(">4sHHQQQ", b"DTA1", sender[0], sender[1], incarnation, sequence,
                             int(time.time() * 1000))
        return signed + hmac.new(key, lcm_bytes + signed, hashlib.sha512).digest()[:32]

    def send(self, kind, data):
        self.lc.publish(self.channel(kind), data)


def main():
    launch, ctl, lcm_gen, config, work = sys.argv[1:6]
    lcm_files = sys.argv[6:]
    try:
        import lcm
    except ImportError:
        print("SKIP: the `lcm` Python module is not installed (scripts/setup.sh installs it)")
        return SKIP
    for tool in (LOGGER, PLAYER):
        check(os.access(tool, os.X_OK), f"{tool} is missing (Debian liblcm-bin)")
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    py_dir = os.path.join(work, "python")
    subprocess.run([lcm_gen, "-p", "--ppath", py_dir] + lcm_files, check=True)
    sys.path.insert(0, py_dir)
    import dtpdu

    with open(config, "rb") as f:
        ex = tomllib.load(f)
    check("key_file" in ex.get("auth", {}), f"{config} is not authenticated with a key")
    with open(os.path.join(os.path.dirname(config), ex["auth"]["key_file"]), "rb") as f:
        key = f.read()
    url = ex["exercise"]["transport"]
    wire = Wire(lcm, dtpdu, url, ex["exercise"]["id"], key)
    log_path = os.path.join(work, "run1.lcmlog")

    # ---- 1. Run 1, recorded from before its start.
    logger = subprocess.Popen([LOGGER, "-q", "-f", f"--lcm-url={url}", "-c", f"DT{wire.id}_.*",
                               log_path])
    run1 = None
    try:
        run1 = Exercise(launch, ctl, config, os.path.join(work, "run1"))
        procs = run1.processes
        n2 = run1.call("node-2", "crater", "100", "120", "5")
        n1 = run1.call("node-1", "crater", "200", "220", "5")
        run1.wait_for("both craters everywhere, acknowledged", lambda s: all(
            s[p]["features"] == "2" for p in procs) and all(
            s[n]["acknowledged_change_seq"] == s[n]["own_change_seq"] == "1"
            for n in ("node-1", "node-2")))
        logger.send_signal(signal.SIGINT)
        logger.wait(20)
        events = [e for e in lcm.EventLog(log_path, "r")]
        constructs = [dtpdu.construct_t.decode(e.data) for e in events
                      if e.channel == wire.channel("CONSTRUCT")]
        logged_ids = {f"{c.origin.site}:{c.origin.host}:{c.feature_number}" for c in constructs}
        check({n1, n2} <= logged_ids, f"the log lacks the craters {n1}, {n2}: it has {logged_ids}")
        # A process drops its own PDUs as echoes before authenticating anything, so it refuses
        # the others' share of the log.
        senders = [(":".join(str(x) for x in struct.unpack(">HH", e.data[15:19])), e.channel)
                   for e in events]
        print(f"recorded {len(events)} PDUs of run 1, {len(constructs)} Constructs")

        # ---- 2. Forgeries from a stranger without the key.
        nodes = len(ex["node"])
        before = run1.wait_for("a quiet exercise", settled(procs, nodes))
        template = next(c for c in constructs
                        if f"{c.origin.site}:{c.origin.host}:{c.feature_number}" == n2)
        forged = template
        forged.sender = forged.origin = forged.created_by = Wire.address(dtpdu, *STRANGER)
        forged.sender_seq = forged.feature_number = forged.change_seq = 1
        forged.lamport = 1000
        forged.position_m = [500.0, 0.0, 520.0]
        construct_bytes = forged.encode()
        site, host, number = (int(x) for x in n2.split(":"))
        d = dtpdu.destruct_t()
        d.header = wire.header(222)
        d.sender = Wire.address(dtpdu, *STRANGER)
        d.changed_by = Wire.address(dtpdu, 1, 1)  # claims node-1 destroyed it
        d.sender_seq = 1000
        d.origin = Wire.address(dtpdu, site, host)
        d.feature_number, d.feature_type = number, 1
        d.change_seq, d.lamport = 2, 1000
        d.is_playback = False
        d.playback_for = Wire.address(dtpdu, 0, 0)
        destruct_bytes = d.encode()
        other_key = os.urandom(32)
        wire.send("CONSTRUCT", construct_bytes)
        wire.send("DESTRUCT", destruct_bytes)
        inc = int(time.time() * 1000)
        wire.send("CONSTRUCT", construct_bytes + Wire.trailer(construct_bytes, other_key,
                                                              STRANGER, inc, 1))
        wire.send("DESTRUCT", destruct_bytes + Wire.trailer(destruct_bytes, other_key, STRANGER,
                                                            inc, 2))
        # Signed with the exercise key, but in the former trailer version: not a trailer now.
        wire.send("CONSTRUCT", construct_bytes + Wire.former_trailer(construct_bytes, key,
                                                                     STRANGER, inc, 3))
        want_counts = {"unauthenticated": 3, "bad_mac": 2}
        after = run1.wait_for("every process to count 3 unauthenticated and 2 bad-MAC PDUs",
                              lambda s: all(
            int(s[p]["rejected_" + r]) >= int(before[p]["rejected_" + r]) + n
            for p in procs for r, n in want_counts.items()))
        for p in procs:
            for reason, n in want_counts.items():
                k = "rejected_" + reason
                check(int(after[p][k]) == int(before[p][k]) + n,
                      f"{p}: {k} went {before[p][k]} -> {after[p][k]}, expected +{n}")
        check(state(after) == state(before), f"forgeries changed state:\n{state(before)}\n"
                                             f"{state(after)}")
        check(n2 in run1.call("node-3", "features").split(), f"node-3 lost {n2}")
        print("forged Construct and Destruct without the key, and a Construct in the former "
              f"trailer version: refused and counted by {len(procs)} processes, nothing changed")

        # ---- 3. Control: the same Construct, signed with the exercise key, passes the key
        # layer; the stranger is then refused by membership (docs/protocol.md, "Rules for what is
        # believed"), so the forgeries above were refused for lack of the key alone.
        before = after
        wire.send("CONSTRUCT", construct_bytes + Wire.trailer(construct_bytes, key, STRANGER,
                                                              int(time.time() * 1000), 1))
        after = run1.wait_for("every process to refuse the key holder's stranger Construct",
                              lambda s: all(int(s[p]["refused_stranger"]) >=
                                            int(before[p]["refused_stranger"]) + 1 for p in procs))
        for p in procs:
            for reason in ("unauthenticated", "bad_mac", "replayed", "stale"):
                k = "rejected_" + reason
                check(after[p][k] == before[p][k], f"{p}: {k} moved for a correctly signed PDU")
        check(state(after) == state(before), f"a stranger's Construct changed state:\n"
                                             f"{state(before)}\n{state(after)}")
        print("control: the same Construct signed by Python with the key passed authentication "
              "and was refused by membership everywhere")

        # ---- 4. The log replayed into run 1, which heard all of it live.
        before = run1.wait_for("a quiet exercise", settled(procs, nodes))
        subprocess.run([PLAYER, "-s", "4", f"--lcm-url={url}", log_path], check=True,
                       timeout=120, stdout=subprocess.DEVNULL)
        want = others(before, senders)
        after = run1.wait_for("every process to refuse the replayed PDUs of the others",
                              lambda s: all(refused(s[p]) >= refused(before[p]) + want[p]
                                            for p in procs))
        for p in procs:
            check(refused(after[p]) == refused(before[p]) + want[p],
                  f"{p}: refused {refused(after[p]) - refused(before[p])} of {want[p]}")
        check(state(after) == state(before), f"the replay changed run 1:\n{state(before)}\n"
                                             f"{state(after)}")
        print(f"replay into run 1: every process refused the others' PDUs ({want}; "
              f"node-1: replayed +{int(after['node-1']['rejected_replayed']) - int(before['node-1']['rejected_replayed'])}, "
              f"stale +{int(after['node-1']['rejected_stale']) - int(before['node-1']['rejected_stale'])}), nothing changed")
        rc = run1.stop()
        check(rc == 0, f"run 1's dt_launch exited {rc}:\n" + "\n".join(run1.lines[-20:]))
        run1 = None

        # ---- 5. A fresh exercise; the old log replayed into it.
        run2 = Exercise(launch, ctl, config, os.path.join(work, "run2"))
        try:
            before = run2.wait_for("a quiet exercise", settled(procs, nodes))
            check(all(before[p]["features"] == "0" for p in procs), "run 2 did not start empty")
            subprocess.run([PLAYER, "-s", "4", f"--lcm-url={url}", log_path], check=True,
                           timeout=120, stdout=subprocess.DEVNULL)
            want = others(before, senders)
            after = run2.wait_for("every process to refuse the replayed PDUs of the others",
                                  lambda s: all(refused(s[p]) >= refused(before[p]) + want[p]
                                                for p in procs))
            for p in procs:
                check(refused(after[p]) == refused(before[p]) + want[p],
                      f"{p}: refused {refused(after[p]) - refused(before[p])} of {want[p]}")
            check(state(after) == state(before), f"the replay changed run 2:\n{state(before)}\n"
                                                 f"{state(after)}")
            for n in ("node-1", "node-2"):
                s = after[n]
                check(s["own_change_seq"] == "0" and s["acknowledged_change_seq"] == "0" and
                      s["features"] == "0", f"{n} moved in run 2: {s}")
            print(f"replay into a fresh run 2: the others' PDUs refused by each process ({want}; "
                  f"node-1: replayed +{int(after['node-1']['rejected_replayed']) - int(before['node-1']['rejected_replayed'])}), "
                  "no feature, no counter moved")
        finally:
            rc = run2.stop()
        check(rc == 0, f"run 2's dt_launch exited {rc}:\n" + "\n".join(run2.lines[-20:]))
    finally:
        if logger.poll() is None:
            logger.kill()
            logger.wait()
        if run1 is not None:
            run1.stop()
    print("PASS")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except Failure as e:
        print(f"FAIL: {e}")
        sys.exit(1)
