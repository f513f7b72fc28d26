#!/usr/bin/env bash
# Runs long chaos campaigns (configs/drills/campaign.toml) one after another, each with its own
# seed, each in a private network namespace, and prints one summary line per campaign.
#   scripts/campaigns.sh <count> <udpm|dds> [first_seed] [drill.toml]
# Seeds are first_seed, first_seed + 100, ... (default first_seed 1000); a failed campaign is
# rerun with the same choices by `dt_drill --drill <drill> --seed <seed>` (docs/launcher.md).
# The build is DT_BUILD_DIR (default build/dev); each campaign's output and run dir are kept in
# <build>/tests/drills/run/campaign-<transport>-<seed>-<date>-<time>{.log,/}.
# Exits 0 if every campaign passed, 1 otherwise.
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ $# -lt 2 || ! "$1" =~ ^[1-9][0-9]*$ || ! "$2" =~ ^(udpm|dds)$ ]]; then
  echo "usage: $0 <count> <udpm|dds> [first_seed] [drill.toml]" >&2
  exit 2
fi
count=$1
transport=$2
first_seed=${3:-1000}
drill=${4:-configs/drills/campaign.toml}
build=${DT_BUILD_DIR:-build/dev}
if [[ ! "$first_seed" =~ ^[0-9]+$ ]]; then
  echo "$0: first_seed \"$first_seed\" is not a whole number" >&2
  exit 2
fi
for program in launcher/dt_drill node/dt_node server/dt_server; do
  if [[ ! -x "$build/$program" ]]; then
    echo "$0: $build/$program is missing; build dt_drill dt_node dt_server first" >&2
    exit 2
  fi
done
[[ -f "$drill" ]] || { echo "$0: no drill file $drill" >&2; exit 2; }

transport_args=()
if [[ "$transport" == dds ]]; then
  transport_args=(--transport "dds://0?config=$PWD/configs/cyclonedds-loopback.xml")
fi
runs="$build/tests/drills/run"
mkdir -p "$runs"
failed=0
for ((i = 0; i < count; ++i)); do
  seed=$((first_seed + 100 * i))
  name="campaign-$transport-$seed-$(date +%Y%m%d-%H%M%S)"  # a rerun keeps the earlier run
  log="$runs/$name.log"
  rc=0
  tests/run_in_netns.sh "$build/launcher/dt_drill" --drill "$drill" --seed "$seed" \
    --run-dir "$runs/$name" --node-bin "$build/node/dt_node" \
    --server-bin "$build/server/dt_server" "${transport_args[@]}" >"$log" 2>&1 || rc=$?
  summary=$(grep '^\[drill\] summary ' "$log" | tail -n 1 | sed 's/^\[drill\] summary //')
  [[ -n "$summary" ]] || summary="result=FAIL (no summary: dt_drill exited $rc)"
  echo "campaign $((i + 1))/$count transport=$transport seed=$seed $summary log=$log"
  if [[ $rc -ne 0 ]]; then
    failed=$((failed + 1))
    # The report's failed checks with their detail lines, and what it says of diverged replicas.
    sed -n '/^== drill /,$p' "$log" |
      awk '/^  \[FAIL\]/ {show = 1; print "    " $0; next}
           /^  \[/ {show = 0; next}
           /^    / && show {print "    " $0; next}
           / beside / || / with other parameters/ {print "    " $0}' || true
  fi
done
echo "campaigns: $count run, $failed failed ($transport, $drill)"
[[ $failed -eq 0 ]]
