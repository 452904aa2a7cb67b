"""Draws the example textures (brick.png, tiles.png, brick_normal.png, lattice.png) as small
PNGs, with Python alone.

Run it here to make them again: python3 draw.py. The images are deterministic.
"""
import random
import struct
import zlib


def png(name, width, height, pixel, alpha=False):
    """Writes an 8-bit RGB PNG, or RGBA when `alpha` (colour type 6)."""
    rows = b"".join(
        b"\x00" + b"".join(bytes(pixel(x, y)) for x in range(width)) for y in range(height)
    )

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    header = struct.pack(">IIBBBBB", width, height, 8, 6 if alpha else 2, 0, 0, 0)
    with open(name, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", header))
        f.write(chunk(b"IDAT", zlib.compress(rows, 9)))
        f.write(chunk(b"IEND", b""))


def mortar(x, y):
    """Whether a pixel of the 128 × 64 brick layout is mortar: two courses of bricks, the
    second offset by half a brick, so that the image tiles seamlessly."""
    course = y // 32
    bx = (x + 32 * course) % 128
    return y % 32 < 4 or bx % 64 < 4


def brick():
    rng = random.Random(7)
    shade = {(c, b): rng.uniform(0.85, 1.1) for c in range(2) for b in range(3)}

    def pixel(x, y):
        course = y // 32
        if mortar(x, y):
            return (196, 190, 178)
        s = shade[(course, (x + 32 * course) // 64 % 2)] * (0.96 + 0.04 * ((x * 7 + y * 13) % 5) / 4)
        return tuple(min(255, int(c * s)) for c in (164, 78, 52))

    png("brick.png", 128, 64, pixel)


def tiles():
    # Rows of rounded roof tiles, darker where one row overlaps the next.
    def pixel(x, y):
        row = y // 16
        tx = (x + 8 * (row % 2)) % 16
        edge = abs(tx - 8) / 8
        depth = (y % 16) / 16
        s = 1.0 - 0.35 * edge * edge - 0.25 * depth
        return tuple(int(c * s) for c in (150, 62, 45))

    png("tiles.png", 64, 64, pixel)


def brick_normal():
    # Tangent-space normals of the brick layout: flat on the bricks and in the mortar, tilted
    # where a brick's edge drops into the mortar (x right, y up the image, z out).
    def height(x, y):
        return 0.0 if mortar(x % 128, y % 64) else 1.0

    def pixel(x, y):
        dx = (height(x + 1, y) - height(x - 1, y)) / 2
        dy = (height(x, y - 1) - height(x, y + 1)) / 2
        n = (-dx, -dy, 1.0)
        length = sum(c * c for c in n) ** 0.5
        return tuple(int(round((c / length + 1) / 2 * 255)) for c in n)

    png("brick_normal.png", 128, 64, pixel)


def lattice():
    # A garden trellis: white laths on the diagonals, transparent between them.
    def pixel(x, y):
        lath = min((x + y) % 32, (x - y) % 32) < 5
        return (236, 232, 220, 255) if lath else (0, 0, 0, 0)

    png("lattice.png", 64, 64, pixel, alpha=True)


brick()
tiles()
brick_normal()
lattice()
