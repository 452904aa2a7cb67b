"""What the Blender checks share: the numpy alias Blender 3.4's glTF importer needs, checks that
print "ok" or "FAIL" and are counted, and running a script's main so that any failure, an
uncaught exception included, exits 1.

Import it before the glTF importer runs (each script puts its own folder on sys.path first).
"""
import sys
import traceback

# Blender 3.4's importer uses numpy's `np.bool`, which numpy 1.24 (Debian bookworm's
# python3-numpy) removed: the import fails with "module 'numpy' has no attribute 'bool'".
# Fixed upstream in the 3.5 add-on (glTF-Blender-IO #1831), not backported to 3.4; the alias
# is exactly the builtin.
import numpy

if "bool" not in numpy.__dict__:
    numpy.bool = bool

failures = []


def check(ok, message):
    """Prints a check's outcome and counts a failure; returns `ok`."""
    print(f"  {'ok  ' if ok else 'FAIL'} {message}")
    if not ok:
        failures.append(message)
    return ok


def run(main):
    """Runs `main`, then exits 1 if any check failed or it raised, else prints "passed"."""
    try:
        main()
    except Exception as error:  # an uncaught error must fail the run, with or without --python-exit-code
        traceback.print_exc()
        failures.append(f"exception: {error}")
    if failures:
        print(f"FAILED: {len(failures)} check(s) failed:")
        for f in failures:
            print(f"  - {f}")
        sys.stdout.flush()
        sys.exit(1)
    print("passed")
