#!/usr/bin/env python3
"""MuJoCo on igms's contact scenes: the same models and shapes as MJCF, for the
contact benchmark (bench/contact_bench.cc times mj_step beside igms's step) and
for the comparison of what each does (creep, sinking, stopping distance, bounce).

Runs in .venv-peers (PyPI mujoco 4.0; scripts/setup/peer_env.sh).
  contact_peers.py --scene scenes/go1_stand.yaml [--scene ...] --out DIR   writes DIR/NAME.xml
  contact_peers.py --scene ... --out DIR --measure [--json FILE]            also runs them and prints the rows
  contact_peers.py --accuracy CASES --csv FILE [--quick]     MuJoCo on igms-accuracy --contact's cases
      (igms-accuracy --contact --write-cases CASES): each case's error against its analytic answer and
      mj_step's run time per simulated second (mujoco.rollout, median of 3), h = 0.25 .. 4 ms, with its
      Euler and its implicit integrator

What is translated, and how (MuJoCo's own defaults otherwise: soft contact, solref
(0.02, 1), pyramidal cone, Newton solver, a 1 ms step):
  robot: its URDF (visuals dropped, meshes by absolute path, igms's robot.collision
    overrides applied), a freejoint on its root if floating; an inertia MuJoCo finds not
    positive definite has its off-diagonal terms zeroed (Go1's base link); a PD controller
    becomes position actuators (kp) with joint damping kd (implicit in MuJoCo's Euler, as igms takes
    its PD implicitly); robot geoms touch the rest of the
    world, not each other (igms's self_collision off).
  free bodies, the ground plane, solid obstacles: the same primitives, masses, inertias and poses; a
    mesh as a mesh asset, which MuJoCo collides by its convex hull.
  friction: each geom its material's mu (MuJoCo takes the larger of a pair; the scenes here
    use one material per contact pair, so the rule does not matter); restitution has no
    MuJoCo counterpart and is left out.
"""
import argparse
import json
import math
import os
import re
import sys

import mujoco
import numpy as np
import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def rpy_quat(rpy):
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = math.cos(r / 2), math.sin(r / 2), math.cos(p / 2), math.sin(p / 2), math.cos(y / 2), math.sin(y / 2)
    return [cr * cp * cy + sr * sp * sy, sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy]


def pose(d):
    return list(d.get("xyz", [0, 0, 0])), rpy_quat(d.get("rpy", [0, 0, 0]))


def material(scene, name):
    m = {"friction": 1.0, "restitution": 0.0}
    m.update((scene.get("materials") or {}).get(name or "default", {}))
    return m


def add_shape(body, d, mu, geom_class):
    kind = d["shape"]
    pos, quat = pose(d)
    if kind == "box":
        g = body.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=[s / 2 for s in d["size"]], pos=pos, quat=quat)
    elif kind == "sphere":
        g = body.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[d["radius"], 0, 0], pos=pos, quat=quat)
    elif kind == "cylinder":
        g = body.add_geom(type=mujoco.mjtGeom.mjGEOM_CYLINDER, size=[d["radius"], d["length"] / 2, 0], pos=pos, quat=quat)
    elif kind == "capsule":
        g = body.add_geom(type=mujoco.mjtGeom.mjGEOM_CAPSULE, size=[d["radius"], d["length"] / 2, 0], pos=pos, quat=quat)
    elif kind == "mesh":
        # MuJoCo collides a mesh by its convex hull.
        spec = body.spec if hasattr(body, "spec") else None
        name = "mesh_" + os.path.splitext(os.path.basename(d["file"]))[0] + f"_{id(d)}"
        MESHES.append((name, d["file"], d.get("scale", [1, 1, 1])))
        g = body.add_geom(type=mujoco.mjtGeom.mjGEOM_MESH, meshname=name, pos=pos, quat=quat)
    else:
        raise SystemExit(f"contact_peers: shape {kind} is not translated")
    g.friction = [mu, 0.005, 0.0001]
    g.contype, g.conaffinity = geom_class
    return g


MESHES = []  # (name, file, scale) the geoms built so far refer to: build() adds them to its spec


def fix_inertias(urdf):
    """Zero the off-diagonal terms of an inertia that is not positive definite (MuJoCo refuses it)."""
    def fix(m):
        attrs = dict(re.findall(r'(\w+)="([^"]*)"', m.group(0)))
        I = np.array([[float(attrs.get("ixx", 0)), float(attrs.get("ixy", 0)), float(attrs.get("ixz", 0))],
                      [float(attrs.get("ixy", 0)), float(attrs.get("iyy", 0)), float(attrs.get("iyz", 0))],
                      [float(attrs.get("ixz", 0)), float(attrs.get("iyz", 0)), float(attrs.get("izz", 0))]])
        if np.linalg.eigvalsh(I).min() > 0:
            return m.group(0)
        d = [max(I[i, i], 1e-9) for i in range(3)]
        return f'<inertia ixx="{d[0]}" ixy="0" ixz="0" iyy="{d[1]}" iyz="0" izz="{d[2]}"/>'
    return re.sub(r"<inertia\s[^>]*/>", fix, urdf)


def robot_spec(scene, scene_dir, robot):
    path = os.path.normpath(os.path.join(scene_dir, robot["model"]))
    urdf = open(path).read()
    urdf = re.sub(r"<visual>.*?</visual>", "", urdf, flags=re.S)
    pkg = os.path.join(ROOT, "third_party")
    urdf = urdf.replace("package:///example-robot-data/", "package://example-robot-data/")
    urdf = urdf.replace("package://example-robot-data/", os.path.join(pkg, "example-robot-data") + "/")
    urdf = re.sub(r'filename="(?!/)([^"]+)"', lambda m: f'filename="{os.path.join(os.path.dirname(path), m.group(1))}"', urdf)
    # igms's collision overrides: a link's shapes instead of (or with) the URDF's.
    overrides = robot.get("collision") or {}
    for link, shapes in overrides.items():
        if "from_urdf" not in shapes:
            urdf = re.sub(rf'(<link name="{link}"[^>]*>.*?)(<collision>.*?</collision>\s*)+(.*?</link>)', r"\1\3", urdf,
                          count=1, flags=re.S)
    urdf = fix_inertias(urdf)
    urdf = re.sub(r"(<robot[^>]*>)", r'\1<mujoco><compiler discardvisual="true" strippath="false" fusestatic="false"/></mujoco>',
                  urdf, count=1)
    spec = mujoco.MjSpec.from_string(urdf)
    mu = material(scene, robot.get("material"))["friction"]
    for g in spec.geoms:
        g.friction = [mu, 0.005, 0.0001]
        g.contype, g.conaffinity = 1, 0  # the world, not itself
    for link, shapes in overrides.items():
        body = spec.body(link)
        for s in shapes:
            if s != "from_urdf":
                add_shape(body, s, mu, (1, 0))
    if robot.get("floating_base"):
        spec.worldbody.first_body().add_freejoint()
    return spec


def build(scene_path):
    scene = yaml.safe_load(open(scene_path))
    scene_dir = os.path.dirname(os.path.abspath(scene_path))
    robot = scene.get("robot")
    if scene.get("robots"):
        raise SystemExit("contact_peers: several robots are not translated")
    spec = robot_spec(scene, scene_dir, robot) if robot else mujoco.MjSpec()
    spec.modelname = scene.get("name", "scene")
    sim = scene.get("simulation") or {}
    spec.option.timestep = sim.get("dt", 0.001)
    spec.option.gravity = scene.get("gravity", [0, 0, -9.81])
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_EULER
    world = spec.worldbody
    MESHES.clear()
    ground = scene.get("ground")
    if ground:
        g = ground if isinstance(ground, dict) else {}
        gp = world.add_geom(type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0, 0, 1], pos=[0, 0, g.get("height", 0)],
                            quat=rpy_quat(g.get("rpy", [0, 0, 0])))
        gp.friction = [material(scene, g.get("material"))["friction"], 0.005, 0.0001]
        gp.contype, gp.conaffinity = 1, 1
    for o in scene.get("obstacles") or []:
        if o.get("solid"):
            add_shape(world, o, material(scene, o.get("material"))["friction"], (1, 1))
    for b in scene.get("bodies") or []:
        pos, quat = pose(b)
        body = world.add_body(name=b["name"], pos=pos, quat=quat)
        body.add_freejoint()
        d = dict(b)
        d.pop("xyz", None)
        d.pop("rpy", None)
        g = add_shape(body, d, material(scene, b.get("material"))["friction"], (1, 1))
        if "inertia" in b:  # igms: [ixx, iyy, izz, ixy, ixz, iyz] about the centre of mass, body axes
            body.explicitinertial = True
            body.mass = b.get("mass", 1.0)
            body.ipos = [0, 0, 0]
            i = b["inertia"]
            body.fullinertia = [i[0], i[1], i[2], i[3], i[4], i[5]]
            g.mass = 0
            g.density = 0
        elif "mass" in b:
            g.mass = b["mass"]
    for name, path, scale in MESHES:
        spec.add_mesh(name=name, file=os.path.normpath(os.path.join(scene_dir, path)), scale=scale)
    actuated = []
    controller = scene.get("controller") or {}
    if robot and controller.get("kind") == "pd":
        kp, kd = controller.get("kp", 100), controller.get("kd", 20)
        for j in spec.joints:
            if j.type == mujoco.mjtJoint.mjJNT_HINGE or j.type == mujoco.mjtJoint.mjJNT_SLIDE:
                a = spec.add_actuator(name="pd_" + j.name, target=j.name, trntype=mujoco.mjtTrn.mjTRN_JOINT)
                a.gaintype = mujoco.mjtGain.mjGAIN_FIXED
                a.biastype = mujoco.mjtBias.mjBIAS_AFFINE
                a.gainprm[0] = kp
                a.biasprm[0:3] = [0, -kp, 0]
                j.damping = [kd, 0, 0]  # MuJoCo's Euler takes joint damping implicitly, as igms takes its PD's kd
                actuated.append(j.name)
    model = spec.compile()
    # The initial state: igms's q (a free root's quaternion w first, as MuJoCo's), then the free bodies.
    data = mujoco.MjData(model)
    q0 = (scene.get("initial") or {}).get("q")
    ctrl = np.zeros(model.nu)
    if robot:
        if q0:
            # igms orders a robot's joints depth-first with a link's children by joint name; map by name.
            order = igms_joint_order(robot, scene_dir)
            offset = 7 if robot.get("floating_base") else 0
            if robot.get("floating_base"):
                data.qpos[0:7] = q0[0:7]
            for k, name in enumerate(order):
                data.qpos[model.joint(name).qposadr[0]] = q0[offset + k]
        for i, name in enumerate(actuated):
            ctrl[i] = data.qpos[model.joint(name).qposadr[0]]
    data.ctrl[:] = ctrl
    for b in scene.get("bodies") or []:
        adr = model.joint(model.body(b["name"]).jntadr[0]).qposadr[0]
        data.qpos[adr:adr + 3] = pose(b)[0]
        data.qpos[adr + 3:adr + 7] = pose(b)[1]
        vadr = model.joint(model.body(b["name"]).jntadr[0]).dofadr[0]
        v = b.get("v", [0, 0, 0])
        R = np.zeros(9)
        mujoco.mju_quat2Mat(R, np.array(pose(b)[1]))
        data.qvel[vadr:vadr + 3] = v
        data.qvel[vadr + 3:vadr + 6] = R.reshape(3, 3).T @ np.array(b.get("w", [0, 0, 0]))  # MuJoCo: local angular
    spec.add_key(name="start", qpos=data.qpos.copy(), qvel=data.qvel.copy(), ctrl=ctrl)
    return scene, spec, spec.compile()


def igms_joint_order(robot, scene_dir):
    """igms's joint order (scripts/lib sees igms-dyn info's order)."""
    import subprocess
    exe = os.path.join(ROOT, "build", "tools", "igms-dyn")
    args = [exe, "info", "--model", os.path.normpath(os.path.join(scene_dir, robot["model"]))]
    if robot.get("floating_base"):
        args.append("--floating-base")
    info = json.loads(subprocess.run(args, capture_output=True, text=True, check=True).stdout)
    return [j["name"] for j in info["joints"] if j["name"] != "root_joint"]


def measure(scene, model, seconds):
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, 0)
    steps = int(round(seconds / model.opt.timestep))
    pen, ncon = 0.0, 0
    first = None
    bodies = [b["name"] for b in scene.get("bodies") or []]
    speed = 0.0
    for k in range(steps):
        mujoco.mj_step(model, data)
        ncon = max(ncon, data.ncon)
        if data.ncon:
            pen = max(pen, -min(data.contact[i].dist for i in range(data.ncon)))
        if k == steps // 2:
            first = data.qpos.copy()
        if k > steps // 2:
            for b in bodies:
                speed = max(speed, np.linalg.norm(data.qvel[model.joint(model.body(b).jntadr[0]).dofadr[0]:][:3]))
    normal = 0.0
    for i in range(data.ncon):
        f = np.zeros(6)
        mujoco.mj_contactForce(model, data, i, f)
        normal += f[0]
    drift = float(np.linalg.norm(data.qpos[:3] - first[:3]))
    return {"contacts": int(ncon), "penetration": pen, "normal_force": normal,
            "drift_second_half": drift, "speed_second_half": speed,
            "final_qpos_head": [float(x) for x in data.qpos[:7]]}


G = 9.81
# MuJoCo's integrators each case runs with: Euler (its default: Coriolis and gyroscopic terms explicit)
# and implicit (their derivatives in the step's matrix).
INTEGRATORS = [("mujoco_euler", mujoco.mjtIntegrator.mjINT_EULER), ("mujoco_implicit", mujoco.mjtIntegrator.mjINT_IMPLICIT)]


def case_error(name, t, pos, vel, angvel):
    """The error igms-accuracy --contact measures (tools/accuracy/contact_accuracy.cc), on MuJoCo's run
    (angvel: the free joint's, in the body frame)."""
    if name == "free_top":  # I (1, 1, 0.3), w (2, 0, 50): 377 J
        w, v = angvel[-1], vel[-1]
        energy = 0.5 * (w[0] ** 2 + w[1] ** 2 + 0.3 * w[2] ** 2) + 0.5 * float(v @ v)
        return abs(energy - 377.0) / 377.0
    if name == "box_slide":
        return abs(pos[-1, 0] - 1.0 / (2 * 0.5 * G))
    if name == "box_slope":
        k = int(np.searchsorted(t, 0.5 + 1e-9)) - 1
        return float(np.linalg.norm(pos[-1] - pos[k]) / (t[-1] - t[k]))
    if name == "sphere_roll":
        a = 5.0 / 7.0 * G * math.sin(math.radians(15))
        return abs(np.linalg.norm(vel[-1]) - a) / a
    if name == "ball_on_mesh":
        return abs(pos[-1, 2] - (0.4 + 0.03))
    if name == "ball_bounce":
        up = np.nonzero(vel[:, 2] > 0)[0]
        if len(up) == 0:
            return 1.0  # never rebounds: the whole e^2 missed
        after = vel[up[0]:, 2]
        down = np.nonzero(after < 0)[0]
        end = up[0] + (down[0] + 1 if len(down) else len(after))
        return abs(pos[up[0]:end, 2].max() - 0.05 - 0.25) / 0.25
    raise SystemExit(f"contact_peers: no measure for case {name}")


def accuracy(cases_dir, csv_path, quick):
    from mujoco import rollout
    import time
    steps = [0.5e-3, 1e-3, 2e-3] if quick else [0.25e-3, 0.5e-3, 1e-3, 2e-3, 4e-3]
    rows = ["case,engine,h_ms,error,unit,wall_s_per_sim_s,failed"]
    index = os.path.join(cases_dir, "cases.json")
    if not os.path.exists(index):
        raise SystemExit(f"contact_peers: {index} missing (igms-accuracy --contact --write-cases {cases_dir})")
    for name, case in json.load(open(index)).items():
        path = os.path.join(cases_dir, name + ".yaml")
        seconds, unit = case["seconds"], case["unit"]
        scene, spec, model = build(path)
        for h, (engine, integrator) in ((h, e) for h in steps for e in INTEGRATORS):
            model.opt.timestep = h
            model.opt.integrator = integrator
            data = mujoco.MjData(model)
            mujoco.mj_resetDataKeyframe(model, data, 0)
            mujoco.mj_forward(model, data)
            kind = mujoco.mjtState.mjSTATE_FULLPHYSICS
            state = np.empty(mujoco.mj_stateSize(model, kind))
            mujoco.mj_getState(model, data, state, kind)
            n = int(round(seconds / h))
            walls = []
            for _ in range(1 if quick else 3):
                t0 = time.perf_counter()
                out, _ = rollout.rollout(model, data, state[None, :], nstep=n)
                walls.append(time.perf_counter() - t0)
            traj = out[0]
            t = traj[:, 0]
            pos = traj[:, 1:4]
            vel = traj[:, 1 + model.nq:1 + model.nq + 3]
            angvel = traj[:, 1 + model.nq + 3:1 + model.nq + 6]
            failed = not np.all(np.isfinite(traj))
            err = float("nan") if failed else case_error(name, t, pos, vel, angvel)
            cost = sorted(walls)[len(walls) // 2] / seconds
            rows.append(f"{name},{engine},{h * 1e3:.17g},{err:.17g},{unit},{cost:.17g},{int(failed)}")
            print(f"  {name:12s} {engine:15s} h={h * 1e3:6.3f} ms  error {err:<10.3g} {unit}  {cost:.3g} s per s")
    with open(csv_path, "w") as f:
        f.write("\n".join(rows) + "\n")


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--accuracy", metavar="CASES", help="MuJoCo on igms-accuracy --contact's cases in CASES")
    p.add_argument("--csv", help="with --accuracy: the rows here")
    p.add_argument("--quick", action="store_true")
    p.add_argument("--scene", action="append")
    p.add_argument("--out")
    p.add_argument("--measure", action="store_true")
    p.add_argument("--seconds", type=float, default=10.0)
    p.add_argument("--json")
    a = p.parse_args()
    if a.accuracy:
        if not a.csv:
            p.error("--accuracy needs --csv")
        accuracy(a.accuracy, a.csv, a.quick)
        return
    if not a.scene or not a.out:
        p.error("--scene and --out are needed (or --accuracy)")
    os.makedirs(a.out, exist_ok=True)
    rows = {}
    for path in a.scene:
        scene, spec, model = build(path)
        name = scene.get("name", os.path.splitext(os.path.basename(path))[0])
        with open(os.path.join(a.out, name + ".xml"), "w") as f:
            f.write(spec.to_xml())
        print(f"contact_peers: {name}: nq {model.nq}, nv {model.nv}, {model.ngeom} geoms -> {a.out}/{name}.xml",
              file=sys.stderr)
        if a.measure:
            rows[name] = measure(scene, model, a.seconds)
            print(name, json.dumps(rows[name]))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
