#!/usr/bin/python3
"""The browser view's figures (a benchmark, not a test): frames per second
in headless Chromium with the PUMA and with a 40-dof humanoid, the server's
step time with and without the viewer attached, the bandwidth to the
browser, and the latency from a mouse press to the drawn reaction.

Run it through scripts/bench/web_bench.sh (a private network namespace, a built
tree). Medians over repeated windows; the server alone is the peer of the
server with the view attached, in the same run, and the ratio is printed.
"""
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.request

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "tests", "browser"))
import browser_session as bs  # noqa: E402

build = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else "build")
source = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
seconds = float(os.environ.get("IGMS_WEB_BENCH_SECONDS", "10"))
url = "udpm://239.255.76.67:7741?ttl=0"
work = tempfile.mkdtemp(prefix="igms-web-bench-")
STATUS = re.compile(r"step p50/p99/max=([0-9.]+)/([0-9.]+)/([0-9.]+) us\s+overruns=(\d+)")


def humanoid_scene():
    """A 40-dof humanoid-like tree (legs, waist, arms, head, two-finger hands), cylinders and boxes."""
    links, joints = ['<link name="pelvis"><visual><geometry><box size="0.3 0.2 0.15"/></geometry></visual></link>'], []

    def chain(parent, prefix, n, length, origin, axes):
        for k in range(n):
            name = "%s%d" % (prefix, k + 1)
            links.append('<link name="%s"><inertial><origin xyz="0 0 %g"/><mass value="%g"/>'
                         '<inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>'
                         '<visual><origin xyz="0 0 %g"/><geometry><cylinder radius="0.035" length="%g"/></geometry>'
                         '</visual></link>' % (name, -length / 2, 1.0, -length / 2, length))
            xyz = origin if k == 0 else "0 0 %g" % -length
            joints.append('<joint name="j_%s" type="revolute"><parent link="%s"/><child link="%s"/>'
                          '<origin xyz="%s"/><axis xyz="%s"/><limit lower="-3" upper="3" effort="100" velocity="5"/>'
                          '<dynamics damping="2.0"/></joint>' % (name, parent, name, xyz, axes[k % len(axes)]))
            parent = name
        return parent

    chain("pelvis", "lleg", 6, 0.12, "0 0.1 -0.08", ["0 0 1", "1 0 0", "0 1 0"])
    chain("pelvis", "rleg", 6, 0.12, "0 -0.1 -0.08", ["0 0 1", "1 0 0", "0 1 0"])
    waist = chain("pelvis", "waist", 3, -0.12, "0 0 0.1", ["0 0 1", "0 1 0", "1 0 0"])
    for side, y in (("l", 0.2), ("r", -0.2)):
        hand = chain(waist, side + "arm", 7, 0.1, "0 %g 0.3" % y, ["0 1 0", "1 0 0", "0 0 1"])
        for finger, dy in (("a", 0.02), ("b", -0.02)):
            chain(hand, side + "finger" + finger, 2, 0.03, "0 %g -0.1" % dy, ["0 1 0"])
    chain(waist, "head", 3, -0.08, "0 0 0.4", ["0 0 1", "0 1 0", "1 0 0"])
    urdf = '<robot name="humanoid40">%s%s</robot>' % ("".join(links), "".join(joints))
    assert urdf.count('type="revolute"') == 40
    with open(os.path.join(work, "humanoid40.urdf"), "w") as f:
        f.write(urdf)
    scene = os.path.join(work, "humanoid40.yaml")
    with open(scene, "w") as f:
        f.write("name: humanoid40\nrobot: {model: humanoid40.urdf}\n"
                "initial:\n  q: [%s]\n" % ", ".join(["0.3"] * 40) +
                "simulation: {integrator: rk4, dt: 0.001, rate_hz: 1000, joint_damping: true}\n")
    return scene


def server_figures(err_path):
    """Median and largest of the per-window p99 step times (10 Hz status lines), and overruns."""
    p99s, overruns = [], 0
    with open(err_path) as f:
        for line in f:
            m = STATUS.search(line)
            if m:
                p99s.append(float(m.group(2)))
                overruns = int(m.group(4))
    p99s = p99s[5:]  # past the start
    return statistics.median(p99s), max(p99s), overruns


def run(scene, with_view, mouse=False):
    procs = bs.Processes(build, work)
    driver = None
    out = {}
    try:
        err = os.path.join(work, "server.%d.log" % time.time_ns())
        with open(err, "w") as e:
            server = subprocess.Popen([os.path.join(build, "server/igms-server"), "--scene", scene, "--lcm-url", url],
                                      stderr=e, cwd=work)
        procs.running.append(server)
        if with_view:
            if mouse:
                _, page_url = procs.start("haptic_client/igms-haptic", ["--scene", scene, "--device", "web:17951",
                                                                        "--lcm-url", url, "--quiet"], first_line=True)
            else:
                _, page_url = procs.start("tools/igms-viewer", ["--lcm-url", url, "--port", "17952"], first_line=True)
            driver = bs.chromium()
            page = bs.Page(driver, page_url)
            bs.wait_for("hello", lambda: page.state("hello"), timeout=30)
            page.wait_frames(30)
            s0, w0 = bs.status(page_url), time.time()
            fps = []
            end = time.time() + seconds
            while time.time() < end:
                time.sleep(1.0)
                fps.append(page.state("fps"))
            s1, w1 = bs.status(page_url), time.time()
            out["fps"] = statistics.median(fps)
            out["frames_per_s"] = (s1["frames_sent"] - s0["frames_sent"]) / (w1 - w0)
            out["kbytes_per_s"] = (s1["bytes_sent"] - s0["bytes_sent"]) / (w1 - w0) / 1000
            out["skipped"] = s1["frames_skipped"] - s0["frames_skipped"]
            if mouse:
                out["mouse_to_draw_ms"] = mouse_latency(driver, page)
        else:
            time.sleep(seconds + 1.5)
        procs.stop(server)
        out["step_p99_median"], out["step_p99_max"], out["overruns"] = server_figures(err)
    finally:
        if driver:
            driver.quit()
        procs.stop_all()
    return out


def mouse_latency(driver, page, n=15):
    from selenium.webdriver.common.action_chains import ActionChains
    page.js("window.igms.resetView()")
    time.sleep(0.5)
    samples = []
    for _ in range(n):
        at = page.js("return window.igms.pointOnLink(window.igms.linkIndex('link2'))")
        if not at:
            continue
        page.js("window.igms.state.mouseToDrawMs = null")
        a = ActionChains(driver)
        a.w3c_actions.pointer_action.move_to_location(at["x"], at["y"])
        a.w3c_actions.pointer_action.pointer_down()
        a.perform()
        ms = bs.wait_for("the drawn tip", lambda: page.state("mouseToDrawMs"), timeout=5, period=0.01)
        samples.append(ms)
        ActionChains(driver).release().perform()
        time.sleep(0.4)
    return statistics.median(samples), max(samples), len(samples)


def main():
    puma = os.path.join(source, "scenes/puma_obstacle.yaml")
    humanoid = humanoid_scene()
    print("web view benchmark: %.0f s windows, headless Chromium (SwiftShader, software WebGL), 2 cores" % seconds)
    alone = run(puma, with_view=False)
    viewed = run(puma, with_view=True)
    tall = run(humanoid, with_view=True)
    mouse = run(puma, with_view=True, mouse=True)
    print("%-44s %10s %10s %10s %10s" % ("", "fps", "frames/s", "kB/s", "step p99"))
    print("%-44s %10s %10s %10s %7.1f us (max %.0f, overruns %d)" % (
        "PUMA, server alone (no viewer)", "-", "-", "-", alone["step_p99_median"], alone["step_p99_max"],
        alone["overruns"]))
    for name, r in (("PUMA, igms-viewer + Chromium", viewed), ("40-dof humanoid, igms-viewer + Chromium", tall),
                    ("PUMA, web device + Chromium", mouse)):
        print("%-44s %10.1f %10.1f %10.1f %7.1f us (max %.0f, overruns %d)" % (
            name, r["fps"], r["frames_per_s"], r["kbytes_per_s"], r["step_p99_median"], r["step_p99_max"],
            r["overruns"]))
    print("server step p99 with the view / without: %.2f" % (viewed["step_p99_median"] / alone["step_p99_median"]))
    med, worst, n = mouse["mouse_to_draw_ms"]
    print("mouse press to the drawn tip (page -> web device -> 1 kHz servo loop -> frame -> page): "
          "median %.1f ms, max %.1f ms over %d presses" % (med, worst, n))
    json.dump({"alone": alone, "puma": viewed, "humanoid40": tall, "mouse": mouse},
              open(os.path.join(source, "out", "bench", "web_view.json"), "w"), indent=1)
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    bs.skip_without_chromium()
    os.makedirs(os.path.join(source, "out", "bench"), exist_ok=True)
    main()
