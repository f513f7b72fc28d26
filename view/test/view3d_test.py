#!/usr/bin/env python3
"""The live view's 3D view in headless chromium (Playwright, WebGL on SwiftShader), on a fixed scene.

scene3d.py answers the page's /terrain3d as dt_view does (view/terrain_window.cc) for a 129 x 129
post terrain (1024 m, 8 m apart) with a crater, a berm, a ditch, an intact and a destroyed bridge,
and sends thirteen vehicles that stand still. With the camera fixed by the page's address
(#3d=x,z,yaw,pitch,dist), asserted: the page drew the window's posts, every bridge solid and every
vehicle in the window, and its picture matches the committed reference (view3d_reference.png)
within a tolerance: at most 1 % of the pixels differ by more than 40 in a channel (the difference
is printed). Printed, not asserted: frames drawn per second while the camera turns, on the 129^2
terrain (in this page and in a 1600 x 1000 one, beside an empty canvas of that size: the bound;
the large page with chromium's compositor on SwiftShader and with its software compositor)
and on a 100 km terrain seen from far (dt_view's step grows, the posts do not). `--update` writes the reference instead.
Exits 77 (skipped) when playwright or chromium is missing. Run inside tests/run_in_netns.sh.

  view3d_test.py <run_dir> [--update]
"""
import base64
import os
import struct
import sys
import time
import zlib

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "../../tests/pylib"))
from browser_prerequisites import CHROMIUM, require_browser  # noqa: E402
import scene3d  # noqa: E402

PORT, LARGE_PORT = 8483, 8484
REFERENCE = os.path.join(HERE, "view3d_reference.png")
CAMERA = "#3d=460,560,0.35,0.42,260"
DIFF_LEVEL = 40        # a channel differing by more than this makes a pixel differ
DIFF_FRACTION = 0.01   # at most this share of the pixels may differ


def fail(why):
    print(f"FAIL: {why}")
    sys.exit(1)


def read_png(data):
    """An 8-bit RGB or RGBA PNG, not interlaced, as an H x W x 3 array (the reference, which
    write_png wrote: every row unfiltered)."""
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("not a PNG")
    at, idat, head = 8, b"", None
    while at < len(data):
        n, kind = struct.unpack(">I4s", data[at:at + 8])
        body = data[at + 8:at + 8 + n]
        if kind == b"IHDR":
            head = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        at += 12 + n
    w, h, depth, colour, _, _, interlace = head
    if depth != 8 or colour not in (2, 6) or interlace:
        raise ValueError(f"PNG depth {depth}, colour type {colour}, interlace {interlace}")
    bpp = 3 if colour == 2 else 4
    rows = np.frombuffer(zlib.decompress(idat), dtype=np.uint8).reshape(h, w * bpp + 1)
    if rows[:, 0].any():
        raise ValueError("a filtered PNG row: write the reference with --update")
    return rows[:, 1:].reshape(h, w, bpp)[:, :, :3].astype(np.int32)


def write_png(path, rgb):
    def chunk(kind, body):
        return (struct.pack(">I", len(body)) + kind + body +
                struct.pack(">I", zlib.crc32(kind + body) & 0xffffffff))
    h, w, _ = rgb.shape
    raw = np.concatenate([np.zeros((h, 1), dtype=np.uint8),
                          rgb.astype(np.uint8).reshape(h, w * 3)], axis=1).tobytes()
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


# The 3D canvas's pixels, from the page's snapshot(): drawn and read in one task (the canvas keeps
# no drawing buffer once shown).
PIXELS = """() => {
  const s = window.dtView3d.snapshot(), d = s.rgba;
  let bin = '';
  for (let i = 0; i < d.length; i += 32768) bin += String.fromCharCode.apply(null, d.subarray(i, i + 32768));
  return [s.width, s.height, btoa(bin)];
}"""


def pixels(page):
    w, h, b64 = page.evaluate(PIXELS)
    return np.frombuffer(base64.b64decode(b64), dtype=np.uint8).reshape(h, w, 4)[:, :, :3].astype(np.int32)


sync_playwright = require_browser()

run_dir = sys.argv[1]
update = "--update" in sys.argv
os.makedirs(run_dir, exist_ok=True)
web = os.path.join(HERE, "../web")
small = scene3d.serve(PORT, web, 1024.0, 8.0)
large = scene3d.serve(LARGE_PORT, web, 100000.0, 8.0)
EXPECTED_VEHICLES = len(scene3d.vehicles())
EXPECTED_SOLIDS = sum(len(scene3d.bridge_solids(b)) for b in scene3d.BRIDGES)


def wait(page, what, timeout_s=30):
    end = time.monotonic() + timeout_s
    while time.monotonic() < end:
        if page.evaluate(what):
            return
        page.wait_for_timeout(50)  # polling the page's state; the condition is the signal
    fail(f"timed out waiting for {what}: {page.evaluate('JSON.stringify(window.dtView3d)')[:400]}")


SETTLE = "new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))"


# Frames per second of a WebGL 2 canvas of w x h pixels that is only cleared, every animation frame
# for 3 s: the rasteriser's and the page's bound, whatever the scene.
EMPTY_CANVAS_FPS = """([w, h]) => new Promise((done) => {
  const c = document.createElement('canvas'); c.width = w; c.height = h;
  c.style = `position:fixed;left:0;top:0;width:${w}px;height:${h}px;z-index:9`;
  document.body.appendChild(c);
  const gl = c.getContext('webgl2', {antialias: false, preserveDrawingBuffer: false});
  let n = 0, t0 = null;
  const step = (t) => {
    if (t0 === null) t0 = t;
    gl.clearColor(0.5, 0.6, 0.8, 1); gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT); ++n;
    if (t - t0 < 3000) requestAnimationFrame(step); else { c.remove(); done((n - 1) * 1000 / (t - t0)); }
  };
  requestAnimationFrame(step); })"""


def fps(page, seconds):
    """Frames drawn per second while the camera turns a little every animation frame (the page
    draws only when something changed)."""
    page.evaluate("""() => { const v = window.dtView3d; v.spinning = true;
        const spin = () => { v.cam.yaw += 0.002; if (v.spinning) requestAnimationFrame(spin); };
        requestAnimationFrame(spin); }""")
    f0 = page.evaluate("window.dtView3d.frames")
    t0 = time.monotonic()
    page.wait_for_timeout(seconds * 1000)
    rate = (page.evaluate("window.dtView3d.frames") - f0) / (time.monotonic() - t0)
    page.evaluate("window.dtView3d.spinning = false")
    return rate


BROWSER_ARGS = ["--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
                "--ignore-gpu-blocklist"]


def full_page(browser, compositor, errors):
    """Prints the frames per second of the scene in a 1600 x 1000 page (a larger canvas, its
    backing store capped) and of an empty WebGL canvas of that backing store, cleared every
    frame: what bounds it."""
    big = browser.new_page(viewport={"width": 1600, "height": 1000})
    big.on("pageerror", lambda e: errors.append(str(e)))
    big.goto(f"http://127.0.0.1:{PORT}/{CAMERA}")
    wait(big, f"window.dtView3d.windows >= 1 && window.dtView3d.drawn.vehicles === {EXPECTED_VEHICLES}")
    big_fps = fps(big, 3)
    size = big.evaluate("[document.getElementById('view3d').width, document.getElementById('view3d').height]")
    empty = big.evaluate(EMPTY_CANVAS_FPS, size)
    print(f"3D view, 129^2 terrain in a 1600 x 1000 page ({size[0]} x {size[1]} pixels, "
          f"{compositor}): {big_fps:.1f} frames/s; an empty canvas of that size {empty:.1f} "
          f"frames/s, load average {os.getloadavg()[0]:.1f}")
    big.close()


with sync_playwright() as pw:
    browser = pw.chromium.launch(executable_path=CHROMIUM, headless=True, args=BROWSER_ARGS)
    try:
        page = browser.new_page(viewport={"width": 1040, "height": 560})
        errors = []
        page.on("pageerror", lambda e: errors.append(str(e)))
        page.goto(f"http://127.0.0.1:{PORT}/{CAMERA}")
        wait(page, "window.dtView3d.error || window.dtView3d.windows >= 1 && "
                   f"window.dtView3d.drawn.vehicles === {EXPECTED_VEHICLES}")
        if page.evaluate("window.dtView3d.error"):
            fail(f"the 3D view: {page.evaluate('window.dtView3d.error')}")
        drawn = page.evaluate("window.dtView3d.drawn")
        print(f"drawn: {drawn}")
        if drawn["solids"] != EXPECTED_SOLIDS:
            fail(f"{drawn['solids']} bridge solids drawn, the window has {EXPECTED_SOLIDS}")
        if drawn["posts"] < 100 * 100 or drawn["step"] != 8.0:
            fail(f"the window near the camera should be the terrain's posts: {drawn}")
        # The help line holds a changing frame rate: hidden, so the picture is the scene's alone.
        page.evaluate("document.getElementById('help3d').style.visibility = 'hidden'")
        page.evaluate(SETTLE)
        got = pixels(page)
        write_png(os.path.join(run_dir, "view3d.png"), got)
        if update:
            write_png(REFERENCE, got)
            print(f"wrote {REFERENCE}")
        else:
            ref = read_png(open(REFERENCE, "rb").read())
            if ref.shape != got.shape:
                fail(f"picture {got.shape[1]}x{got.shape[0]}, reference {ref.shape[1]}x{ref.shape[0]}")
            diff = np.abs(ref - got).max(axis=2)
            share = float((diff > DIFF_LEVEL).mean())
            print(f"difference from the reference: {share * 100:.3f} % of pixels by more than "
                  f"{DIFF_LEVEL}, mean {float(diff.mean()):.2f}, largest {int(diff.max())}")
            if share > DIFF_FRACTION:
                fail(f"{share * 100:.2f} % of the pixels differ from {REFERENCE} "
                     f"(picture in {run_dir}/view3d.png)")
            # The test can fail: the same scene from elsewhere is another picture.
            f0 = page.evaluate("window.dtView3d.frames")
            page.evaluate("window.dtView3d.cam.yaw += 1.0")
            wait(page, f"window.dtView3d.frames > {f0}")
            page.evaluate(SETTLE)
            other = pixels(page)
            moved = float((np.abs(ref - other).max(axis=2) > DIFF_LEVEL).mean())
            if moved <= DIFF_FRACTION:
                fail(f"a turned camera's picture differs in {moved * 100:.2f} % only: "
                     "the comparison cannot tell pictures apart")
        print(f"3D view, 129^2 terrain: {fps(page, 3):.1f} frames/s, load average "
              f"{os.getloadavg()[0]:.1f}")
        # The same scene in a 1600 x 1000 page (a larger canvas, its backing store capped), and
        # what bounds it: an empty WebGL canvas of that backing store, cleared every frame.
        full_page(browser, "chromium's compositor on SwiftShader", errors)
        # The same with chromium's software compositor (what it uses without a usable GPU): with
        # the compositor on SwiftShader every frame composites the whole 1600 x 1000 viewport,
        # which bounds the page whatever its canvas holds (docs/performance.md).
        soft = pw.chromium.launch(executable_path=CHROMIUM, headless=True,
                                  args=BROWSER_ARGS + ["--disable-gpu-compositing"])
        try:
            full_page(soft, "software compositor", errors)
        finally:
            soft.close()

        far = browser.new_page(viewport={"width": 1040, "height": 560})
        far.on("pageerror", lambda e: errors.append(str(e)))
        far.goto(f"http://127.0.0.1:{LARGE_PORT}/#3d=50000,50000,0.5,0.6,30000")
        # A window arrives, then the next frame draws it (and fills `drawn`).
        wait(far, "window.dtView3d.windows >= 1 && 'step' in window.dtView3d.drawn")
        d = far.evaluate("window.dtView3d.drawn")
        if d["posts"] > 257 * 257:
            fail(f"a far view of a large terrain drew {d['posts']} posts")
        print(f"3D view, 100 km terrain from 30 km: {d['posts']} posts every {d['step']} m, "
              f"{fps(far, 3):.1f} frames/s, load average {os.getloadavg()[0]:.1f}")
        if errors:
            fail(f"page errors: {errors}")
    finally:
        browser.close()
        small.shutdown()
        large.shutdown()
print("PASS")
