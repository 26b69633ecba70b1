"""What the browser tests share: igms processes started and always stopped,
a headless Chromium driven by Selenium, and the page's own state
(window.igms) read back.

Every test runs inside a private network namespace (ctest starts it under
scripts/netns_run.sh), so the bus and the web servers stay on this machine.
Without Chromium, its driver or Selenium a test prints "skipped: ..." and
exits 77, which ctest reports as skipped, not passed.
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import urllib.request

SKIP = 77


def skip_without_chromium():
    missing = [p for p in ("chromium", "chromedriver") if shutil.which(p) is None]
    try:
        import selenium  # noqa: F401
    except ImportError:
        missing.append("python3-selenium")
    if missing:
        print("skipped: no Chromium (missing %s; scripts/setup/setup.sh installs them)" % ", ".join(missing))
        sys.exit(SKIP)


class Processes:
    """igms programs of one test; stop() ends them all, newest first."""

    def __init__(self, build, workdir, cwd=None):
        self.build = build
        self.workdir = workdir  # their stderr logs
        self.cwd = cwd or workdir
        self.running = []

    def start(self, name, args, first_line=False):
        """Starts build/<name>; with first_line, waits for and returns its first stdout line."""
        log = open(os.path.join(self.workdir, os.path.basename(name) + ".%d.err" % len(self.running)), "w")
        p = subprocess.Popen([os.path.join(self.build, name)] + args, cwd=self.cwd, stdout=subprocess.PIPE,
                             stderr=log, text=True)
        self.running.append(p)
        if not first_line:
            return p, None
        line = p.stdout.readline().strip()
        if not line:
            raise RuntimeError("%s printed no URL (see %s)" % (name, log.name))
        return p, line

    def stop(self, p):
        if p.poll() is None:
            p.terminate()
            try:
                p.wait(timeout=5)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
        if p in self.running:
            self.running.remove(p)

    def stop_all(self):
        for p in reversed(list(self.running)):
            self.stop(p)


def status(base_url):
    """The igms web process's counters (GET /status.json)."""
    with urllib.request.urlopen(base_url.split("#")[0].split("?")[0].rstrip("/") + "/status.json", timeout=5) as r:
        return json.load(r)


def chromium(width=1200, height=800):
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    options = webdriver.ChromeOptions()
    # The browser renders in software on the same 2 cores as the 1 kHz loops: at a lower
    # priority it takes only what they leave (as a person's browser on another machine would).
    wrapper = os.path.join(tempfile.mkdtemp(prefix="igms-chromium-"), "chromium")
    with open(wrapper, "w") as f:
        f.write('#!/bin/sh\nexec nice -n 10 %s "$@"\n' % shutil.which("chromium"))
    os.chmod(wrapper, 0o755)
    options.binary_location = wrapper
    for flag in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--use-gl=swiftshader",
                 "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist", "--window-size=%d,%d" % (width, height)):
        options.add_argument(flag)
    return webdriver.Chrome(service=Service(shutil.which("chromedriver")), options=options)


def wait_for(what, predicate, timeout=15.0, period=0.05):
    """Polls predicate() until it returns something truthy; fails naming `what`."""
    end = time.time() + timeout
    while time.time() < end:
        value = predicate()
        if value:
            return value
        time.sleep(period)
    raise AssertionError("timed out after %.0f s waiting for %s" % (timeout, what))


class Page:
    """The igms page in a browser tab."""

    def __init__(self, driver, url):
        self.driver = driver
        driver.get(url)
        wait_for("the page's script", lambda: self.js("return !!window.igms"))

    def js(self, script, *args):
        return self.driver.execute_script(script, *args)

    def state(self, expression):
        return self.js("return window.igms.state." + expression)

    def frame(self):
        return self.js("return window.igms.state.frame")

    def wait_frames(self, n=3, timeout=20):
        start = self.state("framesReceived") or 0
        wait_for("%d frames" % n, lambda: (self.state("framesReceived") or 0) >= start + n, timeout)

    def text(self, element_id):
        return self.js("return document.getElementById(arguments[0]).textContent", element_id)

    def visible(self, element_id):
        return self.js("return !document.getElementById(arguments[0]).hidden", element_id)

    def wait_drawn(self, timeout=20):
        """Waits until every mesh has loaded and the page has drawn twice since
        the call, so the canvas holds the latest frame: a loaded machine can
        answer before its first draw, and the canvas is then one colour."""
        drawn = self.state("framesDrawn") or 0
        wait_for("the page to draw", lambda: self.js(
            "return window.igms.robot.meshesPending === 0 && window.igms.state.framesDrawn >= arguments[0] + 2",
            drawn), timeout)

    def canvas_pixels(self, size=240):
        """The drawn canvas, scaled down, as a flat list of RGB values."""
        self.wait_drawn()
        return self.js("""
            const src = document.querySelector('#view canvas');
            const c = document.createElement('canvas');
            c.width = arguments[0]; c.height = Math.round(arguments[0] * src.height / src.width);
            const g = c.getContext('2d');
            g.drawImage(src, 0, 0, c.width, c.height);
            const d = g.getImageData(0, 0, c.width, c.height).data;
            const out = [];
            for (let i = 0; i < d.length; i += 4) out.push(d[i], d[i + 1], d[i + 2]);
            return out;""", size)


def differing_pixels(a, b, threshold=30):
    return sum(1 for i in range(0, len(a), 3)
               if abs(a[i] - b[i]) + abs(a[i + 1] - b[i + 1]) + abs(a[i + 2] - b[i + 2]) > threshold)


def distinct_colours(pixels):
    return len({(pixels[i] // 8, pixels[i + 1] // 8, pixels[i + 2] // 8) for i in range(0, len(pixels), 3)})


class Checks:
    """Assertions that all run and are reported together; exit code 1 on any failure."""

    def __init__(self, name):
        self.name = name
        self.failed = 0

    def check(self, ok, what, detail=""):
        print("%s %s%s" % ("ok  " if ok else "FAIL", what, (": " + detail) if detail else ""), flush=True)
        if not ok:
            self.failed += 1
        return ok

    def finish(self):
        print("%s: %s" % (self.name, "passed" if self.failed == 0 else "%d checks failed" % self.failed))
        return 1 if self.failed else 0


def run_test(name, procs, work, body):
    """Runs body(checks, open_browser) and returns the exit code. A failed
    wait or a crash is a failed check (with a screenshot in `work`); every
    browser and every process started is stopped on every path."""
    checks = Checks(name)
    drivers = []

    def open_browser():
        drivers.append(chromium())
        return drivers[-1]

    try:
        body(checks, open_browser)
    except Exception as e:
        checks.check(False, "the test ran to its end", "%s: %s" % (type(e).__name__, e))
        for d in drivers:
            try:
                d.save_screenshot(os.path.join(work, "failure.png"))
                print("screenshot: %s/failure.png" % work)
            except Exception:
                pass
    finally:
        for d in drivers:
            d.quit()
        procs.stop_all()
    return checks.finish()


def temp_dir(prefix):
    return tempfile.mkdtemp(prefix=prefix)
