#!/usr/bin/python3
"""Summary of one session (scripts/sessions/run_session.sh, scripts/sessions/paper_run.sh) of any scene:
collision-free or not, when the scene's end-effector reached its target (a
cartesian_line trajectory's; the paper's is at the wall), the interactions and
their forces, the closest approach to an obstacle (the line's goal, the
paper's wall, left out), the joints that went beyond their limits, the client's rate and
deadline misses (from the logged client status). Writes OUT/summary.json and
OUT/summary.md, prints the latter.
Usage: scripts/reports/session_summary.py OUT_DIR TITLE"""
import collections
import csv
import json
import os
import sys

import numpy as np
import yaml

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "lib"))
from scene_frames import end_effector  # noqa: E402

MERGE_GAP_S = 0.02  # s: a lapse this short inside a push or pull does not end it


def closest_approach(summary, path, t, near):
    """One definition of "closest approach": the robot's least distance to an obstacle over the session,
    leaving out the obstacle its line is meant to reach (the goal: within 2 cm of the robot when the
    end-effector reaches its target; the paper's wall). From igms-replay export's obstacles.csv (each
    obstacle's distance per step); without it, the states' nearest obstacle, the goal included."""
    if not os.path.exists(path):
        return
    rows = list(csv.DictReader(open(path)))
    if not rows:
        return
    names = [k for k in rows[0] if k not in ("t", "step")]
    dist = {n: np.array([float(r[n]) for r in rows]) for n in names}
    goal = None
    if len(near):
        at = float(t[near[0]])
        k = min(range(len(rows)), key=lambda i: abs(float(rows[i]["t"]) - at))
        touching = [n for n in names if dist[n][k] < 0.02]
        goal = min(touching, key=lambda n: dist[n][k]) if touching else None
    others = [n for n in names if n != goal]
    summary["goal_obstacle"] = goal
    if goal:
        summary["goal_obstacle_distance_m"] = round(float(dist[goal].min()), 4)
    if not others:  # the goal is the only obstacle watched: no approach to speak of
        summary["min_obstacle_distance_m"], summary["closest_obstacle"] = None, None
        return
    closest = min(others, key=lambda n: dist[n].min())
    summary["min_obstacle_distance_m"] = round(float(dist[closest].min()), 4)
    summary["closest_obstacle"] = closest


def last_row(path, running=None):
    """The last row of a CSV file with a header, as a dict (None when empty or absent); with running, the last
    row where that column is above 0 (a status sent while the loop ran, not the final one)."""
    if not os.path.exists(path):
        return None
    rows = [r for r in csv.DictReader(open(path)) if running is None or float(r[running]) > 0]
    return rows[-1] if rows else None


def client_proxy_limited(path):
    """Cycles the clients' proxies ran out of substeps: each client's total (its largest count), summed."""
    most = {}
    for r in csv.DictReader(open(path)):
        c = r.get("client", "")
        most[c] = max(most.get(c, 0), int(r.get("proxy_substep_limited") or 0))
    return sum(most.values())


def hand_interactions(path):
    """{client: {"interactions": [...]}} from the export's hands.csv: each client's stretches of push or pull,
    with the largest force and torque it applied (clients that never interacted are left out)."""
    if not os.path.exists(path):
        return {}
    per = {}
    for r in csv.DictReader(open(path)):
        per.setdefault(int(r["client"]), []).append(r)
    out = {}
    for c, rs in sorted(per.items()):
        events, start, prev_seq = [], None, None
        for i, r in enumerate(rs + [None]):
            m = int(r["mode"]) if r else 0
            seq = int(r["seq"]) if r else None
            # A stretch ends when the mode changes or this hand had no input for a step.
            broken = start is not None and (r is None or m != int(rs[start]["mode"]) or seq != prev_seq + 1)
            if broken:
                chunk = rs[start:i]
                f = max(np.linalg.norm([float(x["fx"]), float(x["fy"]), float(x["fz"])]) for x in chunk)
                tq = max(np.linalg.norm([float(x["tx"]), float(x["ty"]), float(x["tz"])]) for x in chunk)
                if f >= 0.05 or tq > 0:
                    events.append({"mode": "push" if int(rs[start]["mode"]) == 1 else "pull",
                                   "start_s": round(float(rs[start]["t"]), 3), "end_s": round(float(chunk[-1]["t"]), 3),
                                   "max_force_N": round(float(f), 2), "max_torque_Nm": round(float(tq), 3)})
                start = None
            if r and m and start is None:
                start = i
            prev_seq = seq
        if events:
            out[c] = {"interactions": events}
    return out


def client_loop(path, client_id):
    """The rate (median of the running windows) and deadline misses of one client, from client_status.csv."""
    if not os.path.exists(path):
        return {}
    rs = [r for r in csv.DictReader(open(path)) if int(r.get("client") or -1) == client_id]
    running = [float(r["rate_hz"]) for r in rs if float(r["rate_hz"]) > 0]
    if not running:
        return {}
    return {"rate_hz": round(float(np.median(running)), 1), "deadline_misses": int(rs[-1]["deadline_misses"])}


def main():
    out, title = sys.argv[1], sys.argv[2]
    exp = os.path.join(out, "export")
    rows = list(csv.DictReader(open(os.path.join(exp, "states.csv"))))
    scene = yaml.safe_load(open(os.path.join(exp, "scene.yaml"))) or {}
    links = [h[:-2] for h in rows[0] if h.endswith(".x")]
    ee_name = end_effector(scene, links)
    t = np.array([float(r["t"]) for r in rows])
    modes = np.array([int(r["mode"]) for r in rows])
    hit = np.array([int(r["in_collision"]) for r in rows]) > 0
    dist = np.array([float(r["min_obstacle_distance"]) for r in rows])
    force = np.array([[float(r["fx"]), float(r["fy"]), float(r["fz"])] for r in rows])
    ee = np.array([[float(r[f"{ee_name}.x"]), float(r[f"{ee_name}.y"]), float(r[f"{ee_name}.z"])] for r in rows])
    trajectory = scene.get("trajectory") or {}
    target = np.array(trajectory["target"]) if trajectory.get("kind") == "cartesian_line" else None
    near = np.nonzero(np.linalg.norm(ee - target, axis=1) <= 0.01)[0] if target is not None else []
    # Interactions: stretches of push (1) or pull (2).
    events, touches, start = [], [], None
    for i, m in enumerate(modes):
        if m and start is None:
            start = i
        if start is not None and (m != modes[start] or i == len(modes) - 1):
            end = i
            f = np.linalg.norm(force[start:end + 1], axis=1)
            event = {"mode": "push" if modes[start] == 1 else "pull", "start_s": round(t[start], 3),
                     "end_s": round(t[end], 3), "max_force_N": round(float(f.max()), 2)}
            # A push the client saw in its estimate that never reached the robot (under 0.05 N at every step,
            # the client's own release threshold; seen as a 1 ms stretch at a release under load) is a touch,
            # counted apart, not an interaction.
            if event["mode"] == "push" and f.max() < 0.05:
                touches.append(event)
            else:
                events.append(event)
            start = i if m else None
    # A push or pull that lapses for under MERGE_GAP_S and comes back (the tip off the link's surface for
    # a few cycles while both move, or inputs held up on a loaded machine: a real-time run saw an 11 ms
    # lapse inside the Panda push) is one interaction; the lapses are counted.
    merged, lapses = [], 0
    for event in events:
        if merged and merged[-1]["mode"] == event["mode"] and event["start_s"] - merged[-1]["end_s"] <= MERGE_GAP_S:
            merged[-1]["end_s"] = event["end_s"]
            merged[-1]["max_force_N"] = max(merged[-1]["max_force_N"], event["max_force_N"])
            lapses += 1
        else:
            merged.append(dict(event))
    events = merged
    hands = hand_interactions(os.path.join(exp, "hands.csv"))
    client = last_row(os.path.join(exp, "client_status.csv"), running="rate_hz")
    if client:  # the session's rate: the median of the 10 Hz windows the loop ran (the first and last are partial)
        rates = [float(r["rate_hz"]) for r in csv.DictReader(open(os.path.join(exp, "client_status.csv")))
                 if float(r["rate_hz"]) > 0]
        client["rate_hz"] = float(np.median(rates))
    server = last_row(os.path.join(exp, "server_status.csv"))
    obstacles = [o.get("name") for o in scene.get("obstacles") or []]
    summary = {
        "title": title,
        "scene": scene.get("name"),
        "model": (scene.get("robot") or {}).get("model"),
        "end_effector": ee_name,
        "obstacles": len(obstacles),
        "collision_free": not bool(hit.any()),
        "first_collision_s": round(float(t[hit][0]), 3) if hit.any() else None,
        "collision_steps": int(hit.sum()),
        "min_obstacle_distance_m": round(float(dist.min()), 4) if obstacles else None,
        "reached_target": bool(len(near)) if target is not None else None,
        "reached_target_s": round(float(t[near[0]]), 3) if len(near) else None,
        "final_distance_to_target_m": round(float(np.linalg.norm(ee[-1] - target)), 4) if target is not None else None,
        "interactions": events,
        "touches_without_force": len(touches),
        "interaction_lapses": lapses,
        "max_force_on_robot_N": round(float(np.linalg.norm(force, axis=1).max()), 2),
        "client_rate_hz": round(float(client["rate_hz"]), 1) if client else None,
        "deadline_misses": int(client["deadline_misses"]) if client else None,
        "round_trip_p50_us": round(float(client["rtt_us_p50"])) if client else None,
        "round_trip_p99_us": round(float(client["rtt_us_p99"])) if client else None,
        "server_steps": int(server["steps"]) if server else None,
        # Counted, never silent: what the server cut short or left out (0 in a session within its sizing).
        "contact_unconverged": int(server.get("contact_unconverged") or 0) if server else None,
        "contact_candidates_dropped": int(server.get("contact_candidates_dropped") or 0) if server else None,
        # Counted converged, but a slipping friction kept along the sweeps' direction, not against its slip.
        "contact_slips_unturned": int(server.get("contact_slips_unturned") or 0) if server else None,
        # Answered, but on the linearised cone's polytope, not the cone.
        "contact_linearised": int(server.get("contact_linearised") or 0) if server else None,
        "server_proxy_substep_limited": int(server.get("proxy_substep_limited") or 0) if server else None,
        "client_proxy_substep_limited": client_proxy_limited(os.path.join(exp, "client_status.csv")) if client else None,
        "steps": len(rows),
    }
    if len(hands) > 1:  # several people at once: each hand's interactions and its client's loop
        for c, h in hands.items():
            h.update(client_loop(os.path.join(exp, "client_status.csv"), c))
        summary["hands"] = {str(c): h for c, h in hands.items()}
        acting = collections.Counter(r["seq"] for r in csv.DictReader(open(os.path.join(exp, "hands.csv")))
                                     if int(r["mode"]) != 0)
        summary["steps_with_several_hands"] = sum(1 for n in acting.values() if n > 1)
    env_path = os.path.join(exp, "environment.csv")
    if os.path.exists(env_path):  # an environment: its free bodies and its contacts, from the re-simulation
        env = list(csv.DictReader(open(env_path)))
        names = [h[:-2] for h in env[0] if h.endswith(".x") and h[:-2] + ".qz" in env[0]]
        summary["bodies"] = {n: {"start": [round(float(env[0][f"{n}.{c}"]), 4) for c in "xyz"],
                                 "end": [round(float(env[-1][f"{n}.{c}"]), 4) for c in "xyz"]} for n in names}
        summary["max_contacts"] = max(int(r["contacts"]) for r in env)
        summary["max_penetration_m"] = max(float(r["max_penetration"]) for r in env)
        if "robot_body_contacts" in env[0]:  # did a robot touch a free body, and when first
            touched = [float(r["t"]) for r in env if int(r["robot_body_contacts"]) > 0]
            summary["robot_touched_bodies"] = bool(touched)
            summary["robot_first_touched_body_s"] = round(touched[0], 3) if touched else None
    if "wall" in obstacles:  # the paper's scene: its target is at the wall
        summary["reached_wall"], summary["reached_wall_s"] = summary["reached_target"], summary["reached_target_s"]
    closest_approach(summary, os.path.join(exp, "obstacles.csv"), t, near)
    json.dump(summary, open(os.path.join(out, "summary.json"), "w"), indent=2)
    names = {"push": "pushing", "pull": "pulling"}
    counts = {}
    lines = [f"# igms session: {title}", "",
             f"- scene: `{scene.get('name')}` (model `{summary['model']}`), end-effector `{ee_name}`"]
    if obstacles:
        lines.append(f"- collision-free: **{'yes' if summary['collision_free'] else 'no'}**"
                     + ("" if summary["collision_free"] else f" (first at t = {summary['first_collision_s']} s, "
                        f"{summary['collision_steps']} steps in collision)"))
    if target is not None:
        where = "the wall" if "wall" in obstacles else f"the target {[float(x) for x in target]}"
        lines.append(f"- reached {where}: **{'yes' if summary['reached_target'] else 'no'}**"
                     + (f" at t = {summary['reached_target_s']} s" if summary["reached_target"] else
                        f" ({summary['final_distance_to_target_m'] * 1000:.1f} mm from it at the end)"))
    if obstacles and "closest_obstacle" in summary and not summary["closest_obstacle"]:
        lines.append(f"- closest approach to an obstacle: none watched but the line's goal ({summary['goal_obstacle']})")
    elif obstacles and summary.get("closest_obstacle"):
        goal = summary.get("goal_obstacle")
        lines.append(f"- closest approach to an obstacle: {summary['min_obstacle_distance_m'] * 1000:.1f} mm "
                     f"({summary['closest_obstacle']}"
                     + (f"; {goal}, the line's goal, is left out: "
                        f"{summary['goal_obstacle_distance_m'] * 1000:.1f} mm" if goal else "") + ")")
    elif obstacles:
        lines.append(f"- closest approach to an obstacle: {summary['min_obstacle_distance_m'] * 1000:.1f} mm")
    for e in ([] if summary.get("hands") else events):  # with several hands, each hand's are listed below
        counts[e["mode"]] = counts.get(e["mode"], 0) + 1
        lines.append(f"- {names[e['mode']]}{counts[e['mode']]}: {e['start_s']:.3f} s to {e['end_s']:.3f} s, "
                     f"largest force {e['max_force_N']} N")
    if lapses:
        lines.append(f"- {lapses} lapse(s) of under {MERGE_GAP_S * 1000:.0f} ms inside a push or pull, "
                     "each counted within the interaction it interrupted")
    if touches:
        lines.append(f"- {len(touches)} touch(es) of the client's estimate that delivered no force (under 0.05 N), "
                     f"first at {touches[0]['start_s']:.3f} s: not counted as pushes")
    for c, h in (summary.get("hands") or {}).items():
        parts = [f"{names[e['mode']]} {e['start_s']:.3f} s to {e['end_s']:.3f} s (largest force {e['max_force_N']} N"
                 + (f", torque {e['max_torque_Nm']} N m" if e["max_torque_Nm"] > 0 else "") + ")"
                 for e in h["interactions"]]
        loop = (f"; its client {h['rate_hz']:.1f} Hz, {h['deadline_misses']} deadline misses"
                if h.get("rate_hz") is not None else "")
        lines.append(f"- hand of client {c}: " + ("; ".join(parts) or "no interaction") + loop)
    if summary.get("hands"):
        lines.append(f"- several hands on the robot at once in {summary['steps_with_several_hands']} steps")
    if "bodies" in summary:
        for n, b in summary["bodies"].items():
            lines.append(f"- free body `{n}`: from {b['start']} to {b['end']} m")
        lines.append(f"- contact: up to {summary['max_contacts']} points at once, deepest overlap "
                     f"{summary['max_penetration_m'] * 1000:.3f} mm")
        if "robot_touched_bodies" in summary and summary["bodies"]:
            lines.append("- the robot touched a free body: " + (
                f"**yes**, first at t = {summary['robot_first_touched_body_s']} s" if summary["robot_touched_bodies"]
                else "**no**"))
    if server:
        lines.append(f"- cut short or left out: {summary['contact_unconverged']} unconverged contact solves, "
                     f"{summary['contact_candidates_dropped']} candidate contact pairs dropped, "
                     f"{summary['contact_slips_unturned']} active-set answers with a slip left unturned, "
                     f"{summary['contact_linearised']} islands answered on the linearised cone's polytope, "
                     f"{summary['server_proxy_substep_limited']} server proxy cycles and "
                     f"{summary['client_proxy_substep_limited'] or 0} client proxy cycles out of substeps")
    if client and not summary.get("hands"):
        lines.append(f"- haptic client: {summary['client_rate_hz']:.1f} Hz, {summary['deadline_misses']} deadline "
                     f"misses, round trip p50 {summary['round_trip_p50_us']} us, p99 {summary['round_trip_p99_us']} us")
    figures = ["", "![joints](joints.png)", "![forces](forces.png)", "![path](path.png)", "![snapshots](snapshots.png)"]
    open(os.path.join(out, "summary.md"), "w").write("\n".join(lines + figures) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
