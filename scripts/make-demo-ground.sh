#!/usr/bin/env bash
# Writes configs/ground/demo.tif, the demo exercise's ground (docs/real-ground.md "The demo's
# ground"): 129 x 129 posts, 10 m apart, of an analytic surface (two ridges, a hill and a slope),
# written by awk as an ESRI ASCII grid and made a GeoTIFF in UTM zone 10N (EPSG:32610) by
# gdal_translate, its south-west post within 2 m of 36.6 N 121.9 W. The file is committed (66 KB); this
# script remakes it the same. It also writes configs/ground/flat-1m.tif, the earthworks drill's
# ground on real-format data: 161 x 161 posts 1 m apart at 0 m, in the same zone.
set -euo pipefail
cd "$(dirname "$0")/.."
out=configs/ground/demo.tif
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
# The south-west pixel's corner: its centre (post (0, 0)) is 5 m further east and north.
x0=598380
y0=4051060
awk -v n=129 -v d=10 -v x0="$x0" -v y0="$y0" 'BEGIN {
  printf "ncols %d\nnrows %d\nxllcorner %d\nyllcorner %d\ncellsize %d\n", n, n, x0, y0, d
  for (r = n - 1; r >= 0; r--) {        # the first row is the northernmost
    line = ""
    for (c = 0; c < n; c++) {
      x = c * d; z = r * d
      h = 20 + 9 * sin(x / 170) * cos(z / 230) + 14 * exp(-((x - 700)^2 + (z - 560)^2) / 200^2) \
          + 0.008 * z
      line = line sprintf("%s%.3f", c ? " " : "", h)
    }
    print line
  }
}' > "$tmp/demo.asc"
mkdir -p "$(dirname "$out")"
gdal_translate -q -of GTiff -a_srs EPSG:32610 -ot Float32 "$tmp/demo.asc" "$out"
echo "make-demo-ground: wrote $out"

# The flat 160 m square of configs/exercises/earthworks.toml as a GeoTIFF (every post 0 m, so the
# drill's crossings and its flood level are the same as on the generated flat ground).
flat=configs/ground/flat-1m.tif
awk -v n=161 -v x0="$x0" -v y0="$y0" 'BEGIN {
  printf "ncols %d\nnrows %d\nxllcorner %d\nyllcorner %d\ncellsize 1\n", n, n, x0, y0
  for (r = 0; r < n; r++) {
    line = ""
    for (c = 0; c < n; c++) line = line (c ? " 0" : "0")
    print line
  }
}' > "$tmp/flat.asc"
gdal_translate -q -of GTiff -a_srs EPSG:32610 -ot Float32 -co COMPRESS=DEFLATE "$tmp/flat.asc" "$flat"
echo "make-demo-ground: wrote $flat"
