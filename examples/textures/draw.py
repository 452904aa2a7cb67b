"""Draws the example textures (brick.png, tiles.png) as small PNGs, with Python alone.

Run it here to make them again: python3 draw.py. The images are deterministic.
"""
import random
import struct
import zlib


def png(name, width, height, pixel):
    rows = b"".join(
        b"\x00" + b"".join(bytes(pixel(x, y)) for x in range(width)) for y in range(height)
    )

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    with open(name, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", header))
        f.write(chunk(b"IDAT", zlib.compress(rows, 9)))
        f.write(chunk(b"IEND", b""))


def brick():
    # Two courses of bricks, the second offset by half a brick: the image tiles seamlessly.
    rng = random.Random(7)
    shade = {(c, b): rng.uniform(0.85, 1.1) for c in range(2) for b in range(3)}

    def pixel(x, y):
        course = y // 32
        bx = (x + 32 * course) % 128
        if y % 32 < 4 or bx % 64 < 4:
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


brick()
tiles()
