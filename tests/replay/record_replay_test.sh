#!/usr/bin/env bash
# Records a short exercise (server + two nodes running scenarios) with lcm-logger, stops it, then
# replays the log with lcm-logplayer into one fresh node of an exercise without a server
# ([protocol] require_server = false). The node must sign on with no server, end caught up with
# the recorded exercise's final digest and then accept commands, more of them than the window of
# unacknowledged changes a node with a server may keep (docs/pdu.md "Recording and replaying").
# Run inside tests/run_in_netns.sh: every packet stays on this namespace's loopback.
#   record_replay_test.sh <dt_launch> <dt_node> <dt_ctl> <lcm-logger> <lcm-logplayer> <run_dir>
set -euo pipefail
launch=$1 node=$2 ctl=$3 logger=$4 player=$5 run_dir=$6

url="udpm://239.255.76.67:7667?ttl=0"
port=7667
exercise_id=5
rm -rf "$run_dir"
mkdir -p "$run_dir"
cd "$run_dir"

fail() { echo "FAIL: $*" >&2; exit 1; }
# Every process this script starts, stopped by PID however the script ends (only while it is
# still this script's child: a reaped PID may belong to someone else by now).
pids=()
cleanup() {
  for p in "${pids[@]}"; do
    if [[ "$(awk '$1 == "PPid:" { print $2 }' "/proc/$p/status" 2>/dev/null)" == "$$" ]]; then
      kill -TERM "$p" 2>/dev/null || true
    fi
  done
}
trap cleanup EXIT
# Runs until the deadline: a stuck step fails the test instead of hanging ctest.
deadline=$((SECONDS + 100))
left() { local l=$((deadline - SECONDS)); ((l > 0)) || fail "out of time"; echo "$l"; }

# status_key <exercise> <process> <key>: one value of dt_ctl status, empty if unreachable.
status_key() {
  "$ctl" --config "$1" --name "$2" --timeout-ms 2000 status 2>/dev/null |
    awk -v k="$3" '$1 == k { print $2; exit }' || true
}

# ---- the recorded exercise ----
common_exercise() {  # <name> <protocol extra line>
  cat <<EOF
[exercise]
name = "$1"
id = $exercise_id
transport = "$url"
run_dir = "$run_dir/$1"
tick_hz = 30

# Keyless: a keyed recording replays only within the receivers' clock tolerance (docs/pdu.md).
[auth]
mode = "none"

[terrain]
posts_per_side = 65
spacing_m = 10.0
relief_m = 20.0
seed = 77

[protocol]
max_feature_period_ms = 200
silence_ms = 1000
playback_retry_ms = 300
$2
EOF
}
{
  common_exercise recorded "playback_window = 256"
  cat <<EOF

[server]
name = "server"
site = 1
host = 100

[[node]]
name = "node-1"
site = 1
host = 1
scenario = "node-1.toml"

[[node]]
name = "node-2"
site = 1
host = 2
scenario = "node-2.toml"
EOF
} >recorded.toml
cat >node-1.toml <<EOF
[[step]]
at_s = 0.2
action = "crater"
name = "c1"
x_m = 200
z_m = 200
radius_m = 6
[[step]]
at_s = 0.4
action = "berm"
name = "b1"
x_m = 300
z_m = 250
direction_deg = 30
length_m = 60
width_m = 6
height_m = 3
[[step]]
at_s = 0.6
action = "update"
target = "c1"
radius_m = 10
[[step]]
at_s = 0.8
action = "breach"
target = "b1"
gap_start_m = 20
gap_width_m = 10
EOF
cat >node-2.toml <<EOF
[[step]]
at_s = 0.2
action = "crater"
name = "c1"
x_m = 400
z_m = 400
radius_m = 8
[[step]]
at_s = 0.3
action = "crater"
name = "c2"
x_m = 450
z_m = 420
radius_m = 5
[[step]]
at_s = 0.5
action = "destroy"
target = "c2"
[[step]]
at_s = 0.7
action = "update"
target = "c1"
radius_m = 4
EOF

# The logger first, on this exercise's channels only. It prints nothing once subscribed; its
# receive socket bound to the group's port (in this namespace's /proc/net/udp) is the sign.
log_file="$run_dir/recorded.lcmlog"
"$logger" --lcm-url="$url" --channel="DT${exercise_id}_.*" --quiet --force "$log_file" \
  >logger.out 2>&1 &
logger_pid=$!
pids+=("$logger_pid")
port_hex=$(printf ':%04X' "$port")
until awk -v p="$port_hex" 'substr($2, length($2) - 4) == p { found = 1 } END { exit !found }' \
  /proc/net/udp; do
  kill -0 "$logger_pid" 2>/dev/null || fail "lcm-logger exited: $(cat logger.out)"
  left >/dev/null
  sleep 0.05
done

mkfifo launch.out
"$launch" --config recorded.toml --ready-timeout-s 60 >launch.out 2>&1 &
launch_pid=$!
pids+=("$launch_pid")
exec 3<launch.out

# The launcher's READY, then each node's "scenario finished" line (the scenarios start at READY).
ready=0
finished=()
while IFS= read -r -t "$(left)" line <&3; do
  echo "$line"
  [[ "$line" == "READY recorded" ]] && ready=1
  if [[ "$line" =~ ^\[(node-[12])\]\ .*scenario\ finished\ \((.*)\ step\(s\)\ failed\) ]]; then
    [[ "${BASH_REMATCH[2]}" == 0 ]] || fail "${BASH_REMATCH[1]}: a scenario step failed"
    finished+=("${BASH_REMATCH[1]}")
  fi
  ((ready == 1 && ${#finished[@]} == 2)) && break
done
((ready == 1)) || fail "dt_launch never printed READY recorded"
((${#finished[@]} == 2)) || fail "the scenarios did not finish (${finished[*]:-none})"

# Converged: every process caught up on one digest, each node's changes acknowledged.
final_digest=""
final_features=""
while :; do
  digests=()
  settled=1
  for p in server node-1 node-2; do
    [[ $(status_key recorded.toml "$p" caught_up) == 1 ]] || settled=0
    digests+=("$(status_key recorded.toml "$p" digest)")
  done
  for p in node-1 node-2; do
    own=$(status_key recorded.toml "$p" own_change_seq)
    [[ -n "$own" && "$own" == "$(status_key recorded.toml "$p" acknowledged_change_seq)" ]] ||
      settled=0
  done
  if ((settled == 1)) && [[ -n "${digests[0]}" && "${digests[0]}" == "${digests[1]}" &&
    "${digests[0]}" == "${digests[2]}" ]]; then
    final_digest=${digests[0]}
    final_features=$(status_key recorded.toml server features)
    break
  fi
  left >/dev/null
  sleep 0.1
done
# c1 and b1's two pieces of node-1, c1 of node-2: the scenarios did change the terrain.
[[ "$final_features" == 4 ]] || fail "the recorded exercise has $final_features features, not 4"
echo "recorded exercise converged: $final_features features, digest $final_digest"

kill -TERM "$launch_pid"
report=$(cat <&3)
exec 3<&-
echo "$report"
wait "$launch_pid" || fail "dt_launch exited $?"
kill -TERM "$logger_pid"
wait "$logger_pid" || fail "lcm-logger exited $?: $(cat logger.out)"
[[ -s "$log_file" ]] || fail "lcm-logger wrote nothing"
echo "recorded $(stat -c %s "$log_file") bytes"

# ---- the replay: one fresh node of an exercise without a server ----
# playback_window = 4: with a server the node would refuse a fifth unacknowledged command.
{
  common_exercise replay "playback_window = 4
require_server = false"
  # The recorded nodes are members (they are not started): a replica believes only the
  # exercise's members (docs/protocol.md, "Rules for what is believed").
  cat <<EOF

[[node]]
name = "replay"
site = 1
host = 50

[[node]]
name = "node-1"
site = 1
host = 1

[[node]]
name = "node-2"
site = 1
host = 2
EOF
} >replay.toml

mkfifo replay.out
"$node" --config replay.toml --name replay >replay.out 2>&1 &
node_pid=$!
pids+=("$node_pid")
exec 4<replay.out
# READY: signed on with no server to answer (it has heard nothing yet), so it is listening.
ready=0
while IFS= read -r -t "$(left)" line <&4; do
  echo "[replay] $line"
  if [[ "$line" == "READY replay" ]]; then ready=1; break; fi
done
((ready == 1)) || fail "the server-less node never printed READY"
[[ $(status_key replay.toml replay require_server) == 0 ]] || fail "status lacks require_server 0"
[[ $(status_key replay.toml replay signed_on) == 1 ]] || fail "status lacks signed_on 1"
# Its output goes on to a file so it never blocks on a full pipe.
cat <&4 >replay.log &
pids+=("$!")
exec 4<&-

timeout "$(left)" "$player" --lcm-url="$url" --speed=2 "$log_file" >player.out 2>&1 &
player_pid=$!
pids+=("$player_pid")
wait "$player_pid" || fail "lcm-logplayer exited $? (124: still playing at the deadline)"

while :; do
  digest=$(status_key replay.toml replay digest)
  if [[ "$digest" == "$final_digest" && $(status_key replay.toml replay caught_up) == 1 ]]; then
    break
  fi
  if ((deadline - SECONDS <= 0)); then
    "$ctl" --config replay.toml --name replay status || true
    fail "the replayed node has digest $digest, not the recorded $final_digest"
  fi
  sleep 0.1
done
features=$(status_key replay.toml replay features)
[[ "$features" == "$final_features" ]] || fail "replayed $features features, recorded $final_features"
echo "replayed node converged: $features features, digest $digest"

# It takes commands, beyond its window of 4, though nothing is ever acknowledged.
ids=()
for i in 1 2 3 4 5 6; do
  id=$("$ctl" --config replay.toml --name replay crater $((100 + 60 * i)) 560 5) ||
    fail "crater $i refused"
  [[ "$id" =~ ^1:50:[0-9]+$ ]] || fail "crater reply '$id' is not a 1:50 feature ID"
  ids+=("$id")
done
listed=$("$ctl" --config replay.toml --name replay features)
for id in "${ids[@]}"; do
  grep -qx "$id" <<<"$listed" || fail "the replayed node does not list $id"
done
[[ $(status_key replay.toml replay features) == $((final_features + 6)) ]] ||
  fail "the craters did not add 6 features"
[[ $(status_key replay.toml replay digest) != "$final_digest" ]] || fail "craters left the digest"
[[ $(status_key replay.toml replay acknowledged_change_seq) == 0 ]] ||
  fail "something acknowledged changes in an exercise without a server"

kill -TERM "$node_pid"
wait "$node_pid" || fail "the replayed node exited $?"
trap - EXIT
cleanup
echo PASS
