"""Bad input reaches Python as an exception with the CLI's own message
(issue 41): rows of the CLI's bad-input table (tests/test_cli_errors.cpp),
each given to caustica.load or caustica.render and to the built CLI; the
Python message must be the line the CLI prints after "caustica: error: ",
and the exception a caustica.SceneError (the loader's) or caustica.Error (a
ValueError). Nothing crashes, and no RuntimeError leaks C++ internals."""
import json

import numpy as np
import pytest

import caustica
from conftest import ROOT, run_cli, sphere_scene

SPHERE = [{"type": "sphere", "center": [0, 0, 0], "radius": 1}]


def scene_text(shapes=SPHERE, lights=None, nbounces=2):
    d = sphere_scene(width=24, height=16, mode="phong")
    d["nbounces"] = nbounces
    d["scene"]["shapes"] = shapes
    if lights is not None:
        d["scene"]["lightsources"] = lights
    return json.dumps(d)


def cli_error(*args):
    result = run_cli(*args, check=False)
    assert result.returncode != 0, result.stderr
    return result.stderr


# Scenes the loader refuses: (name, file name, contents, parts of the message).
SCENE_ROWS = [
    ("reflectance_1e29", "huge_diffuse.json",
     scene_text([{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": {"diffusecolor": [1.2e29, 0.5, 0.5]}}]),
     ["/scene/shapes/0/material/diffusecolor/0: expected a reflectance in [0, 100]"]),
    ("deep_json", "deep.json", "[" * 100000 + "]" * 100000, ["deep.json: /0/0/0", "nested at most 64 levels"]),
    ("bounces", "bounces.json", scene_text(nbounces=1000000000),
     ["/nbounces: expected an integer in [0, 1024], got 1000000000"]),
    ("directional_zero", "directional_zero.json",
     scene_text(lights=[{"type": "directional", "direction": [0, 0, 0], "intensity": [1, 1, 1]}]),
     ["/scene/lightsources/0/direction: expected a direction of nonzero length"]),
    ("syntax", "syntax.json", '{"nbounces": 2,,}', ["syntax.json:1:", "JSON syntax error"]),
    ("mesh_missing", "mesh_missing.json", scene_text([{"type": "mesh", "file": "no_such.obj"}]),
     ["/scene/shapes/0/file: expected an existing mesh file"]),
]


@pytest.mark.parametrize("name,file,text,parts", SCENE_ROWS, ids=[r[0] for r in SCENE_ROWS])
def test_scene_errors_are_scene_errors_with_the_cli_message(tmp_path, name, file, text, parts):
    path = tmp_path / file
    path.write_text(text)
    with pytest.raises(caustica.SceneError) as raised:
        caustica.load(path)
    message = str(raised.value)
    for part in parts:
        assert part in message
    assert isinstance(raised.value, ValueError)
    assert f"caustica: error: {message}\n" in cli_error("render", path)


def test_missing_and_unreadable_scene_files(tmp_path):
    for path, part in ((tmp_path / "none.json", "scene file not found"),
                       (tmp_path, "is a directory, expected a regular file")):
        with pytest.raises(caustica.SceneError, match=part) as raised:
            caustica.load(path)
        assert f"caustica: error: {raised.value}\n" in cli_error("render", path)


# Options refused before anything renders: (name, keywords, the CLI's arguments, a part of the message).
OPTION_ROWS = [
    ("bvh", dict(bvh="foo"), ["--bvh", "foo"], "--bvh foo: expected fast, sah or spatial"),
    ("image_too_large", dict(width=100000, height=10000), ["--width", 100000, "--height", 10000],
     "image limit of 32768 pixels per side"),
    ("exposure_nan", dict(exposure=float("nan")), ["--exposure", "nan"], "--exposure 'nan': expected"),
    ("gamma_zero", dict(gamma=0.0), ["--gamma", "0.0"], "--gamma '0.0': expected"),
    ("output_extension", dict(output="out.bmp"), ["-o", "out.bmp"], "unknown extension '.bmp'"),
    ("tonemap", dict(tonemap="foo"), ["--tonemap", "foo"], "linear, reinhard, aces"),
    ("plot_without_report", dict(plot="p.png"), ["--plot", "p.png"], "needs --report"),
    ("checkpoint_every_alone", dict(checkpoint_every=5.0), ["--checkpoint-every", "5.0"],
     "--checkpoint-every needs --checkpoint"),
    ("mode", dict(mode="foo"), ["--mode", "foo"], "--mode foo: expected binary, phong or path"),
    ("caustics", dict(caustics="maybe"), ["--caustics", "maybe"], "--caustics"),
    ("target_without_estimate", dict(target_error=0.01, error_estimate=False),
     ["--target-error", "0.01", "--no-error-estimate"], "--target-error needs the error estimate"),
    ("spp_zero", dict(spp=0), ["--spp", 0], "--spp"),
    ("sampler", dict(sampler="foo"), ["--sampler", "foo"], "expected sobol or independent"),
    ("denoise_quality", dict(denoise_quality="best"), ["--denoise-quality", "best"], "--denoise-quality"),
    ("phong_lights", dict(), [], "limit is 1024"),
]


@pytest.mark.parametrize("name,keywords,args,part", OPTION_ROWS, ids=[r[0] for r in OPTION_ROWS])
def test_option_errors_are_value_errors_with_the_cli_message(tmp_path, name, keywords, args, part):
    lights = None
    if name == "phong_lights":
        lights = [{"type": "pointlight", "position": [i % 7, 2, 0], "intensity": [0.01] * 3} for i in range(1500)]
    path = tmp_path / "ok.json"
    path.write_text(scene_text(lights=lights))
    scene = caustica.load(path)
    with pytest.raises(caustica.Error) as raised:
        caustica.render(scene, quiet=True, **keywords)
    message = str(raised.value)
    assert part in message and isinstance(raised.value, ValueError)
    assert not isinstance(raised.value, caustica.SceneError)
    cli = cli_error("render", path, "-q", *args)
    assert message.splitlines()[0] in cli


def test_a_state_that_does_not_exist(tmp_path):
    with pytest.raises(caustica.Error, match="none.cst"):
        caustica.load_state(tmp_path / "none.cst")


def test_unknown_keywords_and_wrong_types_are_python_errors(cornell):
    with pytest.raises(TypeError, match="unexpected keyword argument 'sppp'"):
        caustica.render(cornell, sppp=4)
    with pytest.raises(caustica.Error, match="denoise=1"):
        caustica.render(cornell, denoise=1)
    with pytest.raises(TypeError, match="callback"):
        caustica.render(cornell, spp=1, width=8, callback=3)


def test_load_dict_errors_name_the_pointer():
    d = json.loads(scene_text())
    d["scene"]["shapes"][0]["radius"] = {1, 2}
    with pytest.raises(caustica.SceneError, match=r"<dict>: /scene/shapes/0/radius: expected a dict, list.*got a set"):
        caustica.load_dict(d)
    d["scene"]["shapes"][0]["radius"] = -1.0
    with pytest.raises(caustica.SceneError, match=r"my scene: /scene/shapes/0/radius"):
        caustica.load_dict(d, name="my scene")
    d = json.loads(scene_text())
    d["scene"][3] = "x"
    with pytest.raises(caustica.SceneError, match=r"/scene: expected string keys, got the key 3"):
        caustica.load_dict(d)


def test_inline_mesh_errors_name_the_entry():
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
    for mesh, pattern in (
        ({"indices": [[0, 1, 3]]}, r"/scene/shapes/0/indices/0/2: expected an integer in \[0, 2\], got 3"),
        ({"indices": [0, 1]}, r"/scene/shapes/0/indices: expected a flat list of indices whose length is a multiple of 3"),
        ({"indices": [[0, 1, 2]], "normals": [[0, 0, 1]]}, r"/scene/shapes/0/normals: expected one entry per vertex \(3\), got 1"),
        ({}, r"/scene/shapes/0/indices: required key \"indices\" is missing"),
        ({"indices": [[0, 1, 2]], "file": "x.obj"}, r"/scene/shapes/0: expected either \"vertices\""),
    ):
        d = json.loads(scene_text())
        d["scene"]["shapes"] = [{"type": "mesh", "vertices": vertices, **mesh}]
        with pytest.raises(caustica.SceneError, match=pattern):
            caustica.load_dict(d)
    d = json.loads(scene_text())
    d["scene"]["shapes"] = [{"type": "mesh", "vertices": [[0, 0, 0], [1, 0, float("nan")], [0, 1, 0]], "indices": [[0, 1, 2]]}]
    with pytest.raises(caustica.SceneError, match=r"/scene/shapes/0/vertices/1/2"):
        caustica.load_dict(d)


def test_warnings_are_python_warnings(tmp_path):
    d = json.loads(scene_text())
    d["scene"]["shapes"][0]["colour_of_the_day"] = 1
    with pytest.warns(caustica.SceneWarning, match="colour_of_the_day"):
        scene = caustica.load_dict(d)
    assert any("colour_of_the_day" in w for w in scene.warnings)
    with pytest.raises(caustica.SceneError, match="colour_of_the_day"):
        caustica.load_dict(d, strict=True)
