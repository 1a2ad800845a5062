#!/usr/bin/env python3
"""Save-to-model latency of `blocksmith watch`: for each recipe, saves it 10 times and measures
the time from the write to the server having the new model ready for the page (its /api/state
shows the next version), beside the recipe's own run time. The page's fetch and draw of the .glb
come on top (not measured here).

    cargo build --release --bin blocksmith
    python3 docs/studio_latency.py target/release/blocksmith examples/csg_fig13_die.rhai examples/blocks_fig5_hand.rhai
"""
import json, shutil, statistics, subprocess, sys, tempfile, time, urllib.request
from pathlib import Path

def state(addr):
    with urllib.request.urlopen(f"http://{addr}/api/state") as r:
        return json.load(r)

def measure(binary, recipe, saves=10):
    with tempfile.TemporaryDirectory() as d:
        for helper in Path(recipe).parent.glob("_*.rhai"):
            shutil.copy(helper, d)
        target = Path(d) / Path(recipe).name
        shutil.copy(recipe, target)
        proc = subprocess.Popen([binary, "watch", str(target)], stderr=subprocess.PIPE, text=True)
        try:
            addr = proc.stderr.readline().split("http://")[1].split("/")[0]
            while not (state(addr)["model"]):
                time.sleep(0.01)
            latencies, runs = [], []
            text = target.read_text()
            for i in range(saves):
                before = state(addr)["model"]["version"]
                start = time.perf_counter()
                target.write_text(text + f"\n// save {i}\n")
                while True:
                    s = state(addr)
                    if s["model"]["version"] > before:
                        break
                    time.sleep(0.002)
                latencies.append((time.perf_counter() - start) * 1000)
                runs.append(s["model"]["run_ms"])
                time.sleep(0.2)
        finally:
            proc.kill()
    lat, run = statistics.median(latencies), statistics.median(runs)
    print(f"{Path(recipe).name}: save to model ready {lat:.0f} ms median, of which the run {run:.0f} ms; overhead {lat - run:.0f} ms")

if __name__ == "__main__":
    for recipe in sys.argv[2:]:
        measure(sys.argv[1], recipe)
