#!/usr/bin/env python3
"""Equal-time comparison of caustica's path tracer with Mitsuba 3 and
Blender's Cycles (optional; not part of the tests or CI).

For each scene, the three renderers get the same number of threads and the
same wall time at the same image size; each image's relMSE against a
reference is reported (relMSE = mean over pixels and channels of
(x - ref)^2 / (ref^2 + 0.01)) together with samples/s (spp x pixels / wall
seconds) and relMSE x seconds, which is constant for an unbiased renderer
and so compares them at exactly equal time even where the runs' times
differ a little.

    pip install mitsuba                 # 3.9.1 was used
    apt-get install libllvm19           # Mitsuba's fast llvm_ad_rgb variant
    /usr/bin/python3.11 -m venv bench/cycles/venv      # Cycles: bpy (Debian's Python 3.11)
    bench/cycles/venv/bin/pip install bpy==5.0.1 OpenEXR
    nice -n 19 bench/compare_mitsuba.py --seconds 10 --width 128 --height 128 \\
        --reference-spp 16384 --json out.json

The full table of issue 39 (Cornell box at 128^2 and 512^2, showcase_path,
caustics and two path-traced community scenes, 10 s each):

    C=../shared/scenes-coursework/community
    nice -n 19 bench/compare_mitsuba.py scenes/cornell_box.json@128x128 \\
        scenes/cornell_box.json@512x512 scenes/showcase_path.json@128x128 \\
        scenes/caustics.json@128x128 $C/Kierandon__cpp-raytracer__cornell_box.json@128x128 \\
        $C/michaelzhang4__raytracer__pathtracer_scene.json@192x128 \\
        --seconds 10 --reference-spp 16384 --cycles-reference-spp 8192 --json out.json

(--reference-spp 16384 keeps the references' own noise near a tenth of the
10 s renders' error at 128^2; the default 4096 is faster to make, once:
references are cached. Cycles takes fewer samples in 10 s, so its own
references need fewer.) A scene is SCENE.json or SCENE.json@WxH; without
@WxH it is rendered at --width x --height. Without scene arguments it runs
scenes/cornell_box.json, scenes/caustics.json and scenes/showcase_path.json.
The Markdown (one table per scene, a summary line and a summary table with
each renderer's relMSE x s and samples/s over caustica's) goes to stdout;
progress goes to stderr. --no-cycles leaves Cycles out (so does a missing
venv, and the output says so).

Mitsuba: its fastest variant that runs here, llvm_ad_rgb, when a libLLVM >= 16
is found (DRJIT_LIBLLVM_PATH, else /usr/lib/x86_64-linux-gnu/libLLVM.so.19.1
and the like; Debian 12's own libLLVM 14/15 abort inside LLVM) and a small
test render in a child process succeeds; else scalar_rgb, and the output says
why. Every sampler (independent, stratified, multijitter, ldsampler,
orthogonal) gets a short probe that measures its rate, then one render of
the spp that fills the wall time, rounded to the nearest count the sampler
takes as it is (squares, powers of two, squares of primes, ...: the nearer
by ratio of the two around it), and rendered again (at most twice) with
the rate it measured when its time was more than 15% off; the table
reports the spp that ran. Wall seconds are those of mi.render (JIT compilation included:
"JIT s" says how much, ~0 when Dr.Jit's disk cache had the kernel; every
sampler but independent compiles a new kernel for a new spp); scene loading
is not counted.
Cycles (bpy 5.0.1 in bench/cycles/venv; this script runs with the python3
that has Mitsuba, so Cycles runs in a child process of the venv's python):
bench/compare_cycles.py's converter and child (describe, run_cycles: the
conversion is that script's, see its docstring). Settings: CPU device,
--threads threads, adaptive sampling off, denoising off, clamping off
(direct and indirect), light threshold 0, blur_glossy (filter glossy) 0, box
pixel filter of 1 px, default sampling pattern (tabulated Sobol), seed 1;
emitters are meshes whose Emission shader is zeroed on back faces
(emission sampling FRONT), of the same radiance as caustica's. One render
with samples 2^24 and a time_limit: Cycles' limit counts the sampling
alone, so it is --seconds less the scene sync and the writing after the
last sample that a short probe measured, and the render runs again (at most
twice) with the limit moved by the difference when its time was more than
15% off. Its wall seconds are the bpy.ops.render.render call (sync, BVH
build, sampling, writing the EXR); the child's start, bpy's import and
building the Blender scene are not counted; spp is the largest "Sample N/M"
its render stats reported (every pixel takes the same samples).
caustica: `caustica render SCENE --mode path --time S --width W --height H
--exposure 0 -v -o out.pfm --seed 1` with POCL_MAX_PTHREAD_COUNT = threads,
after an untimed render of up to 32 spp (so that the kernels it runs are
built: PoCL builds a kernel again for another image size, which would count
against --time); its wall seconds are the whole process (start, scene load,
cached kernel build).

Reference: --reference FILE.pfm (one scene), else a long Mitsuba render
(independent sampler, --reference-spp, in chunks with distinct seeds) cached
in bench/mitsuba/cache/ under the scene's name, a hash of its file and of
this converter, the size and the spp (--reference-renderer caustica: a long
caustica render instead; cycles: Cycles'). Its own noise is estimated from
the difference of its two halves and printed: it adds about the same amount
to every row's relMSE, so raise --reference-spp when the output warns about
it. For a scene whose conversion to Mitsuba or to Cycles is approximate, the
main reference belongs to one renderer and the others' error would include
the conversions' bias, so (--own-references auto, the default) every
renderer also renders a long reference and each row is measured against its
own renderer's too; those columns then pick the best sampler and give the
ratios. Cycles' references are bench/compare_cycles.py's (adaptive off, no
denoising, --cycles-reference-spp samples, default --reference-spp, in two
halves of seeds 99 and 100), cached in bench/cycles/cache/ (a cached one of
more samples is used).

Orientation: caustica's camera puts right = up x forward (FORMAT.md), so +x
is on the image's right for a camera along +z with up +y; Mitsuba's and
Blender's cameras put it on the left, so both their images are mirrored
left-right before every comparison. --check-orientation checks it: it
renders bench/compare_cycles.py's asymmetric test scene (a red sphere up on
the +x side of a grey wall) at 64x64 with all three (--orientation-spp
uniform samples) and fails unless caustica draws the sphere at the top right
and Mitsuba's and Cycles' images, mirrored as compared, put it within 1.5 px
of caustica's and differ from caustica's by under a tenth of the relMSE of
their unmirrored images.

Conversion (caustica's meaning: scenes/FORMAT.md, host/scene/*.cpp,
kernels/lib/material.h, bsdf.h):
  * Mitsuba's look_at puts up x forward on the image's left, caustica's on the
    right, so Mitsuba's image is mirrored before comparing;
  * caustica's nbounces (scattering events) is Mitsuba's max_depth - 1;
  * triangles, rectangles, boxes, OBJ meshes (their transform applied here,
    .mtl materials mapped as caustica maps them) become OBJ files; spheres
    are Mitsuba spheres turned so that their uv matches caustica's;
    cylinders an open Mitsuba cylinder plus two disks;
  * opaque surfaces reflect on both sides in caustica: wrapped in "twosided";
    emissive triangles are one-sided area emitters on their counter-clockwise
    side in both; area lights are two black emitting triangles;
  * ks = 0 materials are Lambertian (exact); glass is dielectric /
    roughdielectric (GGX); isreflective is conductor / roughconductor (GGX)
    with a complex index fitted per channel to caustica's Schlick Fresnel of
    F0 = reflectivity x specularcolor (the fit's largest error is printed);
    other materials (caustica's Ashikhmin-Shirley coupled diffuse + GGX
    layer) become roughplastic with GGX alpha and int_ior chosen so that its
    normal-incidence reflectance is ks x specularcolor: APPROXIMATE (the
    diffuse/specular coupling differs), and the scene's rows say so;
  * checkerboard and image textures (x kd) map to checkerboard / bitmap
    textures with caustica's uv convention (v = 0 at the image's bottom);
  * backgroundcolor is a constant emitter; a thin-lens camera is thinlens
    (aperture = diameter, so aperture_radius = aperture / 2).
Rough GGX models use Mitsuba's separable Smith masking where caustica's is
height-correlated: a small difference, listed in the notes. The "mean / ref"
column (image mean over the main reference's) hints at any bias.
Cycles' conversion (bench/compare_cycles.py's docstring) is exact for
Lambertian surfaces, smooth and rough glass and conductors (Metallic BSDF
with F82 = Schlick's curve; GGX height-correlated like caustica's) and
emitters; APPROXIMATE are caustica's plastic (its Ashikhmin-Shirley
coupling becomes a Lambert lobe of the same directional albedo beside the
exact GGX layer), glass spheres (256 x 128 UV-sphere meshes with exact
normals: Cycles' point-cloud spheres refract wrongly) and cylinders (512
sides), each listed in the scene's Cycles notes.
"""
import argparse
import cmath
import glob
import hashlib
import json
import math
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import time

# bench/compare_cycles.py imports this module as compare_mitsuba: run as a
# script, this module is that one too (one Unsupported, one Converter).
sys.modules.setdefault("compare_mitsuba", sys.modules[__name__])

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
CONVERTER_VERSION = "4"  # part of the reference cache key: bump when the conversion changes
DEFAULT_SCENES = ["scenes/cornell_box.json", "scenes/caustics.json", "scenes/showcase_path.json"]
SAMPLERS = ["independent", "stratified", "multijitter", "ldsampler", "orthogonal"]
GGX_ALPHA_MIN = 1e-3


def log(msg):
    print(msg, file=sys.stderr, flush=True)


# ---------------------------------------------------------------- images


def read_pfm(path):
    """(w, h, values): RGB floats, top row first."""
    with open(path, "rb") as f:
        data = f.read()
    header, dims, scale, rest = data.split(b"\n", 3)
    if header.strip() != b"PF":
        sys.exit("%s: not an RGB PFM" % path)
    w, h = map(int, dims.split())
    little = float(scale) < 0
    values = struct.unpack(("<" if little else ">") + "%df" % (w * h * 3), rest[: w * h * 12])
    rows = [values[y * w * 3 : (y + 1) * w * 3] for y in range(h)]
    rows.reverse()  # PFM stores the bottom row first
    return w, h, [v for row in rows for v in row]


def write_pfm(path, w, h, values):
    rows = [values[y * w * 3 : (y + 1) * w * 3] for y in range(h)]
    rows.reverse()
    with open(path, "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (w, h))
        f.write(struct.pack("<%df" % (w * h * 3), *[v for row in rows for v in row]))


def rel_mse(image, reference):
    return sum((a - b) ** 2 / (b * b + 0.01) for a, b in zip(image, reference)) / len(reference)


def mean(values):
    return sum(values) / len(values)


def mirror_rows(flat, w, h):
    out = []
    for y in range(h):
        row = flat[y * w * 3 : (y + 1) * w * 3]
        for x in reversed(range(w)):
            out.extend(row[3 * x : 3 * x + 3])
    return out


# ---------------------------------------------------------------- small vector maths


def add(a, b):
    return [a[0] + b[0], a[1] + b[1], a[2] + b[2]]


def sub(a, b):
    return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]


def mul(a, s):
    return [a[0] * s, a[1] * s, a[2] * s]


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def length(a):
    return math.sqrt(dot(a, a))


def normalize(a):
    l = length(a)
    return [a[0] / l, a[1] / l, a[2] / l]


def matvec(m, v):
    return [dot(m[0], v), dot(m[1], v), dot(m[2], v)]


def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def rotation_xyz(degrees):
    """caustica's R = Rz Ry Rx (degrees about x, then y, then z; right-handed)."""
    x, y, z = (math.radians(d) for d in degrees)
    cx, sx, cy, sy, cz, sz = math.cos(x), math.sin(x), math.cos(y), math.sin(y), math.cos(z), math.sin(z)
    rx = [[1, 0, 0], [0, cx, -sx], [0, sx, cx]]
    ry = [[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]]
    rz = [[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]]
    return matmul(rz, matmul(ry, rx))


def clamp01(c):
    return [min(max(float(v), 0.0), 1.0) for v in c]


# ---------------------------------------------------------------- Fresnel fit


def fresnel_conductor(c, n, k):
    """Exact unpolarised reflectance of a conductor of index n + ik (from air)."""
    eta = complex(n, k)
    ct = cmath.sqrt(1 - (1 - c * c) / (eta * eta))
    rs = (c - eta * ct) / (c + eta * ct)
    rp = (eta * c - ct) / (eta * c + ct)
    return 0.5 * (abs(rs) ** 2 + abs(rp) ** 2)


def fit_conductor(f0):
    """(n, k, max error): the complex index whose exact Fresnel curve is closest
    (cosine-weighted L2) to Schlick's f0 + (1 - f0)(1 - c)^5, with the same
    normal-incidence reflectance f0."""
    f0 = min(max(f0, 1e-4), 0.999)
    cs = [(i + 0.5) / 48 for i in range(48)]
    schlick = [f0 + (1 - f0) * (1 - c) ** 5 for c in cs]
    best = None
    for j in range(240):
        n = 0.01 * math.exp(j / 240 * math.log(1000))
        k2 = (f0 * (n + 1) ** 2 - (n - 1) ** 2) / (1 - f0)
        if k2 < 0:
            continue
        k = math.sqrt(k2)
        f = [fresnel_conductor(c, n, k) for c in cs]
        err = sum(c * (a - b) ** 2 for c, a, b in zip(cs, f, schlick))
        if best is None or err < best[0]:
            best = (err, n, k, max(abs(a - b) for a, b in zip(f, schlick)))
    return best[1], best[2], best[3]


# ---------------------------------------------------------------- caustica scene -> Mitsuba


class Unsupported(Exception):
    pass


def find_any(d, keys):
    for k in keys:
        if k in d:
            return k, d[k]
    return None, None


def read_material(m):
    """caustica's read_material_object (host/scene/scene_materials.cpp)."""
    kind = "phong"
    if "type" in m:
        t = str(m["type"]).lower()
        kind = {"diffuse": "diffuse", "lambertian": "diffuse", "metal": "metal", "dielectric": "dielectric",
                "glass": "dielectric", "emissive": "emissive", "light": "emissive", "phong": "phong"}.get(t)
        if kind is None:
            raise Unsupported("material type %r" % m["type"])
    typed = kind != "phong"
    keys = ["diffusecolor", "basecolor", "albedo"] + ([] if kind == "emissive" else ["colour", "color"])
    _, colour = find_any(m, keys)
    diffuse = list(colour) if colour is not None else ([0.0] * 3 if kind == "emissive" else [0.8] * 3)
    out = {
        "diffuse": diffuse,
        "kd": float(m.get("kd", 0.0 if kind == "emissive" else 1.0 if typed else 0.9)),
        "specular": list(m.get("specularcolor", diffuse if kind == "metal" else [1.0, 1.0, 1.0])),
        "ks": float(m.get("ks", 0.0 if typed else 0.1)),
        "exponent": float(m.get("specularexponent", 20.0)),
        "reflectivity": float(m.get("reflectivity", 1.0)),
        "reflective": bool(m.get("isreflective", kind == "metal")),
        "refractive": bool(m.get("isrefractive", kind == "dielectric")),
        "roughness": float(m.get("roughness", -1.0)),
        "metallic": float(m.get("metallic", 0.0)),
        "twosided": bool(m.get("twosided", False)),
        "texture": None,
    }
    _, ior = find_any(m, ["refractiveindex", "ior"])
    out["ior"] = float(ior) if ior is not None else (1.5 if kind == "dielectric" else 1.0)
    if not out["ior"] > 0:
        out["ior"] = 1.0
    _, e = find_any(m, ["emission", "emissioncolor"])
    if e is not None:
        out["emission"] = list(e)
    elif kind == "emissive":
        _, c = find_any(m, ["colour", "color"])
        out["emission"] = mul(list(c) if c is not None else [1.0] * 3, float(m.get("intensity", 1.0)))
    else:
        out["emission"] = [0.0] * 3
    enabled = m.get("hasTexture", m.get("hastexture", True))
    _, tex = find_any(m, ["texture", "texture_file", "texturefile", "textureFilename", "texturepath"])
    if tex is not None and enabled:
        out["texture"] = tex
    return out


class Converter:
    """Reads a caustica scene into Mitsuba plugin dicts (shapes, emitters,
    camera); `notes` says what is not exact, `approximate` whether that
    changes the image noticeably."""

    def __init__(self, mi, scene_path, folder):
        self.mi = mi
        self.path = scene_path
        self.dir = os.path.dirname(os.path.abspath(scene_path))
        self.folder = folder
        with open(scene_path) as f:
            self.scene = json.load(f)
        self.notes = []
        self.approximate = False
        self.groups = {}  # (material key, has uv, has normals) -> list of triangles
        self.materials = {}  # material key -> material
        self.shapes = {}
        self.textures = {}
        self.fits = {}
        # Each emitter's power (W, the mean of its RGB), for
        # --mitsuba-emitter-weights power: shape name -> power.
        self.emitter_power = {}
        self.emitter_weights = "uniform"

    def note(self, text, approximate=False):
        if text not in self.notes:
            self.notes.append(text)
        self.approximate = self.approximate or approximate

    # ---- paths
    def find_asset(self, written, base, subdir):
        name = os.path.basename(written.replace("\\", "/"))
        for p in [os.path.join(base, written), os.path.join(base, name), os.path.join(base, subdir, name),
                  os.path.join(ROOT, subdir, name), os.path.join(self.dir, name)]:
            if os.path.isfile(p):
                return p
        raise Unsupported("cannot find %s %r" % (subdir[:-1], written))

    # ---- materials
    def material_key(self, m):
        key = json.dumps(m, sort_keys=True)
        self.materials[key] = m
        return key

    def texture(self, tex, kd, base):
        """Mitsuba texture for caustica's texture x kd (colours clamped to [0, 1])."""
        mi = self.mi
        if isinstance(tex, dict):
            if str(tex.get("type", "")).lower() not in ("checkerboard", "checker"):
                raise Unsupported("texture %r" % tex)
            s = float(tex.get("scale", 10.0))
            # caustica: square (floor(u s), floor(v s)) is color1 when the sum
            # is even; Mitsuba: color0 where frac(u') > .5 equals frac(v') > .5,
            # i.e. the same with u' = u s / 2.
            return {"type": "checkerboard",
                    "color0": {"type": "rgb", "value": clamp01(mul(tex.get("color1", [1, 1, 1]), kd))},
                    "color1": {"type": "rgb", "value": clamp01(mul(tex.get("color2", [0, 0, 0]), kd))},
                    "to_uv": mi.ScalarTransform4f().scale([s / 2, s / 2, 1])}
        path = self.find_asset(str(tex), base, "textures/")
        key = (path, kd)
        if key not in self.textures:
            import drjit as dr
            bmp = mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, srgb_gamma=False)
            t = mi.TensorXf(bmp) * kd
            self.textures[key] = mi.Bitmap(dr.minimum(dr.maximum(t, 0.0), 1.0))
        # caustica's v = 0 is the image's bottom row, Mitsuba's its top.
        return {"type": "bitmap", "bitmap": self.textures[key], "raw": True, "filter_type": "bilinear",
                "wrap_mode": "repeat", "to_uv": mi.ScalarTransform4f().translate([0, 1, 0]).scale([1, -1, 1])}

    def conductor(self, f0, alpha):
        ns, ks, worst = [], [], 0.0
        for c in f0:
            if c not in self.fits:
                self.fits[c] = fit_conductor(c)
            n, k, e = self.fits[c]
            ns.append(n)
            ks.append(k)
            worst = max(worst, e)
        self.note("conductor F0 %s: Mitsuba conductor with a fitted complex index (n %s, k %s); "
                  "largest Fresnel difference from caustica's Schlick %.3f"
                  % (fmt3(f0), fmt3(ns), fmt3(ks), worst), approximate=worst > 0.02)
        d = {"eta": {"type": "rgb", "value": ns}, "k": {"type": "rgb", "value": ks}}
        if alpha < GGX_ALPHA_MIN:
            d["type"] = "conductor"
        else:
            d.update({"type": "roughconductor", "distribution": "ggx", "alpha": alpha})
            self.note("rough conductor (GGX alpha %.3g): Mitsuba's separable Smith masking, caustica's "
                      "height-correlated" % alpha)
        return d

    def bsdf(self, m, base, textured_uv_ok=True):
        """kernels/lib/material.h's bsdf_of_material, in Mitsuba's terms."""
        given = m["roughness"] >= 0
        if m["refractive"]:
            alpha = m["roughness"] if given else 0.0
            if m["ior"] == 1.0:
                return {"type": "null"}
            if alpha < GGX_ALPHA_MIN:
                return {"type": "dielectric", "int_ior": m["ior"], "ext_ior": 1.0}
            self.note("rough glass (GGX alpha %.3g, ior %.3g): roughdielectric; Mitsuba's separable Smith "
                      "masking, caustica's height-correlated" % (alpha, m["ior"]))
            return {"type": "roughdielectric", "distribution": "ggx", "alpha": alpha,
                    "int_ior": m["ior"], "ext_ior": 1.0}
        if m["reflective"]:
            f0 = clamp01(mul(m["specular"], m["reflectivity"]))
            return {"type": "twosided", "bsdf": self.conductor(f0, m["roughness"] if given else 0.0)}
        alpha = m["roughness"] if given else math.sqrt(2.0 / (max(m["exponent"], 0.0) + 2.0))
        kd = m["kd"]
        diffuse = clamp01(mul(m["diffuse"], kd))
        specular = clamp01(mul(m["specular"], m["ks"]))
        metallic = min(max(m["metallic"], 0.0), 1.0)
        tex = None
        if m["texture"] is not None:
            tex = self.texture(m["texture"], kd, base)
            if not textured_uv_ok:
                self.note("a texture on a shape whose uv mapping is not converted", approximate=True)
        if metallic >= 1.0:
            if tex is not None:
                self.note("textured metallic material: its texture is left out", approximate=True)
            return {"type": "twosided", "bsdf": self.conductor(diffuse, alpha)}
        if metallic > 0.0:
            self.note("metallic %.2g: approximated as plastic" % metallic, approximate=True)
            specular = [s + (d - s) * metallic for s, d in zip(specular, diffuse)]
            diffuse = [d * (1 - metallic) for d in diffuse]
        reflectance = tex if tex is not None else {"type": "rgb", "value": diffuse}
        if max(specular) <= 0.0:
            return {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": reflectance}}
        f0 = min(sum(specular) / 3, 0.9)
        if max(specular) - min(specular) > 1e-6:
            self.note("coloured plastic highlight %s: grey F0 %.3g" % (fmt3(specular), f0), approximate=True)
        ior = (1 + math.sqrt(f0)) / (1 - math.sqrt(f0))
        self.note("plastic (kd %s, ks %.3g, GGX alpha %.3g): roughplastic, int_ior %.3g so that F0 = ks; "
                  "caustica's Ashikhmin-Shirley diffuse coupling differs"
                  % (fmt3(diffuse) if tex is None else "texture", f0, alpha, ior), approximate=True)
        if alpha < GGX_ALPHA_MIN:
            b = {"type": "plastic", "int_ior": ior, "diffuse_reflectance": reflectance}
        else:
            b = {"type": "roughplastic", "distribution": "ggx", "alpha": alpha, "int_ior": ior,
                 "diffuse_reflectance": reflectance}
        return {"type": "twosided", "bsdf": b}

    def emitter_of(self, m, kind):
        if max(m["emission"]) <= 0.0:
            return None
        if m["twosided"] and kind == "triangle":
            self.note("two-sided emissive triangles: Mitsuba's area emitter is one-sided", approximate=True)
        return {"type": "area", "radiance": {"type": "rgb", "value": [float(v) for v in m["emission"]]}}

    def shape_bsdf(self, m, base, kind):
        b = self.bsdf(m, base, textured_uv_ok=kind != "cylinder")
        if max(m["emission"]) > 0.0 and m["refractive"]:
            self.note("emissive glass", approximate=True)
        return b

    # ---- geometry
    def add_triangle(self, p, m, uv=None, n=None):
        if length(cross(sub(p[1], p[0]), sub(p[2], p[0]))) <= 0.0:
            return
        if m["texture"] is not None and uv is None:
            uv = [[0, 0], [1, 0], [0, 1]]
        key = (self.material_key(m), uv is not None, n is not None)
        self.groups.setdefault(key, []).append((p, uv, n))

    def add_quad(self, q, m):
        uv = [[0, 0], [1, 0], [1, 1], [0, 1]]
        self.add_triangle([q[0], q[1], q[2]], m, [uv[0], uv[1], uv[2]])
        self.add_triangle([q[0], q[2], q[3]], m, [uv[0], uv[2], uv[3]])

    @staticmethod
    def shape_material(s):
        m = read_material(s.get("material", {}))
        if "texture" in s:
            m["texture"] = s["texture"]
        return m

    def add_sphere(self, center, radius, m, base, emitter=None):
        mi = self.mi
        c, r = [float(v) for v in center], float(radius)
        # caustica: u = atan2(n.z, n.x) / 2pi, v = acos(-n.y) / pi; Mitsuba:
        # u = atan2(l.y, l.x) / 2pi, v = acos(l.z) / pi of the local point l:
        # l = (x, z, -y) is a rotation, and to_uv flips v for the image.
        to_world = mi.ScalarTransform4f([[r, 0, 0, c[0]], [0, 0, -r, c[1]], [0, r, 0, c[2]], [0, 0, 0, 1]])
        d = {"type": "sphere", "to_world": to_world}
        if emitter is not None:
            d["emitter"] = emitter
            d["bsdf"] = {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0, 0, 0]}}
        else:
            d["bsdf"] = self.shape_bsdf(m, base, "sphere")
            e = self.emitter_of(m, "sphere")
            if e:
                d["emitter"] = e
        name = "sphere%d" % len(self.shapes)
        if "emitter" in d:
            self.emitter_power[name] = mean(d["emitter"]["radiance"]["value"]) * math.pi * 4 * math.pi * r * r
        self.shapes[name] = d

    def add_cylinder(self, s, m, base):
        mi = self.mi
        c, a = [float(v) for v in s["center"]], normalize([float(v) for v in s["axis"]])
        r, half = float(s["radius"]), float(s["height"])
        p0, p1 = sub(c, mul(a, half)), add(c, mul(a, half))
        bsdf = self.shape_bsdf(m, base, "cylinder")
        e = self.emitter_of(m, "cylinder")
        parts = [{"type": "cylinder", "p0": p0, "p1": p1, "radius": r}]
        # caps: unit disks (z = 0, normal +z) turned to face out along -a and +a
        for centre, n in ((p0, mul(a, -1)), (p1, a)):
            helper = [1.0, 0, 0] if abs(n[0]) < 0.9 else [0, 1.0, 0]
            t = normalize(cross(helper, n))
            b = cross(n, t)
            m4 = [[t[i] * r, b[i] * r, n[i], centre[i]] for i in range(3)] + [[0, 0, 0, 1]]
            parts.append({"type": "disk", "to_world": mi.ScalarTransform4f(m4)})
        for k, p in enumerate(parts):
            p["bsdf"] = bsdf
            name = "cylinder%d" % len(self.shapes)
            if e:
                p["emitter"] = e
                area = 4 * math.pi * r * half if k == 0 else math.pi * r * r
                self.emitter_power[name] = mean(e["radiance"]["value"]) * math.pi * area
            self.shapes[name] = p

    def add_mesh(self, s, m_override):
        t = s.get("transform", {}) if s["type"] == "mesh" else {
            "translate": s.get("offset", [0, 0, 0]), "rotate": s.get("euler", [0, 0, 0]), "scale": s.get("scale", 1)}
        if "vertices" in s and s["type"] == "mesh":
            self.add_inline_mesh(s, t, m_override)
            return
        _, f = find_any(s, ["file", "filename", "path"])
        path = self.find_asset(str(f), self.dir, "models/")
        if not path.lower().endswith(".obj"):
            raise Unsupported("mesh %s: only .obj meshes are converted" % os.path.basename(path))
        scale = t.get("scale", 1.0)
        scale = [float(scale)] * 3 if not isinstance(scale, list) else [float(v) for v in scale]
        rot = rotation_xyz(t.get("rotate", [0, 0, 0]))
        tr = [float(v) for v in t.get("translate", [0, 0, 0])]
        mirror = scale[0] * scale[1] * scale[2] < 0

        def xf(p):
            return add(matvec(rot, [p[0] * scale[0], p[1] * scale[1], p[2] * scale[2]]), tr)

        def xn(n):
            return normalize(matvec(rot, [n[0] / scale[0], n[1] / scale[1], n[2] / scale[2]]))

        mesh_dir = os.path.dirname(path)
        mtl = {}
        vs, vts, vns, current = [], [], [], None
        faces = []
        with open(path) as fobj:
            for line in fobj:
                w = line.split()
                if not w:
                    continue
                if w[0] == "v":
                    vs.append([float(x) for x in w[1:4]])
                elif w[0] == "vt":
                    vts.append([float(x) for x in w[1:3]] + [0.0] * (2 - len(w[1:3])))
                elif w[0] == "vn":
                    vns.append([float(x) for x in w[1:4]])
                elif w[0] == "mtllib":
                    mtl.update(read_mtl(os.path.join(mesh_dir, " ".join(w[1:]))))
                elif w[0] == "usemtl":
                    current = " ".join(w[1:])
                elif w[0] == "f":
                    idx = []
                    for c in w[1:]:
                        parts = (c.split("/") + ["", ""])[:3]
                        get = lambda i, n: (int(i) - 1 if int(i) > 0 else n + int(i)) if i else None
                        idx.append((get(parts[0], len(vs)), get(parts[1], len(vts)), get(parts[2], len(vns))))
                    faces.append((idx, current))
        if any(len(f[0]) > 4 for f in faces):
            self.note("OBJ polygons of more than 4 corners: fan-triangulated (caustica clips ears)")
        mats = {}
        for idx, name in faces:
            if m_override is not None:
                m = m_override
            else:
                if name not in mats:
                    mats[name] = mesh_material(mtl.get(name), mesh_dir)
                m = mats[name]
            for k in range(1, len(idx) - 1):
                tri = [idx[0], idx[k], idx[k + 1]]
                if mirror:
                    tri = [tri[0], tri[2], tri[1]]
                p = [xf(vs[i[0]]) for i in tri]
                uv = [vts[i[1]] for i in tri] if all(i[1] is not None for i in tri) else None
                n = [xn(vns[i[2]]) for i in tri] if all(i[2] is not None for i in tri) else None
                self.add_triangle(p, m, uv, n)

    def add_inline_mesh(self, s, t, m_override):
        """A mesh given in the scene (vertices, indices, optional normals and
        uvs: scenes/FORMAT.md), placed by its transform as a file's."""
        scale = t.get("scale", 1.0)
        scale = [float(scale)] * 3 if not isinstance(scale, list) else [float(v) for v in scale]
        rot = rotation_xyz(t.get("rotate", [0, 0, 0]))
        tr = [float(v) for v in t.get("translate", [0, 0, 0])]
        mirror = scale[0] * scale[1] * scale[2] < 0
        vs = [add(matvec(rot, [p[0] * scale[0], p[1] * scale[1], p[2] * scale[2]]), tr) for p in s["vertices"]]
        ns = [normalize(matvec(rot, [n[0] / scale[0], n[1] / scale[1], n[2] / scale[2]])) for n in s["normals"]] \
            if "normals" in s else None
        uvs = s.get("uvs")
        flat = [int(i) for tri in s["indices"] for i in (tri if isinstance(tri, list) else [tri])]
        m = m_override if m_override is not None else read_material({})
        for k in range(0, len(flat) - 2, 3):
            tri = [flat[k], flat[k + 2], flat[k + 1]] if mirror else flat[k:k + 3]
            self.add_triangle([vs[i] for i in tri], m, [uvs[i] for i in tri] if uvs else None,
                              [ns[i] for i in tri] if ns else None)

    def add_shapes(self):
        """The file's shapes as this converter's triangles, spheres and meshes
        (compare_cycles.py's converter inherits it)."""
        sc = self.scene
        for i, s in enumerate(sc["scene"]["shapes"]):
            t = str(s.get("type", "")).lower()
            if t in ("cubemap", "sphericalmap"):
                self.note("shape %d (%s) skipped, as caustica skips it" % (i, t))
                continue
            if t in ("mesh", "ply"):
                self.add_mesh(s, self.shape_material(s) if "material" in s else None)
                continue
            m = self.shape_material(s)
            if t in ("sphere", "uvsphere"):
                self.add_sphere(s["center"], s["radius"], m, self.dir)
            elif t in ("cylinder", "uvcylinder"):
                self.add_cylinder(s, m, self.dir)
            elif t == "triangle":
                uv = [s["uv0"], s["uv1"], s["uv2"]] if "uv0" in s else None
                self.add_triangle([s["v0"], s["v1"], s["v2"]], m, uv)
            elif t == "rectangle" and "v0" in s:
                self.add_quad([s["v0"], s["v1"], s["v2"], s["v3"]], m)
            elif t == "rectangle":
                c1, c2 = s["corner1"], s["corner2"]
                k = [i for i in range(3) if c1[i] == c2[i]][0]
                a, b = (k + 1) % 3, (k + 2) % 3

                def pt(ua, vb):
                    p = [0.0] * 3
                    p[k], p[a], p[b] = c1[k], ua, vb
                    return p
                la, ha = sorted((c1[a], c2[a]))
                lb, hb = sorted((c1[b], c2[b]))
                self.add_quad([pt(la, lb), pt(ha, lb), pt(ha, hb), pt(la, hb)], m)
            elif t == "box":
                lo = [min(x, y) for x, y in zip(s["min"], s["max"])]
                hi = [max(x, y) for x, y in zip(s["min"], s["max"])]
                rot = rotation_xyz(s.get("rotation", [0, 0, 0]))
                corner = [matvec(rot, [hi[0] if i & 1 else lo[0], hi[1] if i & 2 else lo[1],
                                       hi[2] if i & 4 else lo[2]]) for i in range(8)]
                for f in ((0, 4, 6, 2), (1, 3, 7, 5), (0, 1, 5, 4), (2, 6, 7, 3), (0, 2, 3, 1), (4, 5, 7, 6)):
                    self.add_quad([corner[j] for j in f], m)
            else:
                raise Unsupported("shape type %r" % t)

    def convert(self):
        sc = self.scene
        self.add_shapes()

        for i, l in enumerate(sc["scene"].get("lightsources", [])):
            t = str(l.get("type", "")).lower()
            if t == "pointlight":
                self.shapes["light%d" % i] = {"type": "point", "position": [float(v) for v in l["position"]],
                                              "intensity": {"type": "rgb", "value": l["intensity"]}}
                self.emitter_power["light%d" % i] = 4 * math.pi * mean([float(v) for v in l["intensity"]])
            elif t == "spherelight":
                self.add_sphere(l["position"], l["radius"], None, self.dir,
                                emitter={"type": "area", "radiance": {"type": "rgb", "value": l["intensity"]}})
            elif t == "arealight":
                u, v = area_light_edges(l)
                c = l["position"]
                a = sub(sub(c, mul(u, 0.5)), mul(v, 0.5))
                b = add(sub(c, mul(v, 0.5)), mul(u, 0.5))
                cc = add(add(c, mul(u, 0.5)), mul(v, 0.5))
                d = add(sub(c, mul(u, 0.5)), mul(v, 0.5))
                m = read_material({"type": "emissive", "color": l["intensity"]})
                # caustica's light geometry: (a, b, c), (a, c, d), emitting about u x v
                self.add_triangle([a, b, cc], m)
                self.add_triangle([a, cc, d], m)
            elif t == "ambient":
                self.note("ambient light ignored (as in caustica's path mode)")
            else:
                raise Unsupported("light type %r" % t)

        bg = sc["scene"].get("backgroundcolor", [0, 0, 0])
        if max(bg) > 0:
            self.shapes["background"] = {"type": "constant", "radiance": {"type": "rgb", "value": bg}}
        if float(sc["camera"].get("exposure", 0)) != 0:
            self.note("camera exposure ignored (both images are linear)")

        for n, (key, tris) in enumerate(self.groups.items()):
            mkey, has_uv, has_n = key
            m = self.materials[mkey]
            path = os.path.join(self.folder, "group%d.obj" % n)
            with open(path, "w") as f:
                for p, uv, nn in tris:
                    for k in range(3):
                        f.write("v %.9g %.9g %.9g\n" % tuple(p[k]))
                    if has_uv:
                        for k in range(3):
                            f.write("vt %.9g %.9g\n" % tuple(uv[k][:2]))
                    if has_n:
                        for k in range(3):
                            f.write("vn %.9g %.9g %.9g\n" % tuple(nn[k]))
                for k in range(len(tris)):
                    i = [3 * k + 1, 3 * k + 2, 3 * k + 3]
                    if has_uv and has_n:
                        f.write("f %d/%d/%d %d/%d/%d %d/%d/%d\n" % (i[0], i[0], i[0], i[1], i[1], i[1], i[2], i[2], i[2]))
                    elif has_uv:
                        f.write("f %d/%d %d/%d %d/%d\n" % (i[0], i[0], i[1], i[1], i[2], i[2]))
                    elif has_n:
                        f.write("f %d//%d %d//%d %d//%d\n" % (i[0], i[0], i[1], i[1], i[2], i[2]))
                    else:
                        f.write("f %d %d %d\n" % tuple(i))
            shape = {"type": "obj", "filename": path, "face_normals": not has_n, "flip_tex_coords": False}
            e = self.emitter_of(m, "triangle")
            if e and max(m["diffuse"]) * m["kd"] <= 0 and (m["ks"] <= 0 or max(m["specular"]) <= 0) \
                    and not m["reflective"] and not m["refractive"]:
                shape["bsdf"] = {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0, 0, 0]}}
            else:
                shape["bsdf"] = self.shape_bsdf(m, self.dir, "triangle")
            name = "mesh%d" % len(self.shapes)
            if e:
                shape["emitter"] = e
                area = sum(0.5 * length(cross(sub(p[1], p[0]), sub(p[2], p[0]))) for p, _, _ in tris)
                self.emitter_power[name] = mean(e["radiance"]["value"]) * math.pi * area
            self.shapes[name] = shape
        if not self.approximate:
            self.notes.insert(0, "faithful conversion")
        return self

    def camera(self):
        cam, top = self.scene["camera"], self.scene
        _, aperture = find_any(cam, ["aperture", "apertureSize", "diameter"])
        if aperture is None:
            aperture = top.get("aperture")
        if not top.get("use_dof", True):
            aperture = None
        pos, at = [float(v) for v in cam["position"]], [float(v) for v in cam["lookAt"]]
        _, focus = find_any(cam, ["focalDistance", "focusDistance", "focusdistance", "focalLength", "focus_distance"])
        if focus is None:
            focus = top.get("focus_distance", length(sub(at, pos)))
        d = {"fov_axis": "y", "fov": float(cam["fov"]),
             "to_world": self.mi.ScalarTransform4f().look_at(origin=pos, target=at, up=cam["upVector"])}
        if aperture and float(aperture) > 0:
            d.update({"type": "thinlens", "aperture_radius": 0.5 * float(aperture), "focus_distance": float(focus)})
        else:
            d["type"] = "perspective"
        return d

    def mitsuba_dict(self, width, height, sampler, spp):
        sensor = self.camera()
        sensor["film"] = {"type": "hdrfilm", "width": width, "height": height, "pixel_format": "rgb",
                          "rfilter": {"type": "box"}}
        sensor["sampler"] = {"type": sampler, "sample_count": spp}
        d = {"type": "scene", "integrator": {"type": "path", "max_depth": int(self.scene.get("nbounces", 4)) + 1},
             "sensor": sensor}
        d.update(self.shapes)
        if self.emitter_weights == "power":
            # Mitsuba picks an emitter in proportion to its sampling_weight
            # (1 by default: uniform); by power, as caustica's CDF does. An
            # emitter without a known power (the background) keeps 1.
            for name, power in self.emitter_power.items():
                shape = dict(d[name])
                if "emitter" in shape:
                    shape["emitter"] = dict(shape["emitter"], sampling_weight=max(power, 1e-12))
                else:
                    shape["sampling_weight"] = max(power, 1e-12)
                d[name] = shape
        return d


def fmt3(c):
    return "(" + ", ".join("%.3g" % v for v in c) + ")"


def area_light_edges(l):
    u, v = l.get("u", l.get("u_axis")), l.get("v", l.get("v_axis"))
    if "size" in l or "width" in l or "height" in l:
        w, h = l["size"] if "size" in l else (l["width"], l["height"])
        du = normalize(u if u else [1, 0, 0])
        dv = normalize(v if v else [0, 0, 1])
        if not v and abs(dot(du, dv)) > 0.999:
            dv = [0, 1, 0]
        if not u and abs(dot(du, dv)) > 0.999:
            du = [0, 1, 0]
        return mul(du, w), mul(dv, h)
    if u and v:
        return [float(x) for x in u], [float(x) for x in v]
    return [0.1, 0, 0], [0, 0, 0.1]


def read_mtl(path):
    out, cur = {}, None
    if not os.path.isfile(path):
        return out
    with open(path) as f:
        for line in f:
            w = line.split()
            if not w:
                continue
            if w[0] == "newmtl":
                cur = out.setdefault(" ".join(w[1:]), {})
            elif cur is not None and w[0] in ("Kd", "Ks", "Ke"):
                cur[w[0]] = [float(x) for x in w[1:4]]
            elif cur is not None and w[0] == "Ns":
                cur["Ns"] = float(w[1])
            elif cur is not None and w[0] == "map_Kd":
                cur["map_Kd"] = w[-1]
    return out


def mesh_material(m, mesh_dir):
    """caustica's mesh_material: Kd (kd 1), Ks (ks 1 when nonzero), Ns, Ke, map_Kd."""
    if m is None:  # faces without a material: the default one
        return read_material({})
    ks = [max(0.0, v) for v in m.get("Ks", [0, 0, 0])]
    out = read_material({})
    out.update({"diffuse": [max(0.0, v) for v in m.get("Kd", [0.8, 0.8, 0.8])], "kd": 1.0, "specular": ks,
                "ks": 1.0 if max(ks) > 0 else 0.0, "exponent": max(m.get("Ns", 20.0), 0.0),
                "emission": [max(0.0, v) for v in m.get("Ke", [0, 0, 0])]})
    if "map_Kd" in m:
        out["texture"] = os.path.join(mesh_dir, m["map_Kd"])
    return out


# ---------------------------------------------------------------- Mitsuba


def find_libllvm():
    if os.environ.get("DRJIT_LIBLLVM_PATH"):
        return os.environ["DRJIT_LIBLLVM_PATH"]
    best = None
    for pattern in ["/usr/lib/x86_64-linux-gnu/libLLVM*.so*", "/usr/lib/aarch64-linux-gnu/libLLVM*.so*",
                    "/usr/lib/llvm-*/lib/libLLVM*.so*", "/usr/lib64/libLLVM*.so*", "/usr/local/lib/libLLVM*.so*"]:
        for p in glob.glob(pattern):
            m = re.search(r"LLVM[-.]?(?:so\.)?(\d+)", os.path.basename(p)) or re.search(r"llvm-(\d+)", p)
            if m and int(m.group(1)) >= 16 and (best is None or int(m.group(1)) > best[0]):
                best = (int(m.group(1)), p)
    return best[1] if best else None


def pick_variant(requested):
    """(variant, libllvm path or None, note). Tests llvm_ad_rgb in a child
    process: an unusable libLLVM aborts the process rather than raising."""
    if requested and not requested.startswith("llvm"):
        return requested, None, "asked for with --variant"
    lib = find_libllvm()
    if not lib:
        return "scalar_rgb", None, ("llvm_ad_rgb unavailable: no libLLVM >= 16 found (apt-get install libllvm19, "
                                    "or set DRJIT_LIBLLVM_PATH)")
    test = ("import drjit as dr, mitsuba as mi\nmi.set_variant('llvm_ad_rgb')\ndr.set_thread_count(1)\n"
            "d = mi.cornell_box()\nd['sensor']['film']['width'] = d['sensor']['film']['height'] = 8\n"
            "img = mi.render(mi.load_dict(d), spp=1)\ndr.eval(img)\nprint('ok')\n")
    try:
        r = subprocess.run([sys.executable, "-c", test], env=dict(os.environ, DRJIT_LIBLLVM_PATH=lib),
                           capture_output=True, text=True, timeout=300)
        ok = r.returncode == 0 and "ok" in r.stdout
        why = "exit status %d: %s" % (r.returncode, (r.stderr.strip().splitlines() or [""])[-1])
    except subprocess.TimeoutExpired:
        ok, why = False, "test render timed out"
    if ok:
        os.environ["DRJIT_LIBLLVM_PATH"] = lib
        return requested or "llvm_ad_rgb", lib, "DRJIT_LIBLLVM_PATH=%s" % lib
    return "scalar_rgb", None, "llvm_ad_rgb failed with %s (%s)" % (lib, why)


class Mitsuba:
    def __init__(self, variant, threads):
        import drjit as dr
        import mitsuba as mi
        self.dr, self.mi = dr, mi
        mi.set_variant(variant)
        dr.set_thread_count(threads)
        self.variant = variant
        self.jit = variant.startswith(("llvm", "cuda"))
        if self.jit:
            dr.set_flag(dr.JitFlag.KernelHistory, True)
        self.round_cache = {}

    def sample_count(self, sampler, n):
        key = (sampler, n)
        if key not in self.round_cache:
            level = self.mi.log_level() if hasattr(self.mi, "log_level") else None
            self.mi.set_log_level(self.mi.LogLevel.Error)
            self.round_cache[key] = self.mi.load_dict({"type": sampler, "sample_count": n}).sample_count()
            if level is not None:
                self.mi.set_log_level(level)
        return self.round_cache[key]

    def admissible(self, sampler, target):
        """The largest sample count <= target that the sampler runs as it is
        (its smallest count when none is)."""
        target = max(1, int(target))
        if self.sample_count(sampler, 1) > target:
            return self.sample_count(sampler, 1)
        lo, hi = 1, target  # sample_count(lo) <= target
        while lo < hi:
            mid = (lo + hi + 1) // 2
            if self.sample_count(sampler, mid) <= target:
                lo = mid
            else:
                hi = mid - 1
        return self.sample_count(sampler, lo)

    def nearest(self, sampler, target):
        """The sample count the sampler takes that is nearest to target by
        ratio: the largest one below it or the one it rounds target up to
        (so a power of two is at most a factor sqrt(2) off)."""
        target = max(1, int(target))
        below, above = self.admissible(sampler, target), self.sample_count(sampler, target)
        if below > target or (above > target and above * below < target * target):
            return above
        return below

    def render(self, conv, w, h, sampler, spp, seed, folder):
        """(values mirrored into caustica's orientation, wall s, JIT s, spp run)."""
        mi, dr = self.mi, self.dr
        scene = mi.load_dict(conv.mitsuba_dict(w, h, sampler, spp))
        if self.jit:
            dr.kernel_history()  # clears it
        t0 = time.perf_counter()
        image = mi.render(scene, spp=spp, seed=seed)
        dr.eval(image)
        dr.sync_thread()
        wall = time.perf_counter() - t0
        jit = 0.0
        if self.jit:
            jit = sum(k.get("codegen_time", 0.0) + k.get("backend_time", 0.0) for k in dr.kernel_history()) / 1000
        ran = scene.sensors()[0].sampler().sample_count()
        path = os.path.join(folder, "mitsuba.pfm")
        mi.Bitmap(image).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, srgb_gamma=False).write(path)
        _, _, flat = read_pfm(path)
        return mirror_rows(flat, w, h), wall, jit, ran


# ---------------------------------------------------------------- Cycles


def compare_cycles_module():
    """bench/compare_cycles.py, imported when first needed (it imports this
    module; only the standard library at import time)."""
    sys.path.insert(0, HERE)
    import compare_cycles
    return compare_cycles


class Cycles:
    """Blender's Cycles through bench/compare_cycles.py: its converter
    (SceneDescription, on this module's scene parsing) and its child process
    in the bpy venv, which builds the Blender scene and renders it (CPU,
    adaptive sampling and denoising off: run_cycles). Images come back
    mirrored into caustica's orientation."""

    def __init__(self, args):
        self.cc = compare_cycles_module()
        self.python = self.cc.VENV_PYTHON
        # what compare_cycles' functions read from their args (its own
        # defaults for the mesh resolutions of cylinders and glass spheres)
        self.args = argparse.Namespace(threads=args.threads, seed=1, caustica=args.caustica,
                                       cylinder_segments=512, glass_sphere_segments=256, sphere_mesh=0,
                                       cycles_reference_spp=args.cycles_reference_spp or args.reference_spp)
        self.version = None

    def describe(self, scene):
        return self.cc.describe(scene, self.args)

    def render(self, desc, w, h, folder, seconds=None, samples=None, seed=None, name="cycles"):
        """(values in caustica's orientation, the child's info: wall_s (the
        render call), samples, sync_s, after_s, cpu_s, ...)."""
        info, raw, _ = self.cc.run_cycles(self.args, desc, w, h, folder, name, False, False, seconds=seconds,
                                          samples=samples, seed=seed)
        self.version = info.get("blender")
        return raw.ravel().tolist(), info

    def reference(self, scene, desc, w, h, folder):
        """compare_cycles' cached Cycles reference (bench/cycles/cache/)."""
        ref, info = self.cc.cycles_reference(self.args, scene, desc, w, h, folder, None)
        return ref.ravel().tolist(), info


def cycles_row(args, cy, desc, w, h, folder, stem):
    """(values, row): Cycles' equal-time render. Its time_limit counts
    sampling alone, so it is --seconds less the scene sync and the writing
    after the last sample that a short probe measured; rendered again (at
    most twice) with the limit moved by the difference when the wall time
    is more than 15% off."""
    S = args.seconds
    probe_s = min(max(0.1 * S, 0.2), 2.0)
    _, p = cy.render(desc, w, h, folder, seconds=probe_s, name="cycles_probe")
    if p.get("sync_s") is not None and p.get("after_s") is not None:
        overhead = p["sync_s"] + p["after_s"]
    else:
        overhead = max(p["wall_s"] - probe_s, 0.0)
    limit = max(S - overhead, 0.1 * S)
    log("%s: Cycles: probe %s samples in %.2f s (sync %.2f s, after the last sample %.2f s) -> time limit %.2f s"
        % (stem, p.get("samples"), p["wall_s"], p.get("sync_s") or 0, p.get("after_s") or 0, limit))
    attempts = []
    while True:
        values, info = cy.render(desc, w, h, folder, seconds=limit)
        attempts.append({"time_limit_s": limit, "wall_s": info["wall_s"], "spp": info.get("samples")})
        if abs(info["wall_s"] - S) <= 0.15 * S or len(attempts) == 3:
            break
        log("%s: Cycles: time limit %.2f s took %.2f s: again" % (stem, limit, info["wall_s"]))
        limit = max(limit + S - info["wall_s"], 0.1 * S)
    spp = info.get("samples")
    row = {"renderer": "Cycles %s" % info.get("blender", ""), "sampler": info.get("sampling_pattern"),
           "time_limit_s": limit, "spp": spp, "wall_s": info["wall_s"], "sync_s": info.get("sync_s"),
           "after_s": info.get("after_s"), "cpu_s": info["cpu_s"], "process_s": info["process_s"],
           "import_s": info.get("import_s"), "build_s": info.get("build_s"), "attempts": attempts,
           "samples_per_s": w * h * spp / info["wall_s"] if spp else None,
           "probe": {"time_limit_s": probe_s, "wall_s": p["wall_s"], "spp": p.get("samples"),
                     "sync_s": p.get("sync_s"), "after_s": p.get("after_s")},
           "settings": "CPU, %d threads, time_limit %.2f s, samples 2^24, adaptive sampling off, denoising off, "
                       "clamping off, light tree on, light threshold 0, blur_glossy 0, box filter 1 px, seed %d"
                       % (args.threads, limit, cy.args.seed)}
    log("%s: Cycles: %s spp in %.2f s" % (stem, spp, info["wall_s"]))
    return values, row


# ---------------------------------------------------------------- caustica


def run_caustica(args, scene, w, h, out):
    env = dict(os.environ, POCL_MAX_PTHREAD_COUNT=str(args.threads))
    cmd = [args.caustica, "render", scene, "--mode", "path", "--time", "%g" % args.seconds, "--width",
           str(w), "--height", str(h), "--exposure", "0", "-v", "-o", out, "--seed", "1"]
    t0 = time.perf_counter()
    r = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=args.seconds * 5 + 120)
    wall = time.perf_counter() - t0
    text = r.stdout + r.stderr
    if r.returncode != 0:
        raise RuntimeError("caustica render failed (%d): %s" % (r.returncode, text.strip()[-2000:]))
    res = {"command": " ".join(cmd), "wall_s": wall, "verbose": [l for l in text.splitlines() if l.strip()]}
    m = re.search(r"wrote .*\(\s*\d+\s*x\s*\d+,\s*([\d.]+)\s*spp\)\s*in\s*([\d.]+)\s*s", text)
    if m:
        res["spp"], res["render_s"] = float(m.group(1)), float(m.group(2))
    else:
        m = re.search(r"([\d.]+)(?:/\S+)?\s*spp", text)
        if m:
            res["spp"] = float(m.group(1))
    m = re.search(r"render:\s*([\d.]+)\s*ms", text)
    if m:
        res["render_ms"] = float(m.group(1))
    return res


def run_caustica_spp(args, scene, w, h, spp, seed, out, extra=()):
    """The values of a caustica render of a fixed spp (references, checks)."""
    env = dict(os.environ, POCL_MAX_PTHREAD_COUNT=str(args.threads))
    subprocess.run([args.caustica, "render", scene, "--mode", "path", "--spp", str(spp), "--width", str(w),
                    "--height", str(h), "--exposure", "0", "-q", "-o", out, "--seed", str(seed)] + list(extra),
                   check=True, env=env)
    return read_pfm(out)[2]


def run_bench(args, scene, w, h):
    env = dict(os.environ, POCL_MAX_PTHREAD_COUNT=str(args.threads))
    cmd = [args.caustica, "bench", scene, "--mode", "path", "--spp", str(args.bench_spp), "--width",
           str(w), "--height", str(h)]
    r = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=1800)
    res = {"command": " ".join(cmd), "lines": [], "json": None}
    if r.returncode != 0:
        res["error"] = "exit status %d: %s" % (r.returncode, r.stderr.strip()[-500:])
        return res
    # Blocks: a line that starts in column 0 and the indented lines after it.
    # Kept (loosely, the format changes): render, path and host-traffic
    # blocks and any that mention launches, blocking transfers or device time.
    blocks = []
    for line in r.stdout.splitlines():
        s = line.strip()
        if s.startswith("{"):
            try:
                res["json"] = json.loads(s)
            except ValueError:
                pass
            continue
        if not s:
            continue
        if line[:1].isspace() and blocks:
            blocks[-1].append(line.rstrip())
        else:
            blocks.append([line.rstrip()])
    for b in blocks:
        text = " ".join(b)
        if re.match(r"(render|path|host traffic)\b", b[0]) or re.search(
                r"\d+ launches|blocking transfer|device time per stage", text):
            res["lines"].extend(b)
    return res


# ---------------------------------------------------------------- reference


def scene_hash(path):
    h = hashlib.sha1(CONVERTER_VERSION.encode())
    with open(path, "rb") as f:
        h.update(f.read())
    return h.hexdigest()[:8]


def make_reference(args, ms, cy, conv, desc, scene, w, h, folder, renderer):
    """(values, info): the cached long render of `renderer`, or a new one
    (Cycles': bench/compare_cycles.py's, cached in bench/cycles/cache/)."""
    if renderer == "cycles":
        return cy.reference(scene, desc, w, h, folder)
    spp = args.reference_spp
    stem = os.path.splitext(os.path.basename(scene))[0]
    cache = os.path.join(HERE, "mitsuba", "cache")
    os.makedirs(cache, exist_ok=True)
    name = "%s-%s-%dx%d-%dspp-%s" % (stem, scene_hash(scene), w, h, spp, renderer)
    path = os.path.join(cache, name + ".pfm")
    meta_path = os.path.join(cache, name + ".json")
    if os.path.isfile(path) and os.path.isfile(meta_path):
        with open(meta_path) as f:
            info = json.load(f)
        info.update(path=os.path.relpath(path, ROOT), cached=True)
        log("%s: reference %s (cached)" % (stem, info["path"]))
        return read_pfm(path)[2], info
    log("%s: making the %s reference (%d spp)" % (stem, renderer, spp))
    half = [None, None]
    t0 = time.perf_counter()
    if renderer == "caustica":
        n = max(1, spp // 2)
        for k in range(2):
            half[k] = run_caustica_spp(args, scene, w, h, n, 1000 + k, os.path.join(folder, "ref%d.pfm" % k))
            log("  reference %s: %d / %d spp (%.1f s)" % (stem, n * (k + 1), 2 * n, time.perf_counter() - t0))
        desc = "caustica, %d spp (2 x %d, seeds 1000 and 1001)" % (2 * n, n)
    else:
        per_pass = max(1, min(spp // 2, (1 << 22) // (w * h))) if spp >= 2 else 1
        done, k, sums, counts = 0, 0, [None, None], [0, 0]
        while done < spp:
            n = min(per_pass, spp - done)
            values, _, _, _ = ms.render(conv, w, h, "independent", n, 1000 + k, folder)
            side = k % 2
            sums[side] = [v * n for v in values] if sums[side] is None else \
                [a + v * n for a, v in zip(sums[side], values)]
            counts[side] += n
            done += n
            k += 1
            log("  reference %s: %d / %d spp (%.1f s)" % (stem, done, spp, time.perf_counter() - t0))
        half = [[v / counts[i] for v in sums[i]] if counts[i] else None for i in range(2)]
        if half[1] is None:
            half[1] = half[0]
        desc = "Mitsuba %s, independent sampler, %d spp in %d passes, seeds from 1000" % (ms.variant, spp, k)
    seconds = time.perf_counter() - t0
    ref = [(a + b) / 2 for a, b in zip(half[0], half[1])]
    # The halves' error variance is twice the mean's: E(a - b)^2 / 4 is the mean's.
    own = sum((a - b) ** 2 / (r * r + 0.01) for a, b, r in zip(half[0], half[1], ref)) / (4 * len(ref))
    write_pfm(path, w, h, ref)
    info = {"path": os.path.relpath(path, ROOT), "cached": False, "renderer": desc, "spp": spp,
            "seconds": seconds, "own_rel_mse": own, "width": w, "height": h, "scene": scene,
            "made": time.strftime("%Y-%m-%d %H:%M:%S")}
    with open(meta_path, "w") as f:
        json.dump(info, f, indent=1)
    return ref, info


# ---------------------------------------------------------------- one scene


def display_path(p):
    """Relative to the repository for files in it or beside it (../shared/...)."""
    a = os.path.abspath(p)
    for base in (ROOT, os.path.dirname(ROOT)):
        if a.startswith(base + os.sep):
            return os.path.relpath(a, ROOT)
    return p


def errors(values, refs, main):
    """relMSE of an image against the main reference and each own one."""
    out = {"rel_mse": rel_mse(values, refs[main]), "mean_over_ref": mean(values) / mean(refs[main])}
    for name, ref in refs.items():
        if name != main:
            out["rel_mse_vs_" + name] = rel_mse(values, ref)
    return out


def score(row, values, refs, main, own, renderer):
    """Adds a row's errors, and relMSE x s of its wall_s, against the main
    reference and (own) against its renderer's own."""
    row.update(errors(values, refs, main))
    row["rel_mse_x_s"] = row["rel_mse"] * row["wall_s"]
    row["own_rel_mse"] = row.get("rel_mse_vs_" + renderer, row["rel_mse"]) if own else None
    row["own_rel_mse_x_s"] = row["own_rel_mse"] * row["wall_s"] if own else None


def ratios(c, other, key):
    """caustica's relMSE x s (key) and samples/s over another row's."""
    return {"rel_mse_x_s": c[key] / other[key], "metric": key,
            "samples_per_s": (c["samples_per_s"] / other["samples_per_s"]
                              if c.get("samples_per_s") and other.get("samples_per_s") else None)}


def compare_scene(args, ms, cy, scene, w, h):
    stem = os.path.splitext(os.path.basename(scene))[0]
    res = {"scene": display_path(scene), "name": stem, "width": w, "height": h, "status": "ok"}
    folder = tempfile.mkdtemp(prefix="caustica_mitsuba_")
    try:
        try:
            conv = Converter(ms.mi, scene, folder).convert()
        except (Unsupported, KeyError, OSError) as e:
            res.update(status="skipped", reason="cannot convert: %s" % e)
            log("%s: skipped (%s)" % (stem, res["reason"]))
            return res
        res["approximate"] = conv.approximate
        res["notes"] = conv.notes
        desc = None
        if cy:
            try:
                desc = cy.describe(scene)
                res["cycles_approximate"], res["cycles_notes"] = desc["approximate"], desc["notes"]
            except (Unsupported, KeyError, OSError) as e:
                res["cycles_skipped"] = "cannot convert: %s" % e
                log("%s: Cycles left out (%s)" % (stem, res["cycles_skipped"]))
        S = args.seconds

        # References: "main" for every row; with --own-references (default:
        # where either conversion is approximate) each renderer's also
        # against its own.
        refs, infos = {}, {}
        if args.reference:
            rw, rh, refs["given"] = read_pfm(args.reference)
            if (rw, rh) != (w, h):
                sys.exit("%s is %dx%d, not %dx%d" % (args.reference, rw, rh, w, h))
            infos["given"] = {"path": args.reference, "renderer": "given with --reference", "own_rel_mse": None}
            main = "given"
        else:
            main = args.reference_renderer
        if main == "cycles" and desc is None:
            res.update(status="skipped", reason="the main reference is Cycles', and Cycles is left out")
            return res
        approximate = conv.approximate or bool(desc and desc["approximate"])
        own = args.own_references == "always" or (args.own_references == "auto" and approximate)
        renderers = ["mitsuba", "caustica"] + (["cycles"] if desc else [])
        for renderer in ([main] if main != "given" else []) + (renderers if own else []):
            if renderer not in refs:
                refs[renderer], infos[renderer] = make_reference(args, ms, cy, conv, desc, scene, w, h, folder,
                                                                 renderer)
        res["reference"] = dict(infos[main], role="main")
        res["main_reference"] = main
        res["references"] = infos
        res["own_references"] = own

        # Mitsuba: a warm-up for the scene's kernels and a first rate, then
        # each sampler's probe and its equal-time render.
        _, t, jit, _ = ms.render(conv, w, h, "independent", 4, 7, folder)
        rate0 = 4 / max(t - jit, 1e-3)
        jit_seen = jit  # the longest compilation seen for this scene
        rows = []
        for sampler, weights in [(s_, w_) for w_ in args.mitsuba_emitter_weights for s_ in args.samplers]:
            conv.emitter_weights = weights
            probe_s = min(max(0.1 * S, 0.2), 2.0)
            p = ms.admissible(sampler, max(1, rate0 * probe_s))
            _, pt, pjit, pran = ms.render(conv, w, h, sampler, p, 11, folder)
            rate = pran / max(pt - pjit, 1e-3)
            jit_seen = max(jit_seen, pjit)
            # The samplers other than independent compile a new kernel for a
            # new spp (unless Dr.Jit's disk cache has it from an earlier run,
            # which can also make the probe's compilation look free).
            expect_jit = 0.0 if sampler == "independent" else max(pjit, jit_seen)
            target = max(1, int(rate * max(S - expect_jit, 0.1 * S)))
            spp = ms.nearest(sampler, target)
            log("%s: Mitsuba %s: probe %d spp in %.2f s (JIT %.2f s) -> %d spp" % (stem, sampler, pran, pt, pjit, spp))
            # The timed render; again (at most twice) when its time is more
            # than 15% off, with the rate it measured: a compilation that
            # Dr.Jit's disk cache saved, or a probe too short, misjudge it.
            attempts = []
            while True:
                values, wall, jit, ran = ms.render(conv, w, h, sampler, spp, 1, folder)
                jit_seen = max(jit_seen, jit)
                attempts.append({"spp": ran, "wall_s": wall, "jit_s": jit})
                if abs(wall - S) <= 0.15 * S or len(attempts) == 3:
                    break
                rate = ran / max(wall - jit, 1e-3)
                target = max(1, int(rate * max(S - expect_jit, 0.1 * S)))
                again = ms.nearest(sampler, target)
                if again == ran:
                    break
                log("%s: Mitsuba %s: %d spp took %.2f s (JIT %.2f s): again with %d spp"
                    % (stem, sampler, ran, wall, jit, again))
                spp = again
            row = {"sampler": sampler if weights == "uniform" else "%s, emitters by power" % sampler,
                   "emitter_weights": weights, "requested_spp": target, "spp": ran, "wall_s": wall, "jit_s": jit,
                   "samples_per_s": w * h * ran / wall, "attempts": attempts,
                   "probe": {"spp": pran, "wall_s": pt, "jit_s": pjit, "spp_per_s": pran / max(pt - pjit, 1e-3)}}
            score(row, values, refs, main, own, "mitsuba")
            rows.append(row)
            log("%s: Mitsuba %s: %d spp in %.2f s, relMSE %.3e" % (stem, sampler, ran, wall, row["rel_mse"]))
        res["mitsuba"] = rows
        key = "own_rel_mse_x_s" if own else "rel_mse_x_s"
        best = min(rows, key=lambda r: r[key]) if rows else None
        res["best_sampler"] = best["sampler"] if best else None

        # Cycles
        cyc = None
        if desc:
            values, cyc = cycles_row(args, cy, desc, w, h, folder, stem)
            score(cyc, values, refs, main, own, "cycles")
            log("%s: Cycles: relMSE %.3e" % (stem, cyc["rel_mse"]))
            res["cycles"] = cyc

        # caustica: first an untimed render of up to 32 spp (adaptive from
        # 16) and --seconds, so that every kernel the timed one runs is
        # built (PoCL builds a kernel again for another image size)
        out = os.path.join(folder, "caustica.pfm")
        run_caustica_spp(args, scene, w, h, 32, 1, out, ["--time", "%g" % S])
        c = run_caustica(args, scene, w, h, out)
        score(c, read_pfm(out)[2], refs, main, own, "caustica")
        log("%s: caustica: %s spp in %.2f s, relMSE %.3e" % (stem, c.get("spp", "?"), c["wall_s"], c["rel_mse"]))
        if not args.no_bench:
            log("%s: caustica bench --spp %d" % (stem, args.bench_spp))
            res["bench"] = run_bench(args, scene, w, h)
        if "spp" in c:
            c["samples_per_s"] = w * h * c["spp"] / c["wall_s"]
            c["samples_per_s_source"] = "render -v (spp) / wall time"
        elif res.get("bench", {}).get("json"):
            c["samples_per_s"] = res["bench"]["json"].get("path_samples_per_s")
            c["samples_per_s_source"] = "caustica bench"
        res["caustica"] = c
        if best:
            res["ratios"] = dict(ratios(c, best, key), against=best["sampler"])
        if cyc:
            res["cycles_ratios"] = ratios(c, cyc, key)
        return res
    finally:
        shutil.rmtree(folder, ignore_errors=True)


# ---------------------------------------------------------------- Markdown


def describe_reference(ref):
    own = ref.get("own_rel_mse")
    return "`%s` (%s%s%s)" % (ref["path"], ref["renderer"],
                              ", rendered in %.1f s" % ref["seconds"] if ref.get("seconds") else "",
                              ", its own relMSE ~%.1e" % own if own is not None else "")


def markdown(args, results, mi_version, variant, variant_note, cycles_note):
    out = []
    mname = "Mitsuba %s %s" % (mi_version, variant)
    for r in results:
        W, H = r["width"], r["height"]
        out.append("### %s (%dx%d, %g s, %d threads)" % (r["name"], W, H, args.seconds, args.threads))
        out.append("")
        if r["status"] != "ok":
            out.append("Skipped: %s." % r["reason"])
            out.append("")
            continue
        own = r["own_references"]
        out.append("Conversion%s: %s%s." % (" to Mitsuba" if "cycles_notes" in r else "",
                                            "**approximate**: " if r["approximate"] else "", "; ".join(r["notes"])))
        if "cycles_notes" in r:
            out.append("")
            out.append("Conversion to Cycles (bench/compare_cycles.py): %s%s." % (
                "**approximate**: " if r["cycles_approximate"] else "", "; ".join(r["cycles_notes"])))
        elif r.get("cycles_skipped"):
            out.append("")
            out.append("Cycles left out: %s." % r["cycles_skipped"])
        out.append("")
        if own:
            names = [n for n in ("mitsuba", "caustica", "cycles") if n in r["references"]]
            out.append("References: %s. \"relMSE\" is against the %s one; \"own ref\" against the row's renderer's "
                       "own, which keeps the conversion's bias out of the comparison." % (
                           "; ".join("%s %s" % (n, describe_reference(r["references"][n])) for n in names),
                           "given" if "given" in r["references"] else r["reference"]["renderer"].split()[0]))
            if "given" in r["references"]:
                out.append("Given reference: " + describe_reference(r["references"]["given"]) + ".")
        else:
            out.append("Reference: " + describe_reference(r["reference"]) + ".")
        by_renderer = {"mitsuba": r["mitsuba"], "cycles": [r["cycles"]] if r.get("cycles") else [],
                       "caustica": [r["caustica"]]}
        for name, ref in r["references"].items():
            e = ref.get("own_rel_mse")
            vals = [x["rel_mse"] for xs in by_renderer.values() for x in xs] if name == r["main_reference"] else []
            if own:
                vals += [x["own_rel_mse"] for x in by_renderer.get(name, [])]
            if e is not None and vals and e > 0.2 * min(vals):
                out.append("Warning: the %s reference's own error is %.0f%% of the smallest relMSE measured "
                           "against it; raise --reference-spp." % (name, 100 * e / min(vals)))
        out.append("")
        head = "| renderer | sampler | wall s | JIT s | spp | samples/s | relMSE | relMSE x s | mean / ref |"
        rule = "|---|---|---:|---:|---:|---:|---:|---:|---:|"
        if own:
            head += " relMSE, own ref | relMSE x s, own ref |"
            rule += "---:|---:|"
        out.append(head)
        out.append(rule)

        def cells(x, best):
            c = ["%.3e" % x["rel_mse"], "%.3e" % x["rel_mse_x_s"], "%.3f" % x["mean_over_ref"]]
            if own:
                c += ["%.3e" % x["own_rel_mse"], "%.3e" % x["own_rel_mse_x_s"]]
            if best:
                i = 1 if not own else 4
                c[i] = "**%s**" % c[i]
            return " | ".join(c)

        def num(x, key, f):
            return f % x[key] if x.get(key) else "-"

        for m in r["mitsuba"]:
            best = m["sampler"] == r["best_sampler"]
            out.append("| %s | %s | %.2f | %.2f | %d | %.3g | %s |" % (
                mname, "**%s** (best)" % m["sampler"] if best else m["sampler"], m["wall_s"], m["jit_s"],
                m["spp"], m["samples_per_s"], cells(m, best)))
        y = r.get("cycles")
        if y:
            out.append("| %s (CPU) | %s | %.2f | - | %s | %s | %s |" % (
                y["renderer"], (y["sampler"] or "default").lower().replace("_", " "), y["wall_s"],
                num(y, "spp", "%d"), num(y, "samples_per_s", "%.3g"), cells(y, False)))
        c = r["caustica"]
        out.append("| caustica (PoCL CPU) | sobol | %.2f | - | %s | %s | %s |" % (
            c["wall_s"], num(c, "spp", "%g"), num(c, "samples_per_s", "%.3g"), cells(c, False)))
        out.append("")
        if y:
            out.append("Cycles: %s; wall s is the render call: %.2f s scene sync + %.2f s sampling + %.2f s after "
                       "the last sample (writing the EXR); not counted: the child process's start and bpy "
                       "import (%.2f s) and building the Blender scene (%.2f s)." % (
                           y["settings"], y["sync_s"] or 0, y["wall_s"] - (y["sync_s"] or 0) - (y["after_s"] or 0),
                           y["after_s"] or 0, y.get("import_s") or 0, y.get("build_s") or 0))
            out.append("")
        for q, against in ((r.get("ratios"), "best Mitsuba sampler (%s)" % r["best_sampler"]),
                           (r.get("cycles_ratios"), "Cycles")):
            if q:
                out.append("caustica / %s: relMSE x s%s **%.3g**, samples/s %s%s." % (
                    against, " (own references)" if own else "", q["rel_mse_x_s"],
                    "%.3g" % q["samples_per_s"] if q["samples_per_s"] else "-",
                    "" if c.get("samples_per_s_source", "").startswith("render") else
                    " (caustica's samples/s from `caustica bench`)"))
        out.append("")
        b = r.get("bench")
        if b:
            out.append("`caustica bench %s --mode path --spp %d --width %d --height %d` (%d threads):" % (
                r["scene"], args.bench_spp, W, H, args.threads))
            out.append("")
            out.append("```")
            out.extend(b["lines"] or [b.get("error", "(no render lines in its output)")])
            out.append("```")
            out.append("")
    done = [r for r in results if r["status"] == "ok"]
    skipped = ["%s skipped" % r["name"] for r in results if r["status"] != "ok"]
    parts = []
    for label, q in (("the best Mitsuba sampler's", "ratios"), ("Cycles'", "cycles_ratios")):
        have = [r for r in done if r.get(q)]
        if not have:
            continue
        g = math.exp(sum(math.log(r[q]["rel_mse_x_s"]) for r in have) / len(have))
        parts.append("over %s: %s; geometric mean %.3g" % (label, ", ".join(
            "%s %dx%d %.3g%s" % (r["name"], r["width"], r["height"], r[q]["rel_mse_x_s"],
                                 " (own references)" if r["own_references"] else "") for r in have), g))
    summary = ("**Summary** (%g s, %d threads; %s, %s; %s): caustica's relMSE x s (below 1: caustica better) %s%s."
               % (args.seconds, args.threads, mname, variant_note, cycles_note, "; ".join(parts) or "none",
                  "; " + ", ".join(skipped) if skipped else ""))
    out.append(summary)
    out.append("")
    out.append("| scene, size | renderer | spp | samples/s | relMSE | relMSE x s | **relMSE x s / caustica's** | "
               "samples/s / caustica's |")
    out.append("|---|---|---:|---:|---:|---:|---:|---:|")
    for r in done:
        own = r["own_references"]
        c = r["caustica"]
        best = next((m for m in r["mitsuba"] if m["sampler"] == r["best_sampler"]), None)
        rows = [("caustica", c)] + ([("Mitsuba, %s" % best["sampler"], best)] if best else []) + \
            ([(r["cycles"]["renderer"], r["cycles"])] if r.get("cycles") else [])
        err, ex = ("own_rel_mse", "own_rel_mse_x_s") if own else ("rel_mse", "rel_mse_x_s")
        for k, (name, x) in enumerate(rows):
            scene = "%s %dx%d%s" % (r["name"], r["width"], r["height"], " (own references)" if own else "") \
                if k == 0 else ""
            out.append("| %s | %s | %s | %s | %.3e | %.3e | **%.3g** | %s |" % (
                scene, name, "%g" % x["spp"] if x.get("spp") else "-",
                "%.3g" % x["samples_per_s"] if x.get("samples_per_s") else "-", x[err], x[ex], x[ex] / c[ex],
                "%.3g" % (x["samples_per_s"] / c["samples_per_s"]) if x.get("samples_per_s") and
                c.get("samples_per_s") else "-"))
    out.append("")
    out.append("relMSE x s / caustica's above 1: caustica reaches a lower error in the same time. With own "
               "references, each renderer's error is against its own long render.")
    return "\n".join(out), summary


# ---------------------------------------------------------------- orientation


def red_centroid(values, w):
    """(x, y) mean of the red pixels (R > 2.5 G and R > 0.05), or None."""
    xs, ys = [], []
    for i in range(len(values) // 3):
        if values[3 * i] > 2.5 * values[3 * i + 1] and values[3 * i] > 0.05:
            xs.append(i % w)
            ys.append(i // w)
    return (mean(xs), mean(ys)) if xs else None


def check_orientation(args, ms, cy):
    """Renders bench/compare_cycles.py's asymmetric test scene (a red sphere
    up on the +x side of a grey wall, camera along +z with up +y) at 64x64,
    --orientation-spp uniform samples each, and compares Mitsuba's and
    Cycles' images with caustica's as this script compares them (mirrored)
    and unmirrored."""
    n, spp = 64, args.orientation_spp
    folder = tempfile.mkdtemp(prefix="caustica_orientation_")
    try:
        path = compare_cycles_module().write_orientation_scene(folder)
        ci = run_caustica_spp(args, path, n, n, spp, 1, os.path.join(folder, "c.pfm"), ["--no-adaptive"])
        images = {"mitsuba": ms.render(Converter(ms.mi, path, folder).convert(), n, n, "independent", spp, 1,
                                       folder)[0]}
        if cy:
            images["cycles"] = cy.render(cy.describe(path), n, n, folder, samples=spp)[0]
        c = red_centroid(ci, n)
        res = {"size": n, "spp": spp, "caustica_red_centroid": c,
               "expected": "caustica draws world +x on the image's right (FORMAT.md): the sphere right and up"}
        ok = c is not None and c[0] > n / 2 and c[1] < n / 2
        for name, img in images.items():
            d = {"rel_mse_as_compared": rel_mse(img, ci), "rel_mse_unmirrored": rel_mse(mirror_rows(img, n, n), ci),
                 "mean_over_caustica": mean(img) / mean(ci), "red_centroid_as_compared": red_centroid(img, n)}
            b = d["red_centroid_as_compared"]
            d["centroid_distance_px"] = math.hypot(b[0] - c[0], b[1] - c[1]) if b and c else None
            d["ok"] = bool(d["centroid_distance_px"] is not None and d["centroid_distance_px"] < 1.5
                           and d["rel_mse_as_compared"] < 0.1 * d["rel_mse_unmirrored"])
            ok = ok and d["ok"]
            res[name] = d
        res["ok"] = bool(ok)
        return res
    finally:
        shutil.rmtree(folder, ignore_errors=True)


# ---------------------------------------------------------------- main


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="*", help="caustica scenes, SCENE.json[@WxH] (default: %s)" % " ".join(
        DEFAULT_SCENES))
    ap.add_argument("--seconds", type=float, default=10.0, help="wall time of each render (default 10)")
    ap.add_argument("--threads", type=int, default=2, help="threads of every renderer (default 2)")
    ap.add_argument("--width", type=int, default=128, help="width of scenes given without @WxH (default 128)")
    ap.add_argument("--height", type=int, default=128, help="height of scenes given without @WxH (default 128)")
    ap.add_argument("--reference", help="reference image (.pfm, linear, width x height) for the one scene given")
    ap.add_argument("--reference-spp", type=int, default=4096, help="spp of the made reference (default 4096)")
    ap.add_argument("--cycles-reference-spp", type=int,
                    help="samples of Cycles' own references (default: --reference-spp)")
    ap.add_argument("--reference-renderer", choices=["mitsuba", "caustica", "cycles"], default="mitsuba",
                    help="who renders the main reference when --reference is not given (default mitsuba)")
    ap.add_argument("--own-references", choices=["auto", "always", "never"], default="auto",
                    help="also measure each renderer against its own long render (auto: for approximate scenes)")
    ap.add_argument("--samplers", default=",".join(SAMPLERS), help="Mitsuba samplers (default: all five)")
    ap.add_argument("--variant", default="", help="Mitsuba variant (default: llvm_ad_rgb if it runs, else scalar_rgb)")
    ap.add_argument("--no-cycles", action="store_true", help="leave out Cycles")
    ap.add_argument("--mitsuba-emitter-weights", default="uniform",
                    help="Mitsuba's emitter choice, comma-separated: uniform (its default: every emitter's "
                         "sampling_weight 1) and/or power (sampling_weight = the emitter's power); a row each")
    ap.add_argument("--check-orientation", action="store_true",
                    help="only check the mirror image: an asymmetric scene through all three renderers")
    ap.add_argument("--orientation-spp", type=int, default=1024, help="spp of --check-orientation's renders")
    ap.add_argument("--bench-spp", type=int, default=64, help="spp of the caustica bench run (default 64)")
    ap.add_argument("--no-bench", action="store_true", help="leave out caustica bench")
    ap.add_argument("--json", help="write every number to this file")
    ap.add_argument("--caustica", default=os.path.join(ROOT, "build", "caustica"))
    args = ap.parse_args()
    args.samplers = [s.strip() for s in args.samplers.split(",") if s.strip()]
    args.mitsuba_emitter_weights = [s.strip() for s in args.mitsuba_emitter_weights.split(",") if s.strip()]
    for s in args.mitsuba_emitter_weights:
        if s not in ("uniform", "power"):
            sys.exit("--mitsuba-emitter-weights: %r: expected uniform and/or power" % s)
    for s in args.samplers:
        if s not in SAMPLERS:
            sys.exit("unknown sampler %r (one of %s)" % (s, ", ".join(SAMPLERS)))
    cc = compare_cycles_module()
    scenes = [cc.parse_scene_arg(s, args) for s in args.scenes or DEFAULT_SCENES]
    if args.reference and len(scenes) != 1:
        sys.exit("--reference needs exactly one scene")

    cy, cycles_note = None, "Cycles left out (--no-cycles)"
    if not args.no_cycles:
        if os.path.isfile(cc.VENV_PYTHON):
            cy = Cycles(args)
            cycles_note = "Cycles through %s" % display_path(cc.VENV_PYTHON)
        else:
            cycles_note = "Cycles left out: no bpy venv at %s (see bench/compare_cycles.py)" % display_path(
                cc.VENV_PYTHON)
            log(cycles_note)
    if args.reference_renderer == "cycles" and not cy:
        sys.exit("--reference-renderer cycles: " + cycles_note)
    variant, lib, note = pick_variant(args.variant)
    log("Mitsuba variant %s (%s)" % (variant, note))
    ms = Mitsuba(variant, args.threads)
    mi_version = ms.mi.__version__
    if args.check_orientation:
        res = check_orientation(args, ms, cy)
        print(json.dumps(res, indent=1))
        sys.exit(0 if res["ok"] else 1)
    results = []
    for scene, w, h in scenes:
        results.append(compare_scene(args, ms, cy, scene, w, h))
    if cy and cy.version:
        cycles_note = "Cycles %s (bpy) through %s" % (cy.version, display_path(cc.VENV_PYTHON))
    text, summary = markdown(args, results, mi_version, variant, note, cycles_note)
    print(text)
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"settings": {k: v for k, v in vars(args).items()}, "mitsuba": {
                "version": mi_version, "variant": variant, "variant_note": note, "libllvm": lib},
                "cycles": {"version": cy.version if cy else None, "note": cycles_note},
                "scenes": results, "summary": summary, "markdown": text}, f, indent=1)


if __name__ == "__main__":
    main()
