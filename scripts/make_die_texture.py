#!/usr/bin/python3
"""Writes examples/targets/die_pips.png and die_pips.obj: a die with pips.

The texture is an atlas of the six faces, three across and two down, each
face ivory with dark pips (opposite faces add up to 7); the OBJ is the cube
of die.obj with each face's texture coordinates on its own tile. Pips and
face edges give a target detail at several scales, so that a change of
focus shows. Values are linear light, written as 8-bit sRGB (PNG textures
are decoded exactly: docs/target-format.md). Run it again only to change the
die; the files are committed.

Usage: scripts/make_die_texture.py [OUT_DIR]   (default examples/targets)
"""
import os
import struct
import sys
import zlib

import numpy as np

TILE = 128  # pixels per face
SUPERSAMPLE = 4
IVORY, PIP, EDGE = (0.85, 0.83, 0.75), (0.04, 0.04, 0.05), (0.30, 0.30, 0.28)
PIPS = {  # pip centres in a face's unit square, (s, t) with t up
    1: [(0.5, 0.5)],
    2: [(0.27, 0.73), (0.73, 0.27)],
    3: [(0.27, 0.73), (0.5, 0.5), (0.73, 0.27)],
    4: [(0.27, 0.27), (0.27, 0.73), (0.73, 0.27), (0.73, 0.73)],
    5: [(0.27, 0.27), (0.27, 0.73), (0.5, 0.5), (0.73, 0.27), (0.73, 0.73)],
    6: [(0.27, 0.25), (0.27, 0.5), (0.27, 0.75), (0.73, 0.25), (0.73, 0.5), (0.73, 0.75)],
}
PIP_RADIUS, EDGE_WIDTH = 0.095, 0.035
# The faces of die.obj (its vertex numbers, counter-clockwise seen from outside) and their pips.
FACES = [
    ("-z (front, toward the eye)", (1, 3, 7, 5), 5),
    ("+z (back)", (2, 6, 8, 4), 2),
    ("-x (left)", (1, 2, 4, 3), 3),
    ("+x (right)", (5, 7, 8, 6), 4),
    ("-y (bottom)", (1, 5, 6, 2), 6),
    ("+y (top)", (3, 4, 8, 7), 1),
]
VERTICES = [(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]


def face_image(pips):
    n = TILE * SUPERSAMPLE
    t, s = np.mgrid[0:n, 0:n]
    s = (s + 0.5) / n
    t = 1 - (t + 0.5) / n  # row 0 is the top
    image = np.empty((n, n, 3))
    image[:] = IVORY
    for cs, ct in PIPS[pips]:
        image[(s - cs) ** 2 + (t - ct) ** 2 < PIP_RADIUS**2] = PIP
    edge = np.minimum(np.minimum(s, 1 - s), np.minimum(t, 1 - t)) < EDGE_WIDTH
    image[edge] = EDGE
    return image.reshape(TILE, SUPERSAMPLE, TILE, SUPERSAMPLE, 3).mean(axis=(1, 3))


def srgb(linear):
    linear = np.clip(linear, 0, 1)
    encoded = np.where(linear <= 0.0031308, 12.92 * linear, 1.055 * linear ** (1 / 2.4) - 0.055)
    return np.round(encoded * 255).astype(np.uint8)


def write_png(path, rgb):
    height, width, _ = rgb.shape
    raw = b"".join(b"\x00" + rgb[y].tobytes() for y in range(height))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    with open(path + ".partial", "wb") as f:
        f.write(png)
    os.replace(path + ".partial", path)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "examples", "targets")
    atlas = np.zeros((2 * TILE, 3 * TILE, 3))
    obj = ["# A die with pips: the cube of die.obj, 2 units across, centered on its origin, each face's",
           "# texture coordinates on its own tile of die_pips.png (3 x 2 faces; scripts/make_die_texture.py).",
           "o die_pips"]
    obj += ["v %d %d %d" % v for v in VERTICES]
    for k, (_, _, pips) in enumerate(FACES):
        col, row = (pips - 1) % 3, (pips - 1) // 3
        atlas[row * TILE:(row + 1) * TILE, col * TILE:(col + 1) * TILE] = face_image(pips)
        u0, u1, v0, v1 = col / 3, (col + 1) / 3, 1 - (row + 1) / 2, 1 - row / 2
        obj += ["vt %.6f %.6f" % uv for uv in ((u0, v0), (u1, v0), (u1, v1), (u0, v1))]
    for k, (name, corners, pips) in enumerate(FACES):
        obj.append("# face %s: %d" % (name, pips))
        obj.append("f " + " ".join("%d/%d" % (v, 4 * k + i + 1) for i, v in enumerate(corners)))
    write_png(os.path.join(out, "die_pips.png"), srgb(atlas))
    with open(os.path.join(out, "die_pips.obj.partial"), "w") as f:
        f.write("\n".join(obj) + "\n")
    os.replace(os.path.join(out, "die_pips.obj.partial"), os.path.join(out, "die_pips.obj"))


if __name__ == "__main__":
    main()
