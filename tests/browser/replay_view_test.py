"""A recorded session in the live view's page, in a real headless Chromium:
igms-viewer --log plays tests/replay/data/paper_push.lcmlog.gz with a
timeline; the page plays, pauses, seeks and changes speed through its own
controls, and the pose drawn after a seek is the log's.

  replay_view_test.py BUILD_DIR SOURCE_DIR
"""
import csv
import os
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(__file__))
import browser_session as bs  # noqa: E402

bs.skip_without_chromium()

build, source = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
log = os.path.join(source, "tests/replay/data/paper_push.lcmlog.gz")
work = bs.temp_dir("igms-browser-replay-")

# The log's states by sim time: every link's position.
subprocess.run([os.path.join(build, "tools/igms-replay"), "export", log, os.path.join(work, "export")], check=True,
               stderr=subprocess.DEVNULL)
with open(os.path.join(work, "export/states.csv")) as f:
    rows = list(csv.DictReader(f))
links = [k[:-2] for k in rows[0] if k.endswith(".x")]
by_time = {round(float(r["t"]), 6): r for r in rows}

# The viewer resolves the recorded scene's relative paths from the source tree, as a user runs it.
procs = bs.Processes(build, work, cwd=source)


def timeline(page):
    f = page.frame()
    return f and f.get("timeline")


def seek(page, t):
    page.js("const s = document.getElementById('seek'); s.value = arguments[0];"
            "s.dispatchEvent(new Event('change'));", t)
    return bs.wait_for("the playhead at %.2f s" % t, lambda: (lambda tl: tl and abs(tl["t"] - t) < 0.002 and
                                                              page.frame())(timeline(page)), timeout=5)


def drawn_matches_log(page, frame):
    row = by_time.get(round(frame["t"], 6))
    if row is None:
        return False, "no state at t = %.6f in the log" % frame["t"]
    worst = 0.0
    for i, name in enumerate(links):
        p = page.js("return window.igms.linkPosition(arguments[0])", i)
        worst = max(worst, max(abs(p[k] - float(row[name + "." + "xyz"[k]])) for k in range(3)))
    return worst < 1e-5, "t = %.4f s, largest difference %.2g m over %d links" % (frame["t"], worst, len(links))


def body(checks, open_browser):
    _, url = procs.start("tools/igms-viewer", ["--log", log, "--port", "17871"], first_line=True)
    driver = open_browser()
    page = bs.Page(driver, url)
    bs.wait_for("the recorded session's hello", lambda: page.state("hello"))
    checks.check(not page.state("hello")["error"], "the recorded scene resolves", page.state("hello")["error"])
    tl = bs.wait_for("the timeline", lambda: timeline(page))
    checks.check(page.visible("timeline") and tl["end"] > 1.0, "the page shows a timeline", "%.2f s" % tl["end"])

    # Pause, seek to two times: the drawn pose is the log's there, and later is later.
    if timeline(page)["playing"]:
        driver.find_element("id", "play").click()
    bs.wait_for("paused", lambda: not timeline(page)["playing"])
    end = tl["end"]
    first = seek(page, 0.4 * end)
    time.sleep(0.3)
    checks.check(page.frame()["t"] == first["t"], "paused, the drawing stays")
    ok, detail = drawn_matches_log(page, page.frame())
    checks.check(ok, "after a seek the drawn pose is the log's", detail)
    second = seek(page, 0.8 * end)
    checks.check(second["t"] > first["t"], "a later seek shows a later state",
                 "%.3f s then %.3f s" % (first["t"], second["t"]))
    ok, detail = drawn_matches_log(page, second)
    checks.check(ok, "and draws that state", detail)
    back = seek(page, 0.4 * end)
    checks.check(back["t"] == first["t"], "seeking back shows the same state again")
    ok, detail = drawn_matches_log(page, back)
    checks.check(ok, "and draws that state", detail)

    # Play at 2x: the playhead runs at twice the wall clock.
    page.js("const s = document.getElementById('speed'); s.value = '2'; s.dispatchEvent(new Event('change'));")
    bs.wait_for("speed 2", lambda: timeline(page)["speed"] == 2)
    driver.find_element("id", "play").click()
    bs.wait_for("playing", lambda: timeline(page)["playing"])
    t0, w0 = timeline(page)["t"], time.time()
    time.sleep(0.5)
    t1, w1 = timeline(page)["t"], time.time()
    rate = (t1 - t0) / (w1 - w0)
    checks.check(1.5 < rate < 2.5, "play at 2x runs the playhead at twice the wall clock", "%.2f" % rate)
    checks.check(page.frame()["t"] > back["t"], "the drawn state advances while playing")


sys.exit(bs.run_test("replay_view_test", procs, work, body))
