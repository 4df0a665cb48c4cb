"""caustica from Python: load scenes, render them, get NumPy arrays.

    import caustica
    scene = caustica.load("scenes/cornell_box.json")
    r = caustica.render(scene, spp=64, seed=3)
    r.image            # H x W x 3 float32, linear (the .pfm's values)
    r.error_estimate   # the render's own relMSE estimate (r.error_bound: its 90% upper bound)
    r.save("cornell.png")

Every option of ``caustica render`` is a keyword of :func:`render`, with the
CLI's defaults, checks and messages: the keywords are turned into the
command line and parsed by the CLI's own parser, and the render runs in the
same core library, so ``render(load(p), spp=64, seed=3).image`` has the bits
of ``caustica render p --spp 64 --seed 3 -o out.pfm``. Errors are
:class:`Error` (a ``ValueError``) with the CLI's message; the scene
loader's are :class:`SceneError`. The GIL is released while rendering.
docs/python.md is the tutorial.
"""
from __future__ import annotations

import os
from typing import Any, Callable, Dict, List, Optional, Sequence, Union

import numpy as np

from . import _caustica
from ._caustica import DeviceError, Error, Scene, SceneError, SceneWarning

__all__ = [
    "load", "load_dict", "render", "resume", "load_state", "Render", "State", "RenderInterrupted",
    "devices", "diff", "sky", "Scene", "Error", "SceneError", "SceneWarning", "DeviceError",
]

PathLike = Union[str, "os.PathLike[str]"]
Callback = Callable[[int, float, Optional[float]], Optional[bool]]


class RenderInterrupted(KeyboardInterrupt):
    """Ctrl-C during :func:`render`: the render stopped cleanly at the end of
    its wave; ``.render`` holds what it rendered."""

    def __init__(self, render: "Render") -> None:
        super().__init__(f"render interrupted at {render.spp} spp")
        self.render = render


def load(path: PathLike, *, strict: bool = False, camera: Optional[int] = None) -> Scene:
    """Load a scene file: the coursework JSON format (and its variants), or
    glTF 2.0 (``.gltf``, ``.glb``).

    strict: unknown keys are errors instead of warnings.
    camera: a glTF file's camera index (``--camera``).
    Warnings are issued as :class:`SceneWarning`; errors raise
    :class:`SceneError` naming the file and the JSON pointer.
    """
    return _caustica.load(os.fspath(path), strict, camera)


def load_dict(d: Dict[str, Any], *, base_dir: PathLike = ".", name: str = "<dict>",
              strict: bool = False) -> Scene:
    """Load a scene from a dict with the JSON file's structure (scenes/FORMAT.md).

    Values may be NumPy arrays and scalars. A shape ``{"type": "mesh",
    "vertices": V, "indices": F}`` (V: N x 3 floats, F: M x 3 ints; optional
    per-vertex ``normals`` N x 3 and ``uvs`` N x 2) is an inline mesh.
    Relative asset paths resolve against ``base_dir``; ``name`` stands for the
    file in messages.
    """
    return _caustica.load_dict(d, os.fspath(base_dir), name, strict)


# The keywords of render() that are `caustica render` options: keyword ->
# option. Flags take True; `adaptive`, `error_estimate` and `cache` take
# False for their --no- forms.
_VALUE_OPTIONS = {
    "mode": "--mode", "spp": "--spp", "time": "--time", "seed": "--seed", "device": "--device",
    "width": "--width", "height": "--height", "target_error": "--target-error", "tonemap": "--tonemap",
    "exposure": "--exposure", "gamma": "--gamma", "sampler": "--sampler", "bvh": "--bvh",
    "photons": "--photons", "caustic_radius": "--caustic-radius", "kernel_shape": "--kernel-shape",
    "denoise_quality": "--denoise-quality", "denoise_guides": "--denoise-guides", "output": "-o",
    "report": "--report", "reference": "--reference", "plot": "--plot", "spp_map": "--spp-map",
    "write_every": "--write-every", "checkpoint": "--checkpoint", "checkpoint_every": "--checkpoint-every",
    "aov_dir": "--aov-dir", "passes": "--passes", "light_sampler": "--light-sampler",
}
_FLAGS = {"denoise": "--denoise", "verbose": "--verbose", "quiet": "--quiet", "check_numerics": "--check-numerics"}
_NEGATABLE = {"adaptive": ("--adaptive", "--no-adaptive"), "error_estimate": (None, "--no-error-estimate"),
              "cache": (None, "--no-cache")}


def _option_text(key: str, value: Any) -> str:
    if isinstance(value, (bool, np.bool_)):
        raise Error(f"{key}={value!r}: expected a value, not a bool")
    if isinstance(value, (os.PathLike,)):
        return os.fspath(value)
    if isinstance(value, (float, np.floating)):
        return repr(float(value))  # round-trips: the CLI reads the same double
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    return str(value)


def _command_line(options: Dict[str, Any]) -> List[str]:
    args: List[str] = []
    for key, value in options.items():
        if value is None:
            continue
        if key == "caustics" and isinstance(value, (bool, np.bool_)):
            value = "on" if value else "off"
        if key == "caustics":
            args += ["--caustics", str(value)]
        elif key in _VALUE_OPTIONS:
            args += [_VALUE_OPTIONS[key], _option_text(key, value)]
        elif key in _FLAGS:
            if not isinstance(value, (bool, np.bool_)):
                raise Error(f"{key}={value!r}: expected True or False")
            if value:
                args.append(_FLAGS[key])
        elif key in _NEGATABLE:
            if not isinstance(value, (bool, np.bool_)):
                raise Error(f"{key}={value!r}: expected True or False")
            on, off = _NEGATABLE[key]
            flag = on if value else off
            if flag:
                args.append(flag)
        else:
            raise TypeError(f"render() got an unexpected keyword argument '{key}'")
    return args


class State:
    """A path-mode render's state: what :func:`resume` continues (and what
    ``caustica render --resume`` reads once saved)."""

    def __init__(self, native: Any, scene: Optional[Scene] = None,
                 options: Optional[Dict[str, Any]] = None) -> None:
        self._native = native
        self.scene = scene
        self.options = dict(options or {})

    @property
    def spp(self) -> int:
        """The samples per pixel it holds."""
        return self._native.spp

    def save(self, path: PathLike) -> None:
        """Write it as a state file (``--checkpoint``'s format)."""
        self._native.save(os.fspath(path))

    def __repr__(self) -> str:
        return f"<caustica.State {self.spp} spp of {self.scene.path if self.scene else 'a scene'}>"


class Render:
    """A finished render. ``image`` is linear float32 H x W x 3 (times the
    exposure: what a .pfm holds; denoised with ``denoise=True``)."""

    def __init__(self, native: Any, scene: Scene, options: Dict[str, Any]) -> None:
        self._native = native
        self.scene = scene
        self.options = options

    @property
    def image(self) -> np.ndarray:
        """H x W x 3 float32, linear: the .pfm's values."""
        return self._native.image

    @property
    def spp(self) -> int:
        """Samples per pixel of the film (the mean with adaptive sampling; 1 in binary and phong)."""
        return self._native.spp

    @property
    def mode(self) -> str:
        return self._native.mode

    @property
    def aovs(self) -> Dict[str, np.ndarray]:
        """What the film has besides the image: ``spp`` (H x W sample counts)
        always; ``variance`` with the error estimate; ``albedo``, ``normal``,
        ``depth`` with the aux passes (``denoise=True``, an .exr output or
        ``aov_dir``); ``beauty`` (the raw film) when the image is denoised;
        with the photon pass, ``caustics`` (its caustic radiance, a part of
        the image) and ``caustics_variance`` (that estimate's own noise and
        squared bias, a part of ``variance``)."""
        return self._native.aovs

    @property
    def error_estimate(self) -> Optional[float]:
        """The film's own relMSE estimate (None before 2 spp, without the
        error estimate, or in binary and phong, which are exact)."""
        return self._native.error_estimate

    @property
    def error_bound(self) -> Optional[float]:
        """The 90% upper bound on the render's relMSE, what ``target_error``
        stops on (None where there is no estimate); it stays well above
        the estimate while a pixel rests on a few rare bright samples."""
        return self._native.error_bound

    @property
    def error_map(self) -> Optional[np.ndarray]:
        """Each pixel's estimated relMSE (H x W); its mean is the estimate."""
        return self._native.error_map

    @property
    def stats(self) -> Dict[str, Any]:
        """Samples, rays, seconds, and what the photon pass did and decided."""
        return self._native.stats

    @property
    def report(self) -> List[Dict[str, Optional[float]]]:
        """The error against time rows (``--report``'s columns): after 1, 2, 4, ... spp and at the end."""
        return self._native.report

    def save(self, path: PathLike) -> None:
        """Write the render as ``-o path`` would: .ppm, .png, .pfm or .exr (with the film's passes)."""
        self._native.save(os.fspath(path))

    def state(self) -> State:
        """Its state (path mode), for :func:`resume` or ``State.save``."""
        return State(self._native.state(), self.scene, self.options)

    def __repr__(self) -> str:
        h, w = self._native.image.shape[:2]
        est = self.error_estimate
        error = f", est. relMSE {est:.3g}" if est is not None else ""
        return f"<caustica.Render {self.mode} {w}x{h}, {self.spp} spp{error}>"


def _render(scene: Union[Scene, PathLike], options: Dict[str, Any], callback: Optional[Callback],
            resume: Optional[State]) -> Render:
    if not isinstance(scene, Scene):
        scene = load(scene)
    if callback is not None and not callable(callback):
        raise TypeError("callback: expected a callable (spp, seconds, error) -> bool or None")
    native, interrupted = _caustica.render(scene, _command_line(options), callback,
                                           resume._native if resume is not None else None,
                                           options.get("output") is not None)
    result = Render(native, scene, options)
    if interrupted:
        raise RenderInterrupted(result)
    return result


def render(scene: Union[Scene, PathLike], *, mode: Optional[str] = None, spp: Optional[int] = None,
           time: Optional[float] = None, seed: Optional[int] = None, adaptive: Optional[bool] = None,
           caustics: Union[str, bool, None] = None, device: Union[str, int, None] = None,
           width: Optional[int] = None, height: Optional[int] = None, target_error: Optional[float] = None,
           denoise: Optional[bool] = None, callback: Optional[Callback] = None,
           tonemap: Optional[str] = None, exposure: Optional[float] = None, gamma: Optional[float] = None,
           sampler: Optional[str] = None, error_estimate: Optional[bool] = None, photons: Optional[int] = None,
           caustic_radius: Optional[float] = None, kernel_shape: Optional[str] = None, bvh: Optional[str] = None,
           light_sampler: Optional[str] = None,
           denoise_quality: Optional[str] = None, denoise_guides: Optional[str] = None,
           check_numerics: Optional[bool] = None, output: Optional[PathLike] = None,
           report: Optional[PathLike] = None, reference: Optional[PathLike] = None, plot: Optional[PathLike] = None,
           spp_map: Optional[PathLike] = None, write_every: Optional[float] = None,
           checkpoint: Optional[PathLike] = None, checkpoint_every: Optional[float] = None,
           aov_dir: Optional[PathLike] = None, passes: Optional[str] = None, cache: Optional[bool] = None,
           verbose: Optional[bool] = None, quiet: Optional[bool] = None) -> Render:
    """Render a scene (a :class:`Scene`, or a path, loaded first).

    Every keyword is the ``caustica render`` option of the same name
    (``target_error`` is ``--target-error``), with its default when None:
    mode: binary | phong | path (default: the scene's rendermode)
    spp: samples per pixel (path; default 64), time: a wall-time limit in seconds
    seed: the sample sequences' seed (default 0)
    adaptive: adaptive sampling (default True); False samples every pixel alike
    caustics: "auto" (default), "on"/True, "off"/False: the photon pass
    light_sampler: "auto" (default: the light tree above 3 lights), "tree", "power", "uniform"
    device: an OpenCL device index, name substring, "cpu" or "gpu" (see devices())
    width, height: the image size (one keeps the camera's aspect)
    target_error: stop when the estimated relMSE's 90% upper bound reaches it
    denoise: the image is denoised (Intel Open Image Denoise)
    error_estimate: False leaves out the half buffer (no estimate, no adaptive sampling)
    output, report, plot, spp_map, checkpoint, aov_dir, ...: files, as the CLI writes them
    verbose, quiet: stderr as the CLI (progress shows for renders over a second)
    callback(spp, seconds, error): called between waves (error: the latest
    estimated relMSE or None); returning False stops the render cleanly,
    keeping what it rendered. An exception it raises stops it and is raised.
    Ctrl-C stops it the same way and raises :class:`RenderInterrupted`,
    whose ``.render`` holds what was rendered.
    """
    options = {k: v for k, v in locals().items() if k not in ("scene", "callback")}
    return _render(scene, options, callback, None)


def resume(state: State, *, scene: Optional[Scene] = None, spp: Optional[int] = None,
           time: Optional[float] = None, callback: Optional[Callback] = None, **options: Any) -> Render:
    """Continue a path-mode render from its state, up to ``spp`` (or for
    ``time`` seconds): with ``spp`` the bits are those of a render never
    stopped. The state's scene and render options are used unless given
    (the scene, mode, size, seed and sampling options must match the
    state's, as for ``--resume``)."""
    scene = scene if scene is not None else state.scene
    if scene is None:
        raise Error("resume: this state was read from a file: give scene= (the scene it was rendered from)")
    merged = {k: v for k, v in state.options.items()
              if k not in ("spp", "time", "target_error", "output", "checkpoint", "report", "plot", "spp_map")}
    merged.update(options)
    merged["spp"], merged["time"] = spp, time
    return _render(scene, merged, callback, state)


def load_state(path: PathLike) -> State:
    """Read a state file (``--checkpoint``'s); resume it with ``resume(state, scene=...)``."""
    return State(_caustica.load_state(os.fspath(path)))


def devices() -> List[Dict[str, Any]]:
    """The OpenCL devices, as ``caustica devices`` lists them (index, type,
    name, platform, compute_units, version, memory_bytes, default)."""
    return _caustica.devices()


def diff(image: Union[np.ndarray, Render, PathLike], reference: Union[np.ndarray, Render, PathLike], *,
         metric: str = "relmse", per_pixel: bool = False) -> Union[float, np.ndarray]:
    """The error of ``image`` against ``reference`` (arrays H x W x 3, Renders
    or image files as ``caustica diff`` reads them): relmse, mse or mae,
    as one number or (per_pixel) an H x W map."""
    a = image.image if isinstance(image, Render) else image
    b = reference.image if isinstance(reference, Render) else reference
    return _caustica.diff(a, b, metric, per_pixel)


def sky(*, sun_elevation: Optional[float] = None, sun_azimuth: Optional[float] = None,
        turbidity: Optional[float] = None, width: Optional[int] = None, height: Optional[int] = None,
        output: Optional[PathLike] = None) -> np.ndarray:
    """The Preetham sun and sky as an equirectangular H x W x 3 float32 image
    (``caustica sky``; defaults: elevation 45, azimuth 0, turbidity 3,
    1024 x 512); also written to ``output`` (.pfm or .exr) when given."""
    args: List[str] = []
    for key, value in (("--sun-elevation", sun_elevation), ("--sun-azimuth", sun_azimuth),
                       ("--turbidity", turbidity), ("--width", width), ("--height", height)):
        if value is not None:
            args += [key, _option_text(key, value)]
    args += ["-o", os.fspath(output) if output is not None else "sky.exr"]
    return _caustica.sky(args, output is not None)
