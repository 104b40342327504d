"""The live console in a real browser (CTest label browser): capflow run --serve against headless
Chromium. Usage: test_console.py CAPFLOW WORKDIR"""
import json
import os
import shutil
import sys
import time

from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import Select

from console_run import Console, browser, sha256, shown_image_hash

CONTROL = {
    "capsule": {"law": "skalak", "C": 1},
    "mesh": {"elements": 6, "nb": 8},
    "flow": {"type": "planar-extension"},
    "time": {"dt": "auto", "t_end": 200},
    "ca": 0.3,
    "output": {"dir": "run", "csv_every": 0.05, "vtk_every": 0.5, "checkpoint_every": 0},
}


def main():
    capflow, work = sys.argv[1], sys.argv[2]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    control_path = os.path.join(work, "c.json")
    with open(control_path, "w") as f:
        json.dump(CONTROL, f)
    c = Console([capflow, "run", "c.json", "--serve", "0"], cwd=work)
    b1 = b2 = None
    try:
        # The token guards everything.
        assert c.request("/api/state", token=False)[0] == 401
        assert c.request("/api/state", headers={"Authorization": "Bearer 0" * 1}, token=False)[0] == 401
        assert c.request("/?token=wrong", token=False)[0] == 401
        assert c.request("/api/../../etc/passwd")[0] == 404
        assert c.request("/api/state")[0] == 200

        b1 = browser()
        b1.get(c.url)
        c.wait(lambda: b1.find_element(By.ID, "badge").text == "running", "the page: running")
        c.wait(lambda: int(b1.find_element(By.ID, "view").get_attribute("data-frames") or 0) >= 1,
               "a first image")
        # The 3-D image changes as the run advances.
        first = shown_image_hash(b1)
        c.wait(lambda: shown_image_hash(b1) != first, "a newer image of the running capsule")
        c.wait(lambda: int(b1.find_element(By.ID, "chart").get_attribute("data-rows") or 0) >= 3,
               "rows in the plot")

        # Pause from the page.
        b1.find_element(By.ID, "pause").click()
        c.wait(lambda: c.get_json("/api/state")["state"] == "paused", "paused")
        t_paused = c.get_json("/api/state")["t"]
        time.sleep(0.5)
        assert c.get_json("/api/state")["t"] == t_paused, "the run went on while paused"

        # A drag turns the camera; /api/frame draws the same image for the same parameters.
        before = json.loads(b1.execute_script("return JSON.stringify(window.capflow.cam)"))
        view = b1.find_element(By.ID, "view-wrap")
        ActionChains(b1).move_to_element(view).click_and_hold().move_by_offset(120, 40).release().perform()
        after = json.loads(b1.execute_script("return JSON.stringify(window.capflow.cam)"))
        assert (after["yaw"], after["pitch"]) != (before["yaw"], before["pitch"]), (before, after)
        time.sleep(1.0)  # the last frame of the drag lands
        url = b1.find_element(By.ID, "view").get_attribute("data-url")
        assert "yaw=%.2f" % after["yaw"] in url and "pitch=%.2f" % after["pitch"] in url, url
        status, body = c.request("/" + url)
        assert status == 200
        assert sha256(body) == shown_image_hash(b1), "the page's image differs from /api/frame's"
        b1.save_screenshot(os.path.join(work, "console.png"))

        # Ca set from the page reaches the control file.
        Select(b1.find_element(By.ID, "seg-kind")).select_by_value("hold")
        b1.find_element(By.ID, "seg-ca").send_keys("0.45")
        b1.find_element(By.ID, "seg-apply").click()
        c.wait(lambda: json.load(open(control_path)).get("ca") == 0.45, "ca = 0.45 in the control file")

        # A second browser sees the first one's edit.
        b2 = browser()
        b2.get(c.url)
        c.wait(lambda: b2.find_elements(By.CSS_SELECTOR, '[data-path="output.csv_every"]'), "fields")
        box = b1.find_element(By.CSS_SELECTOR, '[data-path="output.csv_every"]')
        box.clear()
        box.send_keys("0.04")
        box.find_element(By.XPATH, "following-sibling::button").click()
        c.wait(lambda: b2.find_element(By.CSS_SELECTOR, '[data-path="output.csv_every"]')
               .get_attribute("value") == "0.04", "the second browser shows csv_every = 0.04", 10)

        # A hand edit of the file shows up in the page within a second.
        doc = json.load(open(control_path))
        doc["output"]["csv_every"] = 0.03
        with open(control_path + ".tmp", "w") as f:
            json.dump(doc, f)
        os.replace(control_path + ".tmp", control_path)
        edited = time.time()
        c.wait(lambda: b1.find_element(By.CSS_SELECTOR, '[data-path="output.csv_every"]')
               .get_attribute("value") == "0.03", "the hand edit in the page", 5)
        assert time.time() - edited < 1.0, "the hand edit took %.2f s to show" % (time.time() - edited)

        # A refused value shows the schema's message next to its field.
        tol = b1.find_element(By.CSS_SELECTOR, '[data-path="time.tolerance"]')
        tol.clear()
        tol.send_keys("5")
        tol.find_element(By.XPATH, "following-sibling::button").click()
        msg = lambda: b1.find_element(By.CSS_SELECTOR, '.msg[data-for="time.tolerance"]').text
        c.wait(lambda: "0.01" in msg(), "the refusal's message")
        assert json.load(open(control_path))["time"].get("tolerance") is None

        # A stale revision is refused (409) and the page reloads the current values.
        rev = c.get_json("/api/state")["revision"]
        status, body = c.request("/api/control", "POST", {"revision": rev - 1, "patch": {"ca": 0.5}})
        assert status == 409, (status, body)
        b2.execute_script("window.capflow.state.revision -= 1")
        b2.execute_script("window.capflow.send({ca: 0.5})")
        c.wait(lambda: "changed meanwhile" in b2.find_element(By.ID, "steer-msg").text, "stale message")
        assert json.load(open(control_path)).get("ca") == 0.45
        # A POST with the token in a cookie only is refused.
        status, _ = c.request("/api/control", "POST", {"revision": rev, "patch": {"ca": 0.5}},
                              headers={"Cookie": "capflow_token=" + c.token}, token=False)
        assert status == 403

        # Resume: the new Ca reaches timeseries.csv.
        b1.find_element(By.ID, "resume").click()
        def ca_in_rows():
            with open(os.path.join(work, "run", "timeseries.csv")) as f:
                return any(l.split(",")[1] == "0.45" for l in f.read().splitlines()[1:])
        c.wait(ca_in_rows, "Ca = 0.45 in timeseries.csv")

        # Stop from the page.
        b1.find_element(By.ID, "stop").click()
        code, rest = c.finish()
        assert code == 0, (code, rest)
        print("console browser test: ok")
    finally:
        for b in (b1, b2):
            if b:
                b.quit()
        if c.proc.poll() is None:
            c.proc.kill()


if __name__ == "__main__":
    main()
