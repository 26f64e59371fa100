"""Render image on the page, timed: one headless chromium (SwiftShader) opens the built page,
clicks Render image N times on the resting view and prints, for each, what the page says (the
render's own work in its slices, and the clock from the click to the comparison shown), the
frames drawn meanwhile and the page's long tasks (over 50 ms) in that time.

    python3 benches/peers/render_clock.py DIST webgl2|webgpu [QUERY] [N]

DIST is a page built by web/build.sh (dist/); QUERY is added to the address (e.g.
"&preview-backend=gpu"). BENCHMARKS.md, "Render image on the clock".
"""
import sys
import time

import run


def click(b, name):
    k = b.run("const r = document.getElementById('voxcast-canvas').getBoundingClientRect(); "
              "return [r.left, r.top, r.width, window.voxcastStatus().canvas[0]]")
    status = b.run("return window.voxcastStatus()")
    t = [t[1] for t in status["targets"] if t[0] == name][0]
    scale = k[2] / k[3]
    x, y = k[0] + (t[0] + t[2] / 2) * scale, k[1] + (t[1] + t[3] / 2) * scale
    actions = [{"type": "pointerMove", "duration": 0, "origin": "viewport", "x": round(x), "y": round(y)},
               {"type": "pointerDown", "button": 0}, {"type": "pause", "duration": 50},
               {"type": "pointerUp", "button": 0}]
    b.s("POST", "/actions", {"actions": [{"type": "pointer", "id": "mouse",
                                          "parameters": {"pointerType": "mouse"}, "actions": actions}]})
    b.s("DELETE", "/actions")


def main():
    dist, graphics = sys.argv[1], sys.argv[2]
    query = sys.argv[3] if len(sys.argv) > 3 else ""
    n = int(sys.argv[4]) if len(sys.argv) > 4 else 8
    port = run.serve(dist)
    b = run.Browser(run.WEBGPU_ARGS if graphics == "webgpu" else [], (1280, 850))
    try:
        b.open(f"http://127.0.0.1:{port}/?gpu={graphics}{query}")
        b.wait("try { return window.voxcastStatus().frames > 30 } catch (e) { return false }", 120)
        b.run("window.__lt = []; new PerformanceObserver((l) => { for (const e of l.getEntries()) "
              "window.__lt.push(Math.round(e.duration)); }).observe({entryTypes: ['longtask']});")
        for i in range(n):
            for _ in range(3):  # clicked again where a click was lost
                click(b, "render image")
                try:
                    b.wait("return window.voxcastStatus().render === 'rendering'", 5)
                    break
                except TimeoutError:
                    pass
            b.run("window.__lt.length = 0")
            frames = b.run("return window.voxcastStatus().frames")
            said = b.wait("const s = window.voxcastStatus(); "
                          "return s.render.startsWith('done') && s.render", 300)
            frames = b.run("return window.voxcastStatus().frames") - frames
            long_tasks = b.run("return window.__lt")
            print(f"{graphics}{query} {i}: {said}; {frames} frames meanwhile; long tasks (ms): "
                  f"{long_tasks}", flush=True)
            time.sleep(0.5)
        scene = b.run("return window.voxcastStatus().scene")
        print(f"the scene: {scene[2]:.0f}×{scene[3]:.0f}")
    finally:
        b.close()


if __name__ == "__main__":
    main()
