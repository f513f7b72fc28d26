"""The processes of an exercise under test, for the cross-process Python tests: each started by
PID with its own READY line as readiness (docs/launcher.md), asked with dt_ctl, waited for by
polling a condition under a deadline, and stopped by PID.

    from exercise_processes import ExerciseProcesses
    ex = ExerciseProcesses(programs, "exercise.toml", "run/dir")  # programs: name -> path
    ex.start("node-1", "dt_node"); ex.ctl("node-1", "status"); ex.stop_all()

A test's scripts find this folder by their own path (sys.path), so they run by hand as in ctest.
"""
import os
import select
import shutil
import signal
import subprocess
import sys
import time


class ExerciseProcesses:
    def __init__(self, programs, exercise, run_dir):
        """Empties run_dir. programs maps a program name ("dt_node", "dt_ctl", ...) to its path."""
        self.programs = programs
        self.exercise = exercise
        self.run_dir = run_dir
        self.procs = {}
        shutil.rmtree(run_dir, ignore_errors=True)
        os.makedirs(run_dir)

    def start(self, name, program, *extra, config=None, ready_s=60, wait_ready=True):
        """Starts `program` as process `name` of the exercise (or of `config`) and returns once it
        printed "READY <name>" (at once if not `wait_ready`: a process expected never to be ready);
        its stdout and its stderr go to <run_dir>/<name>.log. A process silent past `ready_s`
        fails the test, so a missing READY is never a hang."""
        args = [self.programs[program], "--config", config or self.exercise, "--run-dir",
                self.run_dir, "--name", name, *extra]
        log = open(os.path.join(self.run_dir, f"{name}.log"), "ab")
        if not wait_ready:
            self.procs[name] = subprocess.Popen(args, stdout=log, stderr=log)
            return self.procs[name]
        p = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=log)
        self.procs[name] = p
        deadline = time.time() + ready_s
        pending = b""
        fd = p.stdout.fileno()
        while time.time() < deadline:
            readable, _, _ = select.select([fd], [], [], max(0.0, deadline - time.time()))
            if not readable:
                break
            chunk = os.read(fd, 4096)  # readiness: the process's own READY line, read as it comes
            if not chunk:
                break
            log.write(chunk)
            log.flush()
            pending += chunk
            *lines, pending = pending.split(b"\n")
            if any(line.strip() == f"READY {name}".encode() for line in lines):
                return p
        self.fail(f"{name} never printed READY {name}")

    def ctl(self, name, *command, config=None):
        """dt_ctl's answer of process `name`; a refusal or an unreachable process fails the test."""
        r = subprocess.run([self.programs["dt_ctl"], "--config", config or self.exercise,
                            "--run-dir", self.run_dir, "--name", name, *command],
                           capture_output=True, text=True, timeout=10)
        if r.returncode != 0:
            self.fail(f"dt_ctl {name} {' '.join(command)}: {r.stderr.strip()}")
        return r.stdout.strip()

    def status(self, name):
        """`status` as a dict of its "key value" lines (runtime/status_report.h defines them;
        of a repeated key such as max_feature or vehicle, the last line)."""
        return dict(line.split(" ", 1) for line in self.ctl(name, "status").splitlines()
                    if " " in line)

    def poll(self, what, check, timeout_s=15.0, period_s=0.1):
        """Calls check() until it returns something true, which it returns; `what` names the
        condition when the deadline passes, which fails the test."""
        deadline = time.time() + timeout_s
        while time.time() < deadline:
            got = check()
            if got:
                return got
            time.sleep(period_s)  # polling a condition, bounded by the deadline
        self.fail(f"timed out waiting for {what}")

    def stop(self, name, timeout_s=15):
        """SIGTERM to `name`; its exit code (killed, and the test failed, if it does not stop)."""
        p = self.procs[name]
        if p.poll() is None:
            p.send_signal(signal.SIGTERM)
        try:
            return p.wait(timeout=timeout_s)
        except subprocess.TimeoutExpired:
            p.kill()
            self.fail(f"{name} did not stop on SIGTERM")

    def stop_all(self, timeout_s=10):
        """SIGTERM to every process still running, then waits (killing what does not stop); the
        exit codes by name."""
        for p in self.procs.values():
            if p.poll() is None:
                p.send_signal(signal.SIGTERM)
        for p in self.procs.values():
            try:
                p.wait(timeout=timeout_s)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
        return {name: p.returncode for name, p in self.procs.items()}

    def kill_all(self):
        for p in self.procs.values():
            if p.poll() is None:
                p.kill()

    def fail(self, what):
        print(f"FAIL: {what}")
        self.kill_all()
        sys.exit(1)
