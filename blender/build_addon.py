"""Builds the Blender add-on's zip: the `shapegram` module as an abi3 wheel (maturin, release),
its extension module put inside the add-on's folder beside the Python files.

    python blender/build_addon.py target/shapegram_blender.zip [--wheel shapegram-….whl]

Run it with a Python whose environment has maturin (a venv: `pip install maturin`), or give
it a wheel maturin built already."""

import argparse
import pathlib
import shutil
import subprocess
import sys
import tempfile
import zipfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
ADDON = ROOT / "blender" / "shapegram_blender"


def build_wheel(folder):
    """Builds the module's wheel into `folder` and returns its path."""
    maturin = shutil.which("maturin", path=str(pathlib.Path(sys.executable).parent)) or shutil.which("maturin")
    if maturin is None:
        sys.exit("error: no maturin next to this Python or on PATH (pip install maturin in a venv)")
    subprocess.run(
        [maturin, "build", "--release", "--strip", "-m", str(ROOT / "crates/shapegram-py/Cargo.toml"), "-o", folder],
        check=True,
    )
    (wheel,) = pathlib.Path(folder).glob("shapegram-*.whl")
    return wheel


def main():
    parser = argparse.ArgumentParser(description="Builds the Blender add-on's zip.")
    parser.add_argument("out", type=pathlib.Path, help="the zip to write")
    parser.add_argument("--wheel", type=pathlib.Path, help="a wheel maturin built (else one is built)")
    arguments = parser.parse_args()
    out = arguments.out
    with tempfile.TemporaryDirectory() as folder:
        wheel = arguments.wheel or build_wheel(folder)
        with zipfile.ZipFile(wheel) as archive:
            (module,) = [n for n in archive.namelist() if n.endswith(".abi3.so")]
            native = archive.read(module)
    out.parent.mkdir(parents=True, exist_ok=True)
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as archive:
        for path in sorted(ADDON.glob("*.py")):
            archive.write(path, f"shapegram_blender/{path.name}")
        info = zipfile.ZipInfo("shapegram_blender/shapegram.abi3.so", date_time=(2024, 1, 1, 0, 0, 0))
        info.external_attr = 0o755 << 16
        archive.writestr(info, native, zipfile.ZIP_DEFLATED)
    print(f"{out}: {wheel.name}'s module in the add-on")


if __name__ == "__main__":
    main()
