#!/usr/bin/env python3
"""Voxcast's page beside its web peers, niivue and vtk.js, in one headless chromium on this
machine (benches/web.sh runs it): the same volume file, canvas size and, where the peer allows,
the same sample distance, transfer function, shading and view (the VTK peer harness's files,
../shared/tools/peer/). Prints one table row per page and volume: the median frame time resting
and orbiting (5° a frame) and how much of the canvas the volume covers, and saves a screenshot
of each into OUT.

    python3 benches/peers/run.py [--dist dist] [--out benches/peers/out] [--frames 40]

Needs chromium and chromedriver (Debian: chromium chromium-driver) and npm (the peers are
fetched once from the npm registry at the versions pinned below, into benches/peers/lib/).
"""

import argparse
import base64
import http.server
import io
import json
import os
import re
import shutil
import socket
import subprocess
import sys
import tarfile
import tempfile
import threading
import time
import urllib.request

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SHARED = os.path.join(os.path.dirname(ROOT), "shared")
# The peers, pinned: the npm package, its version, and the one bundled file the page loads.
PEERS = {
    "niivue": ("@niivue/niivue", "0.69.0", "package/dist/niivue.umd.js", "niivue.umd.js"),
    "vtk": ("vtk.js", "37.3.1", "package/vtk.js", "vtk.js"),
}
VOLUMES = {
    "bunny": (os.path.join(ROOT, "assets/volumes/bunny_sdf.nrrd"), "bunny.json", "bunny_sdf.json"),
    "ct": (os.path.join(SHARED, "data/ct_cranium.nrrd"), "ct_skin_bone.json", "ct_cranium.json"),
}
CHROMIUM_ARGS = [
    "--headless=new", "--no-sandbox", "--disable-gpu-sandbox", "--enable-unsafe-swiftshader",
    "--use-angle=swiftshader", "--disable-background-networking", "--disable-component-update",
    "--disable-sync", "--disable-extensions", "--no-first-run", "--mute-audio",
]
WEBGPU_ARGS = ["--enable-unsafe-webgpu", "--enable-features=Vulkan", "--use-vulkan=swiftshader",
               "--use-webgpu-adapter=swiftshader"]


def fetch_peers():
    lib = os.path.join(HERE, "lib")
    os.makedirs(lib, exist_ok=True)
    for name, (package, version, inside, file) in PEERS.items():
        path = os.path.join(lib, file)
        stamp = path + ".version"
        if os.path.exists(path) and os.path.exists(stamp) and open(stamp).read() == version:
            continue
        with tempfile.TemporaryDirectory() as tmp:
            subprocess.run(["npm", "pack", "--silent", f"{package}@{version}", "--pack-destination", tmp],
                           check=True, stdout=subprocess.DEVNULL)
            (tarball,) = [f for f in os.listdir(tmp) if f.endswith(".tgz")]
            with tarfile.open(os.path.join(tmp, tarball)) as t:
                with t.extractfile(inside) as src, open(path, "wb") as dst:
                    shutil.copyfileobj(src, dst)
        open(stamp, "w").write(version)
        print(f"({name}: {package} {version} from the npm registry)", file=sys.stderr)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def serve(directory):
    handler = lambda *a, **k: http.server.SimpleHTTPRequestHandler(*a, directory=directory, **k)
    http.server.SimpleHTTPRequestHandler.log_message = lambda *a: None
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    return server.server_address[1]


class Browser:
    """chromedriver with one headless chromium session (WebDriver over HTTP)."""

    def __init__(self, extra, size):
        self.port = free_port()
        self.driver = subprocess.Popen(["chromedriver", f"--port={self.port}"],
                                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        self.profile = tempfile.mkdtemp()
        for _ in range(100):
            try:
                self.call("GET", "/status")
                break
            except OSError:
                time.sleep(0.1)
        args = CHROMIUM_ARGS + extra + [f"--window-size={size[0]},{size[1]}",
                                        f"--user-data-dir={self.profile}"]
        caps = {"capabilities": {"alwaysMatch": {"goog:chromeOptions": {
            "binary": "/usr/bin/chromium", "args": args}}}}
        self.session = self.call("POST", "/session", caps)["sessionId"]

    def call(self, method, path, body=None):
        data = json.dumps(body).encode() if body is not None else None
        req = urllib.request.Request(f"http://127.0.0.1:{self.port}{path}", data=data, method=method,
                                     headers={"Content-Type": "application/json"})
        with urllib.request.urlopen(req, timeout=600) as r:
            return json.loads(r.read())["value"]

    def s(self, method, path, body=None):
        return self.call(method, f"/session/{self.session}{path}", body)

    def open(self, url):
        self.s("POST", "/url", {"url": url})

    def run(self, script, *args):
        return self.s("POST", "/execute/sync", {"script": script, "args": list(args)})

    def viewport(self, w, h):
        # The window's outer size that gives a w×h page.
        inner = self.run("return [window.innerWidth, window.innerHeight]")
        rect = self.s("GET", "/window/rect")
        self.s("POST", "/window/rect", {"width": rect["width"] + w - inner[0],
                                        "height": rect["height"] + h - inner[1]})

    def wait(self, script, seconds):
        end = time.time() + seconds
        while time.time() < end:
            value = self.run(script)
            if value:
                return value
            time.sleep(0.5)
        raise TimeoutError(script)

    def screenshot(self, path):
        png = base64.b64decode(self.s("GET", "/screenshot"))
        open(path, "wb").write(png)
        return png

    def close(self):
        try:
            self.s("DELETE", "")
        finally:
            self.driver.terminate()
            shutil.rmtree(self.profile, ignore_errors=True)


def coverage(png, box):
    """The share of the box's pixels that are not the black background."""
    from PIL import Image
    image = Image.open(io.BytesIO(png)).convert("RGB").crop(box)
    pixels = list(image.get_flattened_data() if hasattr(image, "get_flattened_data") else image.getdata())
    return sum(1 for p in pixels if max(p) > 8) / len(pixels)


def ms(x):
    return f"{x:.0f} ms" if x >= 10 else f"{x:.1f} ms"


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--dist", default=os.path.join(ROOT, "dist"))
    parser.add_argument("--out", default=os.path.join(HERE, "out"))
    parser.add_argument("--frames", type=int, default=40)
    parser.add_argument("--size", default="896x669",
                        help="the peers' canvas: the page's scene in its 1280×720 window")
    parser.add_argument("--only", choices=["peers", "page"], help="measure only these")
    opts = parser.parse_args()
    w, h = map(int, opts.size.split("x"))
    os.makedirs(opts.out, exist_ok=True)
    fetch_peers()

    site = tempfile.mkdtemp()
    os.symlink(HERE, os.path.join(site, "peers"))
    os.symlink(os.path.abspath(opts.dist), os.path.join(site, "page"))
    for d in ("tf", "cams"):
        os.symlink(os.path.join(SHARED, "tools/peer", d), os.path.join(site, d))
    os.makedirs(os.path.join(site, "data"))
    volumes = {}
    for name, (path, tf, cam) in VOLUMES.items():
        if os.path.exists(path):
            os.symlink(path, os.path.join(site, "data", os.path.basename(path)))
            volumes[name] = (os.path.basename(path), tf, cam)
        else:
            print(f"({name}: {path} is missing here: left out)", file=sys.stderr)
    port = serve(site)
    base = f"http://127.0.0.1:{port}"

    print(f"| page | volume | drawn by | canvas | resting frame | orbiting frame | volume's share of the canvas |")
    print("| --- | --- | --- | --- | ---: | ---: | ---: |")
    # The peers: WebGL2 (both draw with it), SwiftShader here.
    notes = []
    def peers_browser():
        b = Browser([], (w + 100, h + 200))
        b.viewport(w, h)
        return b

    browser = peers_browser()
    try:
        if opts.only == "page":
            volumes = {}
        for name, (file, tf, cam) in volumes.items():
            for peer in PEERS:
                url = (f"{base}/peers/peer.html?peer={peer}&volume=../data/{file}&tf=../tf/{tf}"
                       f"&camera=../cams/{cam}&size={w}x{h}&frames={opts.frames}")
                try:
                    browser.open(url)
                    result = browser.wait("return window.peerResult", 600)
                except Exception as e:  # a peer that hangs or crashes the tab: its row says so
                    result = {"error": f"{type(e).__name__}: {e}"}
                    browser.close()
                    browser = peers_browser()
                if "error" in result:
                    print(f"| {peer} | {name} | – | – | failed: {result['error'].splitlines()[0]} | | |")
                    continue
                png = browser.screenshot(os.path.join(opts.out, f"{peer}_{name}.png"))
                share = coverage(png, (0, 0, w, h))
                print(f"| {PEERS[peer][0]} {PEERS[peer][1]} | {name} | WebGL2 | {w}×{h} | "
                      f"{ms(result['resting'])} | {ms(result['orbiting'])} | {100 * share:.0f} % |",
                      flush=True)
                notes.append(f"{peer}, {name}: {result['frames']} frames a median; step "
                             f"{result['step']}; transfer function {result['transfer']}; "
                             f"{result['renderer']}")
    finally:
        browser.close()

    # Voxcast's page: the bunny (its built-in), each build, as a visitor gets it and with the GPU
    # preview forced to whole frames; the page's own measurement (`?measure-frames`).
    for graphics in ("webgl2", "webgpu") if opts.only != "peers" else ():
        extra = WEBGPU_ARGS if graphics == "webgpu" else []
        # The third: forced as the second, at niivue's step (one voxel: its shader's `stepSize`)
        # and unshaded, as niivue draws by default — the same step as the faster peer.
        for forced, suffix, how in (
                ("", "", "as a visitor gets it"),
                ("&preview-backend=gpu&whole-frames", "_gpu", "GPU preview forced, whole frames"),
                ("&preview-backend=gpu&whole-frames&step=1&shading=off", "_gpu_niivue_step",
                 "GPU preview forced, whole frames, niivue's step (1 voxel), unshaded")):
            row = {}
            scene = None
            for label, orbit in (("resting", ""), ("orbiting", "&auto-orbit=5")):
                browser = Browser(extra, (1400, 900))
                try:
                    browser.viewport(1280, 720)
                    browser.open(f"{base}/page/?gpu={graphics}&no-rays&measure-frames={opts.frames}{orbit}{forced}")
                    text = browser.wait("const s = window.voxcastStatus && window.voxcastStatus(); "
                                        "return s && s.measured", 900)
                    status = browser.run("return window.voxcastStatus()")
                    m = re.search(r"median ([0-9.]+) ms", text)
                    row[label] = float(m.group(1)) if m else float("nan")
                    scene = status["scene"]
                    if label == "resting":
                        png = browser.screenshot(os.path.join(
                            opts.out, f"voxcast_{graphics}{suffix}_bunny.png"))
                        ratio = browser.run("return window.innerWidth") / status["canvas"][0]
                        box = tuple(round(v * ratio) for v in (scene[0], scene[1], scene[0] + scene[2], scene[1] + scene[3]))
                        row["share"] = coverage(png, box)
                        row["backend"] = status["backend"]
                finally:
                    browser.close()
            who = {"gpu": "GPU preview", "cpu": "CPU live view"}.get(row.get("backend"), row.get("backend"))
            print(f"| Voxcast {graphics} ({how}) | bunny | {who} | {scene[2]:.0f}×{scene[3]:.0f} | "
                  f"{ms(row['resting'])} | {ms(row['orbiting'])} | {100 * row['share']:.0f} % |", flush=True)
    print()
    for note in notes:
        print(f"- {note}")
    print(f"\n(screenshots in {opts.out})")


if __name__ == "__main__":
    main()
