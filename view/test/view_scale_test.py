#!/usr/bin/env python3
"""The live view's page at exercise scale, in headless chromium (Playwright).

A synthetic feed (synthetic_feed.py: dt_view's messages, without the nodes that would drive so
many vehicles) sends a snapshot and 30 deltas a second for N vehicles of three owners and M
features. Asserted: the page's model holds all N; at the whole terrain every one is drawn (the
page's count of what it drew) and the canvas holds owner-colour pixels for every mark it drew and
for every owner; zoomed in, the vehicles in view (counted here from the page's model and view) are
drawn one marker each, and the pixels hold them; at the whole terrain most of the terrain is left
uncovered by the vehicles' drawing (the relief and features readable). Printed, not asserted (speed is a benchmark's to
measure): frames per second, the worst frame and the page's lag behind its messages over 10 s of
panning and zooming, and the WebSocket's bytes per second (the vehicles' moves in the binary
message, or with `json` as JSON rows, the format before it); then the 3D view's frames per second with
every vehicle on the feed's terrain window. Asserted after the panning: the view is back where it
began (the panning's moves undo each other, so its picture shows the terrain). Asserted in 3D, on
one picture: the vehicles it placed are the model's on its window, shapes (the nearest, up to the
page's cap), points and thinned add up to them, and every owner's colour shows. Exits 77 (skipped) when playwright or
chromium is not installed. Run inside tests/run_in_netns.sh.

  view_scale_test.py <vehicles> <features> <run_dir> [<seconds of panning> [json]]
"""
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "../../tests/pylib"))
from browser_prerequisites import CHROMIUM, require_browser  # noqa: E402
import synthetic_feed  # noqa: E402

PORT = 8482


def fail(why):
    print(f"FAIL: {why}")
    sys.exit(1)


sync_playwright = require_browser()

vehicles, features, run_dir = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
pan_s = float(sys.argv[4]) if len(sys.argv) > 4 else 10.0
json_vehicles = len(sys.argv) > 5 and sys.argv[5] == "json"
os.makedirs(run_dir, exist_ok=True)
built = time.monotonic()
server = synthetic_feed.serve(PORT, os.path.join(HERE, "../web"), vehicles, features,
                              json_vehicles)
# At the whole terrain, at least this share of it must show through the vehicles' drawing: the
# cells' glyphs leave the relief readable (90 % at 9000 vehicles; the filled and outlined cells
# before them left 59 %).
UNCOVERED_MIN = 0.75

# Owner-colour pixels of the overlay canvas: exact matches (fills are opaque, edges blend), per
# owner, with the page's own colours.
COUNT_PIXELS = """() => {
  const c = document.getElementById('overlay');
  const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
  const owners = ['node-1', 'node-2', 'node-3'];
  const rgb = owners.map(o => window.dtView.ownerRgb(o));
  const counts = Object.fromEntries(owners.map(o => [o, 0]));
  for (let i = 0; i < d.length; i += 4) {
    for (let k = 0; k < rgb.length; ++k) {
      const [r, g, b] = rgb[k];
      if (Math.abs(d[i] - r) <= 2 && Math.abs(d[i + 1] - g) <= 2 && Math.abs(d[i + 2] - b) <= 2) {
        ++counts[owners[k]]; break;
      }
    }
  }
  return counts;
}"""

# The share of the terrain's area, on a grid of points every 3 pixels, where the overlay canvas
# (vehicles, and features when many) leaves the relief uncovered (alpha 0).
UNCOVERED = """() => {
  const st = window.dtView.state, v = st.view, c = document.getElementById('overlay');
  const s = Math.max(v.w / c.clientWidth, v.h / c.clientHeight);
  const ox = v.x + (v.w - c.clientWidth * s) / 2, oy = v.y + (v.h - c.clientHeight * s) / 2;
  const x0 = Math.max(0, Math.ceil(-ox / s)), y0 = Math.max(0, Math.ceil(-oy / s));
  const x1 = Math.min(c.width, Math.floor((st.size_x - ox) / s)),
        y1 = Math.min(c.height, Math.floor((st.size_z - oy) / s));
  const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
  let n = 0, clear = 0;
  for (let y = y0; y < y1; y += 3) for (let x = x0; x < x1; x += 3) {
    ++n; if (d[(y * c.width + x) * 4 + 3] === 0) ++clear;
  }
  return {points: n, uncovered: clear / Math.max(n, 1)};
}"""

# The vehicles in the page's view, counted from its model and view box here (as the SVG's
# viewBox places them), not by the page's drawing code.
IN_VIEW = """() => {
  const st = window.dtView.state, v = st.view, c = document.getElementById('overlay');
  const s = Math.max(v.w / c.clientWidth, v.h / c.clientHeight);
  const x0 = v.x + (v.w - c.clientWidth * s) / 2, y0 = v.y + (v.h - c.clientHeight * s) / 2;
  let n = 0;
  for (const r of st.vehicles.values()) {
    const y = st.size_z - r[4];
    if (r[3] >= x0 && r[3] <= x0 + c.clientWidth * s && y >= y0 && y <= y0 + c.clientHeight * s) ++n;
  }
  return n;
}"""

# The 3D view: a picture drawn now (snapshot), the vehicles on its terrain window counted from the
# page's vehicle table (not by the 3D view's code), what the picture drew, and per owner the pixels
# of exactly its colour (alive points are drawn unlit in it).
COUNT_3D = """() => {
  const v = window.dtView3d, st = window.dtView.state, tb = st.vehicles, w = v.win;
  const shot = v.snapshot(), d = shot.rgba;
  const x1 = w.x0 + (w.nx - 1) * w.step, z1 = w.z0 + (w.nz - 1) * w.step;
  let model = 0;
  for (const r of tb.values()) if (r[3] >= w.x0 && r[3] <= x1 && r[4] >= w.z0 && r[4] <= z1) ++model;
  const owners = ['node-1', 'node-2', 'node-3'], rgb = owners.map(o => window.dtView.ownerRgb(o));
  const pixels = Object.fromEntries(owners.map(o => [o, 0]));
  for (let i = 0; i < d.length; i += 4) for (let k = 0; k < 3; ++k) {
    if (Math.abs(d[i] - rgb[k][0]) <= 2 && Math.abs(d[i + 1] - rgb[k][1]) <= 2 &&
        Math.abs(d[i + 2] - rgb[k][2]) <= 2) { ++pixels[owners[k]]; break; }
  }
  return {model, drawn: Object.assign({}, v.drawn), pixels, near_max: v.instances.nearMax,
          points_all: v.instances.pointsAll};
}"""

# What is in view, what the last frame drew and the owners' pixels, read in one task of the page.
READ_MARKERS = f"""() => ({{
  in_view: ({IN_VIEW})(),
  drawn: Object.assign({{}}, window.dtView.drawn),
  pixels: ({COUNT_PIXELS})(),
}})"""

# The panning's drags in pixels, a cycle of six moves (see the panning below); 1.2 is the page's
# zoom step (map_view.js): 125 * 1.2^3 = 216. Whole pixels, from a whole pixel, as the browser's
# mouse events are.
PAN_PX = [(125, 125), (-120, 80), (90, -110), (-216, -216), (-90, 110), (120, -80)]
SETTLE = "new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))"


def pan_and_zoom(page, cx, cy, step):
    """Move `step` of the panning's cycle: a drag from the map's centre, then a wheel step there."""
    page.mouse.move(cx, cy)
    page.mouse.down()
    dx, dy = PAN_PX[step % 6]
    page.mouse.move(cx + dx, cy + dy, steps=12)
    page.mouse.up()
    # The page ends a drag in a task after mouseup: past it, moving back is not a drag.
    page.evaluate("new Promise(r => setTimeout(r, 0))")
    page.mouse.move(cx, cy)
    page.mouse.wheel(0, -240 if step % 6 < 3 else 240)

with sync_playwright() as pw:
    browser = pw.chromium.launch(executable_path=CHROMIUM, headless=True,
                                 # WebGL on SwiftShader where there is no GPU, for the 3D view;
                                 # the 2D canvas is left to chromium's default.
                                 args=["--no-sandbox", "--enable-unsafe-swiftshader"])
    try:
        page = browser.new_page(viewport={"width": 1600, "height": 1000})
        page_errors = []  # the page's uncaught errors: none expected
        page.on("pageerror", lambda e: page_errors.append(str(e)))
        page.goto(f"http://127.0.0.1:{PORT}/")
        page.wait_for_function("window.dtView.snapshotAt > 0", timeout=120000)
        print(f"the page received its snapshot {time.monotonic() - built:.1f} s after start")
        held = page.evaluate("window.dtView.state.vehicles.size")
        if held != vehicles:
            fail(f"the page's model holds {held} vehicles, not {vehicles}")
        page.wait_for_function(f"window.dtView.drawn && window.dtView.drawn.vehicles === {vehicles}"
                               f" && window.dtView.drawn.features === {features}", timeout=20000)
        drawn = page.evaluate("window.dtView.drawn")
        pixels = page.evaluate(COUNT_PIXELS)
        ground = page.evaluate(UNCOVERED)
        page.screenshot(path=os.path.join(run_dir, f"scale-{vehicles}-whole.png"))
        print(f"whole terrain: model {held} vehicles, drawn {drawn}, owner pixels {pixels}, "
              f"terrain uncovered {100 * ground['uncovered']:.1f} % of {ground['points']} points")
        # With more than 2000 features the canvas holds them too (their density picture covers
        # the ground at 10^5): the check is of the vehicles' drawing alone.
        if features <= 2000 and (ground["points"] < 10000 or ground["uncovered"] < UNCOVERED_MIN):
            fail(f"the vehicles' drawing leaves {100 * ground['uncovered']:.1f} % of the terrain "
                 f"uncovered ({ground['points']} points), not {100 * UNCOVERED_MIN:.0f} %")
        # Each mark (a marker, or a cell's square of at least 4 x 4 pixels) shows at least 4 pure
        # pixels of its owner's colour; every owner shows.
        if sum(pixels.values()) < 4 * drawn["marks"] or min(pixels.values()) == 0:
            fail(f"{drawn['marks']} marks drawn but the canvas holds {pixels} owner pixels")

        # Zoomed in until the vehicles in view are drawn one marker each.
        box = page.locator("#map").bounding_box()
        cx, cy = round(box["x"] + box["width"] / 2), round(box["y"] + box["height"] / 2)
        page.mouse.move(cx, cy)
        zoomed_in = 0  # wheel steps in, each undone on the way back to the whole terrain
        for _ in range(40):
            if page.evaluate("window.dtView.drawn.mode") == "markers":
                break
            page.mouse.wheel(0, -120)
            zoomed_in += 1
            page.wait_for_timeout(30)
        # The vehicles move: one may cross into view and turn the markers back into cells between
        # the zoom and the reads. The reads are one task of the page (no frame between them); if
        # it drew cells, zoom in one more step and read again.
        for _ in range(10):
            page.wait_for_function("window.dtView.drawn.mode === 'markers'", timeout=5000)
            read = page.evaluate(READ_MARKERS)
            if read["drawn"]["mode"] == "markers":
                break
            page.mouse.wheel(0, -120)
            zoomed_in += 1
        else:
            fail("the page went back to cells each of 10 times it was read zoomed in")
        in_view, drawn, pixels = read["in_view"], read["drawn"], read["pixels"]
        page.screenshot(path=os.path.join(run_dir, f"scale-{vehicles}-markers.png"))
        print(f"zoomed in: {in_view} vehicles in view, drawn {drawn}, owner pixels {pixels}")
        # The model takes messages between the last frame and the read: allow the few vehicles that
        # crossed the view's edge meanwhile.
        if in_view < 10 or abs(drawn["marks"] - in_view) > max(5, in_view // 20):
            fail(f"{in_view} vehicles in view, {drawn['marks']} markers drawn")
        live_marks = drawn["marks"] - drawn["dead"]
        if sum(pixels.values()) < 3 * live_marks:
            fail(f"{live_marks} live markers drawn but the canvas holds {pixels} owner pixels")

        # Back to the whole terrain (as many steps out as in, about the same point: the view as it
        # was), then 10 s of panning and zooming with a pause every fourth move, timed by the
        # page's own animation frames.
        page.mouse.move(cx, cy)
        for _ in range(zoomed_in):
            page.mouse.wheel(0, 120)
            page.wait_for_timeout(10)
        whole_view = page.evaluate("Object.assign({}, window.dtView.state.view)")
        page.evaluate("""() => { const d = window.dtView; d.maxLagMs = 0; d.frameMs = [];
            d.maxTransitMs = 0; d.maxQueuedMs = 0; performance.clearMeasures();
            d.longTasks = []; d.from = performance.now(); d.renders0 = featureCache.renders || 0;
            new PerformanceObserver((l) => { for (const e of l.getEntries())
              d.longTasks.push([e.startTime, e.duration]); }).observe({type: 'longtask'});
            d.wsBytes0 = d.wsBytes; d.wsAt0 = performance.now();
            d.cost = {messages: 0, applyMs: 0, draws: 0, drawMs: 0};
            d.lags = []; let last = performance.now();
            const rec = (t) => { d.frameMs.push(t - last); last = t; d.lags.push(d.lagMs);
                                 if (!d.stopRecording) requestAnimationFrame(rec); };
            requestAnimationFrame(rec); }""")
        feed = server.feeds["feed"]
        sent0, t0 = feed.sent_bytes, time.monotonic()
        feed.max_send_s = 0.0
        step = 0
        while time.monotonic() - t0 < pan_s:
            # A cycle of six moves that ends where it began, so the view stays over the terrain
            # however long the panning: zoomed about the map's centre (three steps in, three out)
            # and each drag undone by one at the same zoom (moves 1 and 5, 2 and 4) or, between
            # moves 0 and 3, by one as long in metres (three 1.2x steps in: 1.2^3 the pixels).
            pan_and_zoom(page, cx, cy, step)
            step += 1
            if step % 4 == 0:
                # The operator pauses (the view rests, so the features' cache is rendered again,
                # as when panning stops): part of what is timed, not a wait for the page.
                page.wait_for_timeout(400)
        rate = (feed.sent_bytes - sent0) / (time.monotonic() - t0)
        stats = page.evaluate("""() => { const d = window.dtView; d.stopRecording = true;
            const f = d.frameMs.slice(1), lags = d.lags.slice().sort((a, b) => a - b);
            const total = f.reduce((a, b) => a + b, 0);
            return {frames: f.length, fps: 1000 * f.length / total, worst: Math.max(...f),
                    lag_median: lags[Math.floor(lags.length / 2)], lag_max: d.maxLagMs,
                    mode: d.drawn.mode, cost: d.cost, ms: total,
                    ws_Bps: 1000 * (d.wsBytes - d.wsBytes0) / (performance.now() - d.wsAt0)}; }""")
        load = os.getloadavg()
        print(f"{vehicles} vehicles, {features} features, {pan_s:.0f} s of panning and zooming: "
              f"{stats['fps']:.1f} fps over {stats['frames']} frames, worst frame "
              f"{stats['worst']:.0f} ms, lag median {stats['lag_median']} ms max "
              f"{stats['lag_max']} ms, WebSocket {stats['ws_Bps'] / 1e6:.2f} MB/s received "
              f"({rate / 1e6:.2f} MB/s sent, {'JSON' if json_vehicles else 'binary'} vehicles), "
              f"load average "
              f"{load[0]:.2f} {load[1]:.2f} {load[2]:.2f}")
        c = stats["cost"]
        print(f"the page's time over {stats['ms'] / 1000:.1f} s: {c['messages']} messages applied "
              f"in {c['applyMs']:.0f} ms, {c['draws']} frames drawn in {c['drawMs']:.0f} ms")
        # Where the lag came from, by the page's own timeline: before its thread received the
        # message (the feed, the network, the browser) or waiting in it; its long tasks (over
        # 50 ms) and its own slow steps (performance measures dt:apply, dt:draw, dt:feature-cache).
        timing = page.evaluate("""() => { const d = window.dtView;
            const slow = performance.getEntriesByType('measure').filter((e) => e.startTime >= d.from)
              .sort((a, b) => b.duration - a.duration).slice(0, 5)
              .map((e) => `${e.name}${e.detail !== null ? ` (${e.detail})` : ''} ${e.duration.toFixed(0)} ms`);
            const long = d.longTasks.map((t) => t[1]).sort((a, b) => b - a);
            return {transit: d.maxTransitMs, queued: d.maxQueuedMs, long_tasks: long.length,
                    renders: (featureCache.renders || 0) - d.renders0, last: featureCache.lastRender,
                    longest: long.slice(0, 5).map(Math.round), slow}; }""")
        print(f"lag split: at most {timing['transit']} ms before the page's thread received a "
              f"message, at most {timing['queued']} ms queued in it; {timing['long_tasks']} long "
              f"tasks, longest {timing['longest']} ms; slowest steps {timing['slow']}; the feed's "
              f"longest send {1000 * feed.max_send_s:.0f} ms")
        if features > 2000:
            print(f"the features' cache rendered {timing['renders']} times, the last {timing['last']}")
        # The cycles complete, the view is where the panning began: the after picture shows the
        # terrain, its vehicles and features.
        while step % 6:
            pan_and_zoom(page, cx, cy, step)
            step += 1
        page.evaluate(SETTLE)
        after_view = page.evaluate("Object.assign({}, window.dtView.state.view)")
        if any(abs(after_view[k] - whole_view[k]) > 1e-6 * whole_view["w"] for k in "xywh"):
            fail(f"the view drifted while panning: {whole_view} before, {after_view} after")
        page.screenshot(path=os.path.join(run_dir, f"scale-{vehicles}-after.png"))

        # The 3D view over the whole terrain with every vehicle, while the deltas keep coming:
        # frames per second and lag printed, not asserted. In a browser of its own whose WebGL
        # runs on ANGLE's SwiftShader (the default software path blocks the page's thread; forced
        # for the 2D page, it slows that one's canvas instead).
        # A delta's vehicles_removed leaves the model (the feed's later moves of that slot are
        # skipped), and the page goes on drawing.
        gone = page.evaluate("""() => { const d = window.dtView, f = d.frames;
            applyMessage({type: 'delta', vehicles_removed: ['node-1/0', 'node-2/0']});
            return {size: d.state.vehicles.size, has: d.state.vehicles.has('node-1/0'), f}; }""")
        page.wait_for_function(f"window.dtView.frames > {gone['f'] + 2}", timeout=10000)
        if gone["size"] != vehicles - 2 or gone["has"] or page.evaluate(
                "window.dtView.state.vehicles.size") != vehicles - 2:
            fail(f"after two vehicles removed the model holds {gone}")
        page.close()  # its deltas would cost the 3D page's machine
        if page_errors:
            fail(f"errors in the page: {page_errors}")
        browser3d = pw.chromium.launch(executable_path=CHROMIUM, headless=True,
                                       args=["--no-sandbox", "--use-angle=swiftshader",
                                             "--enable-unsafe-swiftshader"])
        try:
            p3 = browser3d.new_page(viewport={"width": 1600, "height": 1000})
            p3.on("pageerror", lambda e: page_errors.append(str(e)))
            p3.goto(f"http://127.0.0.1:{PORT}/#3d=500,500,0.5,0.6,700")  # the whole terrain
            p3.wait_for_function(f"window.dtView3d.error || window.dtView3d.windows >= 1 && "
                                 f"window.dtView3d.drawn.vehicles === {vehicles}", timeout=60000)
            if p3.evaluate("window.dtView3d.error"):
                fail(f"the 3D view: {p3.evaluate('window.dtView3d.error')}")
            # The camera turns a little every animation frame (a redraw each), as the operator
            # turning it would; the frames drawn, the page's animation frames and its lag.
            p3.evaluate("""() => { const v = window.dtView3d; v.spinning = true; v.raf = 0;
              const spin = () => { v.cam.yaw += 0.002; ++v.raf;
                                   if (v.spinning) requestAnimationFrame(spin); };
              requestAnimationFrame(spin); window.dtView.maxLagMs = 0; }""")
            f0, t0 = p3.evaluate("window.dtView3d.frames"), time.monotonic()
            p3.wait_for_timeout(5000)
            r = p3.evaluate("""() => { const v = window.dtView3d; v.spinning = false;
              return {frames: v.frames, raf: v.raf, lag: window.dtView.maxLagMs, drawn: v.drawn}; }""")
            dt = time.monotonic() - t0
            d3 = r["drawn"]
            load = os.getloadavg()
            print(f"3D view, {d3['vehicles']} vehicles ({d3['whole']} whole shapes, "
                  f"{d3['shapes'] - d3['whole']} hulls, {d3['points']} points, {d3['thinned']} "
                  f"thinned) on {d3['posts']} posts, {d3['pixels']} pixels, the camera turning: "
                  f"{(r['frames'] - f0) / dt:.1f} fps, animation frames {r['raf'] / dt:.1f}/s, "
                  f"lag max {r['lag']} ms, load average {load[0]:.2f}")
            p3.screenshot(path=os.path.join(run_dir, f"scale-{vehicles}-3d.png"))
            # The instances drawn against the page's model, in one task: a picture drawn now,
            # the vehicles on the terrain window counted here from the vehicle table, and the
            # owners' colours among the picture's pixels (the points are drawn unlit).
            got = p3.evaluate(COUNT_3D)
            model, drawn3, cap = got["model"], got["drawn"], got["near_max"]
            print(f"3D view, one picture: model {model} vehicles on the window, drawn {drawn3}, "
                  f"owner pixels {got['pixels']}")
            if drawn3["vehicles"] != model:
                fail(f"{model} vehicles on the 3D window, the page placed {drawn3['vehicles']}")
            if drawn3["shapes"] + drawn3["points"] + drawn3["thinned"] != model:
                fail(f"shapes, points and thinned do not add up to the {model} vehicles: {drawn3}")
            if not 0.9 * min(cap, model) <= drawn3["shapes"] <= cap:
                fail(f"{drawn3['shapes']} shapes drawn, the nearest {min(cap, model)} expected")
            if model <= got["points_all"] and drawn3["thinned"]:
                fail(f"{drawn3['thinned']} thinned with only {model} vehicles")
            if min(got["pixels"].values()) < drawn3["points"] // 20:
                fail(f"{drawn3['points']} points drawn, owner pixels {got['pixels']}")
            if page_errors:
                fail(f"errors in the 3D page: {page_errors}")
        finally:
            browser3d.close()
    finally:
        browser.close()
        server.shutdown()
print("PASS")
