"""Where the page's CPU goes, by thread: one headless chromium (SwiftShader) opens the built
page, waits, and reads every chromium thread's CPU time from /proc over ten seconds; it prints
the frames drawn in that time and each busy thread's CPU milliseconds per frame. SwiftShader's
rasterizer threads are named Thread<00>, Thread<01>…; the page's own thread (its WebAssembly)
is one of the threads named chromium. Linux only.

    python3 benches/peers/threads.py DIST webgl2|webgpu [QUERY] [WIDTHxHEIGHT]

DIST is a page built by web/build.sh (dist/); QUERY is added to the address: nothing for the
page at rest (it is read 8 s after it opened), "&no-rays&measure-frames=100000&auto-orbit=5"
for every frame drawn while the camera turns. BENCHMARKS.md, "The page at rest".
"""
import collections
import os
import sys
import time

import run


def threads():
    """(pid, tid) → (thread name, CPU ticks) for every thread of every chromium process."""
    out = {}
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            command = open(f"/proc/{pid}/cmdline", "rb").read().split(b"\0")
            tids = os.listdir(f"/proc/{pid}/task")
        except OSError:
            continue
        if not command or b"chromium" not in command[0]:
            continue
        for tid in tids:
            try:
                stat = open(f"/proc/{pid}/task/{tid}/stat").read()
            except OSError:
                continue
            name = stat[stat.index("(") + 1:stat.rindex(")")]
            fields = stat[stat.rindex(")") + 2:].split()
            out[(pid, tid)] = (name, int(fields[11]) + int(fields[12]))
    return out


def main():
    dist, graphics = sys.argv[1], sys.argv[2]
    query = sys.argv[3] if len(sys.argv) > 3 else ""
    size = tuple(int(v) for v in (sys.argv[4] if len(sys.argv) > 4 else "1280x850").split("x"))
    port = run.serve(dist)
    b = run.Browser(run.WEBGPU_ARGS if graphics == "webgpu" else [], size)
    try:
        b.open(f"http://127.0.0.1:{port}/?gpu={graphics}{query}")
        b.wait("try { return window.voxcastStatus().frames > 30 } catch (e) { return false }", 120)
        time.sleep(8)
        frames, before, start = b.run("return window.voxcastStatus().frames"), threads(), time.time()
        time.sleep(10)
        frames = b.run("return window.voxcastStatus().frames") - frames
        after, seconds = threads(), time.time() - start
        resting = b.run("return window.voxcastStatus().resting")
    finally:
        b.close()
    busy = collections.Counter()
    for key, (name, ticks) in after.items():
        if key in before:
            busy[name] += ticks - before[key][1]
    hz = os.sysconf("SC_CLK_TCK")
    total = sum(busy.values()) / hz
    print(f"{graphics}{query} at {size[0]}×{size[1]}: {frames} frames in {seconds:.1f} s "
          f"({'at rest' if resting else 'awake'}); chromium's CPU {total / seconds:.2f} cores; "
          "CPU ms per frame by thread:")
    for name, ticks in busy.most_common(8):
        if ticks:
            print(f"  {name:24s} {ticks * 1000 / hz / max(frames, 1):7.1f}")


if __name__ == "__main__":
    main()
