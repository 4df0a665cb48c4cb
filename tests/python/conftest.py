"""Fixtures of the Python module's tests (tests/python/, run by ctest as
python_*): the repository, the built CLI to compare against, a PFM reader,
and small scenes."""
import os
import pathlib
import subprocess

import numpy as np
import pytest

import caustica

ROOT = pathlib.Path(os.environ.get("CAUSTICA_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
CLI = os.environ.get("CAUSTICA_BINARY", str(ROOT / "build" / "caustica"))
SHARED = ROOT.parent / "shared"


def read_pfm(path):
    """A little-endian RGB PFM as H x W x 3 float32, top row first."""
    data = pathlib.Path(path).read_bytes()
    parts = data.split(b"\n", 3)
    assert parts[0] == b"PF", path
    width, height = map(int, parts[1].split())
    assert float(parts[2]) < 0, "big-endian PFM"
    pixels = np.frombuffer(parts[3], dtype="<f4", count=width * height * 3).reshape(height, width, 3)
    return pixels[::-1].copy()


def run_cli(*args, check=True):
    """The CLI with these arguments; its CompletedProcess (stdout and stderr as text)."""
    result = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True, timeout=600)
    if check and result.returncode != 0:
        raise AssertionError(f"caustica {' '.join(map(str, args))} failed:\n{result.stderr}")
    return result


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture(scope="session")
def cornell():
    return caustica.load(ROOT / "scenes" / "cornell_box.json")


def sphere_scene(width=32, height=24, mode="path", extra_shapes=(), lights=None):
    """A small scene as a dict: a sphere on a floor under an area light."""
    return {
        "nbounces": 4,
        "rendermode": mode,
        "camera": {"type": "pinhole", "width": width, "height": height, "position": [0, 1, -4],
                   "lookAt": [0, 0.5, 0], "upVector": [0, 1, 0], "fov": 45},
        "scene": {
            "backgroundcolor": [0.1, 0.1, 0.1],
            "lightsources": lights if lights is not None else [
                {"type": "pointlight", "position": [0, 3, -2], "intensity": [8, 8, 8]}],
            "shapes": [
                {"type": "sphere", "center": [0, 0.5, 0], "radius": 0.5,
                 "material": {"diffusecolor": [0.8, 0.3, 0.2]}},
                {"type": "triangle", "v0": [-3, 0, -3], "v1": [3, 0, -3], "v2": [3, 0, 3],
                 "material": {"diffusecolor": [0.7, 0.7, 0.7]}},
                {"type": "triangle", "v0": [-3, 0, -3], "v1": [3, 0, 3], "v2": [-3, 0, 3],
                 "material": {"diffusecolor": [0.7, 0.7, 0.7]}},
                *extra_shapes,
            ],
        },
    }
