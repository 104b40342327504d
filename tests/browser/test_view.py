"""capflow view RUN_DIR in a real browser (CTest label browser): a finished run's timeline renders
a saved surface at a chosen time; a run still going on is shown live and steered through its
control file. Usage: test_view.py CAPFLOW WORKDIR"""
import json
import os
import shutil
import subprocess
import sys
import time

from selenium.webdriver.common.by import By

from console_run import Console, browser, sha256, shown_image_hash

BASE = {
    "capsule": {"law": "skalak", "C": 1},
    "mesh": {"elements": 6, "nb": 8},
    "flow": {"type": "planar-extension"},
    "time": {"dt": "auto", "t_end": 1.0},
    "ca": 0.4,
    "output": {"dir": "done", "csv_every": 0.05, "vtk_every": 0.25},
}


def finished_run(capflow, work):
    with open(os.path.join(work, "done.json"), "w") as f:
        json.dump(BASE, f)
    subprocess.run([capflow, "run", "done.json"], cwd=work, check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    c = Console([capflow, "view", "done", "--serve", "0"], cwd=work)
    b = None
    try:
        s = c.get_json("/api/state")
        assert s["state"] == "finished" and not s["live"] and abs(s["t"] - 1.0) < 1e-9, s
        times = c.get_json("/api/surfaces")["times"]
        assert times == [0, 0.25, 0.5, 0.75, 1], times
        b = browser()
        b.get(c.url)
        c.wait(lambda: b.find_element(By.ID, "badge").text == "finished", "finished")
        c.wait(lambda: b.find_element(By.ID, "timeline").get_attribute("max") == "4", "the timeline")
        c.wait(lambda: int(b.find_element(By.ID, "chart").get_attribute("data-rows") or 0) >= 20,
               "the recorded rows")
        # Scrub to t = 0.5: the page draws that saved surface, as /api/frame does.
        b.execute_script("""const tl = document.getElementById('timeline');
                            tl.value = 2; tl.dispatchEvent(new Event('input'));""")
        c.wait(lambda: "time=0.5" in (b.find_element(By.ID, "view").get_attribute("data-url") or ""),
               "a frame of t = 0.5")
        time.sleep(0.5)
        url = b.find_element(By.ID, "view").get_attribute("data-url")
        status, at_half = c.request("/" + url)
        assert status == 200
        assert sha256(at_half) == shown_image_hash(b), "the page's t = 0.5 differs from /api/frame's"
        status, at_end = c.request("/" + url.replace("time=0.5", "time=1"))
        assert status == 200 and sha256(at_end) != sha256(at_half), "t = 1 looks like t = 0.5"
        # An ended run takes no edits.
        rev = c.get_json("/api/state")["revision"]
        status, body = c.request("/api/control", "POST", {"revision": rev, "patch": {"ca": 0.5}})
        assert status == 422 and b"ended" in body, (status, body)
    finally:
        if b:
            b.quit()
        c.proc.terminate()
        c.finish()


def live_run(capflow, work):
    control = dict(BASE, time={"dt": "auto", "t_end": 500}, output={"dir": "live", "csv_every": 0.05})
    path = os.path.join(work, "live.json")
    with open(path, "w") as f:
        json.dump(control, f)
    run = subprocess.Popen([capflow, "run", "live.json"], cwd=work, stdout=subprocess.DEVNULL,
                           stderr=subprocess.DEVNULL)
    c = None
    try:
        deadline = time.time() + 30
        while not os.path.exists(os.path.join(work, "live", "events.jsonl")):
            assert time.time() < deadline, "the run did not start"
            time.sleep(0.1)
        c = Console([capflow, "view", "live", "--serve", "0"], cwd=work)
        s0 = c.wait(lambda: (lambda s: s if s["t"] > 0 else None)(c.get_json("/api/state")), "rows")
        assert s0["live"] and s0["state"] == "running", s0
        c.wait(lambda: c.get_json("/api/state")["t"] > s0["t"], "t growing")
        # Steered through the run's own control file.
        rev = c.get_json("/api/state")["revision"]
        status, body = c.request("/api/control", "POST",
                                 {"revision": rev, "patch": {"run": {"state": "paused"}}})
        assert status == 200, (status, body)
        assert json.load(open(path))["run"]["state"] == "paused"
        c.wait(lambda: c.get_json("/api/state")["state"] == "paused", "paused (its event)")
        rev = c.get_json("/api/state")["revision"]
        status, body = c.request("/api/control", "POST",
                                 {"revision": rev, "patch": {"run": {"state": "stopped"}}})
        assert status == 200, (status, body)
        assert run.wait(timeout=60) == 0
        c.wait(lambda: c.get_json("/api/state")["state"] == "stopped", "stopped")
    finally:
        if run.poll() is None:
            run.kill()
        if c:
            c.proc.terminate()
            c.finish()


def main():
    capflow, work = os.path.abspath(sys.argv[1]), sys.argv[2]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    finished_run(capflow, work)
    live_run(capflow, work)
    print("view browser test: ok")


if __name__ == "__main__":
    main()
