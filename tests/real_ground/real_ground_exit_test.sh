#!/usr/bin/env bash
# Every process refuses bad real ground with exit 2 and a message naming the file: an elevation
# file GDAL cannot read (dt_launch, dt_node, dt_server, dt_view, dt_dis, at config load), and one
# with nodata posts and no fill (each process when it builds its ground). Rasters are made here
# with gdal_translate; nothing is fetched. Run inside tests/run_in_netns.sh.
#   real_ground_exit_test.sh <bin dir> <dir>
set -euo pipefail
bin=$1 dir=$2
rm -rf "$dir"
mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }

# A 20 x 20 UTM grid, 10 m apart, with one nodata pixel (column 3 of the southern row).
{
  printf 'ncols 20\nnrows 20\nxllcorner 500000\nyllcorner 5200000\ncellsize 10\nNODATA_value -9999\n'
  for r in $(seq 19 -1 0); do
    line=""
    for c in $(seq 0 19); do
      v=$((100 + c + 2 * r))
      [[ $r == 0 && $c == 3 ]] && v=-9999
      line+="$v "
    done
    echo "$line"
  done
} > "$dir/holes.asc"
gdal_translate -q -of GTiff -a_srs EPSG:32633 "$dir/holes.asc" "$dir/holes.tif"
echo "not a raster" > "$dir/junk.tif"

exercise() {  # exercise <file> <raster>
  cat > "$1" <<TOML
[exercise]
name = "rg"
transport = "udpm://239.255.76.67:7667?ttl=0"
run_dir = "$dir/run"
[auth]
mode = "none"
[terrain]
elevation_file = "$2"
[server]
name = "server"
site = 1
host = 1
[[node]]
name = "node-1"
site = 1
host = 2
[view]
name = "view"
site = 1
host = 3
http_port = 18480
[dis]
name = "dis"
site = 1
host = 4
udp_port = 13000
TOML
}
exercise "$dir/junk.toml" junk.tif
exercise "$dir/holes.toml" holes.tif

expect_exit2() {  # expect_exit2 <what> <text> <command...>
  local what=$1 text=$2 rc=0
  shift 2
  timeout 60 "$@" > "$dir/out" 2>&1 || rc=$?
  [[ $rc == 2 ]] || { cat "$dir/out"; fail "$what exited $rc, not 2"; }
  grep -qF -- "$text" "$dir/out" || { cat "$dir/out"; fail "$what did not say: $text"; }
  echo "ok: $what exits 2: $(grep -F -- "$text" "$dir/out" | head -1 | cut -c1-160)"
}

for cfg in junk holes; do
  if [[ $cfg == junk ]]; then
    text="$dir/junk.tif: GDAL cannot read it as a raster"
  else
    text="1 of the 20 x 20 posts have no data"
  fi
  expect_exit2 "dt_node ($cfg)" "$text" "$bin/node/dt_node" --config "$dir/$cfg.toml" --name node-1
  expect_exit2 "dt_server ($cfg)" "$text" "$bin/server/dt_server" --config "$dir/$cfg.toml" \
    --name server
  expect_exit2 "dt_view ($cfg)" "$text" "$bin/view/dt_view" --config "$dir/$cfg.toml"
  expect_exit2 "dt_dis ($cfg)" "$text" "$bin/dis/dt_dis" --config "$dir/$cfg.toml"
done
expect_exit2 "dt_launch (junk)" "$dir/junk.tif: GDAL cannot read it as a raster" \
  "$bin/launcher/dt_launch" --config "$dir/junk.toml"
rm -rf "$dir"
echo "PASS"
