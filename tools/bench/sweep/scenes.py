"""Scene variants of the sweeps: pane corridors, glass thickness, panes in view; bundled scenes."""
from __future__ import annotations

import copy
import math

from .stats import REPO

def pane_corridor_geojson(angle_deg: float, thickness: float = 0.01) -> dict:
    """A 20 m x 3 m corridor with a 2 m gap in its upper wall into a 6 m x 4 m room; one 2 m glass
    pane hinged at the gap's left end, rotated by angle_deg from the corridor axis into the room."""
    def line(a, b, mat, th):
        return {"type": "Feature", "properties": {"material": mat, "thickness": th},
                "geometry": {"type": "LineString", "coordinates": [list(a), list(b)]}}
    a = math.radians(angle_deg)
    walls = [((0, 0), (20, 0)), ((0, 3), (9, 3)), ((11, 3), (20, 3)), ((0, 0), (0, 3)),
             ((20, 0), (20, 3)), ((7, 3), (7, 7)), ((7, 7), (13, 7)), ((13, 7), (13, 3))]
    feats = [line(p, q, "wall", 0.15) for p, q in walls]
    feats.append(line((9, 3), (round(9 + 2 * math.cos(a), 6), round(3 + 2 * math.sin(a), 6)),
                      "glass", thickness))
    return {"type": "FeatureCollection", "name": f"pane-{angle_deg:g}deg", "features": feats}


def set_glass_thickness(geojson: dict, thickness: float) -> dict:
    g = copy.deepcopy(geojson)
    for f in g["features"]:
        if f.get("properties", {}).get("material") == "glass":
            f["properties"]["thickness"] = thickness
    return g


PANE_SLOTS = 9   # 2 m slots per corridor side between x = 1 and x = 19


def spread_slots(k: int, slots: int = PANE_SLOTS) -> list[int]:
    """k distinct slot indices out of `slots`, spread evenly (0 -> [], slots -> all)."""
    if not 0 <= k <= slots:
        raise ValueError(f"{k} panes do not fit in {slots} slots")
    if k == 0:
        return []
    if k == 1:
        return [slots // 2]
    return sorted({round(i * (slots - 1) / (k - 1)) for i in range(k)})


def panes_corridor_geojson(n: int, thickness: float = 0.01) -> dict:
    """A 20 m x 3 m corridor (y 0..3) between two 20 m x 4 m rooms (y 3..7 and -4..0), its two
    walls made of 2 m slots between x = 1 and x = 19 (walls at both ends): n of the 18 slots are glass
    panes, ceil(n/2) in the upper wall and floor(n/2) in the lower one, spread evenly along each; the
    others are wall. The rooms behind give transmitted beams something to return from."""
    if not 0 <= n <= 2 * PANE_SLOTS:
        raise ValueError(f"0..{2 * PANE_SLOTS} panes, not {n}")
    def line(a, b, mat, th):
        return {"type": "Feature", "properties": {"material": mat, "thickness": th},
                "geometry": {"type": "LineString", "coordinates": [list(a), list(b)]}}
    feats = [line(p, q, "wall", 0.15) for p, q in
             [((0, -4), (20, -4)), ((0, 7), (20, 7)), ((0, -4), (0, 7)), ((20, -4), (20, 7)),
              ((0, 0), (1, 0)), ((19, 0), (20, 0)), ((0, 3), (1, 3)), ((19, 3), (20, 3))]]
    for y, k in ((3, (n + 1) // 2), (0, n // 2)):
        glass = set(spread_slots(k))
        x0 = 1
        for i in range(PANE_SLOTS + 1):      # merge neighbouring wall slots into one segment
            if i == PANE_SLOTS or i in glass:
                if 1 + 2 * i > x0:
                    feats.append(line((x0, y), (1 + 2 * i, y), "wall", 0.15))
                if i < PANE_SLOTS:
                    feats.append(line((1 + 2 * i, y), (3 + 2 * i, y), "glass", thickness))
                x0 = 3 + 2 * i
    return {"type": "FeatureCollection", "name": f"panes-{n}", "features": feats}



def scene_yaml(name):
    return REPO / "maps" / name / "scene.yaml"
