#!/usr/bin/python3
"""Plots of an igms session, like the paper's figures, from `igms-replay export LOG DIR`:

  joints.{png,svg}     joint trajectories with the interaction events marked (Fig. 6a, 8)
  forces.{png,svg}     the interaction forces over time (Fig. 6b)
  path.{png,svg}       the end-effector path in 3-D against the obstacles and the wall
  snapshots.{png,svg}  the robot along the path (Fig. 7), from the link poses

Usage: scripts/reports/plot_session.py EXPORT_DIR [--out DIR] [--title TEXT] [--ee LINK]
Uses Debian's python3 (matplotlib, numpy, yaml from apt)."""
import argparse
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import yaml  # noqa: E402
from mpl_toolkits.mplot3d import Axes3D  # noqa: E402,F401

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "lib"))
from scene_frames import end_effector  # noqa: E402

MODES = {1: "push", 2: "pull"}


def read_states(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    header, data = rows[0], np.array(rows[1:], dtype=float)
    return {name: data[:, i] for i, name in enumerate(header)}, header


def intervals(t, mode):
    """(start, end, kind) of each stretch of interaction."""
    out, start = [], None
    for i in range(len(t)):
        m = int(mode[i])
        if m and start is None:
            start, kind = i, m
        if start is not None and (not m or m != kind or i == len(t) - 1):
            out.append((t[start], t[i], MODES.get(kind, "?")))
            start = None
            if m:
                start, kind = i, m
    return out


def mark_events(ax, events):
    counts = {}
    for a, b, kind in events:
        counts[kind] = counts.get(kind, 0) + 1
        ax.axvspan(a, b, color="tab:orange" if kind == "push" else "tab:purple", alpha=0.15)
        ax.annotate(f"{kind}ing{counts[kind]}", (a, 1.0), xycoords=("data", "axes fraction"), fontsize=8,
                    va="bottom", ha="left")


def label_time_plot(ax, events, ylabel, title, what, ncol):
    """A plot against time: the touches shaded, its axes, title and legend."""
    mark_events(ax, events)
    ax.set_xlabel("time (s)")
    ax.set_ylabel(ylabel)
    ax.set_title(f"{title}: {what}" if title else what)
    ax.legend(fontsize=8, ncol=ncol)
    ax.grid(alpha=0.3)


def box_edges(center, size, rpy):
    cx, cy, cz = center
    hx, hy, hz = np.array(size) / 2.0
    r, p, y = rpy
    R = (np.array([[np.cos(y), -np.sin(y), 0], [np.sin(y), np.cos(y), 0], [0, 0, 1]])
         @ np.array([[np.cos(p), 0, np.sin(p)], [0, 1, 0], [-np.sin(p), 0, np.cos(p)]])
         @ np.array([[1, 0, 0], [0, np.cos(r), -np.sin(r)], [0, np.sin(r), np.cos(r)]]))
    corners = [np.array([sx * hx, sy * hy, sz * hz]) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]
    pts = [R @ c + np.array([cx, cy, cz]) for c in corners]
    edges = []
    for i in range(8):
        for j in range(i + 1, 8):
            if bin(i ^ j).count("1") == 1:
                edges.append((pts[i], pts[j]))
    return edges


def draw_obstacles(ax, scene):
    """Draws the scene's obstacles; returns points that bound them (for the axes)."""
    bounds = []
    for o in scene.get("obstacles", []) or []:
        xyz = o.get("xyz", [0, 0, 0])
        color = "tab:gray" if o.get("name") == "wall" else "tab:red"
        if o["shape"] == "box":
            for a, b in box_edges(xyz, o["size"], o.get("rpy", [0, 0, 0])):
                ax.plot(*zip(a, b), color=color, lw=0.8)
                bounds += [a, b]
        elif o["shape"] == "sphere":
            u, v = np.mgrid[0:2 * np.pi:16j, 0:np.pi:8j]
            r = o["radius"]
            ax.plot_wireframe(xyz[0] + r * np.cos(u) * np.sin(v), xyz[1] + r * np.sin(u) * np.sin(v),
                              xyz[2] + r * np.cos(v), color=color, lw=0.5)
            bounds += [np.array(xyz) - r, np.array(xyz) + r]
        elif o["shape"] == "cylinder":
            th = np.linspace(0, 2 * np.pi, 24)
            r, h = o["radius"], o["length"] / 2
            for z in (-h, h):
                ax.plot(xyz[0] + r * np.cos(th), xyz[1] + r * np.sin(th), xyz[2] + z, color=color, lw=0.8)
            bounds += [np.array(xyz) - max(r, h), np.array(xyz) + max(r, h)]
    return bounds


def equal_axes(ax, pts):
    pts = np.asarray(pts)
    c = (pts.max(0) + pts.min(0)) / 2
    r = (pts.max(0) - pts.min(0)).max() / 2 + 0.05
    ax.set_xlim(c[0] - r, c[0] + r)
    ax.set_ylim(c[1] - r, c[1] + r)
    ax.set_zlim(c[2] - r, c[2] + r)


def save(fig, out, name):
    for ext in ("png", "svg"):
        fig.savefig(os.path.join(out, f"{name}.{ext}"), dpi=110, bbox_inches="tight")
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("export_dir")
    ap.add_argument("--out", default=None)
    ap.add_argument("--title", default="")
    ap.add_argument("--ee", default=None, help="the frame whose path is drawn (default: the scene's end-effector)")
    args = ap.parse_args()
    out = args.out or args.export_dir
    os.makedirs(out, exist_ok=True)
    s, header = read_states(os.path.join(args.export_dir, "states.csv"))
    scene = {}
    scene_file = os.path.join(args.export_dir, "scene.yaml")
    if os.path.exists(scene_file):
        scene = yaml.safe_load(open(scene_file)) or {}
    t, mode = s["t"], s["mode"]
    events = intervals(t, mode)
    joints = sorted([h for h in header if h.startswith("q") and h[1:].isdigit()], key=lambda h: int(h[1:]))
    title = args.title or scene.get("name", "")

    fig, ax = plt.subplots(figsize=(8, 4.5))
    for j in joints:
        ax.plot(t, s[j], label=f"joint{int(j[1:]) + 1}")
    label_time_plot(ax, events, "joint angle (rad)", title, "joint trajectories", ncol=3)
    save(fig, out, "joints")

    fig, ax = plt.subplots(figsize=(8, 3.5))
    f = np.sqrt(s["fx"] ** 2 + s["fy"] ** 2 + s["fz"] ** 2)
    ax.plot(t, f, color="k", label="|F|")
    for c, col in (("fx", "tab:red"), ("fy", "tab:green"), ("fz", "tab:blue")):
        ax.plot(t, s[c], color=col, lw=0.8, label=c)
    label_time_plot(ax, events, "force on the robot (N)", title, "interaction forces", ncol=4)
    save(fig, out, "forces")

    links = [h[:-2] for h in header if h.endswith(".x")]
    ee = args.ee if args.ee and f"{args.ee}.x" in s else end_effector(scene, links)
    path = np.stack([s[f"{ee}.x"], s[f"{ee}.y"], s[f"{ee}.z"]], 1)
    fig = plt.figure(figsize=(6.5, 6))
    ax = fig.add_subplot(projection="3d")
    bounds = draw_obstacles(ax, scene)
    ax.plot(*path.T, color="tab:blue", lw=1.5, label="end-effector")
    hit = s["in_collision"] > 0
    if hit.any():
        ax.scatter(*path[hit].T, color="tab:red", s=4, label="in collision")
    ax.scatter(*path[0], color="green", s=30, label="start")
    ax.scatter(*path[-1], color="black", s=30, label="end")
    equal_axes(ax, list(path) + bounds)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_zlabel("z (m)")
    ax.set_title(f"{title}: end-effector path" if title else "end-effector path")
    ax.legend(fontsize=8)
    save(fig, out, "path")

    fig = plt.figure(figsize=(6.5, 6))
    ax = fig.add_subplot(projection="3d")
    bounds = draw_obstacles(ax, scene)
    frames = np.linspace(0, len(t) - 1, 8).astype(int)
    all_pts = []
    for k, i in enumerate(frames):
        pts = np.array([[s[f"{l}.x"][i], s[f"{l}.y"][i], s[f"{l}.z"][i]] for l in links])
        all_pts.extend(pts)
        ax.plot(*pts.T, "-o", ms=2, lw=1.5, color=plt.cm.viridis(k / max(1, len(frames) - 1)),
                label=f"t = {t[i]:.2f} s")
    ax.plot(*path.T, color="tab:blue", lw=0.6, alpha=0.6)
    equal_axes(ax, all_pts + bounds)
    ax.set_title(f"{title}: snapshots" if title else "snapshots")
    ax.legend(fontsize=7)
    save(fig, out, "snapshots")
    print(f"plot_session: wrote joints, forces, path, snapshots (.png, .svg) to {out}/")


if __name__ == "__main__":
    main()
