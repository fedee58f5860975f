#!/usr/bin/env python3
"""Moves a log, a plan or a raster by (DX, DY) metres: the far-coordinate checks of
docs/reliability.md (results must not depend on where the frame's origin lies).

  tools/shift_xy.py IN OUT DX DY

IN by its name: a CARMEN log (.log/.clf, optionally .gz: the laser and odometry poses of
ROBOTLASER1/FLASER/RLASER lines, ODOM and TRUEPOS poses), a TUM trajectory (.tum: x and y), a
GeoJSON plan (.geojson: every coordinate), or a GeoTIFF (.tif: the geotransform's origin, through
GDAL's Python bindings).
Numbers are written in their shortest exact form (repr), so only the shift changes them.
"""
import gzip
import json
import shutil
import sys


def shift_log(src, dst, dx, dy):
    opener = gzip.open if src.endswith(".gz") else open
    out_opener = gzip.open if dst.endswith(".gz") else open
    with opener(src, "rt") as fin, out_opener(dst, "wt") as fout:
        for number, line in enumerate(fin, 1):
            t = line.split()
            if not t or t[0].startswith("#"):
                fout.write(line)
                continue

            def move(i):
                t[i] = repr(float(t[i]) + dx)
                t[i + 1] = repr(float(t[i + 1]) + dy)

            try:
                if t[0].startswith("ROBOTLASER"):
                    k = 9 + int(t[8])
                    k += 1 + int(t[k])  # remissions
                    move(k)  # laser pose
                    move(k + 3)  # robot (odometry) pose
                elif t[0] in ("FLASER", "RLASER"):
                    k = 2 + int(t[1])
                    move(k)
                    move(k + 3)
                elif t[0] == "ODOM":
                    move(1)
                elif t[0] == "TRUEPOS":
                    move(1)
                    move(4)
            except (IndexError, ValueError) as e:
                sys.exit(f"{src}:{number}: cannot shift a {t[0]} line: {e}")
            fout.write(" ".join(t) + "\n")


def shift_tum(src, dst, dx, dy):
    with open(src) as fin, open(dst, "w") as fout:
        for line in fin:
            t = line.split()
            if len(t) >= 3 and not t[0].startswith("#"):
                t[1] = repr(float(t[1]) + dx)
                t[2] = repr(float(t[2]) + dy)
                line = " ".join(t) + "\n"
            fout.write(line)


def shift_geojson(src, dst, dx, dy):
    with open(src) as f:
        d = json.load(f)

    def move(c):
        if c and isinstance(c[0], (int, float)):
            return [c[0] + dx, c[1] + dy] + list(c[2:])
        return [move(x) for x in c]

    for feature in d.get("features", []):
        g = feature.get("geometry")
        if g and "coordinates" in g:
            g["coordinates"] = move(g["coordinates"])
    with open(dst, "w") as f:
        json.dump(d, f)


def shift_tif(src, dst, dx, dy):
    from osgeo import gdal  # Debian: python3-gdal

    shutil.copyfile(src, dst)
    ds = gdal.Open(dst, gdal.GA_Update)
    if ds is None:
        sys.exit(f"{dst}: GDAL cannot open it")
    g = list(ds.GetGeoTransform())
    g[0] += dx
    g[3] += dy
    ds.SetGeoTransform(g)
    ds = None


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    src, dst, dx, dy = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
    if src.endswith(".tum"):
        shift_tum(src, dst, dx, dy)
    elif src.endswith(".geojson"):
        shift_geojson(src, dst, dx, dy)
    elif src.endswith((".tif", ".tiff")):
        shift_tif(src, dst, dx, dy)
    else:
        shift_log(src, dst, dx, dy)


if __name__ == "__main__":
    main()
