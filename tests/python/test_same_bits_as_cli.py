"""caustica.render gives the CLI's bits (issue 41, point 3): the image of
render(load(p), spp=64, seed=3) equals the .pfm `caustica render p --spp 64
--seed 3` writes, bit for bit, on the Cornell box, caustics.json (the
photon pass on) and a glTF scene; sizes are reduced to keep the suite
short (the same size on both sides)."""
import numpy as np
import pytest

import caustica
from conftest import ROOT, read_pfm, run_cli

CASES = [
    ("cornell_box.json", dict(spp=64, seed=3, width=64), []),
    ("caustics.json", dict(spp=64, seed=3, width=96, caustics="on"), ["--caustics", "on"]),
    ("gltf_example.gltf", dict(spp=64, seed=3, width=64), []),
]


@pytest.mark.parametrize("scene,options,extra", CASES, ids=[c[0] for c in CASES])
def test_render_has_the_bits_of_the_cli_pfm(tmp_path, scene, options, extra):
    path = ROOT / "scenes" / scene
    out = tmp_path / "cli.pfm"
    run_cli("render", path, "--spp", options["spp"], "--seed", options["seed"], "--width", options["width"],
            *extra, "-o", out, "--quiet")
    r = caustica.render(caustica.load(path), quiet=True, **options)
    cli_image = read_pfm(out)
    assert r.image.shape == cli_image.shape
    assert np.array_equal(r.image.view(np.uint32), cli_image.view(np.uint32))
    if scene == "caustics.json":
        assert r.stats["photon_maps"] > 0, "the photon pass did not run"


def test_exposure_and_denoise_reach_the_image_as_in_the_pfm(tmp_path):
    path = ROOT / "scenes" / "cornell_box.json"
    out = tmp_path / "cli.pfm"
    run_cli("render", path, "--spp", 8, "--width", 48, "--exposure", 1.5, "-o", out, "--quiet")
    r = caustica.render(caustica.load(path), spp=8, width=48, exposure=1.5, quiet=True)
    assert np.array_equal(r.image, read_pfm(out))


def test_denoised_image_is_the_cli_denoised_pfm(tmp_path):
    try:
        caustica.render(caustica.load(ROOT / "scenes" / "cornell_box.json"), spp=1, width=8, denoise=True, quiet=True)
    except caustica.Error as e:
        pytest.skip(f"no denoiser in this build: {e}")
    path = ROOT / "scenes" / "cornell_box.json"
    out = tmp_path / "cli.pfm"
    run_cli("render", path, "--spp", 8, "--width", 48, "--denoise", "-o", out, "--quiet")
    r = caustica.render(caustica.load(path), spp=8, width=48, denoise=True, quiet=True)
    assert np.array_equal(r.image, read_pfm(out))
    assert "beauty" in r.aovs and not np.array_equal(r.aovs["beauty"], r.image)
    assert caustica.diff(r.image, r.aovs["beauty"]) > 0
