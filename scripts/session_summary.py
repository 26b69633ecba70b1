#!/usr/bin/python3
"""Summary of one of the paper's experiments (scripts/paper_run.sh): collision-free or
not, when the end-effector reached the wall, the interactions and their forces, the
rate and the deadline misses. Writes OUT/summary.json and OUT/summary.md, prints the latter.
Usage: scripts/session_summary.py OUT_DIR MODE"""
import csv
import json
import os
import re
import sys

import numpy as np
import yaml


def main():
    out, mode = sys.argv[1], sys.argv[2]
    exp = os.path.join(out, "export")
    rows = list(csv.DictReader(open(os.path.join(exp, "states.csv"))))
    scene = yaml.safe_load(open(os.path.join(exp, "scene.yaml")))
    t = np.array([float(r["t"]) for r in rows])
    modes = np.array([int(r["mode"]) for r in rows])
    hit = np.array([int(r["in_collision"]) for r in rows]) > 0
    dist = np.array([float(r["min_obstacle_distance"]) for r in rows])
    force = np.array([[float(r["fx"]), float(r["fy"]), float(r["fz"])] for r in rows])
    ee = np.array([[float(r["ee_link.x"]), float(r["ee_link.y"]), float(r["ee_link.z"])] for r in rows])
    target = np.array(scene["trajectory"]["target"])
    near = np.nonzero(np.linalg.norm(ee - target, axis=1) <= 0.01)[0]
    # Interactions: stretches of push (1) or pull (2).
    events, start = [], None
    for i, m in enumerate(modes):
        if m and start is None:
            start = i
        if start is not None and (m != modes[start] or i == len(modes) - 1):
            end = i if not m else i
            f = np.linalg.norm(force[start:end + 1], axis=1)
            events.append({"mode": "push" if modes[start] == 1 else "pull", "start_s": round(t[start], 3),
                           "end_s": round(t[end], 3), "max_force_N": round(float(f.max()), 2)})
            start = i if m else None
    client = open(os.path.join(out, "client.log")).read() if os.path.exists(os.path.join(out, "client.log")) else ""
    rate = re.search(r"cycles in ([\d.]+) s \(([\d.]+) Hz\), (\d+) deadline misses", client)
    rtt = re.search(r"round trip p50 (\d+) us, p99 (\d+) us", client)
    summary = {
        "experiment": mode,
        "scene": scene.get("name"),
        "collision_free": not bool(hit.any()),
        "first_collision_s": round(float(t[hit][0]), 3) if hit.any() else None,
        "collision_steps": int(hit.sum()),
        "min_obstacle_distance_m": round(float(dist.min()), 4),
        "reached_wall": bool(len(near)),
        "reached_wall_s": round(float(t[near[0]]), 3) if len(near) else None,
        "final_distance_to_target_m": round(float(np.linalg.norm(ee[-1] - target)), 4),
        "interactions": events,
        "max_force_on_robot_N": round(float(np.linalg.norm(force, axis=1).max()), 2),
        "client_rate_hz": float(rate.group(2)) if rate else None,
        "deadline_misses": int(rate.group(3)) if rate else None,
        "round_trip_p50_us": int(rtt.group(1)) if rtt else None,
        "round_trip_p99_us": int(rtt.group(2)) if rtt else None,
        "steps": len(rows),
    }
    json.dump(summary, open(os.path.join(out, "summary.json"), "w"), indent=2)
    names = {"push": "pushing", "pull": "pulling"}
    counts = {}
    lines = [f"# igms: the paper's {mode} experiment", "",
             f"- scene: `scenes/puma_obstacle.yaml` (PUMA 560, straight line to the wall, obstacle in the way of link 2)",
             f"- collision-free: **{'yes' if summary['collision_free'] else 'no'}**"
             + ("" if summary["collision_free"] else f" (first at t = {summary['first_collision_s']} s, "
                f"{summary['collision_steps']} steps in collision)"),
             f"- reached the wall: **{'yes' if summary['reached_wall'] else 'no'}**"
             + (f" at t = {summary['reached_wall_s']} s" if summary["reached_wall"] else ""),
             f"- closest approach to an obstacle or the wall: {summary['min_obstacle_distance_m'] * 1000:.1f} mm"]
    for e in events:
        counts[e["mode"]] = counts.get(e["mode"], 0) + 1
        lines.append(f"- {names[e['mode']]}{counts[e['mode']]}: {e['start_s']:.3f} s to {e['end_s']:.3f} s, "
                     f"largest force {e['max_force_N']} N")
    if summary["client_rate_hz"]:
        lines.append(f"- haptic client: {summary['client_rate_hz']:.1f} Hz, {summary['deadline_misses']} deadline "
                     f"misses, round trip p50 {summary['round_trip_p50_us']} us, p99 {summary['round_trip_p99_us']} us")
    lines += ["", "![joints](joints.png)", "![forces](forces.png)", "![path](path.png)", "![snapshots](snapshots.png)"]
    open(os.path.join(out, "summary.md"), "w").write("\n".join(lines) + "\n")
    print("\n".join(lines[:-5]))


if __name__ == "__main__":
    main()
