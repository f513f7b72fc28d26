"""dt_ctl run once for a Python test of an exercise started with dt_launch (no run dir of its own):
its answer, or the test's own failure naming the command, the exit code and dt_ctl's message."""
import subprocess


def ctl_answer(ctl_bin, config, name, *words, failure=RuntimeError, timeout_s=10):
    r = subprocess.run([ctl_bin, "--config", config, "--name", name, *words], capture_output=True,
                       text=True, timeout=timeout_s)
    if r.returncode != 0:
        raise failure(f"dt_ctl --name {name} {' '.join(words)}: exit {r.returncode}: "
                      f"{r.stderr.strip()}")
    return r.stdout.strip()
