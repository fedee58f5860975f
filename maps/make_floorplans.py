#!/usr/bin/env python3
"""Writes the floorplan.geojson of each bundled scene (maps/<scene>/floorplan.geojson).

The floorplans are source data, kept in git; this script documents how they were drawn and
rewrites them identically. Coordinates in metres, local frame. Run: python3 maps/make_floorplans.py
"""
import json
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))


class Plan:
    def __init__(self):
        self.segs = []

    def wall(self, a, b, t=0.15):
        self.segs.append((a, b, "wall", t))

    def glass(self, a, b, t=0.01):
        self.segs.append((a, b, "glass", t))

    def poly(self, pts, t=0.15):
        for a, b in zip(pts, pts[1:]):
            self.wall(a, b, t)

    def wall_with_gaps(self, a, b, gaps, t=0.15, glass_gaps=()):
        """Wall from a to b (axis-aligned or not) with openings given as (s0, s1) distances along it.
        glass_gaps: openings closed by a glass pane instead of left open."""
        ax, ay = a
        bx, by = b
        length = math.hypot(bx - ax, by - ay)
        ux, uy = (bx - ax) / length, (by - ay) / length
        cuts = sorted([(s0, s1, False) for s0, s1 in gaps] + [(s0, s1, True) for s0, s1 in glass_gaps])
        s = 0.0
        for s0, s1, is_glass in cuts:
            if s0 > s:
                self.wall((ax + ux * s, ay + uy * s), (ax + ux * s0, ay + uy * s0), t)
            if is_glass:
                self.glass((ax + ux * s0, ay + uy * s0), (ax + ux * s1, ay + uy * s1))
            s = s1
        if s < length:
            self.wall((ax + ux * s, ay + uy * s), (bx, by), t)

    def desk(self, x, y, w=1.6, d=0.8):
        self.poly([(x, y), (x + w, y), (x + w, y + d), (x, y + d), (x, y)], t=0.08)

    def write(self, name, folder=None):
        feats = []
        for a, b, mat, t in self.segs:
            feats.append({"type": "Feature",
                          "properties": {"material": mat, "thickness": t},
                          "geometry": {"type": "LineString",
                                       "coordinates": [[round(a[0], 4), round(a[1], 4)],
                                                       [round(b[0], 4), round(b[1], 4)]]}})
        out = {"type": "FeatureCollection", "name": name, "features": feats}
        path = os.path.join(folder or os.path.join(HERE, name), "floorplan.geojson")
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w") as f:
            json.dump(out, f, indent=0)
            f.write("\n")
        n_glass = sum(1 for s in self.segs if s[2] == "glass")
        print(f"{name}: {len(self.segs)} segments, {n_glass} glass")


def paper_corridor():
    """Modelled on the paper's Fig. 7: an L-shaped corridor, six panes at different angles."""
    p = Plan()
    # Corridor A: y in [0, 2], x in [0, 24]. South wall with P1 (0 deg) and the angled P3 alcove.
    p.wall((0, 0), (3, 0)); p.glass((3, 0), (6, 0))                      # P1
    p.wall((6, 0), (13, 0)); p.glass((13, 0), (15.5, -1.0))              # P3, -21.8 deg
    p.wall((15.5, -1.0), (15.5, 0)); p.wall((15.5, 0), (24, 0))
    # North wall with P2 (0 deg, overlapping P1 in x: glass on both sides) and the angled P4.
    p.wall((0, 2), (5, 2)); p.glass((5, 2), (8, 2))                      # P2
    p.wall((8, 2), (16, 2)); p.glass((16, 2), (18, 3.5))                 # P4, 36.9 deg
    p.wall((18, 3.5), (18, 2)); p.wall((18, 2), (22, 2))
    p.wall((0, 0), (0, 2))
    # Corridor B: x in [22, 24], y in [2, 14]. East wall with P5 (90 deg), west wall with P6.
    p.wall((24, 0), (24, 5)); p.glass((24, 5), (24, 8))                  # P5
    p.wall((24, 8), (24, 14)); p.wall((22, 14), (24, 14))
    p.wall((22, 2), (22, 9)); p.glass((22, 9), (21, 11.5))               # P6, 111.8 deg
    p.wall((21, 11.5), (22, 11.5)); p.wall((22, 11.5), (22, 14))
    # Rooms south of A.
    p.poly([(0, 0), (0, -5), (24, -5), (24, 0)])
    p.wall((9, -5), (9, 0)); p.wall((19, -5), (19, -1.0))
    p.desk(1.5, -4.0); p.desk(4.0, -2.5, 1.2, 0.6); p.desk(11, -4.2); p.desk(20.5, -3.5)
    # Rooms north of A.
    p.poly([(0, 2), (0, 7), (17, 7), (17, 14), (22, 14)])
    p.wall((11, 2), (11, 7)); p.wall((17, 7), (22, 7))
    p.desk(2, 5.5); p.desk(6, 4.5, 1.2, 0.6); p.desk(13, 5.0); p.desk(18.5, 10.5, 1.0, 1.6)
    # Rooms east of B.
    p.poly([(24, -5), (29, -5), (29, 14), (24, 14)])
    p.wall((24, 4), (29, 4)); p.desk(26, 6.5, 1.2, 2.0); p.desk(26.5, 1.0)
    p.write("paper-corridor")


def glass_corridor():
    """A corridor with glass on both sides for 14 m (the paper's 'Two G' case)."""
    p = Plan()
    w = 2.4
    p.wall((0, 0), (3, 0)); p.wall((0, w), (3, w))
    for x in range(3, 17, 2):
        p.glass((x, 0), (x + 2, 0))
        p.glass((x, w), (x + 2, w))
    p.wall((17, 0), (20, 0)); p.wall((17, w), (20, w))
    p.wall((0, 0), (0, w)); p.wall((20, 0), (20, w))
    # Rooms behind both sides, with furniture the transmitted beams return from.
    p.poly([(0, 0), (0, -4.5), (20, -4.5), (20, 0)])
    p.poly([(0, w), (0, w + 4.5), (20, w + 4.5), (20, w)])
    for x in (5, 9.5, 14):
        p.wall((x, -4.5), (x, -1.5)); p.wall((x + 0.5, w + 4.5), (x + 0.5, w + 1.5))
    p.desk(1.0, -3.5); p.desk(6.0, -2.5, 1.2, 0.6); p.desk(10.5, -3.8); p.desk(15.5, -2.8, 1.2, 1.2)
    p.desk(2.0, w + 3.0); p.desk(7.0, w + 2.0, 1.0, 1.0); p.desk(11.5, w + 3.2); p.desk(16.0, w + 2.5)
    p.write("glass-corridor")


def office_floor():
    """About 60 m x 40 m: glass meeting rooms, glass doors, an 81.5 deg glass facade."""
    p = Plan()
    fx0, fx1 = 56.0, 62.0           # facade from (56, 0) to (62, 40)
    p.wall((0, 0), (fx0, 0)); p.wall((0, 40), (fx1, 40)); p.wall((0, 0), (0, 40))
    n = 16
    for i in range(n):              # facade: 16 panes of ~2.5 m
        a = (fx0 + (fx1 - fx0) * i / n, 40.0 * i / n)
        b = (fx0 + (fx1 - fx0) * (i + 1) / n, 40.0 * (i + 1) / n)
        p.glass(a, b, 0.012)
    # Main corridor y in [18, 21], x in [0, 50]; N-S corridor x in [28, 30.5].
    # North rooms y in [21, 29], 6 m wide, doors 1 m; meeting rooms [6,12] and [36,42] glass-fronted.
    north_x = [0, 6, 12, 18, 24, 28]
    gaps, glass_gaps = [], []
    for x0, x1 in zip(north_x, north_x[1:]):
        if x0 == 6:
            glass_gaps.append((x0 + 0.3, x1 - 1.6)); glass_gaps.append((x1 - 1.5, x1 - 0.5))  # front + door
        else:
            gaps.append((x1 - 1.5, x1 - 0.5))
    p.wall_with_gaps((0, 21), (28, 21), gaps, glass_gaps=glass_gaps)
    east_x = [30.5, 36, 42, 50]
    p.wall_with_gaps((30.5, 21), (50, 21), [(2.0, 3.0), (13.0, 14.0)],
                     glass_gaps=[(5.8, 10.5), (10.6, 11.3)])
    for x in north_x[1:-1] + east_x[1:]:
        p.wall((x, 21), (x, 29))
    p.wall_with_gaps((0, 29), (28, 29), [(13.0, 14.5)])
    p.wall_with_gaps((30.5, 29), (50, 29), [(8.0, 9.5)])
    # South rooms y in [10, 18], 8 m wide; a glass meeting room at x in [16, 24] with a half-open glass door.
    p.wall_with_gaps((0, 18), (28, 18), [(6.0, 7.0), (13.0, 14.0), (22.5, 23.5)], glass_gaps=[(16.5, 21.5)])
    p.glass((22.5, 18), (23.3, 18.6))   # glass door open at ~37 deg
    p.wall_with_gaps((30.5, 18), (50, 18), [(3.0, 4.0), (12.0, 13.0)])
    for x in (8, 16, 24, 38, 44):
        p.wall((x, 10), (x, 18))
    p.wall_with_gaps((0, 10), (28, 10), [(3.0, 4.5), (19.0, 20.5)])
    p.wall_with_gaps((30.5, 10), (50, 10), [(5.0, 6.5)])
    # N-S corridor walls with door gaps and one glass section.
    p.wall_with_gaps((28, 0), (28, 18), [(5.0, 6.5)])
    p.wall_with_gaps((30.5, 0), (30.5, 18), [(12.0, 13.0)], glass_gaps=[(2.0, 6.0)])
    p.wall_with_gaps((28, 21), (28, 40), [(10.0, 11.5)])
    p.wall_with_gaps((30.5, 21), (30.5, 40), [(14.0, 15.0)])
    # Main corridor ends at x = 50 in the open area by the facade.
    p.wall((50, 10), (50, 18)); p.wall((50, 21), (50, 29))
    # Open-plan areas: desks and pillars.
    for x in (3, 9, 15, 21):
        for y in (3, 6.5):
            p.desk(x, y)
    for x in (33, 39, 45):
        for y in (32, 35.5):
            p.desk(x, y)
    for x in (4, 12, 20):
        p.desk(x, 33, 2.0, 1.0)
    for (x, y) in ((36, 5), (44, 5), (47, 3)):
        p.poly([(x, y), (x + 0.5, y), (x + 0.5, y + 0.5), (x, y + 0.5), (x, y)], t=0.5)
    p.write("office-floor")


def no_glass():
    """A control floor: corridor, rooms and doors, no glass at all."""
    p = Plan()
    p.poly([(0, 0), (30, 0), (30, 20), (0, 20), (0, 0)])
    p.wall_with_gaps((0, 9), (30, 9), [(4.0, 5.0), (12.0, 13.0), (22.0, 23.0)])
    p.wall_with_gaps((0, 11), (30, 11), [(6.0, 7.0), (14.5, 15.5), (25.0, 26.0)])
    for x in (10, 20):
        p.wall((x, 0), (x, 9)); p.wall((x, 11), (x, 20))
    p.desk(2, 3); p.desk(13, 2, 1.2, 1.2); p.desk(24, 4); p.desk(3, 15); p.desk(12, 16.5); p.desk(25, 14, 1.0, 2.0)
    p.write("no-glass")


def glass_room(angle_deg=25.0, folder=None):
    """A glass meeting room (4 m x 3 m, a 0.9 m door gap, a table inside) turned angle_deg in a
    14 m x 12 m hall with desks along its walls. The scene's trajectory circles the room at 1.6 m
    from its panes (glass_room_waypoints), so each pane is seen near its normal and at every slant."""
    p = Plan()
    p.poly([(0, 0), (14, 0), (14, 12), (0, 12), (0, 0)])
    p.desk(0.5, 0.5, 1.2, 0.6); p.desk(12.3, 10.9, 1.2, 0.6); p.desk(0.5, 10.9, 0.6, 0.6); p.desk(12.9, 0.5, 0.6, 1.2)
    c, s_ = math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg))

    def at(x, y):  # room frame (centre 0, 0) -> hall
        return (7 + c * x - s_ * y, 6 + s_ * x + c * y)
    corners = [(-2, -1.5), (2, -1.5), (2, 1.5), (-2, 1.5)]
    for i in range(4):
        a, b = corners[i], corners[(i + 1) % 4]
        if i == 0:  # the south pane has the door gap, 0.9 m at its west end
            p.glass(at(-1.1, -1.5), at(2, -1.5))
        else:
            p.glass(at(*a), at(*b))
    # A table inside: what the transmitted beams return from.
    t = [at(-0.8, -0.4), at(0.8, -0.4), at(0.8, 0.4), at(-0.8, 0.4), at(-0.8, -0.4)]
    p.poly(t, t=0.08)
    p.write("glass-room", folder)


def glass_room_waypoints(angle_deg=25.0):
    """A loop around the glass room 1.6 m from its panes, in hall coordinates."""
    c, s_ = math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg))
    loop = [(-3.6, -3.1), (3.6, -3.1), (3.6, 3.1), (-3.6, 3.1), (-3.6, -3.1)]
    return [[round(7 + c * x - s_ * y, 3), round(6 + s_ * x + c * y, 3)] for x, y in loop]


if __name__ == "__main__":
    paper_corridor()
    glass_corridor()
    office_floor()
    no_glass()
    glass_room()
