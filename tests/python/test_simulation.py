"""igms.Scene and igms.Simulation from Python: the step is the server's (the same numbers as igms-scenario),
q and v are views, the contacts and the hands are what the step used, bad input raises before anything runs."""
import threading

import numpy as np
import pytest

import igms

G = 9.81


def box_slide():
    return igms.Simulation(igms.Scene.load("scenes/box_slide.yaml"))


def test_a_sliding_box_stops_where_coulomb_says():
    sim = box_slide()
    sim.step(400)
    assert sim.steps == 400 and sim.time == pytest.approx(0.4)
    # The step's own solution (contact_analytic_test): v_k = v0 - k a h while positive, x = h sum v_k.
    h, v0, a = 0.001, 1.0, 0.5 * G
    x = sum(h * (v0 - k * a * h) for k in range(1, 10000) if v0 - k * a * h > 0)
    box = sim.body("box")
    assert box.position[0] == pytest.approx(x, abs=1e-9)
    assert np.linalg.norm(box.velocity) < 1e-9
    assert sim.q[0] == box.position[0]


def test_the_same_numbers_as_the_scenario_runner():
    scene = igms.Scene.load("scenes/box_slide.yaml")
    sim = igms.Simulation(scene)
    sim.step(300)
    run = igms.run_scenario(scene, None, 0.3)
    np.testing.assert_array_equal(run["samples"]["q"][-1], sim.q)
    assert run["q_columns"] == sim.coordinate_names


def test_q_and_v_are_views_that_follow_the_steps():
    sim = box_slide()
    q, v = sim.q, sim.v
    assert not q.flags.writeable and not q.flags.owndata
    before = q.copy()
    sim.step(10)
    assert q[0] > before[0]  # the same memory, stepped
    assert np.shares_memory(q, sim.q)
    with pytest.raises(ValueError):
        q[0] = 1.0


def test_set_state_puts_the_body_where_asked():
    sim = box_slide()
    q = np.array([0.5, 0.2, 0.3, 1, 0, 0, 0])
    v = np.array([0, 0, 0, 0, 0, 1.0])
    sim.set_state(q, v)
    np.testing.assert_array_equal(sim.q, q)
    np.testing.assert_array_equal(sim.v, v)
    np.testing.assert_allclose(sim.body("box").pose[:3, 3], q[:3])
    sim.step(100)  # it falls 0.2 m: 0.1 s of free fall touches nothing
    assert sim.q[2] == pytest.approx(0.3 - 0.5 * G * 0.1**2, abs=2e-3)


def test_contacts_hold_the_weight():
    scene = igms.Scene.from_yaml(open("scenes/box_slide.yaml").read().replace("v: [1, 0, 0]", "v: [0, 0, 0]"),
                                 base_dir="scenes")
    sim = igms.Simulation(scene)
    sim.step(200)
    c = sim.contacts()
    assert c.dtype.names == ("body_a", "body_b", "geom_a", "geom_b", "point", "normal", "impulse", "depth")
    assert len(c) == 4 and set(c["geom_b"]) == {"ground"} and set(c["body_b"]) == {"world"}
    # The four corners carry m g h between them; the normal points from the box into the ground.
    assert np.sum(c["impulse"] @ np.array([0, 0, -1.0])) == pytest.approx(1.0 * G * 0.001, rel=1e-9)
    np.testing.assert_allclose(c["normal"], np.tile([0, 0, -1.0], (4, 1)), atol=1e-12)
    assert np.all(np.abs(c["depth"]) < 1e-9)
    s = sim.summary()
    assert s["max_contacts"] == 4 and s["contact_solve"]["solves"] == 200 and s["contact_solve"]["unconverged"] == 0
    # nothing slips on a resting box: no friction to turn against a slip
    assert s["contact_solve"]["slips_unturned"] == 0 and s["contact_solve"]["max_slip_angle"] == 0.0
    assert s["contact_solve"]["polish_cycles"] == 0
    np.testing.assert_array_equal(s["bodies"]["box"]["end"], sim.q)
    np.testing.assert_array_equal(s["bodies"]["box"]["start"], [0, 0, 0.1, 1, 0, 0, 0])


def test_a_hand_pushes_as_the_bus_would():
    scene = igms.Scene.load("scenes/box_push.yaml")
    sim = igms.Simulation(scene)
    sim.step(10)
    assert sim.hands.active == []
    sim.hands.push(tip=[-0.105, 0, 0.1], client=1)  # 5 mm into the box's -x face (tip radius 1 cm)
    sim.step(1)
    out = sim.hands.outcome()
    assert [h["client"] for h in out] == [1] and out[0]["mode"] == "push"
    # c = k_p d (eq. 3), 15 N, less the coupling's damper and the box's give over the step: the implicit step
    # takes the spring at its end.
    assert 0.97 * 3000 * 0.005 < out[0]["force"][0] < 3000 * 0.005
    np.testing.assert_allclose(out[0]["force"][1:], 0, atol=1e-9)
    sim.step(200)
    assert sim.body("box").position[0] > 1e-4  # it moved away from the hand
    sim.hands.release(1)
    sim.step(1)
    assert sim.hands.outcome() == [] and sim.hands.active == []
    # The summary lists the push: one stretch, from the first step it acted to its last.
    (push,) = sim.summary()["interactions"]
    assert push["client"] == 1 and push["mode"] == "push"
    assert push["start"] == pytest.approx(0.011) and push["end"] == pytest.approx(0.211)
    assert 14 < push["max_force"] < 15.01


def test_hand_input_the_gate_rejects_raises():
    sim = igms.Simulation(igms.Scene.load("scenes/box_push.yaml"))
    with pytest.raises(ValueError, match="UnknownLink|unknown"):
        sim.hands.push(tip=[0, 0, 0.1], link="no_such_link")
    with pytest.raises(ValueError, match="not finite"):
        sim.hands.push(tip=[0, np.nan, 0.1])
    with pytest.raises(ValueError, match="Range|range"):
        sim.hands.push(tip=[0, 0, 0.1], radius=5.0)
    with pytest.raises(ValueError, match="client"):
        sim.hands.push(tip=[0, 0, 0.1], client=7)
    assert sim.hands.active == []


def test_bad_state_and_names_raise_before_anything_runs():
    sim = box_slide()
    with pytest.raises(ValueError, match=r"q: expected shape \(7,\), got \(3,\)"):
        sim.set_state(np.zeros(3), np.zeros(6))
    with pytest.raises(ValueError, match=r"q\[6\] is not finite"):
        sim.set_state([0, 0, 0.1, 1, 0, 0, np.nan], np.zeros(6))
    with pytest.raises(TypeError, match="dtype"):
        sim.set_state(["x"] * 7, np.zeros(6))
    with pytest.raises(KeyError, match="no body or link 'ball'.*box"):
        sim.body("ball")
    with pytest.raises(ValueError, match="n must be >= 0"):
        sim.step(-1)
    assert sim.steps == 0 and sim.q[2] == 0.1


def test_scene_errors_name_the_file_line_and_key(tmp_path):
    with pytest.raises(igms.SceneError, match="nope.yaml"):
        igms.Scene.load("nope.yaml")
    bad = tmp_path / "bad.yaml"
    bad.write_text("name: x\nground: {height: 0}\nbodies:\n  - {name: b, shape: box, size: [1, 1], mass: 1}\n")
    with pytest.raises(igms.SceneError, match=r"bad.yaml:4: bodies\[0\].size: expected 3 numbers"):
        igms.Scene.load(str(bad))
    with pytest.raises(igms.SceneError, match="<string>"):
        igms.Scene.from_yaml("name: [")


def test_a_diverging_state_raises_and_stays_at_the_last_good_one():
    # A pendulum-free check: a free body thrown at 1e200 m/s overflows the state.
    sim = igms.Simulation(igms.Scene.load("scenes/box_push.yaml"))
    sim.set_state([0, 0, 5, 1, 0, 0, 0], [1e300, 0, 0, 0, 0, 0])
    with pytest.raises(igms.SimulationDiverged):
        sim.step(100)
    assert sim.diverged and np.all(np.isfinite(sim.q))


def test_two_threads_give_the_serial_numbers():
    scene = igms.Scene.load("scenes/sphere_pile.yaml")
    serial = igms.Simulation(scene)
    serial.step(300)
    sims = [igms.Simulation(scene) for _ in range(2)]
    threads = [threading.Thread(target=s.step, args=(300,)) for s in sims]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for s in sims:
        np.testing.assert_array_equal(s.q, serial.q)


def test_one_simulation_is_not_stepped_by_two_threads_at_once():
    sim = igms.Simulation(igms.Scene.load("scenes/sphere_pile.yaml"))
    errors = []

    def step():
        try:
            sim.step(2000)
        except RuntimeError as e:
            errors.append(str(e))

    threads = [threading.Thread(target=step) for _ in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == ["this Simulation is already stepping on another thread"]
    assert sim.steps == 2000


def test_a_log_re_simulates_bit_for_bit():
    log = igms.Log("tests/replay/data/push.lcmlog")
    assert log.has_session and not log.damaged
    inputs = log.inputs
    assert len(inputs["seq"]) > 100 and inputs["tip_position"].shape == (len(inputs["seq"]), 3)
    assert set(inputs["mode"]) <= {0, 1, 2} and 1 in set(inputs["mode"])  # it pushes
    states = log.states
    assert states["q"].shape[0] == len(states["t"]) > 100
    r = igms.resimulate(log)
    assert r["ok"] and r["identical"], r
    assert r["steps"] >= len(states["t"]) - 1  # every step after the initial state
    np.testing.assert_array_equal(r["final_q"], states["q"][-1])
    with pytest.raises(igms.LogError):
        igms.Log("no_such.lcmlog")
