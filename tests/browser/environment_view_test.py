"""The live view of an environment in a real headless Chromium, over the real
bus, as a person uses it: igms-server (realtime), igms-haptic --device web and
the page.

  1. scenes/puma_table.yaml: the boxes, the table and the ground are drawn with
     the contacts (points and force arrows; key c hides and shows them), and a
     drag pushes a box along the table by more than 3 cm, and a drag whose
     first message reaches the client with the next (a busy machine) still
     starts at the picked point.
  2. scenes/hand_table.yaml (the PUMA still, boxes and a ball on the table):
     a shift-drag lifts the ball with the pull spring; let go, it falls and
     settles. A malformed message from the page changes nothing.
  3. scenes/sphere_pile.yaml (216 spheres) in a viewer page with its contacts
     drawn, live (the server stepping the pile at 1 kHz on the same 2 cores:
     the frame rate is printed and only a floor of 5 fps asserted) and replayed
     from its log (igms-viewer --log, the page alone; both frame rates printed,
     floors asserted: the 30 fps asked for is not reached by this software renderer).
  4. scenes/log_pile.yaml: the page has no capsule of its own; each log is drawn from the
     triangles of its surface the hello carries (core/geometry/shape_surface.h), as a kind
     added later would be: as many triangles, the capsule's extents, under some pixel.

  environment_view_test.py BUILD_DIR SOURCE_DIR
"""
import os
import re
import sys
import time

sys.path.insert(0, os.path.dirname(__file__))
import browser_session as bs  # noqa: E402

bs.skip_without_chromium()

from selenium.webdriver.common.action_chains import ActionChains  # noqa: E402
from selenium.webdriver.common.actions.wheel_input import ScrollOrigin  # noqa: E402
from selenium.webdriver.common.keys import Keys  # noqa: E402

build, source = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
url = "udpm://239.255.76.67:7735?ttl=0"
device_port, viewer_port = 17871, 17872
work = bs.temp_dir("igms-browser-environment-")
procs = bs.Processes(build, work)
# The issue asks 30 fps; this software renderer (SwiftShader) on these 2 cores measured 16-29 fps
# replayed (docs/environment.md has the figures): this is a floor against regressions, not the goal.
MIN_PILE_FPS = 12.0


def scene(name):
    return os.path.join(source, "scenes", name)


def start_session(scene_file, viewer=False):
    """A server and a web device on scene_file (and a viewer); returns (server, client, page URL)."""
    server = procs.start("server/igms-server", ["--scene", scene_file, "--lcm-url", url, "--quiet"])[0]
    client, device_url = procs.start("haptic_client/igms-haptic", ["--scene", scene_file, "--device",
                                                                    "web:%d" % device_port, "--lcm-url", url,
                                                                    "--quiet"], first_line=True)
    if not viewer:
        return server, client, device_url
    v, viewer_url = procs.start("tools/igms-viewer", ["--lcm-url", url, "--port", str(viewer_port)], first_line=True)
    return server, client, viewer_url


def position(page, link):
    return page.js("return window.igms.linkPosition(arguments[0])", link)


def swing(page, link, seconds=1.0, period=0.05):
    """A link's positions over `seconds`: (their mean, the largest distance of one from it)."""
    samples = []
    for _ in range(int(seconds / period)):
        samples.append(position(page, link))
        time.sleep(period)
    mean = [sum(p[i] for p in samples) / len(samples) for i in range(3)]
    return mean, max(distance(p, mean) for p in samples)


def distance(a, b):
    return sum((x - y) ** 2 for x, y in zip(a, b)) ** 0.5


def open_page(driver, page_url):
    page = bs.Page(driver, page_url)
    bs.wait_for("the session's hello", lambda: page.state("hello"))
    page.wait_frames(5)
    return page


# How far below a standing box's top edge the drag presses its face: more than the tip's radius
# (scenes/puma_table.yaml, interaction.push.tip_radius: 1 cm).
BELOW_TOP_EDGE = 0.015


def push_box(checks, driver, page, box, start):
    """A drag on the box with the wheel turned 40 notches into the screen; how far the box moved, m.
    It presses the face that meets the camera most squarely, as a person would press it: on the face,
    not on its edge. (Under perspective the squarest pixel of a side face lies along its top edge; a
    tip of 1 cm radius pressed 1 mm below that edge is as near the top face as the side, and where its
    proxy settled on the top the push went down into the box and the table: 0.9 cm in 1 of 8 runs.)"""
    at = page.js("return window.igms.pointOnLink(arguments[0])", box)
    checks.check(at is not None, "the box is under some pixel", str(at))
    point = list(at["point"])
    point[2] = min(point[2], start[2] + 0.04 - BELOW_TOP_EDGE)  # the box stands: its top at z + 0.04
    at = page.js("return window.igms.screenOf(arguments[0])", point)
    at = {"x": round(at["x"]), "y": round(at["y"])}
    actions = ActionChains(driver)
    actions.w3c_actions.pointer_action.move_to_location(at["x"], at["y"])
    actions.w3c_actions.pointer_action.pointer_down()
    actions.w3c_actions.pointer_action.pause(0.1)
    actions.perform()
    for _ in range(40):  # 20 cm into the screen, a notch every 50 ms
        ActionChains(driver).scroll_from_origin(ScrollOrigin.from_viewport(at["x"], at["y"]), 0, 100).perform()
        time.sleep(0.05)
    # A busy page coalesces wheel events; the page counts the notches in their deltas.
    depth = page.js("const d = window.igms.device.drag; return d ? d.depth : null")
    checks.check(depth is not None and abs(depth - 0.2) < 1e-6, "every wheel notch moved the tip 5 mm deeper",
                 "depth %s m after 40 notches" % depth)
    # The box slides as the 1 kHz loop pushes; a slow machine may take a while.
    deadline = time.time() + 5.0
    while time.time() < deadline and distance(position(page, box), start) < 0.05:
        time.sleep(0.1)
    ActionChains(driver).release().perform()
    time.sleep(1.0)
    return distance(position(page, box), start)


def drag_start_survives_merging(checks, driver, page, box):
    """A busy machine hands the client a drag's first message (the jump to the picked point) with the next:
    the tip must still start at the picked point. (It used to start from where it was parked, 1.5 m up, and
    came down on the box's top: CI's first runs pushed the box 1-2 cm.)"""
    page.js("""const d = window.igms.device; const send = d.send; let held = null;
               window.igmsRestoreSend = () => { d.send = send; };
               d.send = (m) => { if (m.jump) { held = m; return; } if (held) { send(held); held = null; } send(m); };""")
    at = page.js("return window.igms.pointOnLink(arguments[0])", box)
    actions = ActionChains(driver)
    actions.w3c_actions.pointer_action.move_to_location(at["x"], at["y"])
    actions.w3c_actions.pointer_action.pointer_down()
    actions.w3c_actions.pointer_action.pause(0.1)
    actions.perform()
    ActionChains(driver).scroll_from_origin(ScrollOrigin.from_viewport(at["x"], at["y"]), 0, 100).perform()
    bs.wait_for("the drag's targets", lambda: page.frame()["device"]["active"], timeout=5, period=0.02)
    time.sleep(0.2)  # the loop has read them (a tip from the parked place would still be over a metre away)
    tip = page.frame()["device"]["tip"]
    ActionChains(driver).release().perform()
    page.js("window.igmsRestoreSend()")
    checks.check(distance(tip, at["point"]) < 0.05, "a drag whose first message came with the next starts at the "
                 "picked point", "tip %s, picked %s" % ([round(x, 3) for x in tip], [round(x, 3) for x in at["point"]]))
    time.sleep(1.0)


def table_and_push(checks, driver):
    server, client, device_url = start_session(scene("puma_table.yaml"))
    page = open_page(driver, device_url)
    hello = page.state("hello")
    names = [link["name"] for link in hello["links"]]
    obstacles = {o["name"]: o for o in hello["obstacles"]}
    checks.check(all(b in names for b in ("box_a", "box_b", "box_c")), "the hello describes the three boxes",
                 ", ".join(n for n in names if n.startswith("box")))
    checks.check(obstacles.get("table", {}).get("solid") and obstacles.get("ground", {}).get("kind") == "plane",
                 "the table is solid and the ground is drawn", str(sorted(obstacles)))
    # The arm's line crosses the table: wait until it is done and the boxes are at rest.
    bs.wait_for("the end of the nominal motion", lambda: page.frame()["t"] > hello["nominal_end"] + 0.5, timeout=20)
    drawn = bs.wait_for("contacts drawn", lambda: page.js(
        "const c = window.igms.contacts; return c.count > 0 && "
        "[c.count, c.total, c.arrowCount, document.getElementById('contacts').textContent]"), timeout=5)
    count, total, arrows, hud = drawn
    checks.check(total >= 12 and count == min(total, 512), "every contact is drawn (the boxes' corners on the table)",
                 "%d in the step, %d drawn, %d with a force arrow" % (total, count, arrows))
    # One friction per patch: the solve may carry a box on some of its corners only.
    checks.check(arrows >= 3, "the table's forces on the boxes are drawn as arrows", "%d arrows" % arrows)
    checks.check(hud == str(total), "the HUD counts them", hud)
    # The contact solve's counts, as the server's status gives them (igms-server, realtime).
    server_contact = page.frame()["server"]["contact"]
    solve_hud = page.js("return document.getElementById('contact-solve').textContent")
    checks.check(server_contact["solves"] > 1000 and
                 re.fullmatch(r"\d+ · \d+ unconverged · \d+ slips unturned", solve_hud) is not None,
                 "the HUD shows the contact solve's counts", "%s; the status: %s" % (solve_hud, server_contact))
    shown = page.canvas_pixels()
    ActionChains(driver).send_keys("c").perform()
    time.sleep(0.3)
    hidden = page.canvas_pixels()
    checks.check(not page.js("return window.igms.contacts.points.visible") and bs.differing_pixels(shown, hidden) > 5,
                 "key c hides the contacts", "%d pixels changed" % bs.differing_pixels(shown, hidden))
    ActionChains(driver).send_keys("c").perform()
    checks.check(bs.wait_for("contacts shown again", lambda: page.js("return window.igms.contacts.points.visible"),
                             timeout=2), "key c shows them again")

    # The box nearest the camera that is still on the table: a drag on it, the wheel turned into the screen.
    boxes = [names.index(b) for b in ("box_a", "box_b", "box_c")]
    on_table = [b for b in boxes if abs(position(page, b)[2] - 0.16) < 0.01]
    checks.check(len(on_table) >= 1, "a box stands on the table after the arm went by", str(on_table))
    box = on_table[0]
    start = position(page, box)
    moved = push_box(checks, driver, page, box, start)
    # 4.7-5.0 cm from where the arm's knock leaves box_a since the patches' limit surface (6.7-6.8 cm
    # before, from another pose); a press that fails, on the edge, moved it 0.9 cm.
    checks.check(moved > 0.03, "the drag pushed the box more than 3 cm",
                 "%.3f m from %s" % (moved, [round(x, 3) for x in start]))
    drag_start_survives_merging(checks, driver, page, box)
    step = page.frame()["client"]["max_force_step"]
    checks.check(step <= 1.0 + 1e-6, "the rendered force stepped by at most 1 N a cycle", "%.3f N" % step)
    for p in (client, server):
        procs.stop(p)


def lift_and_drop(checks, driver):
    server, client, device_url = start_session(scene("hand_table.yaml"))
    page = open_page(driver, device_url)
    names = [link["name"] for link in page.state("hello")["links"]]
    ball = names.index("ball")
    time.sleep(0.5)
    start = position(page, ball)
    at = page.js("return window.igms.pointOnLink(arguments[0])", ball)
    checks.check(at is not None, "the ball is under some pixel", str(at))
    actions = ActionChains(driver)
    actions.key_down(Keys.SHIFT)
    actions.w3c_actions.pointer_action.move_to_location(at["x"], at["y"])
    actions.w3c_actions.pointer_action.pointer_down()
    for k in range(1, 21):  # straight up the screen
        actions.w3c_actions.pointer_action.move_to_location(at["x"], at["y"] - 6 * k)
        actions.w3c_actions.pointer_action.pause(0.03)
    actions.perform()
    bs.wait_for("a frame in pull mode", lambda: page.frame()["mode"] == 2, timeout=5, period=0.02)
    time.sleep(1.5)
    lifted = position(page, ball)
    checks.check(page.frame()["input"]["attach_link"] == "ball" and lifted[2] > start[2] + 0.03,
                 "shift-drag lifts the ball with the pull spring",
                 "z %.3f -> %.3f m" % (start[2], lifted[2]))
    # Untrusted input while it hangs: a malformed message moves nothing and is counted. Held by one
    # point of its surface, the ball swings about it as a pendulum: sampled, its centre went 1.3 cm
    # either way along one line and rose 2 mm at both ends, as a 4.25 cm pendulum's does, with little
    # to damp it; two readings of its centre were once 3.3 cm apart. So its swing is sampled for a
    # second before and after, and must be the same swing.
    before_swing = swing(page, ball)
    before = bs.status(device_url)
    page.js("window.igms.send('{not json'); window.igms.send(JSON.stringify({type: 'device', tip: 'x'}));")
    after = bs.wait_for("the rejections counted", lambda: (lambda s: s if s["rejected_malformed"] >=
                                                          before["rejected_malformed"] + 2 else None)(
                                                              bs.status(device_url)), timeout=5)
    after_swing = swing(page, ball)
    # Applied, either would end the pull or move the tip, and the ball would drop or leap by tens of
    # cm: the swing's centre would move, or its reach grow.
    moved = distance(before_swing[0], after_swing[0])
    checks.check(moved < 0.02 and after_swing[1] < before_swing[1] + 0.02 and page.frame()["mode"] == 2,
                 "a malformed message changes nothing",
                 "%d malformed counted, still pulling, the swing's centre moved %.4f m, its reach %.4f -> %.4f m" % (
                     after["rejected_malformed"] - before["rejected_malformed"], moved, before_swing[1],
                     after_swing[1]))
    ActionChains(driver).release().key_up(Keys.SHIFT).perform()
    # Let go with some sideways speed, it may roll to the table's edge and drop to the ground (one
    # run in CI was still falling 3 s after the release): watched until still, for at most 10 s.
    time.sleep(2.0)
    for _ in range(16):
        z = []
        for _ in range(10):
            z.append(position(page, ball)[2])
            time.sleep(0.05)
        if max(z) - min(z) < 1e-3:
            break
    # At rest on the table (its top at 0.12 m) or on the ground (-0.4 m), if it rolled off.
    resting = any(abs(max(z) - top - 0.04) < 2e-3 for top in (0.12, -0.4))
    checks.check(max(z) < lifted[2] - 0.02 and max(z) - min(z) < 1e-3 and resting,
                 "let go, the ball falls and settles on a surface",
                 "z %.3f m when let go, %.4f .. %.4f m once still" % (lifted[2], min(z), max(z)))
    step = page.frame()["client"]["max_force_step"]
    checks.check(step <= 1.0 + 1e-6, "the rendered force stepped by at most 1 N a cycle", "%.3f N" % step)
    for p in (client, server):
        procs.stop(p)


def median_fps(page, seconds=4):
    """The page's frame rate (counted each second), the median over `seconds`."""
    fps = []
    for _ in range(seconds):
        time.sleep(1.0)
        fps.append(page.state("fps"))
    fps.sort()
    return 0.5 * (fps[(len(fps) - 1) // 2] + fps[len(fps) // 2]), fps


def pile_frame_rate(checks, driver):
    # Live: the viewer on the bus while igms-server steps the pile at 1 kHz on the same 2 cores
    # (and igms-logger records it for the replay below).
    log = os.path.join(work, "pile.lcmlog")
    logger = procs.start("tools/igms-logger", [log, "--lcm-url", url, "-q", "--wait-session-s", "0"])[0]
    server = procs.start("server/igms-server", ["--scene", scene("sphere_pile.yaml"), "--lcm-url", url, "--quiet",
                                                "--duration", "14"])[0]
    viewer, viewer_url = procs.start("tools/igms-viewer", ["--lcm-url", url, "--port", str(viewer_port)],
                                     first_line=True)
    page = open_page(driver, viewer_url)
    bs.wait_for("contacts drawn", lambda: (page.js("return window.igms.contacts.count") or 0) >= 216, timeout=10)
    time.sleep(3.0)  # past the switch to half resolution, when it comes
    live, samples = median_fps(page)
    checks.check(live >= 5.0, "live, the pile draws beside its 1 kHz simulation",
                 "%.1f fps median (%s), render scale %s" % (live, ", ".join("%.1f" % x for x in samples),
                                                             page.state("renderScale")))
    server.wait(timeout=30)
    time.sleep(0.5)
    for p in (viewer, logger):
        procs.stop(p)
    # Replayed: the page alone with the same frames (igms-viewer --log), as a person scrubs a recorded pile.
    viewer, viewer_url = procs.start("tools/igms-viewer", ["--log", log, "--port", str(viewer_port)], first_line=True)
    page = open_page(driver, viewer_url)
    if not page.js("return window.igms.state.frame.timeline.playing"):
        driver.find_element("id", "play").click()
    bs.wait_for("contacts drawn", lambda: (page.js("return window.igms.contacts.count") or 0) >= 216, timeout=10)
    time.sleep(3.0)
    replayed, samples = median_fps(page)
    links = len(page.state("hello")["links"])
    checks.check(replayed >= MIN_PILE_FPS,
                 "replayed, the 216-sphere pile with its contacts draws at >= %.0f fps" % MIN_PILE_FPS,
                 "%.1f fps median (%s), %d bodies, %d contacts drawn, render scale %s" % (
                     replayed, ", ".join("%.1f" % x for x in samples), links,
                     page.js("return window.igms.contacts.count"), page.state("renderScale")))
    print("pile_fps live %.1f replayed %.1f" % (live, replayed))
    procs.stop(viewer)


def logs_drawn_from_their_surface(checks, driver):
    server, client, device_url = start_session(scene("log_pile.yaml"))
    page = open_page(driver, device_url)
    links = page.state("hello")["links"]
    for name in ("left", "right", "top"):
        i = next(k for k, link in enumerate(links) if link["name"] == name)
        shape = links[i]["shapes"][0]
        sent = len(shape.get("surface", {}).get("triangles", [])) // 3
        drawn = page.js("""
            const T = window.igms.THREE, box = new T.Box3();
            let triangles = 0;
            window.igms.robot.links[arguments[0]].group.traverse((o) => {
              if (!o.isMesh) return;
              triangles += o.geometry.index.count / 3;
              o.geometry.computeBoundingBox();
              box.union(o.geometry.boundingBox);
            });
            return [triangles, box.min.toArray(), box.max.toArray()];""", i)
        r, half = shape["size"][0], 0.5 * shape["size"][1]
        extents = [r, r, half + r]
        off = max(abs(hi - e) + abs(lo + e) for lo, hi, e in zip(drawn[1], drawn[2], extents))
        checks.check(shape["kind"] == "capsule" and sent > 0 and drawn[0] == sent and off < 1e-6,
                     "the log '%s' is drawn from its surface's triangles" % name,
                     "%d sent, %d drawn, extents off by %.1e m" % (sent, drawn[0], off))
        at = page.js("return window.igms.pointOnLink(arguments[0])", i)
        checks.check(at is not None, "the log '%s' is under some pixel" % name, str(at))
    for p in (client, server):
        procs.stop(p)


def body(checks, open_browser):
    driver = open_browser()
    logs_drawn_from_their_surface(checks, driver)
    table_and_push(checks, driver)
    lift_and_drop(checks, driver)
    pile_frame_rate(checks, driver)


sys.exit(bs.run_test("environment_view_test", procs, work, body))
