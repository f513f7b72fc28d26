#!/usr/bin/env bash
# A running dt_server (the demo exercise's, alone) answers `import`/`export` of what is not a
# regular terrain file (a FIFO with no writer, a directory, /dev/zero) with an error reply and keeps
# answering `status`; SIGTERM still stops it with exit 0. Then a database that is not the server's
# (an empty file, a text file) stops the start with exit 2 and a message naming the file.
# Run inside tests/run_in_netns.sh.
#   server_files_test.sh <dt_server> <dt_ctl> <exercise.toml> <run_dir>
set -euo pipefail
server=$1 ctl=$2 exercise=$3 run_dir=$4
rm -rf "$run_dir"
mkdir -p "$run_dir"

fail() { echo "FAIL: $*" >&2; exit 1; }
# Bounded: a server whose loop is held by a file would otherwise leave dt_ctl waiting for ever.
ctl_() { timeout 30 "$ctl" --config "$exercise" --run-dir "$run_dir" --name server "$@"; }
# expect_error <reply fragment> <command...>: the command must get an error reply (exit 1).
expect_error() {
  local fragment=$1 out rc
  shift
  set +e
  out=$(ctl_ "$@" 2>&1)
  rc=$?
  set -e
  [[ $rc == 1 ]] || fail "'$*' exited $rc, not 1 (reply: $out)"
  [[ "$out" == *"$fragment"* ]] || fail "'$*' replied '$out', which lacks '$fragment'"
  echo "ok: '$*' -> $out"
}

out_fifo="$run_dir/server.out"
mkfifo "$out_fifo"
"$server" --config "$exercise" --run-dir "$run_dir" --name server >"$out_fifo" 2>&1 &
pid=$!
exec 3<"$out_fifo"
trap 'kill -TERM $pid 2>/dev/null || true' EXIT

# Wait for READY (the read blocks, no sleeps), then keep draining the output so it never fills.
ready=0
while IFS= read -r -t 60 line <&3; do
  echo "$line"
  if [[ "$line" == "READY server" ]]; then ready=1; break; fi
done
[[ $ready == 1 ]] || fail "dt_server never printed READY server"
cat <&3 >"$run_dir/server.log" &
drain_pid=$!

mkfifo "$run_dir/in.dtt"  # nobody ever writes to it
expect_error "$run_dir/in.dtt: is a FIFO" import "$run_dir/in.dtt"
ctl_ status | grep -q '^role server$' || fail "no status after importing a FIFO"
expect_error "$run_dir: is a directory" import "$run_dir"
expect_error "/dev/zero: is a character device" import /dev/zero
expect_error "$run_dir/in.dtt: is a FIFO" export "$run_dir/in.dtt"
[[ -p "$run_dir/in.dtt" ]] || fail "export replaced the FIFO"
ctl_ status | grep -q '^role server$' || fail "no status after the refused files"
ctl_ export "$run_dir/t.dtt" >/dev/null || fail "exporting to a new file failed"
ctl_ import "$run_dir/t.dtt" >/dev/null || fail "importing the exported file failed"

kill -TERM $pid
trap - EXIT
wait $pid || fail "dt_server exited $? after SIGTERM"
wait $drain_pid || true
cat "$run_dir/server.log"
grep -q "import refused: $run_dir/in.dtt: is a FIFO" "$run_dir/server.log" ||
  fail "the log lacks the refused import"

# start_refused <fragment>: dt_server must exit 2 with the fragment on stderr.
start_refused() {
  local fragment=$1 err rc
  set +e
  err=$(timeout 60 "$server" --config "$exercise" --run-dir "$run_dir" --name server 2>&1 >/dev/null)
  rc=$?
  set -e
  [[ $rc == 2 ]] || fail "dt_server over a bad database exited $rc, not 2 ($err)"
  [[ "$err" == *"$fragment"* ]] || fail "dt_server said '$err', which lacks '$fragment'"
  echo "ok: refused at start: $(tail -n 1 <<<"$err")"
}
db="$run_dir/server.db"
rm -f "$db" "$db-wal" "$db-shm"
: >"$db"
start_refused "dt_server server: $db: is empty (0 bytes)"
echo "notes, not a database; long enough to have been a header" >"$db"
start_refused "dt_server server: $db: is not an SQLite database"
echo PASS
