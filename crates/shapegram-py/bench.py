"""Per-call times of the Python module from a loaded grammar: `Grammar.derive` (the GIL
released while it derives, the buffers copied into bytes once) for examples/house.cga and the
topological houses, as the C ABI's benchmark times `sg_state_derive` + `sg_state_mesh`
(docs/runtimes.md). Prints; asserts nothing.

    RAYON_NUM_THREADS=1 python crates/shapegram-py/bench.py
"""

import pathlib
import time

import shapegram

EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "examples"


def main():
    for name, target_ms in (("house.cga", 3.0), ("topo_house.grammar", 0.2), ("topo_pyramid.grammar", 0.2)):
        grammar = shapegram.Grammar.load(EXAMPLES / name)
        mesh = grammar.derive()
        started = time.perf_counter()
        grammar.derive()
        once = time.perf_counter() - started
        # About a second of calls, at least ten.
        runs = max(10, min(100_000, int(1.0 / max(once, 1e-6))))
        times = []
        for _ in range(runs):
            started = time.perf_counter()
            grammar.derive()
            times.append((time.perf_counter() - started) * 1e3)
        times.sort()
        print(
            f"{name}: derive {times[runs // 2]:.3f} ms median, {times[0]:.3f} ms min, "
            f"{times[runs * 95 // 100]:.3f} ms p95 over {runs} calls (target {target_ms} ms); "
            f"{mesh.vertex_count} vertices, {mesh.triangle_count} triangles, {len(mesh.parts)} parts"
        )


if __name__ == "__main__":
    main()
