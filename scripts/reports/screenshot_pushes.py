#!/usr/bin/python3
"""Screenshots of the live view at the moment of each push (and pull) of a
recorded session, taken in headless Chromium from igms-viewer --log.

  scripts/reports/screenshot_pushes.py LOG OUT_DIR [--build build]

For every stretch of the log where the user acts on the robot (push or pull
mode), the moment of the largest force is found in the exported states; the
viewer's timeline is moved there and the page is captured as
OUT_DIR/view_<mode><n>.png. Prints one line per screenshot.
"""
import argparse
import csv
import os
import shutil
import subprocess
import sys
import tempfile
import time

MODES = {1: "push", 2: "pull"}


def moments(states_csv):
    """(sim time, mode, |force|) at the largest force of each interaction stretch."""
    out, best, mode = [], None, 0
    with open(states_csv) as f:
        for row in csv.DictReader(f):
            m = int(row["mode"])
            force = sum(float(row[k]) ** 2 for k in ("fx", "fy", "fz")) ** 0.5
            if m != mode and best:
                out.append(best)
                best = None
            mode = m
            if m in MODES and (best is None or force > best[2]):
                best = (float(row["t"]), m, force)
    if best:
        out.append(best)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("log")
    ap.add_argument("out")
    ap.add_argument("--build", default="build")
    a = ap.parse_args()
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service
    except ImportError:
        print("screenshots: skipped (python3-selenium missing; scripts/setup/setup.sh installs it)")
        return 0
    if not shutil.which("chromium") or not shutil.which("chromedriver"):
        print("screenshots: skipped (no Chromium; scripts/setup/setup.sh installs it)")
        return 0
    work = tempfile.mkdtemp(prefix="igms-shots-")
    subprocess.run([os.path.join(a.build, "tools/igms-replay"), "export", a.log, work], check=True,
                   stderr=subprocess.DEVNULL)
    targets = moments(os.path.join(work, "states.csv"))
    viewer = subprocess.Popen([os.path.join(a.build, "tools/igms-viewer"), "--log", a.log, "--port", "0"],
                              stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    driver = None
    try:
        url = viewer.stdout.readline().strip()
        options = webdriver.ChromeOptions()
        options.binary_location = shutil.which("chromium")
        for flag in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--use-gl=swiftshader",
                     "--enable-unsafe-swiftshader", "--window-size=1200,800", "--hide-scrollbars"):
            options.add_argument(flag)
        driver = webdriver.Chrome(service=Service(shutil.which("chromedriver")), options=options)
        driver.get(url + ("&" if "?" in url else "?") + "resolution=full")  # a picture: never the half-resolution fallback
        js = driver.execute_script

        def wait(predicate, timeout=10):
            end = time.time() + timeout
            while time.time() < end:
                v = predicate()
                if v:
                    return v
                time.sleep(0.05)
            raise RuntimeError("the viewer page did not answer")

        tl = wait(lambda: js("const f = window.igms && window.igms.state.frame; return f && f.timeline"))
        if tl["playing"]:
            js("document.getElementById('play').click()")
        wait(lambda: not js("return window.igms.state.frame.timeline.playing"))

        resent = []  # per seek asked again: whether the page's socket was open then

        def seek(t):
            # The frame's sim time, boxed: before the log's first state it is 0.0, which is an answer too
            # (unboxed, a falsy 0.0 read as "no answer yet" and the wait timed out: a loaded machine's
            # Go1 server loads late, so the bisection probed that stretch). The page drops what it would
            # send while its socket is closed (main.js, send), so a seek not answered within a second is
            # asked again, and said below: a loaded CI run once waited 10 s for one answer.
            def ask():
                js("const s = document.getElementById('seek'); s.value = arguments[0];"
                   "s.dispatchEvent(new Event('change'));", t)

            def answer():
                f = js("return window.igms.state.frame")
                return [f["t"]] if f and abs(f["timeline"]["t"] - t) < 0.002 else None
            for attempt in range(10):
                ask()
                try:
                    return wait(answer, timeout=1)[0]
                except RuntimeError:
                    if attempt == 9:
                        raise
                    resent.append(js("return window.igms.state.connected"))

        end = tl["end"]
        counts = {}
        for sim_time, mode, force in targets:
            # The log's clock is the wall's; find the playhead that shows this sim time.
            lo, hi = 0.0, end
            for _ in range(20):
                mid = 0.5 * (lo + hi)
                if seek(mid) < sim_time - 1e-9:
                    lo = mid
                else:
                    hi = mid
            seek(hi)
            time.sleep(0.3)  # a few frames drawn
            counts[mode] = counts.get(mode, 0) + 1
            name = os.path.join(a.out, "view_%s%d.png" % (MODES[mode], counts[mode]))
            driver.save_screenshot(name)
            print("screenshot: %s (t = %.3f s, %s, %.1f N)" % (name, sim_time, MODES[mode], force))
        if resent:
            print("screenshot: %d seeks asked again, %d of them while the page's socket was closed" %
                  (len(resent), sum(not connected for connected in resent)))
    finally:
        if driver:
            driver.quit()
        viewer.terminate()
        viewer.wait()
        shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
