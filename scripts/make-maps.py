#!/usr/bin/env python3
"""Writes the example surface maps in assets/maps/ (standard library only; deterministic):

- scales-normal.png: a tiling normal map (tangent space, OpenGL convention: green up the image) of round scales in
  staggered rows, each flat on top with a border that falls steeply (a quarter circle) into a valley of hinge skin,
  so that its rim faces every way;
- scales-pigment.png: the same scales' colour (sRGB): dark red-brown centres, paler borders.

Usage: python3 scripts/make-maps.py [OUT_DIR]   (default assets/maps)
"""
import math
import os
import struct
import sys
import zlib

SIZE = 256          # texels a side (one repeat)
COLUMNS, ROWS = 4, 4  # scales per repeat (rows staggered by half a scale; ROWS even, so the tile repeats)
RIM = 0.22          # the border's width, as a share of a scale's half-width
HEIGHT = 0.35       # the dome's height over the valley, in scale half-widths (sets how far the rims turn the normal)
CENTRE_SRGB = (96, 46, 34)
BORDER_SRGB = (196, 164, 132)


def png(path, rows):
    """An 8-bit RGB PNG from rows of (r, g, b) tuples."""
    raw = b"".join(b"\x00" + bytes(c for px in row for c in px) for row in rows)
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    header = struct.pack(">IIBBBBB", len(rows[0]), len(rows), 8, 2, 0, 0, 0)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def centres():
    """The scale centres (texels) of one repeat and its eight neighbours (so that the nearest is always among them)."""
    w, h = SIZE / COLUMNS, SIZE / ROWS
    out = []
    for ty in (-1, 0, 1):
        for tx in (-1, 0, 1):
            for r in range(ROWS):
                for c in range(COLUMNS):
                    x = (c + 0.5 + 0.5 * (r % 2)) * w + tx * SIZE
                    y = (r + 0.5) * h + ty * SIZE
                    out.append((x, y))
    return out


def border_distance(x, y, points, radius):
    """How far (texels) the point is inside its scale: inside both its Voronoi cell (the distance to the cell's
    nearest edge, the perpendicular bisector towards a neighbour) and the disc of `radius` about its centre."""
    best = sorted(points, key=lambda p: (p[0] - x) ** 2 + (p[1] - y) ** 2)[:6]
    (ax, ay) = best[0]
    edge = radius - math.hypot(x - ax, y - ay)
    for (bx, by) in best[1:]:
        mx, my = (ax + bx) / 2, (ay + by) / 2
        nx, ny = bx - ax, by - ay
        length = math.hypot(nx, ny)
        edge = min(edge, ((mx - x) * nx + (my - y) * ny) / length)
    return edge


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "assets/maps"
    os.makedirs(out, exist_ok=True)
    points = centres()
    half = SIZE / COLUMNS / 2
    rim = RIM * half
    # The disc touches the cell's sides (the nearest neighbour is a row's step away, or the next row's diagonal).
    w, h = SIZE / COLUMNS, SIZE / ROWS
    radius = 0.5 * min(w, math.hypot(w / 2, h))
    edge = [[border_distance(x + 0.5, y + 0.5, points, radius) for x in range(SIZE)] for y in range(SIZE)]
    # The height: flat on the scale, falling as a quarter circle across the rim into the valley (texels).
    def height(e):
        t = min(max(e / rim, 0.0), 1.0)
        return HEIGHT * half * math.sqrt(1.0 - (1.0 - t) ** 2)
    h = [[height(e) for e in row] for row in edge]
    normal_rows, pigment_rows = [], []
    for y in range(SIZE):
        nrow, prow = [], []
        for x in range(SIZE):
            dx = (h[y][(x + 1) % SIZE] - h[y][(x - 1) % SIZE]) / 2
            drow = (h[(y + 1) % SIZE][x] - h[(y - 1) % SIZE][x]) / 2
            # Up the image is −row: n = (−∂h/∂x, −∂h/∂up, 1) = (−∂h/∂x, +∂h/∂row, 1).
            n = (-dx, drow, 1.0)
            length = math.sqrt(sum(c * c for c in n))
            nrow.append(tuple(round((c / length + 1) / 2 * 255) for c in n))
            t = min(max(edge[y][x] / (2 * rim), 0.0), 1.0)
            prow.append(tuple(round(b + (c - b) * t) for c, b in zip(CENTRE_SRGB, BORDER_SRGB)))
        normal_rows.append(nrow)
        pigment_rows.append(prow)
    png(os.path.join(out, "scales-normal.png"), normal_rows)
    png(os.path.join(out, "scales-pigment.png"), pigment_rows)
    steepest = max(math.degrees(math.acos((2 * c[2] / 255) - 1)) for row in normal_rows for c in row)
    print(f"wrote {out}/scales-normal.png and scales-pigment.png ({SIZE}², {COLUMNS}×{ROWS} scales, rims to "
          f"{steepest:.0f}°)")


if __name__ == "__main__":
    main()
