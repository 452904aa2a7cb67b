#!/usr/bin/env python3
"""Shapegram's marching cubes against the plain NumPy pipeline, side by side.

Meshes the benchmark scene of crates/shapegram-implicit/benches/scene.rs (twelve primitives,
differences and a morph) with Shapegram (the bench_scene example, best of three runs), then
evaluates the same field with NumPy on the same grid and meshes it with scikit-image and PyMCubes
(each timed as NumPy evaluation + marching cubes, best of three). Prints one line per pipeline
and the ratios. Not part of CI; needs numpy, and scikit-image and/or PyMCubes:

    python3 -m venv /tmp/venv && /tmp/venv/bin/pip install numpy scikit-image PyMCubes
    /tmp/venv/bin/python bench/compare.py 128 256
"""

import json
import os
import subprocess
import sys
import time

import numpy as np


def run_shapegram(cells):
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    out = subprocess.run(
        ["cargo", "run", "-q", "--release", "-p", "shapegram-implicit", "--example",
         "bench_scene", "--", str(cells)],
        cwd=root, check=True, capture_output=True, text=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def length(*parts):
    return np.sqrt(sum(p * p for p in parts))


def sphere(x, y, z, r):
    return r - length(x, y, z)


def box(x, y, z, sx, sy, sz):
    qx, qy, qz = np.abs(x) - sx / 2, np.abs(y) - sy / 2, np.abs(z) - sz / 2
    outside = length(np.maximum(qx, 0), np.maximum(qy, 0), np.maximum(qz, 0))
    return -(outside + np.minimum(np.maximum(np.maximum(qx, qy), qz), 0))


def cylinder_y(x, y, z, r, h):
    dr, dy = length(x, z) - r, np.abs(y) - h / 2
    return -(np.minimum(np.maximum(dr, dy), 0) + length(np.maximum(dr, 0), np.maximum(dy, 0)))


def torus_xz(x, y, z, major, minor):
    return minor - length(length(x, z) - major, y)


def capsule_x(x, y, z, r, l):
    dx = x - np.clip(x, -l / 2, l / 2)
    return r - length(dx, y, z)


def cone_y(x, y, z, r, h):
    norm = np.hypot(r, h)
    side = length(x, z) * (h / norm) + (y - h / 2) * (r / norm)
    return -np.maximum(side, -h / 2 - y)


def scene(x, y, z):
    """The field of benches/scene.rs: positive inside."""
    s = box(x, y, z, 3.0, 2.0, 2.0)
    for cx in (-1.5, 1.5):
        s = np.maximum(s, sphere(x - cx, y, z, 0.9))
    for cx in (-1.2, -0.4, 0.4, 1.2):
        # A cylinder turned a quarter about x: its axis runs along z.
        s = np.minimum(s, -cylinder_y(x - cx, z, -y, 0.35, 3.0))
    s = np.maximum(s, torus_xz(x, y - 1.0, z, 1.2, 0.3))
    s = np.minimum(s, -capsule_x(x, y + 0.6, z, 0.4, 2.5))
    s = np.maximum(s, cone_y(x, y - 1.6, z, 0.8, 1.5))
    s = np.minimum(s, -sphere(x, y, z - 1.0, 0.5))
    return 0.7 * s + 0.3 * sphere(x, y, z, 2.0)


def evaluate(grid):
    h, (ox, oy, oz), (nx, ny, nz) = grid["cell_size"], grid["origin"], grid["grid"]
    xs = ox + h * np.arange(nx + 1)
    ys = oy + h * np.arange(ny + 1)
    zs = oz + h * np.arange(nz + 1)
    x, y, z = np.meshgrid(xs, ys, zs, indexing="ij")
    return scene(x, y, z)


def best_of(n, work):
    best, result = float("inf"), None
    for _ in range(n):
        started = time.perf_counter()
        result = work()
        best = min(best, time.perf_counter() - started)
    return best, result


def main():
    sizes = [int(a) for a in sys.argv[1:]] or [128, 256]
    pipelines = []
    try:
        from skimage.measure import marching_cubes as skimage_mc
        pipelines.append(("numpy + scikit-image", lambda v: skimage_mc(v, level=0.0)[1]))
    except ImportError:
        print("scikit-image not installed: skipped")
    try:
        import mcubes
        pipelines.append(("numpy + PyMCubes", lambda v: mcubes.marching_cubes(v, 0.0)[1]))
    except ImportError:
        print("PyMCubes not installed: skipped")
    for cells in sizes:
        ours = run_shapegram(cells)
        nx, ny, nz = ours["grid"]
        print(f"\n{cells}^3 (grid {nx} x {ny} x {nz}, {(nx + 1) * (ny + 1) * (nz + 1) / 1e6:.1f} M samples)")
        print(f"  shapegram             {ours['seconds'] * 1e3:9.1f} ms  {ours['triangles']:>9} triangles")
        eval_time, volume = best_of(3, lambda: evaluate(ours))
        print(f"  numpy evaluation      {eval_time * 1e3:9.1f} ms")
        for name, mc in pipelines:
            mc_time, faces = best_of(3, lambda: mc(volume))
            total = eval_time + mc_time
            print(f"  {name:<21} {total * 1e3:9.1f} ms  {len(faces):>9} triangles"
                  f"  (marching cubes {mc_time * 1e3:.1f} ms)  shapegram is {total / ours['seconds']:.1f}x faster")


if __name__ == "__main__":
    main()
