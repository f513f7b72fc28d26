#!/usr/bin/env bash
# dt_launch starts the demo exercise (real dt_server and dt_node processes); dt_ctl then places a
# crater, is refused a bad command, drives (told of a clamped speed, refused -inf), reads status;
# SIGTERM stops everything with exit 0.
# Run inside tests/run_in_netns.sh.
#   launch_ctl_test.sh <dt_launch> <dt_ctl> <exercise.toml> <run_dir>
set -euo pipefail
launch=$1 ctl=$2 exercise=$3 run_dir=$4
rm -rf "$run_dir"
mkdir -p "$run_dir"
fifo="$run_dir/launch.out"
mkfifo "$fifo"
"$launch" --config "$exercise" --run-dir "$run_dir" --ready-timeout-s 60 >"$fifo" 2>&1 &
launch_pid=$!
exec 3<"$fifo"
trap 'kill -TERM $launch_pid 2>/dev/null || true' EXIT

fail() { echo "FAIL: $*" >&2; exit 1; }
ctl_() { "$ctl" --config "$exercise" --run-dir "$run_dir" "$@"; }

# Wait for the launcher's own READY (it prints it after every child's); the read blocks, no sleeps.
ready=0
while IFS= read -r -t 90 line <&3; do
  echo "$line"
  if [[ "$line" == "READY demo" ]]; then ready=1; break; fi
done
[[ $ready == 1 ]] || fail "dt_launch never printed READY demo"
for n in server node-1 node-2 node-3; do
  [[ -S "$run_dir/$n.sock" ]] || fail "no control socket for $n"
done

id=$(ctl_ --name node-2 crater 100 200 5)
[[ "$id" =~ ^1:2:[0-9]+$ ]] || fail "crater reply '$id' is not a node-2 feature ID"
ctl_ --name node-2 features | grep -qx "$id" || fail "node-2 does not list $id"

set +e
err=$(ctl_ --name node-2 crater 100 200 -5 2>&1)
rc=$?
set -e
[[ $rc == 1 ]] || fail "a bad crater exited $rc, not 1"
[[ "$err" == error:*radius* ]] || fail "a bad crater said '$err'"
set +e
ctl_ --name node-9 status >/dev/null 2>&1
rc=$?
set -e
[[ $rc == 2 ]] || fail "an unknown process exited $rc, not 2"

# node-2 drives a truck (25 m/s top speed, docs/terrain.md "Vehicles"): a clamped speed is said,
# and -inf reaches the command parser as an argument, which refuses it.
out=$(ctl_ --name node-2 drive 0 1e30 0)
[[ "$out" == "speed 1e+30 m/s clamped to 25 m/s, the truck's top speed" ]] ||
  fail "a clamped drive said '$out'"
set +e
err=$(ctl_ --name node-2 drive 0 -inf 0 2>&1)
rc=$?
set -e
[[ $rc == 1 ]] || fail "drive with -inf exited $rc, not 1"
[[ "$err" == 'error: speed_mps "-inf" is not a finite number' ]] || fail "drive -inf said '$err'"
ctl_ --name node-2 drive 0 0 0 >/dev/null

ctl_ --name node-1 status | grep -q '^signed_on 1$' || fail "node-1 status lacks signed_on 1"
ctl_ --name server status | grep -q '^role server$' || fail "server status lacks role server"

kill -TERM $launch_pid
trap - EXIT
# The rest of the launcher's output: every child's exit report.
report=$(cat <&3)
echo "$report"
wait $launch_pid || fail "dt_launch exited $?"
for n in server node-1 node-2 node-3; do
  grep -q "^\[launch\] $n: exited 0$" <<<"$report" || fail "$n did not exit 0"
done
echo PASS
