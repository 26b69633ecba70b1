#!/usr/bin/env python3
"""Writes the closed test meshes beside this script (committed; run again only to change them):
  cube.obj   a 0.4 m cube centred on the origin, 12 triangles: a convex solid whose faces are two
             triangles each (a sphere of any size resting on a face touches one triangle's interior);
  bowl.obj   a solid bowl of revolution about z: a cylinder 0.5 m across and 0.2 m tall, its base on
             z = 0, with a spherical cavity of radius 0.25 m opened at the top (0.15 m deep), 48
             segments around and 16 along the cavity: a non-convex solid (its convex hull is a lid
             across the cavity, where MuJoCo would rest a ball dropped into it)."""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))


def write(name, header, vertices, faces):
    with open(os.path.join(HERE, name), "w") as f:
        for line in header.strip().splitlines():
            f.write("# " + line + "\n")
        for v in vertices:
            f.write("v %.6f %.6f %.6f\n" % tuple(v))
        for t in faces:
            f.write("f %d %d %d\n" % tuple(i + 1 for i in t))


def cube():
    h = 0.2
    v = [(x, y, z) for z in (-h, h) for y in (-h, h) for x in (-h, h)]
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]  # outward
    faces = [t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))]
    write("cube.obj", "A 0.4 m cube centred on the origin (make_meshes.py): a closed convex mesh for the contact tests.",
          v, faces)


def bowl():
    R, H, cavity, depth, around, along = 0.25, 0.2, 0.25, 0.15, 48, 16
    # The profile from the bottom's centre outward, up the wall, across the rim, down the cavity to its
    # lowest point: (radius, height), counter-clockwise seen with r to the right (the solid on the left).
    centre = H - depth + cavity  # the cavity sphere's centre height
    rim = math.sqrt(cavity ** 2 - (centre - H) ** 2)
    profile = [(0.0, 0.0), (R, 0.0), (R, H), (rim, H)]
    top = math.atan2(H - centre, rim)  # the cavity's angle at the rim (below its centre's horizon)
    for k in range(1, along + 1):
        a = top + (-math.pi / 2 - top) * k / along
        profile.append((cavity * math.cos(a), centre + cavity * math.sin(a)))
    profile[-1] = (0.0, profile[-1][1])
    # Revolve: the two points on the axis are poles.
    v, rings = [], []
    for r, z in profile:
        if r == 0.0:
            rings.append([len(v)])
            v.append((0.0, 0.0, z))
        else:
            rings.append(list(range(len(v), len(v) + around)))
            v += [(r * math.cos(2 * math.pi * i / around), r * math.sin(2 * math.pi * i / around), z) for i in range(around)]
    faces = []
    for a, b in zip(rings, rings[1:]):
        for i in range(around):
            j = (i + 1) % around
            if len(a) == 1:
                faces.append((a[0], b[j], b[i]))
            elif len(b) == 1:
                faces.append((a[i], a[j], b[0]))
            else:
                faces += [(a[i], a[j], b[j]), (a[i], b[j], b[i])]
    write("bowl.obj", "A solid bowl (make_meshes.py): 0.5 m across, 0.2 m tall, base on z = 0, a spherical cavity of\n"
          "radius 0.25 m opened 0.15 m deep at the top; non-convex, closed.", v, faces)


cube()
bowl()
