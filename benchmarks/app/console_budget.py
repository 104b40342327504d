#!/usr/bin/env python3
"""The live console's cost and speed (docs/performance.md, "The live console").

Runs benchmarks/app/console_run.json (Skalak Ca=0.45, NE=6, NB=9, 1200 fixed steps, no frames)
ROUNDS times in each of three ways, alternately: without --serve; with --serve and no client; with
--serve and one client that asks what the page asks at its default cadence (state and rows every
250 ms, events every 500 ms, a 1280x720 JPEG of the newest state whenever the last one has arrived
and 250 ms have passed). Prints the median wall times and the per-round ratios to the run without
--serve. During the watched runs it also times how long a new timeseries.csv row takes to reach
the client (from the moment the row is in the file, watched every 2 ms, to the client's answer).
Then it pauses a run and turns the camera as a drag does (one request in flight, yaw + 3 degrees
each), 1280x720: images per second and request-to-image times.
The client here stands in for a browser on another machine (the usual case, through ssh -L); a
browser on the compute node itself would add its own CPU.
Usage: benchmarks/app/console_budget.py [BUILD_DIR] [ROUNDS]   (defaults: build, 5)"""
import json
import os
import re
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
CONTROL = os.path.join(ROOT, "benchmarks", "app", "console_run.json")


def start(exe, out, serve, extra_control=None):
    control = CONTROL
    if extra_control:
        c = json.load(open(CONTROL))
        c.update(extra_control)
        control = os.path.join(out, "control.json")
        json.dump(c, open(control, "w"))
    args = [exe, "run", control, "-o", os.path.join(out, "run")]
    if serve:
        args += ["--serve", "0"]
    err = open(os.path.join(out, "stderr"), "w")
    t0 = time.monotonic()
    p = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=err)
    url = None
    while serve and url is None and p.poll() is None:
        m = re.search(r"console at (http://\S+)", open(os.path.join(out, "stderr")).read())
        url = m.group(1) if m else None
        time.sleep(0.002)
    return p, t0, url


class Client:
    """What the page asks for, at its cadence."""

    def __init__(self, url, rows_path):
        self.base, self.token = url.split("/?token=")
        self.rows_path = rows_path
        self.stop = False
        self.frames = 0
        self.row_seen = {}      # row index -> monotonic time the row was in the file
        self.row_received = {}  # row index -> monotonic time the client had it
        self.last_t = None
        self.rows = 0

    def get(self, path):
        req = urllib.request.Request(self.base + path, headers={"Authorization": "Bearer " + self.token})
        with urllib.request.urlopen(req, timeout=30) as r:
            return r.read()

    def watch_file(self):
        n = 0
        while not self.stop:
            try:
                with open(self.rows_path) as f:
                    lines = f.read().count("\n")
            except OSError:
                lines = 0
            now = time.monotonic()
            for i in range(n, max(n, lines - 1)):  # rows without the header
                self.row_seen.setdefault(i, now)
            n = max(n, lines - 1)
            time.sleep(0.002)

    def poll(self):
        last_frame = last_events = 0.0
        next_event = 0
        while not self.stop:
            t = time.monotonic()
            try:
                self.get("/api/state")
                rows = json.loads(self.get("/api/timeseries" + ("" if self.last_t is None else f"?since={self.last_t}")))["rows"]
                now = time.monotonic()
                for r in rows:
                    self.row_received[self.rows] = now
                    self.rows += 1
                if rows:
                    self.last_t = rows[-1][0]
                if t - last_events >= 0.5:
                    next_event = json.loads(self.get(f"/api/events?since={next_event}"))["next"]
                    last_events = t
                if t - last_frame >= 0.25:
                    self.get("/api/frame?width=1280&height=720")
                    self.frames += 1
                    last_frame = t
            except Exception:
                pass
            time.sleep(max(0.0, 0.25 - (time.monotonic() - t)))


def budget(exe, rounds):
    walls = {"plain": [], "serve": [], "watch": []}
    cpus = {"plain": [], "serve": [], "watch": []}
    latencies, frames = [], []
    for r in range(rounds):
        for mode in ("plain", "serve", "watch"):
            out = tempfile.mkdtemp(prefix="capflow_console_")
            ru = resource.getrusage(resource.RUSAGE_CHILDREN)
            p, t0, url = start(exe, out, mode != "plain")
            client = None
            threads = []
            if mode == "watch":
                client = Client(url, os.path.join(out, "run", "timeseries.csv"))
                threads = [threading.Thread(target=client.watch_file), threading.Thread(target=client.poll)]
                for th in threads:
                    th.start()
            p.wait()
            walls[mode].append(time.monotonic() - t0)
            ru2 = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpus[mode].append(ru2.ru_utime + ru2.ru_stime - ru.ru_utime - ru.ru_stime)
            if client:
                client.stop = True
                for th in threads:
                    th.join()
                frames.append(client.frames)
                latencies += [client.row_received[i] - client.row_seen[i]
                              for i in client.row_received if i in client.row_seen]
            shutil.rmtree(out)
        print(f"round {r + 1}: " + ", ".join(f"{m} {walls[m][-1]:.2f} s" for m in walls), flush=True)
    med = {m: statistics.median(v) for m, v in walls.items()}
    cmed = {m: statistics.median(v) for m, v in cpus.items()}
    print("\n| run | wall s (median) | wall / without --serve (median of rounds) | per round | "
          "CPU s (median) | CPU / without --serve |")
    print("|---|---|---|---|---|---|")
    print(f"| without --serve | {med['plain']:.2f} | 1 | | {cmed['plain']:.2f} | 1 |")
    for m, name in (("serve", "--serve, no client"), ("watch", "--serve, one client at the page's cadence")):
        ratios = [a / b for a, b in zip(walls[m], walls["plain"])]
        cratios = [a / b for a, b in zip(cpus[m], cpus["plain"])]
        print(f"| {name} | {med[m]:.2f} | **{statistics.median(ratios):.3f}** | "
              f"{' '.join(f'{x:.2f}' for x in ratios)} | {cmed[m]:.2f} | "
              f"{statistics.median(cratios):.3f} |")
    latencies.sort()
    print(f"\nframes drawn per watched run: {' '.join(map(str, frames))}")
    print(f"a row's time from the file to the client: median {1000 * statistics.median(latencies):.0f} ms, "
          f"95th percentile {1000 * latencies[int(0.95 * (len(latencies) - 1))]:.0f} ms, "
          f"max {1000 * latencies[-1]:.0f} ms ({len(latencies)} rows)")


def drags(exe, n=120):
    out = tempfile.mkdtemp(prefix="capflow_console_")
    p, _, url = start(exe, out, True, {"time": {"dt": 0.004, "t_end": 400}})
    c = Client(url, "")
    time.sleep(1.0)
    state = json.loads(c.get("/api/state"))
    body = json.dumps({"revision": state["revision"], "patch": {"run": {"state": "paused"}}}).encode()
    req = urllib.request.Request(c.base + "/api/control", data=body, method="POST",
                                 headers={"Authorization": "Bearer " + c.token})
    urllib.request.urlopen(req).read()
    while json.loads(c.get("/api/state"))["state"] != "paused":
        time.sleep(0.05)
    c.get("/api/frame?width=1280&height=720")  # the renderer's set-up
    times = []
    t0 = time.monotonic()
    for i in range(n):
        a = time.monotonic()
        c.get(f"/api/frame?width=1280&height=720&yaw={36 + 3 * i}&pitch=30")
        times.append(time.monotonic() - a)
    total = time.monotonic() - t0
    p.terminate()
    p.wait()
    shutil.rmtree(out)
    times.sort()
    print(f"\npaused, a drag at 1280x720 ({n} images, one in flight): {n / total:.1f} images/s; "
          f"request to image median {1000 * statistics.median(times):.1f} ms, "
          f"95th percentile {1000 * times[int(0.95 * (n - 1))]:.1f} ms, max {1000 * times[-1]:.1f} ms")


def main():
    build = sys.argv[1] if len(sys.argv) > 1 else "build"
    rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 5
    exe = os.path.abspath(os.path.join(build, "src", "app", "capflow"))
    budget(exe, rounds)
    drags(exe)


if __name__ == "__main__":
    main()
