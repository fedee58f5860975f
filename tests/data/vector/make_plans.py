#!/usr/bin/env python3
"""Writes the test plans of the vector stage (tests/data/vector/<name>.geojson): buildings whose
walls do not all run along two axes, for tools/plan_bench.py and tests/vector.

- pentagon: a pentagonal building (circumradius 16 m) around a pentagonal courtyard (7 m): ten
  rooms between the rings (a wall from each courtyard corner and each courtyard edge's middle to
  the facade), each with a 1 m door onto a ring corridor 2 m wide along the courtyard. Five wall
  directions 36 degrees apart.
- angled-office: a 30 m x 18 m office turned 23 degrees, rooms on both sides of a corridor, with a
  wing at 45 degrees to it (two rooms).

Walls 0.15 m thick, coordinates in metres. The files are source data kept in git; this script
documents how they were drawn and rewrites them identically. Run:
python3 tests/data/vector/make_plans.py
"""
import json
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
T = 0.15


def write(name, segs):
    feats = [{"type": "Feature", "properties": {"material": "wall", "thickness": T},
              "geometry": {"type": "LineString",
                           "coordinates": [[round(a[0], 4), round(a[1], 4)], [round(b[0], 4), round(b[1], 4)]]}}
             for a, b in segs]
    with open(os.path.join(HERE, name + ".geojson"), "w") as f:
        json.dump({"type": "FeatureCollection", "name": name, "features": feats}, f, indent=0)
        f.write("\n")
    print(f"{name}: {len(segs)} segments")


def lerp(a, b, t):
    return (a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t)


def with_gaps(a, b, gaps):
    """Segments of the wall a..b with openings (s0, s1) in metres along it."""
    length = math.dist(a, b)
    out, s = [], 0.0
    for s0, s1 in sorted(gaps):
        if s0 > s:
            out.append((lerp(a, b, s / length), lerp(a, b, s0 / length)))
        s = s1
    if s < length:
        out.append((lerp(a, b, s / length), b))
    return out


def pentagon():
    def ring(r):
        return [(r * math.cos(math.radians(90 + 72 * k)), r * math.sin(math.radians(90 + 72 * k))) for k in range(5)]

    outer, inner = ring(16.0), ring(7.0)
    corridor = ring(7.0 + 2.0 / math.cos(math.radians(36)))  # walls of rooms 2 m from the courtyard
    segs = []
    for k in range(5):
        segs.append((outer[k], outer[(k + 1) % 5]))
        segs.append((inner[k], inner[(k + 1) % 5]))
        # The corridor's outer wall: two rooms per side, a 1 m door in each.
        a, b = corridor[k], corridor[(k + 1) % 5]
        side = math.dist(a, b)
        segs += with_gaps(a, b, [(0.25 * side - 0.5, 0.25 * side + 0.5), (0.75 * side - 0.5, 0.75 * side + 0.5)])
        # Room walls: from each corridor corner and each corridor side's middle to the facade.
        segs.append((corridor[k], outer[k]))
        segs.append((lerp(a, b, 0.5), lerp(outer[k], outer[(k + 1) % 5], 0.5)))
    # The courtyard is not part of the building: the corridor opens onto it nowhere; one entrance.
    return segs


def angled_office():
    th = math.radians(23.0)
    c, s = math.cos(th), math.sin(th)

    def P(x, y):
        return (c * x - s * y, s * x + c * y)

    segs = []

    def wall(a, b, gaps=()):
        for p, q in with_gaps(a, b, list(gaps)):
            segs.append((P(*p), P(*q)))

    W, H = 30.0, 18.0
    wall((0, 0), (W, 0))
    wall((W, 0), (W, H))
    wall((W, H), (0, H), [(W - 24.0, W - 20.0)])  # (the wing joins at x in [20, 24])
    wall((0, H), (0, 0))
    # Corridor y in [8, 10.5]; rooms 5 m wide on both sides, a 1 m door each.
    for y in (8.0, 10.5):
        gaps = [(x + 2.0, x + 3.0) for x in range(0, 30, 5)]
        wall((0, y), (W, y), gaps)
    for x in range(5, 30, 5):
        wall((x, 0), (x, 8.0))
        if x not in (20,):
            wall((x, 10.5), (x, H))
    # The wing: from the top edge x in [20, 24] out at 45 degrees to the office, 12 m long (2.8 m
    # wide across), a cross wall half way with a 1 m door.
    u = (math.cos(math.radians(45)), math.sin(math.radians(45)))
    L = 12.0

    def along(p, t):
        return (p[0] + t * u[0], p[1] + t * u[1])

    base_l, base_r = (20.0, H), (24.0, H)
    wall(base_l, along(base_l, L))
    wall(base_r, along(base_r, L))
    wall(along(base_l, L), along(base_r, L))
    wall(along(base_l, L / 2), along(base_r, L / 2), [(1.4, 2.4)])
    return segs


if __name__ == "__main__":
    write("pentagon", pentagon())
    write("angled-office", angled_office())
