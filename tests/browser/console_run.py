"""Helpers of the live console's browser tests: a capflow process with --serve, the HTTP API with
its token, and headless Chromium (Debian's chromium + chromium-driver, python3-selenium)."""
import hashlib
import json
import os
import re
import subprocess
import time
import urllib.error
import urllib.request

from selenium import webdriver
from selenium.webdriver.chrome.service import Service


class Console:
    """A capflow command started with --serve 0: its URL, token and API."""

    def __init__(self, args, cwd):
        args = [os.path.abspath(args[0])] + list(args[1:])
        self.err_path = os.path.join(cwd, "stderr.log")
        self.out = open(os.path.join(cwd, "stdout.log"), "w")
        self.err = open(self.err_path, "w")
        self.proc = subprocess.Popen(args, cwd=cwd, stdout=self.out, stderr=self.err)
        self.url = None
        deadline = time.time() + 60
        while time.time() < deadline and self.url is None and self.proc.poll() is None:
            m = re.search(r"console at (http://\S+)", self.stderr())
            if m:
                self.url = m.group(1)
            time.sleep(0.05)
        if self.url is None:
            self.proc.kill()
            raise RuntimeError("capflow printed no console URL: " + self.stderr())
        self.base, self.token = self.url.split("/?token=")

    def stderr(self):
        with open(self.err_path) as f:
            return f.read()

    def request(self, path, method="GET", body=None, headers=None, token=True):
        h = dict(headers or {})
        if token:
            h["Authorization"] = "Bearer " + self.token
        data = None if body is None else (body if isinstance(body, bytes) else json.dumps(body).encode())
        if data is not None:
            h.setdefault("Content-Type", "application/json")
        req = urllib.request.Request(self.base + path, data=data, method=method, headers=h)
        try:
            with urllib.request.urlopen(req, timeout=30) as r:
                return r.status, r.read()
        except urllib.error.HTTPError as e:
            return e.code, e.read()

    def get_json(self, path):
        status, body = self.request(path)
        assert status == 200, (path, status, body)
        return json.loads(body)

    def wait(self, predicate, what, timeout=60):
        deadline = time.time() + timeout
        while time.time() < deadline:
            v = predicate()
            if v:
                return v
            time.sleep(0.1)
        raise AssertionError("timed out waiting for " + what)

    def finish(self, timeout=60):
        try:
            self.proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            raise
        return self.proc.returncode, self.stderr()


def browser():
    o = webdriver.ChromeOptions()
    o.binary_location = "/usr/bin/chromium"
    for a in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
              "--window-size=1400,1000"):
        o.add_argument(a)
    return webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=o)


def shown_image_hash(driver):
    """SHA-256 of the bytes of the image the page shows (its blob)."""
    return driver.execute_async_script("""
        const done = arguments[arguments.length - 1];
        fetch(document.getElementById('view').src).then(r => r.arrayBuffer())
          .then(b => crypto.subtle.digest('SHA-256', b))
          .then(h => done(Array.from(new Uint8Array(h)).map(x => x.toString(16).padStart(2, '0')).join('')))
          .catch(e => done('error ' + e));""")


def sha256(data):
    return hashlib.sha256(data).hexdigest()
