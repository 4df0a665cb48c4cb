"""The tutorial's examples (examples/python/, docs/python.md) run at small
sizes, and what they print and draw holds: adaptive sampling's error is
judged against the reference, the sweep's images differ by roughness, and
every device renders."""
import importlib.util
import pathlib

import numpy as np
import pytest

import caustica
from conftest import ROOT

matplotlib = pytest.importorskip("matplotlib", reason="the examples draw with matplotlib (python3-matplotlib)")


def example(name):
    spec = importlib.util.spec_from_file_location(name, ROOT / "examples" / "python" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_error_vs_time(tmp_path):
    finals = example("error_vs_time").main(["--small", "--out", str(tmp_path)])
    assert (tmp_path / "error_vs_time.png").stat().st_size > 10000
    for name in ("uniform", "adaptive"):
        spp, seconds, true, estimated = finals[name]
        assert spp >= 4 and 0 < true < 1 and 0 < estimated < 1


def test_material_sweep(tmp_path):
    renders = example("material_sweep").main(["--small", "--out", str(tmp_path)])
    assert (tmp_path / "material_sweep.png").stat().st_size > 10000
    assert len(renders) == 6
    # A mirror-smooth sphere and a rough one are different images.
    assert caustica.diff(renders[0], renders[-1], metric="mae") > 1e-3


def test_every_device(tmp_path):
    results = example("every_device").main(["--small", "--out", str(tmp_path)])
    assert (tmp_path / "every_device.png").stat().st_size > 5000
    assert len(results) == len(caustica.devices())
    for device, r, against_first in results:
        assert np.isfinite(r.image).all() and against_first < 1e-3
