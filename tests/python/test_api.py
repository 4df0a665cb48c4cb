"""The API surface of `import caustica` (issue 41): what a render returns,
its parts checked against what they must be (the error map against the
estimate, saved files against the image, the report's rows), devices,
diff and sky."""
import inspect
import pathlib

import numpy as np
import pytest

import caustica
from conftest import read_pfm, sphere_scene


@pytest.fixture(scope="module")
def path_render():
    return caustica.render(caustica.load_dict(sphere_scene()), spp=16, seed=1, quiet=True)


def test_render_returns_the_image_and_what_the_film_has(path_render):
    r = path_render
    assert isinstance(r, caustica.Render)
    assert r.image.shape == (24, 32, 3) and r.image.dtype == np.float32
    assert np.isfinite(r.image).all() and r.image.max() > 0
    assert r.spp == 16 and r.mode == "path"
    aovs = r.aovs
    assert aovs["spp"].shape == (24, 32) and aovs["spp"].dtype == np.uint32
    assert (aovs["spp"] == 16).all()  # adaptive sampling starts after 16 spp
    assert aovs["variance"].shape == (24, 32) and (aovs["variance"] >= 0).all()
    assert "albedo" not in aovs  # no aux passes asked for: the film has none


def test_error_map_averages_to_the_estimate(path_render):
    r = path_render
    assert r.error_estimate is not None and r.error_estimate > 0
    assert r.error_map.shape == (24, 32)
    assert r.error_map.mean() == pytest.approx(r.error_estimate, rel=1e-9)
    # The 90% bound target_error stops on (docs/error.md): never below the estimate.
    assert r.error_bound is not None and r.error_bound >= r.error_estimate


def test_the_photon_pass_shows_its_own_image_and_variance():
    r = caustica.render(caustica.load(pathlib.Path(__file__).parents[2] / "scenes" / "caustics.json"), width=32,
                        height=24, spp=8, caustics="on", adaptive=False, quiet=True)
    aovs = r.aovs
    assert aovs["caustics"].shape == (24, 32, 3) and aovs["caustics_variance"].shape == (24, 32)
    assert aovs["caustics"].max() > 0 and (aovs["caustics"] >= 0).all()
    # Parts of the image and of its variance: never more than the whole.
    assert (aovs["caustics"] <= r.image + 1e-6).all()
    assert (aovs["caustics_variance"] <= aovs["variance"] * (1 + 1e-5) + 1e-12).all()
    off = caustica.render(caustica.load(pathlib.Path(__file__).parents[2] / "scenes" / "caustics.json"), width=32,
                          height=24, spp=2, caustics="off", quiet=True)
    assert "caustics" not in off.aovs and "caustics_variance" not in off.aovs


def test_stats_count_every_sample_and_ray(path_render):
    s = path_render.stats
    assert s["spp"] == 16 and s["samples"] == 16 * 32 * 24
    assert s["camera_rays"] == s["samples"]
    assert s["rays"] == s["camera_rays"] + s["secondary_rays"] + s["shadow_rays"] + s["photon_rays"]
    assert s["seconds"] > 0 and s["stopped_by_callback"] is False
    assert s["caustics"] in ("on", "off", "none") and isinstance(s["caustics_decision"], str)


def test_report_rows_follow_the_error_monitor(path_render):
    rows = path_render.report
    assert [row["spp"] for row in rows] == [1, 2, 4, 8, 16]
    assert rows[0]["est_relmse"] is None  # no estimate from one pass
    assert rows[-1]["est_relmse"] == pytest.approx(path_render.error_estimate)
    assert rows[0]["est_relmse_bound"] is None
    assert rows[-1]["est_relmse_bound"] == pytest.approx(path_render.error_bound)
    assert all(rows[i]["seconds"] <= rows[i + 1]["seconds"] for i in range(len(rows) - 1))


def test_aux_passes_with_denoise_or_exr(tmp_path):
    scene = caustica.load_dict(sphere_scene())
    r = caustica.render(scene, spp=4, output=tmp_path / "out.exr", quiet=True)
    aovs = r.aovs
    assert aovs["albedo"].shape == (24, 32, 3) and aovs["normal"].shape == (24, 32, 3)
    assert aovs["depth"].shape == (24, 32) and (aovs["depth"] > 0).any()
    assert (tmp_path / "out.exr").exists()


def test_save_writes_every_format_with_the_image(path_render, tmp_path):
    for ext in ("png", "ppm", "pfm", "exr"):
        path_render.save(tmp_path / f"out.{ext}")
        assert (tmp_path / f"out.{ext}").stat().st_size > 0
    assert np.array_equal(read_pfm(tmp_path / "out.pfm"), path_render.image)
    assert caustica.diff(tmp_path / "out.exr", tmp_path / "out.pfm", metric="mse") == 0.0
    with pytest.raises(caustica.Error, match=r"\.bmp"):
        path_render.save(tmp_path / "out.bmp")


def test_binary_and_phong_are_one_exact_pass():
    scene = caustica.load_dict(sphere_scene(mode="phong"))
    r = caustica.render(scene, quiet=True)
    assert r.mode == "phong" and r.spp == 1 and r.error_estimate is None and r.error_map is None
    b = caustica.render(scene, mode="binary", quiet=True)
    assert b.mode == "binary" and set(np.unique(b.image[..., 1])) <= {0.0}  # red on black


def test_scene_properties(cornell):
    assert cornell.path.endswith("cornell_box.json") and cornell.mode == "path"
    assert (cornell.width, cornell.height) == (512, 512)
    assert cornell.counts["triangles"] > 0 and cornell.counts["materials"] >= 4  # its light is an emissive quad
    assert "cornell_box.json" in repr(cornell)


def test_render_accepts_a_path():
    r = caustica.render(pathlib.Path(__file__).parents[2] / "scenes" / "simple_phong.json", width=40, quiet=True)
    assert r.image.shape[1] == 40


def test_devices_lists_what_the_cli_lists():
    devices = caustica.devices()
    assert devices, "no OpenCL device"
    assert sum(d["default"] for d in devices) == 1
    for d in devices:
        assert set(d) >= {"index", "type", "name", "platform", "compute_units", "version", "memory_bytes"}


def test_diff_metrics():
    a = np.ones((4, 5, 3), np.float32)
    b = np.full((4, 5, 3), 2.0, np.float32)
    assert caustica.diff(a, b, metric="mse") == pytest.approx(1.0)
    assert caustica.diff(a, b, metric="mae") == pytest.approx(1.0)
    assert caustica.diff(a, b) == pytest.approx(1.0 / (4.0 + 0.01))
    m = caustica.diff(a, b, metric="mse", per_pixel=True)
    assert m.shape == (4, 5) and np.allclose(m, 1.0)
    with pytest.raises(caustica.Error, match="expected relmse, mse or mae"):
        caustica.diff(a, b, metric="psnr")
    with pytest.raises(caustica.Error, match="4x5.*5x4|5x4.*4x5"):
        caustica.diff(a, np.ones((5, 4, 3), np.float32))
    with pytest.raises(caustica.Error, match="H x W x 3"):
        caustica.diff(np.ones((4, 5)), b)


def test_sky_is_the_cli_sky(tmp_path):
    from conftest import run_cli
    image = caustica.sky(sun_elevation=30, turbidity=4, width=64, height=32, output=tmp_path / "py.pfm")
    assert image.shape == (32, 64, 3) and image.dtype == np.float32
    run_cli("sky", "--sun-elevation", 30, "--turbidity", 4, "--width", 64, "--height", 32, "-o", tmp_path / "cli.pfm")
    assert np.array_equal(read_pfm(tmp_path / "cli.pfm"), image)
    assert np.array_equal(read_pfm(tmp_path / "py.pfm"), image)
    with pytest.raises(caustica.Error, match="--turbidity"):
        caustica.sky(turbidity=20)


def test_every_public_call_is_documented_with_its_options():
    for name in caustica.__all__:
        obj = getattr(caustica, name)
        assert inspect.getdoc(obj), f"caustica.{name} has no docstring"
    params = inspect.signature(caustica.render).parameters
    for option in ("mode", "spp", "time", "seed", "adaptive", "caustics", "device", "width", "height",
                   "target_error", "denoise", "callback"):
        assert option in params
        assert option in inspect.getdoc(caustica.render)
    stub = pathlib.Path(caustica.__file__).with_name("_caustica.pyi")
    assert stub.exists() and pathlib.Path(caustica.__file__).with_name("py.typed").exists()
