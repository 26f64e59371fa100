"""The page's first frame on its own clock: N times, a new headless chromium (SwiftShader, an
empty profile) opens the built page from 127.0.0.1 — a first visit — and then reloads it (the
module's compiled code cached by the browser); for each load it prints the milliseconds from
navigation to the module downloaded, to it compiled and instantiated, and to the sandbox's
second frame (the first one drawn with its panels laid out), read with `performance.now()` by
a script chromium runs before the page's own; then the medians.

    python3 benches/peers/first_frame.py DIST webgl2|webgpu [N]

DIST is a page built by web/build.sh (dist/). BENCHMARKS.md, "In a browser" (issue 55's goal:
the first frame within 1.5 s).
"""
import statistics
import sys

import run

# Before the page's scripts: WebAssembly's instantiation timed, and the frames polled on every
# animation frame until the second.
MARKS = """
window.__vx = {};
for (const name of ['instantiate', 'instantiateStreaming']) {
  const original = WebAssembly[name];
  WebAssembly[name] = async function (...args) {
    const result = await original.apply(WebAssembly, args);
    window.__vx.instantiated ??= performance.now();
    return result;
  };
}
const poll = () => {
  try {
    if (window.voxcastStatus().frames >= 2) {
      window.__vx.second_frame = performance.now();
      return;
    }
  } catch (_) { /* not started yet */ }
  requestAnimationFrame(poll);
};
requestAnimationFrame(poll);
"""

READ = """
const wasm = performance.getEntriesByType('resource').find((e) => e.name.endsWith('.wasm'));
return window.__vx.second_frame && [wasm ? wasm.responseEnd : null, window.__vx.instantiated,
  window.__vx.second_frame];
"""


def load(b, url):
    """One load of the page: its three marks (ms after navigation)."""
    b.open("about:blank")
    b.open(url)
    return b.wait(READ, 120)


def main():
    dist, graphics = sys.argv[1], sys.argv[2]
    n = int(sys.argv[3]) if len(sys.argv) > 3 else 5
    port = run.serve(dist)
    url = f"http://127.0.0.1:{port}/?gpu={graphics}"
    visits = {"first visit": [], "reload": []}
    for i in range(n):
        b = run.Browser(run.WEBGPU_ARGS if graphics == "webgpu" else [], (1280, 850))
        try:
            b.s("POST", "/goog/cdp/execute",
                {"cmd": "Page.addScriptToEvaluateOnNewDocument", "params": {"source": MARKS}})
            for kind, rows in visits.items():
                marks = load(b, url)
                rows.append(marks)
                print(f"{graphics} {kind} {i + 1}: module downloaded at {run.ms(marks[0])}, "
                      f"compiled and instantiated at {run.ms(marks[1])}, second frame at "
                      f"{run.ms(marks[2])}", flush=True)
        finally:
            b.close()
    for kind, rows in visits.items():
        m = [statistics.median(r[k] for r in rows) for k in range(3)]
        print(f"{graphics}, {kind}, the median of {n}: module downloaded at {run.ms(m[0])}, "
              f"instantiated at {run.ms(m[1])}, second frame at {run.ms(m[2])} (goal: 1500 ms)")


if __name__ == "__main__":
    main()
