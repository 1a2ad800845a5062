#!/usr/bin/env python3
"""Save-to-screen latency of `blocksmith watch`, measured in a real browser.

For each recipe: `blocksmith watch` runs it, headless chromium shows the page, and the recipe is
saved 10 times. Each latency runs from the write to the page having drawn the new model (the
page's `studio.shown.at`, taken two animation frames after the model is in the scene; the
browser and this script read the same clock). Printed beside the recipe's own run time (the
server's `run_ms`), so the overhead is what the studio adds, and split where the page tells
(`studio.shown.received`, `.loaded`): the server's part (the debounce, the .glb and facts, the
WebSocket message) beyond the run, the page's fetch and parse of the layers, and its draw.

`--big` adds a 1.3M-triangle model (`icosphere(1, 8)`): its save-to-screen latency, and the
time a freshly opened page takes from navigation start to the model drawn (server send + page
load), with the size of its .glb.

    cargo build --release --workspace --bin blocksmith
    python3 docs/studio_latency.py target/release/blocksmith examples/csg_fig13_die.rhai \\
        examples/blocks_fig5_hand.rhai --big

Needs chromium (Debian's `chromium`) and nothing beyond Python's standard library: the DevTools
protocol is spoken over a small WebSocket client below.
"""
import base64, json, os, shutil, socket, statistics, struct, subprocess, sys, tempfile, time, urllib.request
from pathlib import Path

SAVES = 10


class WebSocket:
    """A client WebSocket for text messages (RFC 6455): enough for the DevTools protocol."""

    def __init__(self, url):
        hostport, path = url.removeprefix("ws://").split("/", 1)
        host, port = hostport.split(":")
        self.sock = socket.create_connection((host, int(port)))
        key = base64.b64encode(os.urandom(16)).decode()
        self.sock.sendall((f"GET /{path} HTTP/1.1\r\nHost: {hostport}\r\nUpgrade: websocket\r\n"
                           f"Connection: Upgrade\r\nSec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\n\r\n").encode())
        head = b""
        while b"\r\n\r\n" not in head:
            head += self.sock.recv(1)
        if b" 101 " not in head.split(b"\r\n")[0]:
            raise RuntimeError(f"no WebSocket upgrade: {head!r}")
        self.buf = b""

    def send(self, text):
        data, mask = text.encode(), os.urandom(4)
        n = len(data)
        head = bytes([0x81]) + (bytes([0x80 | n]) if n < 126 else
                                bytes([0x80 | 126]) + struct.pack(">H", n) if n < 65536 else
                                bytes([0x80 | 127]) + struct.pack(">Q", n))
        self.sock.sendall(head + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(data)))

    def _take(self, n):
        while len(self.buf) < n:
            chunk = self.sock.recv(1 << 16)
            if not chunk:
                raise EOFError("the browser closed the connection")
            self.buf += chunk
        out, self.buf = self.buf[:n], self.buf[n:]
        return out

    def recv(self):
        message = b""
        while True:
            b0, b1 = self._take(2)
            n = b1 & 0x7F
            if n == 126:
                n = struct.unpack(">H", self._take(2))[0]
            elif n == 127:
                n = struct.unpack(">Q", self._take(8))[0]
            mask = self._take(4) if b1 & 0x80 else None
            payload = self._take(n)
            if mask:
                payload = bytes(b ^ mask[i % 4] for i, b in enumerate(payload))
            op = b0 & 0x0F
            if op == 8:
                raise EOFError("closed")
            if op in (0, 1, 2):
                message += payload
                if b0 & 0x80:
                    return message.decode()


class Browser:
    """Headless chromium on `url`, its page attached as a flat DevTools session."""

    def __init__(self, url):
        self.profile = tempfile.TemporaryDirectory()
        self.proc = subprocess.Popen(
            ["chromium", "--headless", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
             "--window-size=800,600", "--remote-debugging-port=0", "--no-first-run",
             f"--user-data-dir={self.profile.name}", url],
            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        for line in self.proc.stderr:
            if "DevTools listening on " in line:
                ws = line.split("DevTools listening on ")[1].strip()
                break
        self.ws, self.next, self.session = WebSocket(ws), 0, None
        while True:
            pages = [t for t in self.call("Target.getTargets")["targetInfos"] if t["type"] == "page"]
            if pages:
                break
            time.sleep(0.05)
        self.session = self.call("Target.attachToTarget", {"targetId": pages[0]["targetId"], "flatten": True})["sessionId"]

    def call(self, method, params=None):
        self.next += 1
        message = {"id": self.next, "method": method, "params": params or {}}
        if self.session:
            message["sessionId"] = self.session
        self.ws.send(json.dumps(message))
        while True:
            reply = json.loads(self.ws.recv())
            if reply.get("id") == self.next:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply["result"]

    def eval(self, expression):
        r = self.call("Runtime.evaluate", {"expression": expression, "returnByValue": True, "awaitPromise": True})
        return r["result"].get("value")

    def wait(self, expression, limit=120):
        start = time.monotonic()
        while True:
            v = self.eval(expression)
            if v:
                return v
            if time.monotonic() - start > limit:
                raise TimeoutError(expression)
            time.sleep(0.002)

    def close(self):
        self.proc.kill()
        self.proc.wait()
        self.profile.cleanup()


# The studio's token for each address (it answers nothing of the model without it).
TOKENS = {}


def get(addr, path):
    request = urllib.request.Request(f"http://{addr}{path}", headers={"X-Blocksmith-Token": TOKENS[addr]})
    return urllib.request.urlopen(request)


def state(addr):
    with get(addr, "/api/state") as r:
        return json.load(r)


def watch(binary, target):
    proc = subprocess.Popen([binary, "watch", str(target)], stderr=subprocess.PIPE, text=True)
    url = proc.stderr.readline().split("http://")[1].split()[0]
    addr, token = url.split("/?token=")
    TOKENS[addr] = token
    while not state(addr)["model"]:
        time.sleep(0.01)
    return proc, addr


def shown_after(browser, version):
    return browser.wait(f"window.studio && studio.shown && studio.shown.version > {version} && studio.shown")


def measure(binary, recipe, text=None, fresh_page=False):
    with tempfile.TemporaryDirectory() as d:
        name = Path(recipe).name
        if text is None:
            for helper in Path(recipe).parent.glob("_*.rhai"):
                shutil.copy(helper, d)
            text = Path(recipe).read_text()
        target = Path(d) / name
        target.write_text(text)
        proc, addr = watch(binary, target)
        browser = Browser(f"http://{addr}/?token={TOKENS[addr]}")
        try:
            first = shown_after(browser, 0)
            triangles = browser.eval("studio.triangles")
            if fresh_page:
                glb = state(addr)["model"]["layers"][0]["url"]
                with get(addr, glb) as r:
                    size = len(r.read())
                loads, steps = [], []
                for _ in range(3):
                    browser.call("Page.reload", {"ignoreCache": True})
                    time.sleep(0.05)
                    shown = shown_after(browser, 0)
                    loads.append(shown["sincePageStart"])
                    if "received" in shown:
                        origin = shown["at"] - shown["sincePageStart"]
                        steps.append((shown["received"] - origin, shown["loaded"] - origin))
                print(f"{name}: {triangles} triangles, .glb {size / 1e6:.1f} MB; a fresh page draws it "
                      f"{statistics.median(loads):.0f} ms after navigation start (median of 3; first page {first['sincePageStart']:.0f} ms)")
                if steps:
                    print(f"{name}:   medians: the model's message arrives at {statistics.median(s[0] for s in steps):.0f} ms, "
                          f"its layers are loaded at {statistics.median(s[1] for s in steps):.0f} ms")
            latencies, runs, parts = [], [], []
            for i in range(SAVES):
                before = browser.eval("studio.shown.version")
                start = time.time() * 1000
                target.write_text(text + f"\n// save {i}\n")
                shown = shown_after(browser, before)
                latencies.append(shown["at"] - start)
                run = state(addr)["model"]["run_ms"]
                runs.append(run)
                if "received" in shown:
                    parts.append((shown["received"] - start - run, shown["loaded"] - shown["started"],
                                  shown["at"] - shown["loaded"]))
                time.sleep(0.2)
        finally:
            browser.close()
            proc.kill()
    lat, run = statistics.median(latencies), statistics.median(runs)
    print(f"{name}: save to screen {lat:.0f} ms median (min {min(latencies):.0f}, max {max(latencies):.0f}), "
          f"of which the run {run:.0f} ms; the studio adds {lat - run:.0f} ms")
    if parts:
        server, load, draw = (statistics.median(p[k] for p in parts) for k in range(3))
        print(f"{name}:   medians: server beyond the run {server:.0f} ms (debounce, .glb, facts, message), "
              f"page fetch and parse {load:.0f} ms, draw {draw:.0f} ms")


if __name__ == "__main__":
    args = sys.argv[1:]
    big = "--big" in args
    args = [a for a in args if a != "--big"]
    for recipe in args[1:]:
        measure(args[0], recipe)
    if big:
        measure(args[0], "big.rhai", text="icosphere(1, 8)", fresh_page=True)
