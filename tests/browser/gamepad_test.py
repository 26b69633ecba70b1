"""A gamepad as the haptic device, in a real headless Chromium over the real
bus: igms-server (scenes/puma_obstacle.yaml, realtime) and igms-haptic
--device web. The page's input layer reads a scripted pad
(window.igmsGamepadSource), steered like a person would steer it: the
left stick across the screen, the right stick in depth. With A released the
cursor goes to just outside link 2; A held (the tip starts at the cursor), it
goes 3 cm in: the push reaches link 2 where the sticks aimed (push mode,
force on the robot at the pad's point, the device renders it). B held on
link 3 grabs it (pull mode). A SpaceMouse's WebHID reports parse into six
axes.

  gamepad_test.py BUILD_DIR SOURCE_DIR
"""
import os
import sys
import time

sys.path.insert(0, os.path.dirname(__file__))
import browser_session as bs  # noqa: E402

bs.skip_without_chromium()

build, source = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
scene = os.path.join(source, "scenes/puma_obstacle.yaml")
url = "udpm://239.255.76.67:7734?ttl=0"
device_port = 17871
work = bs.temp_dir("igms-browser-gamepad-")
procs = bs.Processes(build, work)

PAD = """
window.__pad = {id: 'scripted pad', mapping: 'standard', axes: [0, 0, 0, 0],
                buttons: [{pressed: false}, {pressed: false}, {pressed: false}, {pressed: false}]};
window.igmsGamepadSource = () => [window.__pad];
"""

# The axes that move the cursor toward `goal` (world), as a person's thumbs would: in the camera's
# frame, proportional to the distance (full tilt from 6 cm), so the cursor settles on the goal.
STEER = """
const T = window.igms.THREE, g = window.igms.gamepad, cam = window.igms.camera;
const goal = new T.Vector3(...arguments[0]);
const e = goal.clone().sub(g.cursor);
const right = new T.Vector3().setFromMatrixColumn(cam.matrixWorld, 0).normalize();
const up = new T.Vector3().setFromMatrixColumn(cam.matrixWorld, 1).normalize();
const into = new T.Vector3(); cam.getWorldDirection(into);
const c = (x) => Math.max(-1, Math.min(1, x / 0.06));
const a = [c(e.dot(right)), -c(e.dot(up)), 0, -c(e.dot(into))];
a.forEach((x, k) => { if (Math.abs(x) > 1e-3) a[k] = Math.sign(x) * (0.12 + 0.88 * Math.abs(x)); });
window.__pad.axes = a;
return e.length();
"""


def steer(page, goal, within=0.004, timeout=20.0, watch=None):
    """Moves the cursor to `goal`; returns the distance left. watch(): called as the cursor goes."""
    end = time.time() + timeout
    left = 1.0
    while time.time() < end:
        left = page.js(STEER, goal)
        if watch:
            watch()
        if left < within:
            break
        time.sleep(0.03)
    page.js("window.__pad.axes = [0, 0, 0, 0];")
    return left


def button(page, k, down):
    page.js("window.__pad.buttons[arguments[0]].pressed = arguments[1];", k, down)


def view_direction(page):
    return page.js("const d = new window.igms.THREE.Vector3(); window.igms.camera.getWorldDirection(d); "
                   "return d.toArray();")


def body(checks, open_browser):
    procs.start("server/igms-server", ["--scene", scene, "--lcm-url", url, "--quiet"])
    _, device_url = procs.start("haptic_client/igms-haptic",
                                ["--scene", scene, "--device", "web:%d" % device_port, "--lcm-url", url, "--quiet"],
                                first_line=True)
    driver = open_browser()
    page = bs.Page(driver, device_url)
    hello = bs.wait_for("the session's hello", lambda: page.state("hello"))
    page.wait_frames(5)
    checks.check(page.state("role") == "device", "the page with the token is the device")
    checks.check(page.text("gamepad") == "none", "no gamepad: the HUD says none")

    # The SpaceMouse's WebHID reports (no device here): translation, rotation, buttons.
    parsed = page.js("const s = {axes: [0, 0, 0, 0, 0, 0], buttons: []};"
                     "window.igms.spaceMouseReport(s, 1, new Uint8Array([94, 1, 0, 0, 162, 254]));"
                     "window.igms.spaceMouseReport(s, 2, new Uint8Array([175, 0, 0, 0, 0, 0]));"
                     "window.igms.spaceMouseReport(s, 3, new Uint8Array([2]));"
                     "return [s.axes, s.buttons.map((b) => b.pressed)];")
    checks.check([round(x, 3) for x in parsed[0]] == [1.0, 0.0, -1.0, 0.5, 0.0, 0.0] and parsed[1] == [False, True],
                 "a SpaceMouse's WebHID reports parse into six axes and its buttons", str(parsed))

    # The robot at rest at the end of its nominal motion, so link 2 stays where the pad goes.
    bs.wait_for("the end of the nominal motion", lambda: page.frame()["t"] > hello["nominal_end"] + 0.3, timeout=15)
    page.js(PAD)
    bs.wait_for("the pad in the HUD", lambda: page.text("gamepad") == "scripted pad", timeout=5)
    checks.check(page.js("return window.igms.gamepad.cursor !== null"), "a pad shows: the cursor appears at the view's centre")

    link2 = page.js("return window.igms.linkIndex('link2')")
    at = page.js("return window.igms.pointOnLink(arguments[0])", link2)
    checks.check(at is not None, "link 2 is in view", str(at))
    into = view_direction(page)
    surface = at["point"]
    outside = [surface[i] - 0.04 * into[i] for i in range(3)]
    inside = [surface[i] + 0.03 * into[i] for i in range(3)]
    left = steer(page, outside)
    checks.check(left < 0.01 and page.frame()["mode"] == 0, "A released: the sticks bring the cursor to 4 cm before link 2, "
                 "no push", "%.1f mm from there" % (1e3 * left))
    targets_before = bs.status(device_url)["device_targets"]
    # The press starts the tip at the cursor, and it follows the cursor in: the push's first frame
    # (watched for while the sticks steer, since the link then gives way) is where the pad was steered.
    button(page, 0, True)
    cursor = page.js("return window.igms.gamepad.cursor.toArray()")

    def tip_gap():
        f = page.frame()
        tip = f.get("device", {}).get("tip") if f and f.get("device", {}).get("active") else None
        return sum((tip[i] - cursor[i]) ** 2 for i in range(3)) ** 0.5 if tip else 1.0
    try:
        bs.wait_for("the tip at the cursor", lambda: tip_gap() < 0.005, timeout=2.0, period=0.02)
    except AssertionError:
        pass  # checked and reported below
    gap = tip_gap()
    checks.check(gap < 0.005, "A pressed: the tip starts at the cursor, not where it was parked",
                 "%.1f mm from it" % (1e3 * gap))
    first_push = []

    def push_frame():
        f = page.frame()
        if not first_push and f and f["mode"] == 1 and sum(x * x for x in f["force"]) > 1:
            first_push.append(f)
        return first_push[0] if first_push else None
    steer(page, inside, timeout=8, watch=push_frame)
    pushed = bs.wait_for("a frame in push mode with force", push_frame, timeout=5, period=0.02)
    d = sum((pushed["point"][i] - surface[i]) ** 2 for i in range(3)) ** 0.5
    checks.check(d < 0.05, "A held, the right stick in: the pad pushes link 2 where it was steered",
                 "|f| = %.1f N at %.1f cm from the point on link 2" % (sum(x * x for x in pushed["force"]) ** 0.5, 100 * d))
    time.sleep(0.6)
    checks.check(page.state("maxDeviceForce") > 0.5, "the device renders the push's force",
                 "up to %.2f N" % page.state("maxDeviceForce"))
    checks.check(bs.status(device_url)["device_targets"] > targets_before, "the pad's targets reached the device")
    button(page, 0, False)
    bs.wait_for("the push's end", lambda: page.frame()["mode"] == 0, timeout=5)
    checks.check(page.state("maxOffNominal") > 0.01, "the push moved the robot off its nominal path",
                 "%.3f m" % page.state("maxOffNominal"))

    # B held on link 3: a grab, the pull from the point under the cursor. The arm is still on its way
    # back from the push, so the point is aimed at again before each press: a press whose ray from the
    # eye misses the link (it moved on while the sticks steered) grabs nothing, as it should; it is
    # released and aimed again, at most three times (the attempts are printed).
    link3 = page.js("return window.igms.linkIndex('link3')")
    pulled, attempts, at3 = None, 0, None
    while pulled is None and attempts < 3:
        attempts += 1
        at3 = page.js("return window.igms.pointOnLink(arguments[0])", link3)
        if at3 is None:
            continue
        steer(page, [at3["point"][i] - 0.005 * into[i] for i in range(3)])
        button(page, 1, True)
        up = [at3["point"][0], at3["point"][1], at3["point"][2] + 0.08]
        steer(page, up, timeout=4)
        try:
            pulled = bs.wait_for("a frame in pull mode",
                                 lambda: (lambda f: f if f and f["mode"] == 2 else None)(page.frame()),
                                 timeout=5, period=0.02)
        except AssertionError:
            button(page, 1, False)
            time.sleep(0.3)
    checks.check(at3 is not None, "link 3 is in view", str(at3))
    checks.check(pulled is not None, "B held on link 3 grabs it: pull mode",
                 "|f| = %.1f N, in %d attempt(s)" % ((sum(x * x for x in pulled["force"]) ** 0.5) if pulled else 0.0,
                                                   attempts))
    button(page, 1, False)
    bs.wait_for("the grab's end", lambda: page.frame()["mode"] == 0, timeout=5)
    checks.check(True, "releasing B lets go")
    checks.check(page.frame()["client"]["max_force_step"] <= 1.0 + 1e-6, "the rendered force stepped by at most 1 N a cycle",
                 "%.3f N" % page.frame()["client"]["max_force_step"])


sys.exit(bs.run_test("gamepad_test", procs, work, body))
