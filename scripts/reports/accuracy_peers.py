#!/usr/bin/env python3
"""The accuracy report's independent engines, on the cases igms wrote
(`igms-accuracy --write-cases DIR`: <case>.urdf + <case>.json, in igms's
coordinate order). Runs in .venv-peers (scripts/setup/peer_env.sh: PyPI pin, mujoco,
scipy), never inside igms.

1. The independent truth: SciPy's DOP853 (adaptive, 8th order) on Pinocchio's
   articulated-body algorithm, rtol = atol = 1e-12, checked against itself at
   1e-13; written as <case>.truth.json (q, v, end effector every 32 ms). The
   pull's force from Pinocchio's frame Jacobian; the push's from the link's
   collision cylinder as Pinocchio reads it, with eq. 3 written here anew.
2. MuJoCo on the same axes: Euler (semi-implicit, damping implicit), implicit,
   implicitfast and RK4, from the same URDF and initial state, contacts and
   constraints (limits) off, over the same steps; errors against the
   independent truth, as rows in igms-accuracy's CSV format (mujoco.csv).
   MuJoCo's compiler rebalances inertias that break the triangle inequality
   (the PUMA's link 3) and bounds zero masses (its link 1): the exact URDF
   masses and inertias are written back after compiling, and the joint-space
   inertia matrix and bias forces at q0 are compared with Pinocchio's
   (peers.json), so both engines integrate the same equations.

Usage: accuracy_peers.py CASES_DIR [--quick] [--repeats N]
"""
import argparse
import json
import os
import platform
import re
import sys
import time

import mujoco
import numpy as np
import pinocchio as pin
from mujoco import rollout
from scipy.integrate import solve_ivp

RTOL = 1e-12
INTEGRATORS = [("mujoco_euler", mujoco.mjtIntegrator.mjINT_EULER),
               ("mujoco_implicit", mujoco.mjtIntegrator.mjINT_IMPLICIT),
               ("mujoco_implicitfast", mujoco.mjtIntegrator.mjINT_IMPLICITFAST),
               ("mujoco_rk4", mujoco.mjtIntegrator.mjINT_RK4)]
CSV_HEADER = ("case,method,h_ms,q_rms,q_max,ee_max,energy_drift,linear_momentum_drift,angular_momentum_drift,"
              "wall_s_per_sim_s,diverged,timing_runs,wall_s_per_sim_s_min,wall_s_per_sim_s_max,energy_rate_w,q_max_per_joint")


class Case:
    """One case: its Pinocchio model and the maps between igms's and Pinocchio's coordinates."""

    def __init__(self, path):
        self.dir = os.path.dirname(path)
        self.spec = json.load(open(path))
        s = self.spec
        self.name = s["name"]
        self.urdf_path = os.path.join(self.dir, s["urdf"])
        self.floating = s["floating_base"]
        root = pin.JointModelFreeFlyer()
        self.model = (pin.buildModelFromUrdf(self.urdf_path, root) if self.floating
                      else pin.buildModelFromUrdf(self.urdf_path))
        self.model.gravity.linear = np.array(s["gravity"])
        self.data = self.model.createData()
        self.nq, self.nv = s["nq"], s["nv"]
        if (self.model.nq, self.model.nv) != (self.nq, self.nv):
            sys.exit(f"{path}: Pinocchio reads nq {self.model.nq}, nv {self.model.nv}; igms has {self.nq}, {self.nv}")
        # Revolute and prismatic joints by name: (igms q, igms v, Pinocchio q, Pinocchio v).
        self.scalar = []
        for j in s["joints"]:
            if j["type"] == "floating":
                continue
            jid = self.model.getJointId(j["name"])
            if jid >= self.model.njoints:
                sys.exit(f"{path}: joint '{j['name']}' is not in Pinocchio's model of {self.urdf_path}")
            jm = self.model.joints[jid]
            self.scalar.append((j["q_index"], j["v_index"], jm.idx_q, jm.idx_v))
        self.iq = np.array([t[0] for t in self.scalar], dtype=int)
        self.iv = np.array([t[1] for t in self.scalar], dtype=int)
        self.pq = np.array([t[2] for t in self.scalar], dtype=int)
        self.pv = np.array([t[3] for t in self.scalar], dtype=int)
        self.damping = self.v_to_pin(np.array(s["damping"]))
        self.ee = self.model.getFrameId(s["ee_frame"])
        if self.ee >= len(self.model.frames):
            sys.exit(f"{path}: no frame '{s['ee_frame']}' in Pinocchio's model")
        self.q0, self.v0 = self.q_to_pin(np.array(s["q0"])), self.v_to_pin(np.array(s["v0"]))
        self.hand = s.get("hand")
        if self.hand:
            self.hand_frame = self.model.getFrameId(self.hand["link"])
            self.hand_point, self.hand_tip = np.array(self.hand["point"]), np.array(self.hand["tip"])
            self.push = self.hand["mode"] == "push"
            if self.push:  # the link's collision cylinder, read from the URDF by Pinocchio (coal shapes)
                geoms = pin.buildGeomFromUrdf(self.model, self.urdf_path, pin.GeometryType.COLLISION)
                mine = [o for o in geoms.geometryObjects
                        if self.model.frames[o.parentFrame].name == self.hand["link"]]
                if len(mine) != 1 or type(mine[0].geometry).__name__ != "Cylinder":
                    sys.exit(f"{path}: the push's truth needs one collision cylinder on {self.hand['link']}")
                self.cylinder = mine[0]
        self.samples = int(round(s["duration"] / s["sample"])) + 1
        self.t = np.arange(self.samples) * s["sample"]

    # igms: floating base [p, w x y z]; Pinocchio: [p, x y z w]. Velocities are
    # both body-frame [linear, angular].
    def q_to_pin(self, q):
        out = np.empty(self.nq)
        if self.floating:
            out[0:3], out[3:6], out[6] = q[0:3], q[4:7], q[3]
        out[self.pq] = q[self.iq]
        return out

    def q_to_igms(self, q):
        out = np.empty(self.nq)
        if self.floating:
            out[0:3], out[3], out[4:7] = q[0:3], q[6], q[3:6]
        out[self.iq] = q[self.pq]
        return out

    def v_to_pin(self, v):
        out = np.empty(self.nv)
        if self.floating:
            out[0:6] = v[0:6]
        out[self.pv] = v[self.iv]
        return out

    def v_to_igms(self, v):
        out = np.empty(self.nv)
        if self.floating:
            out[0:6] = v[0:6]
        out[self.iv] = v[self.pv]
        return out

    def normalized(self, q):
        if self.floating:
            q = q.copy()
            q[3:7] /= np.linalg.norm(q[3:7])
        return q

    def ee_position(self, q):
        pin.framesForwardKinematics(self.model, self.data, self.normalized(q))
        return self.data.oMf[self.ee].translation.copy()

    def pull_point(self, q):
        """The pull's attachment point (world) and its Jacobian (3 x nv, world axes), Pinocchio order."""
        J = pin.computeFrameJacobian(self.model, self.data, q, self.hand_frame, pin.LOCAL_WORLD_ALIGNED)
        X = self.data.oMf[self.hand_frame]
        r = X.rotation @ self.hand_point
        return X.translation + r, J[:3] - pin.skew(r) @ J[3:]

    def push_contact(self, q):
        """Eq. 3 on the link's cylinder, written here from its geometry: the tip sphere's depth d into it,
        the outward normal n and the surface point under the tip (world), and that point's Jacobian."""
        c = self.cylinder
        pin.forwardKinematics(self.model, self.data, q)
        X = self.data.oMi[c.parentJoint] * c.placement
        local = X.rotation.T @ (self.hand_tip - X.translation)
        radius, half = c.geometry.radius, c.geometry.halfLength
        rho = np.hypot(local[0], local[1])
        radial = np.array([local[0] / rho, local[1] / rho, 0.0]) if rho > 1e-15 else np.array([1.0, 0, 0])
        inside = rho <= radius and abs(local[2]) <= half
        if not inside:
            surface = radial * min(rho, radius) + np.array([0, 0, np.clip(local[2], -half, half)])
            normal = (local - surface) / np.linalg.norm(local - surface)
            distance = np.linalg.norm(local - surface)
        elif radius - rho < half - abs(local[2]):
            surface, normal = radial * radius + np.array([0, 0, local[2]]), radial
            distance = -(radius - rho)
        else:
            sign = 1.0 if local[2] >= 0 else -1.0
            surface, normal = np.array([local[0], local[1], sign * half]), np.array([0, 0, sign])
            distance = -(half - abs(local[2]))
        depth = self.hand["tip_radius"] - distance
        point = X.act(surface)
        pin.computeJointJacobians(self.model, self.data, q)
        J = pin.getJointJacobian(self.model, self.data, c.parentJoint, pin.LOCAL_WORLD_ALIGNED)
        r = point - self.data.oMi[c.parentJoint].translation
        return depth, X.rotation @ normal, J[:3] - pin.skew(r) @ J[3:]

    def energy(self, q, v):
        q = self.normalized(q)
        E = (pin.computeKineticEnergy(self.model, self.data, q, v) +
             pin.computePotentialEnergy(self.model, self.data, q))
        if self.hand and self.push:
            depth = self.push_contact(q)[0]
            E += 0.5 * self.hand["k"] * max(depth, 0.0) ** 2
        elif self.hand:
            x, _ = self.pull_point(q)
            E += 0.5 * self.hand["k"] * np.sum((self.hand_tip - x) ** 2)
        return E

    def momentum(self, q, v):
        """Spatial momentum about the world origin, world axes: [linear, angular]."""
        pin.forwardKinematics(self.model, self.data, self.normalized(q), v)
        total = pin.Force.Zero()
        for i in range(1, self.model.njoints):
            total += self.data.oMi[i].act(self.model.inertias[i] * self.data.v[i])
        return np.concatenate([total.linear, total.angular])


def rhs(case):
    m, d, nq, damping = case.model, case.data, case.nq, case.damping

    def f(_t, y):
        q, v = y[:nq], y[nq:]
        qn = case.normalized(q)
        tau = -damping * v
        if case.hand and case.push:  # eq. 3: c = k_p d into the link at the surface point, U_E = J^T c
            depth, n, Jp = case.push_contact(qn)
            if depth > 0:
                tau = tau + Jp.T @ (-case.hand["k"] * depth * n)
        elif case.hand:  # eq. 4: F = k (x_tip - x) - b xdot at the attachment point, tau = J^T F
            x, Jp = case.pull_point(qn)
            tau = tau + Jp.T @ (case.hand["k"] * (case.hand_tip - x) - case.hand["b"] * (Jp @ v))
        a = pin.aba(m, d, qn, v, tau)
        dq = np.empty(nq)
        dq[case.pq] = v[case.pv]
        if case.floating:
            quat = q[3:7]  # x y z w; its norm drifts only at the tolerance
            R = pin.Quaternion(qn[6], qn[3], qn[4], qn[5]).toRotationMatrix()
            w = v[3:6]
            dq[0:3] = R @ v[0:3]
            dq[3:6] = 0.5 * (quat[3] * w + np.cross(quat[0:3], w))
            dq[6] = -0.5 * quat[0:3] @ w
        return np.concatenate([dq, a])

    return f


def integrate(case, rtol):
    y0 = np.concatenate([case.q0, case.v0])
    sol = solve_ivp(rhs(case), (0.0, case.t[-1]), y0, method="DOP853", rtol=rtol, atol=rtol, t_eval=case.t)
    if not sol.success:
        sys.exit(f"{case.name}: DOP853 failed: {sol.message}")
    qs = [case.normalized(y[:case.nq]) for y in sol.y.T]
    vs = [y[case.nq:] for y in sol.y.T]
    return qs, vs, sol.nfev


def joint_errors(case, q, q_ref):
    """Per coordinate group: |dq| per joint; a floating base as |dp| and the rotation angle."""
    e = []
    if case.floating:
        e.append(np.linalg.norm(q[0:3] - q_ref[0:3]))
        a = pin.Quaternion(q[6], q[3], q[4], q[5])  # w, x, y, z
        b = pin.Quaternion(q_ref[6], q_ref[3], q_ref[4], q_ref[5])
        r = a.conjugate() * b  # the angle by atan2: arccos of a dot product near 1 loses half the digits
        e.append(2 * np.arctan2(np.linalg.norm([r.x, r.y, r.z]), abs(r.w)))
    return np.array(e + list(np.abs(q[case.pq] - q_ref[case.pq])))  # igms's order: the base, then the joints


def truth(case, out):
    t0 = time.perf_counter()
    qs, vs, nfev = integrate(case, RTOL)
    seconds = time.perf_counter() - t0
    check, _, _ = integrate(case, RTOL / 10)
    self_check = max(joint_errors(case, a, b).max() for a, b in zip(qs, check))
    method = f"SciPy DOP853 on Pinocchio aba, rtol = atol = {RTOL:g}"
    doc = {"case": case.name, "method": method, "self_check_q_max": float(self_check),
           "evaluations": nfev, "seconds": seconds,
           "q": [case.q_to_igms(q).tolist() for q in qs], "v": [case.v_to_igms(v).tolist() for v in vs],
           "ee": [case.ee_position(q).tolist() for q in qs]}
    json.dump(doc, open(os.path.join(out, f"{case.name}.truth.json"), "w"))
    print(f"{case.name}: {method}: {nfev} evaluations, {seconds:.1f} s; against itself at rtol {RTOL / 10:g}: "
          f"{self_check:.2e} rad")
    return qs, vs


def mujoco_model(case):
    xml = open(case.urdf_path).read()
    xml = re.sub(r"<visual[\s\S]*?</visual>", "", xml)
    xml = re.sub(r"<collision[\s\S]*?</collision>", "", xml)
    xml = re.sub(r"<robot([^>]*)>", r'<robot\1><mujoco><compiler inertiafromgeom="false" balanceinertia="true" '
                 r'boundmass="1e-6" boundinertia="1e-10" discardvisual="true"/></mujoco>', xml, count=1)
    spec = mujoco.MjSpec.from_string(xml)
    if case.floating:
        spec.worldbody.first_body().add_freejoint()
    if case.hand:
        # The undamped pull as a spatial tendon of rest length 0 between the attachment point and
        # the device point: its force k L along the line is exactly k (x_tip - x).
        spec.body(case.hand["link"]).add_site(name="igms_hand_point", pos=case.hand["point"])
        spec.worldbody.add_site(name="igms_hand_tip", pos=case.hand["tip"])
        tendon = spec.add_tendon(name="igms_pull")
        tendon.wrap_site("igms_hand_point")
        tendon.wrap_site("igms_hand_tip")
        tendon.stiffness = [case.hand["k"], 0.0, 0.0]  # MuJoCo 4: the linear coefficient first
        tendon.springlength = [0.0, 0.0]
    m = spec.compile()
    # No contacts or constraints (joint limits), and no automatic reset on a blow-up: a divergence
    # must reach the state, where it is detected and reported.
    m.opt.disableflags |= (mujoco.mjtDisableBit.mjDSBL_CONTACT | mujoco.mjtDisableBit.mjDSBL_CONSTRAINT |
                           mujoco.mjtDisableBit.mjDSBL_EQUALITY | mujoco.mjtDisableBit.mjDSBL_AUTORESET)
    m.opt.gravity[:] = case.spec["gravity"]
    # The URDF's exact mass and inertia on every body (see the module comment).
    restored = []
    for b in range(1, m.nbody):
        name = m.body(b).name
        fid = case.model.getFrameId(name)
        if fid >= len(case.model.frames):
            continue
        jid = case.model.frames[fid].parentJoint
        if jid == 0 or not np.allclose(case.model.frames[fid].placement.homogeneous, np.eye(4)):
            continue  # the fixed root, or a link on a fixed joint: not a joint's body in Pinocchio
        inertia = case.model.inertias[jid]
        w, V = np.linalg.eigh(inertia.inertia)
        if np.linalg.det(V) < 0:
            V[:, 0] = -V[:, 0]
        quat = np.empty(4)
        mujoco.mju_mat2Quat(quat, V.flatten())
        if (abs(m.body_mass[b] - inertia.mass) > 1e-12 * max(1.0, inertia.mass) or
                np.abs(np.sort(m.body_inertia[b]) - w).max() > 1e-12 * max(1.0, w.max())):
            restored.append(name)
        m.body_mass[b] = inertia.mass
        m.body_ipos[b] = inertia.lever
        m.body_iquat[b] = quat
        m.body_inertia[b] = w
    m.dof_armature[:] = 0
    m.dof_frictionloss[:] = 0
    m.jnt_stiffness[:] = 0
    m.dof_damping[:] = 0
    d = mujoco.MjData(m)
    mujoco.mj_setConst(m, d)
    # igms coordinates -> MuJoCo's, by joint name.
    qadr, vadr = np.empty(case.nq, dtype=int), np.empty(case.nv, dtype=int)
    for j in case.spec["joints"]:
        if j["type"] == "floating":
            continue
        mj = m.joint(j["name"])
        qadr[j["q_index"]], vadr[j["v_index"]] = mj.qposadr[0], mj.dofadr[0]
    if case.floating:
        free = [k for k in range(m.njnt) if m.jnt_type[k] == mujoco.mjtJoint.mjJNT_FREE][0]
        qadr[0:7] = m.jnt_qposadr[free] + np.arange(7)
        vadr[0:6] = m.jnt_dofadr[free] + np.arange(6)
    m.dof_damping[vadr] = case.spec["damping"]
    return m, d, qadr, vadr, restored


def mj_set(case, m, d, qadr, vadr, q_igms, v_igms):
    """igms's (q, v) into MuJoCo: a free joint's linear velocity is in world axes there."""
    d.qpos[qadr] = q_igms
    v = v_igms.copy()
    if case.floating:
        R = np.empty(9)
        mujoco.mju_quat2Mat(R, q_igms[3:7])
        v[0:3] = R.reshape(3, 3) @ v_igms[0:3]
    d.qvel[vadr] = v


def mj_get(case, m, d, qadr, vadr):
    q, v = d.qpos[qadr].copy(), d.qvel[vadr].copy()
    if case.floating:
        q[3:7] /= np.linalg.norm(q[3:7])
        R = np.empty(9)
        mujoco.mju_quat2Mat(R, q[3:7])
        v[0:3] = R.reshape(3, 3).T @ v[0:3]
    return q, v


def same_equations(case, m, d, qadr, vadr):
    """MuJoCo's joint-space inertia and bias at q0 against Pinocchio's, in igms order."""
    q_igms, v_igms = case.q_to_igms(case.q0), case.v_to_igms(case.v0) + 0.3
    if case.floating:  # the engines' base velocity coordinates differ (MuJoCo's linear part is in world axes),
        v_igms[0:6] = 0  # and so do the bias forces that go with them; at rest they coincide
    hand, case.hand = case.hand, None  # the arm's own equations; the tendon is checked by the run
    mj_set(case, m, d, qadr, vadr, q_igms, v_igms)
    mujoco.mj_forward(m, d)
    M = np.zeros((m.nv, m.nv))
    mujoco.mj_fullM(m, d, M)
    qp, vp = case.q_to_pin(q_igms), case.v_to_pin(v_igms)
    H = pin.crba(case.model, case.data, qp)
    H = np.triu(H) + np.triu(H, 1).T
    b = pin.rnea(case.model, case.data, qp, vp, np.zeros(case.nv))
    # Pinocchio in igms order, then MuJoCo's order through vadr. A floating
    # base's linear rows are in world axes in MuJoCo: compare the fixed-base part.
    perm = np.empty(case.nv, dtype=int)
    perm[case.iv] = case.pv
    if case.floating:
        perm[0:6] = np.arange(6)
    Hi = H[np.ix_(perm, perm)]
    bi = b[perm]
    Mm = M[np.ix_(vadr, vadr)]
    bm = d.qfrc_bias[vadr]
    s = 6 if case.floating else 0
    dH = np.abs(Hi[s:, s:] - Mm[s:, s:]).max() / max(1e-300, np.abs(Hi).max())
    db = np.abs(bi[s:] - bm[s:]).max() / max(1e-300, np.abs(bi).max())
    case.hand = hand
    return float(dH), float(db)


def run_mujoco(case, m, d, qadr, vadr, integrator, h):
    m.opt.integrator, m.opt.timestep = integrator, h
    per = int(round(case.spec["sample"] / h))
    mj_set(case, m, d, qadr, vadr, case.q_to_igms(case.q0), case.v_to_igms(case.v0))
    d.time = 0.0
    mujoco.mj_forward(m, d)
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    state = np.empty(mujoco.mj_stateSize(m, spec))
    mujoco.mj_getState(m, d, state, spec)
    qs, vs = [case.q0.copy()], [case.v0.copy()]
    wall, diverged = 0.0, False
    for _ in range(case.samples - 1):
        t0 = time.perf_counter()
        out, _ = rollout.rollout(m, d, state[None, :], nstep=per)
        wall += time.perf_counter() - t0
        state = out[0, -1].copy()
        mujoco.mj_setState(m, d, state, spec)
        q, v = mj_get(case, m, d, qadr, vadr)
        if not (np.all(np.isfinite(q)) and np.all(np.isfinite(v)) and np.abs(q).max() < 1e10 and
                np.abs(v).max() < 1e10):
            diverged = True
            break
        qs.append(case.q_to_pin(q))
        vs.append(case.v_to_pin(v))
    return qs, vs, wall, diverged


def errors(case, qs, vs, tq, tv):
    per = [joint_errors(case, a, b) for a, b in zip(qs, tq)]
    q_max = max(e.max() for e in per)
    per_joint = np.max(per, axis=0)
    q_rms = float(np.sqrt(np.mean(np.concatenate(per) ** 2)))
    ee = max(np.linalg.norm(case.ee_position(a) - case.ee_position(b)) for a, b in zip(qs, tq))
    E0 = abs(case.energy(tq[0], tv[0]))
    E0 = E0 if E0 > 1e-9 else 1.0
    energies = [case.energy(q, v) for q, v in zip(qs, vs)]
    drift = max(abs(E - energies[0]) for E in energies) / E0
    lin = ang = float("nan")
    if np.linalg.norm(case.spec["gravity"]) == 0 and case.floating:
        p = [case.momentum(q, v) for q, v in zip(qs, vs)]
        p0 = case.momentum(tq[0], tv[0])
        lin = max(np.linalg.norm(x[:3] - p[0][:3]) for x in p) / max(1e-9, np.linalg.norm(p0[:3]))
        ang = max(np.linalg.norm(x[3:] - p[0][3:]) for x in p) / max(1e-9, np.linalg.norm(p0[3:]))
    rate = (energies[-1] - energies[0]) / case.spec["duration"]
    if any(case.spec["damping"]) or (case.hand and case.hand["b"] != 0):
        drift = float("nan")
    return q_rms, q_max, ee, drift, lin, ang, rate, per_joint


def steps(quick):
    h, out = (0.25e-3 if quick else 1e-3 / 64), []
    while h <= (4e-3 if quick else 32e-3) * 1.0001:
        out.append(h)
        h *= 2
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("cases_dir")
    ap.add_argument("--quick", action="store_true", help="0.25 .. 4 ms steps (as igms-accuracy --quick)")
    ap.add_argument("--repeats", type=int, default=3, help="timing runs per row (median), for runs under 2 s")
    a = ap.parse_args()
    a.cases_dir = os.path.abspath(a.cases_dir)
    os.chdir(a.cases_dir)  # MuJoCo writes MUJOCO_LOG.TXT (its warnings) into the working directory
    names = sorted(f[:-5] for f in os.listdir(a.cases_dir) if f.endswith(".json") and ".truth" not in f
                   and f != "peers.json")
    if not names:
        sys.exit(f"{a.cases_dir}: no case files (igms-accuracy --write-cases {a.cases_dir})")
    info = {"pinocchio": pin.__version__, "mujoco": mujoco.__version__,
            "scipy": __import__("scipy").__version__, "python": platform.python_version(), "cases": {}}
    with open(os.path.join(a.cases_dir, "mujoco.csv"), "w") as csv:
        csv.write(CSV_HEADER + "\n")
        for name in names:
            case = Case(os.path.join(a.cases_dir, name + ".json"))
            tq, tv = truth(case, a.cases_dir)
            if case.hand and case.push:
                print("  MuJoCo skipped: its contact is a soft constraint, another model than eq. 3's penalty")
                continue
            if case.hand and case.hand["b"] != 0:
                print("  MuJoCo skipped: a tendon's damping acts along the line only; eq. 4's acts on the whole "
                      "velocity")
                continue
            m, d, qadr, vadr, restored = mujoco_model(case)
            dH, db = same_equations(case, m, d, qadr, vadr)
            print(f"  MuJoCo model: exact inertias written back on {restored or 'no body'}; against Pinocchio at q0: "
                  f"H {dH:.1e}, bias {db:.1e} (relative, max)")
            info["cases"][name] = {"restored_inertias": restored, "H_relative_difference": dH,
                                   "bias_relative_difference": db}
            for method, integrator in INTEGRATORS:
                for h in steps(a.quick):
                    qs, vs, wall, diverged = run_mujoco(case, m, d, qadr, vadr, integrator, h)
                    walls = [wall]
                    while wall < 2.0 and len(walls) < a.repeats:
                        walls.append(run_mujoco(case, m, d, qadr, vadr, integrator, h)[2])
                    walls = np.array(walls) / case.spec["duration"]
                    if diverged or len(qs) != len(tq):
                        e = [float("inf")] * 7 + [[]]
                    else:
                        e = errors(case, qs, vs, tq, tv)
                    csv.write(f"{name},{method},{h * 1e3:.17g}," + ",".join(f"{x:.17g}" for x in e[:6]) +
                              f",{np.median(walls):.17g},{int(diverged)},{len(walls)},{walls.min():.17g},"
                              f"{walls.max():.17g},{e[6]:.17g}," + ";".join(f"{x:.17g}" for x in e[7]) + "\n")
                    print(f"  {method:20s} h={h * 1e3:8.4f} ms  q_max {e[1]:<10.3g} ee_max {e[2]:<10.3g} "
                          f"energy drift {e[3]:<10.3g} {'DIVERGED' if diverged else ''} "
                          f"{np.median(walls):.3g} s per s")
    json.dump(info, open(os.path.join(a.cases_dir, "peers.json"), "w"), indent=1)


if __name__ == "__main__":
    main()
