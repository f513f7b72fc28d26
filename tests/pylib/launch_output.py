"""A launched program whose output (stdout and stderr together) is read line by line under
deadlines, for the cross-process Python tests: readiness is a line read, never a sleep.

    from launch_output import LaunchOutput
    launch = LaunchOutput([dt_launch, "--config", "x.toml"], failure=Failure)
    launch.wait_for("node-1's READY", re.compile(r"node-1.*READY"))
    launch.stop()  # SIGTERM by PID, then SIGKILL after 30 s

A test's scripts find this folder by their own path (sys.path), so they run by hand as in ctest.
"""
import os
import select
import signal
import subprocess
import time


class LaunchOutput:
    def __init__(self, argv, failure=RuntimeError, wait_s=30, name="dt_launch"):
        """Starts argv. `failure` is the exception class raised when a wait gives up; wait_s the
        default wait; name how messages call the program."""
        self.lines = []
        self.failure = failure
        self.wait_s = wait_s
        self.name = name
        self.proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
        self.buffer = b""

    def _read_line(self, deadline):
        """The next line, or None at the end of the output or the deadline."""
        while b"\n" not in self.buffer:
            left = deadline - time.monotonic()
            if left <= 0:
                return None
            ready, _, _ = select.select([self.proc.stdout], [], [], left)
            if not ready:
                return None
            chunk = os.read(self.proc.stdout.fileno(), 65536)
            if not chunk:
                return None
            self.buffer += chunk
        line, _, self.buffer = self.buffer.partition(b"\n")
        text = line.decode(errors="replace")
        self.lines.append(text)
        return text

    def wait_for(self, what, pattern, timeout_s=None):
        """Reads lines until one matches `pattern` (a compiled regex); returns the match. Lines
        already read while waiting for something else count."""
        timeout_s = self.wait_s if timeout_s is None else timeout_s
        for line in self.lines:
            m = pattern.search(line)
            if m:
                return m
        deadline = time.monotonic() + timeout_s
        while True:
            line = self._read_line(deadline)
            if line is None:
                raise self.failure(f"no line with {what} within {timeout_s} s")
            m = pattern.search(line)
            if m:
                return m

    def wait_exit(self, timeout_s=None):
        """Reads the output to its end and returns the exit status."""
        timeout_s = self.wait_s if timeout_s is None else timeout_s
        deadline = time.monotonic() + timeout_s
        while self._read_line(deadline) is not None:
            pass
        try:
            return self.proc.wait(max(0.0, deadline - time.monotonic()))
        except subprocess.TimeoutExpired:
            raise self.failure(f"{self.name} still running {timeout_s} s after it should have "
                               "ended")

    def stop(self):
        """SIGTERM by PID; SIGKILL if it still runs 30 s later."""
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            try:
                self.proc.wait(30)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
