#!/usr/bin/env python3
"""The live view's relief tiles in a real browser: Playwright driving Debian's chromium headless.

On flat ground of 2049 x 2049 posts 1 m apart (relief-test.toml: more posts than one relief
picture of kReliefMaxPostsPerSide holds), with a crater 6 m across made before the page opens:
the page opens and its picture is complete; the crater is not in level 0's tile (8 m a pixel),
whose pixel there is the ground's; zoomed to 200 m, the page draws the finest level's tiles and
the crater shows in their pixels; a crater made while zoomed shows in its tile, and the page asks
again for that tile and level 0's only (the tiles the change touched that it shows), the other
tiles keeping their versions. The page's time to its first complete picture and the time from
dt_ctl to the new crater drawn are printed (docs/performance.md), not asserted. Exits 77 (skipped)
when playwright or chromium is not installed. Run inside tests/run_in_netns.sh.

  relief_tiles_browser_test.py <dt_server> <dt_node> <dt_view> <dt_ctl> <exercise.toml> <run_dir>
"""
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../tests/pylib"))
from browser_prerequisites import CHROMIUM, require_browser  # noqa: E402
from relief_tile_pixels import rgb_array, tile_pixels  # noqa: E402
from exercise_processes import ExerciseProcesses  # noqa: E402



sync_playwright = require_browser()

ex = ExerciseProcesses(dict(zip(["dt_server", "dt_node", "dt_view", "dt_ctl"], sys.argv[1:5])),
                       sys.argv[5], sys.argv[6])
run_dir, ctl, fail = ex.run_dir, ex.ctl, ex.fail
URL = "http://127.0.0.1:8482/"
SIZE_M = 2048.0
A = (720.0, 720.0)  # made before the page opens: tile 3/2/2
B = (820.0, 800.0)  # made while zoomed: tile 3/3/3
RADIUS_M = "3"

# The relief as the page draws it: its tile images composited in their order onto a canvas of the
# map's size with the map's transform (view_state.js transform()), and that transform.
DRAWN = """async () => {
  const t = transform(), c = document.createElement('canvas');
  c.width = t.W; c.height = t.H;
  const g = c.getContext('2d');
  g.imageSmoothingEnabled = false;
  for (const el of document.querySelectorAll('#relieftiles image')) {
    const img = new Image();
    img.src = el.getAttribute('href');
    await img.decode();
    const x = +el.getAttribute('x'), y = +el.getAttribute('y'), s = +el.getAttribute('width');
    g.drawImage(img, (x - t.ox) / t.s, (y - t.oy) / t.s, s / t.s, s / t.s);
  }
  const d = g.getImageData(0, 0, c.width, c.height).data;
  let bin = '';
  for (let i = 0; i < d.length; i += 32768) bin += String.fromCharCode.apply(null, d.subarray(i, i + 32768));
  return [c.width, c.height, btoa(bin), t.s, t.ox, t.oy];
}"""


class Drawn:
    """The page's drawn relief and where a terrain point falls on it."""

    def __init__(self, page):
        w, h, b64, self.s, self.ox, self.oy = page.evaluate(DRAWN)
        self.rgb = rgb_array(w, h, b64)

    def at(self, x, z):
        col, row = int((x - self.ox) / self.s), int((SIZE_M - z - self.oy) / self.s)
        return self.rgb[row, col]


def differs(a, b):
    return int(np.abs(a - b).sum())


ex.start("server", "dt_server")
ex.start("node-1", "dt_node")
ex.start("view", "dt_view")
crater_a = ctl("node-1", "crater", str(A[0]), str(A[1]), RADIUS_M)


def stop_all_on_error(kind, value, tb):
    ex.kill_all()
    sys.__excepthook__(kind, value, tb)


sys.excepthook = stop_all_on_error  # a Playwright timeout must not leave processes behind

with sync_playwright() as pw:
    browser = pw.chromium.launch(executable_path=CHROMIUM, headless=True, args=["--no-sandbox"])
    page_errors, asked = [], []
    page = browser.new_page(viewport={"width": 1400, "height": 900})
    page.on("pageerror", lambda e: page_errors.append(str(e)))
    page.on("request", lambda r: asked.append(r.url) if "/relief/" in r.url else None)
    page.goto(URL)
    page.wait_for_function(f"'{crater_a}' in window.dtView.drawnAt", timeout=20000)
    page.wait_for_function("window.dtView.relief.complete", timeout=30000)
    levels = page.evaluate("window.dtView.relief.info.levels")
    opened_ms = page.evaluate("window.dtView.relief.completeAt - performance.timeOrigin")
    print(f"the page opened: {levels} levels, level {page.evaluate('window.dtView.relief.level')} "
          f"for the whole world, first complete picture {opened_ms:.0f} ms after navigation")
    if levels != 4:
        fail(f"a 2048 m world at 1 m has levels of 8, 4, 2 and 1 m a pixel; the page has {levels}")

    # Level 0 (8 m a pixel) leaves the 6 m crater out: its pixel there is the ground's.
    tile0 = tile_pixels(page, "/relief/0/0/0.png")
    px = lambda x, z: tile0[int((SIZE_M - z) / 8.0), int(x / 8.0)]  # noqa: E731
    if differs(px(*A), px(1500.0, 1500.0)) > 6:
        fail(f"level 0 draws the 6 m crater at 8 m a pixel: {px(*A)} against {px(1500.0, 1500.0)}")

    # Zoomed to 200 m around the corner of four finest tiles (768, 768): the finest level, and
    # the crater in its pixels.
    page.evaluate("() => { state.view = {x: 668, y: 2048 - 868, w: 200, h: 200}; applyView(); }")
    page.wait_for_function(f"window.dtView.relief.complete && window.dtView.relief.level === {levels - 1}",
                           timeout=30000)
    need = page.evaluate("window.dtView.relief.need")
    if sorted(need) != sorted(["0/0/0", "3/2/2", "3/3/2", "3/2/3", "3/3/3"]):
        fail(f"zoomed to (668..868, 668..868) m the page shows tiles {need}")
    drawn = Drawn(page)
    ground = drawn.at(A[0] + 40.0, A[1])
    if differs(drawn.at(*A), ground) < 15:  # the flat ground is one colour
        fail(f"zoomed in, the crater at {A} is not in the relief: {drawn.at(*A)} against {ground}")
    print(f"zoomed in: level {levels - 1}, the crater shows ({drawn.at(*A)} against the ground's "
          f"{ground})")
    page.screenshot(path=os.path.join(run_dir, "relief-zoomed.png"))

    # A crater made while zoomed: its tile (and level 0's, always shown) asked again, no other.
    versions = {k: page.evaluate(f"window.dtView.relief.tiles.get('{k}').version") for k in need}
    asked.clear()
    before_ms = time.time() * 1000.0
    crater_b = ctl("node-1", "crater", str(B[0]), str(B[1]), RADIUS_M)
    page.wait_for_function(
        f"window.dtView.relief.complete && window.dtView.relief.tiles.get('3/3/3').version > "
        f"{versions['3/3/3']}", timeout=30000)
    drawn_ms = time.time() * 1000.0 - before_ms
    drawn = Drawn(page)
    if differs(drawn.at(*B), drawn.at(B[0], B[1] - 40.0)) < 15:
        fail(f"the crater made while zoomed at {B} is not in the relief")
    for k in need:
        now = page.evaluate(f"window.dtView.relief.tiles.get('{k}').version")
        if (now != versions[k]) != (k in ("0/0/0", "3/3/3")):
            fail(f"tile {k} went from version {versions[k]} to {now} for a crater at {B}")
    tiles_asked = sorted({u.split("/relief/")[1].split(".png")[0] for u in asked})
    if tiles_asked != ["0/0/0", "3/3/3"]:
        fail(f"after a crater in tile 3/3/3 the page asked for {tiles_asked}")
    print(f"a crater made while zoomed ({crater_b}) is drawn in tile 3/3/3 {drawn_ms:.0f} ms after "
          f"dt_ctl ran; the page asked again for {tiles_asked} only")
    page.screenshot(path=os.path.join(run_dir, "relief-zoomed-crater.png"))
    if page_errors:
        fail(f"errors in the page: {page_errors}")
    browser.close()

for name, rc in ex.stop_all(timeout_s=15).items():
    if rc != 0:
        fail(f"{name} exited {rc} on SIGTERM")
print("PASS")
