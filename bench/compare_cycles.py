#!/usr/bin/env python3
"""Equal wall time against Blender's Cycles, raw and OIDN-denoised (optional;
not part of the tests or CI).

What it measures: for each scene and image size, every renderer gets the same
wall time (--seconds, default 10) and the same number of threads (--threads,
default 2); each image's relMSE against a long caustica reference is
reported, raw and (where the row has one) denoised with Intel Open Image
Denoise:

    relMSE = mean over pixels and channels of (x - ref)^2 / (ref^2 + 0.01)

on linear radiance (caustica gets --exposure 0: its .exr/.pfm are otherwise
scaled by 2^(the camera's exposure)). Rows:

  * caustica, raw:  POCL_MAX_PTHREAD_COUNT=T build/caustica render SCENE --mode path
        --time S --width W --height H --seed 1 --exposure 0 -o raw.exr -q
        (after an untimed 1-spp render of the same scene, so that its kernels
        come from caustica's cache: a first build counts against --time);
  * caustica, --denoise: the same command with --denoise (when
        `caustica render --help` lists it): the .exr's main image is the
        denoised one, its `beauty` layer the raw film of the same run;
  * Cycles (bpy 5.0.1, CPU, T threads), adaptive sampling off and on: ONE
        render with time_limit = S and a sample count that time cuts short,
        OIDN denoising (albedo + normal guiding, prefilter ACCURATE) and
        denoising_store_passes, written (write_still) as a 32-bit multilayer,
        multi-part EXR: the "Combined" pass is the denoised film, "Noisy
        Image" the raw film of the same samples. So the raw and denoised
        columns share one wall time, OIDN's included; the render_stats
        handler's timestamps split it into scene sync until the first
        sample, sampling, and what follows the last sample (OIDN, writing);
        "samples" is the largest "Sample N/M" the stats reported, and with
        adaptive sampling the mean spp is that times the mean of the Debug
        Sample Count pass (the fraction of it each pixel took);
  * Mitsuba 3 rows are left out: the `mitsuba` package is not installed in
        this venv and Mitsuba has no CPU denoiser; bench/compare_mitsuba.py
        compares the raw renders of all three (its Cycles rows use this
        script's converter and child: adaptive sampling and denoising off).

Wall seconds: caustica's are the whole process (start, scene load, cached
kernel build, render, write). Cycles': "wall s" is the bpy.ops.render.render
call (scene sync, BVH build, rendering, denoising, writing the EXR);
building the Blender scene from the caustica file and importing bpy (the
child process's start) are reported apart and not counted. "cpu s" is the
child's user + system CPU time: about threads x wall when the machine was
otherwise idle, less when something else held the cores.

Commands (Debian 12; the venv holds bpy, numpy and OpenEXR):

    apt-get install python3.11-venv
    /usr/bin/python3.11 -m venv bench/cycles/venv
    bench/cycles/venv/bin/pip install bpy==5.0.1 OpenEXR
    nice -n 19 bench/cycles/venv/bin/python bench/compare_cycles.py \\
        [SCENE[@WxH] ...] [--seconds 10] [--json out.json] [--images DIR]
    nice -n 19 bench/cycles/venv/bin/python bench/compare_cycles.py --check-orientation

(Run with another python3, the script restarts itself under the venv's.)
Without scenes it runs DEFAULT_SCENES below (Cornell box at 128^2 and 512^2,
showcase_path, caustics and two community scenes from
../shared/scenes-coursework/community/).

References: a long caustica render per scene and size, `--no-adaptive --spp
N` in two halves of N/2 (seeds 99 and 100), averaged; the halves'
difference estimates the reference's own relMSE, printed beside it (it adds
about that much to every row). N is --reference-spp, or by default the spp
that fits --reference-cpu (360) CPU seconds at the rate (mean spp per
CPU second) of the scene's equal-time caustica row, rounded down to a
multiple of 64; a cached reference of at least that many spp is reused.
Cached in
bench/cycles/cache/ under the scene's name, a hash of the scene file and
this converter, the size and the spp. Conversion bias: Cycles also renders
its own long reference (adaptive off, no denoising, same two-halves scheme,
--cycles-reference-spp, or sized like caustica's from the uniform Cycles
row's samples per CPU second) for the scenes in --cycles-references (default:
the 128^2 Cornell box and every scene whose conversion is approximate), and
the rows then give Cycles' error against it ("own ref"), and the Cycles
reference's error against caustica's ("Cycles ref vs caustica ref": what
the conversion and the two renderers' models disagree on).

Caustic region (scenes with a smooth glass or mirror and --caustic-mask, on
by default for caustics.json): two extra caustica renders of the scene
changed so that nothing focuses light: every smooth glass gets IOR 1 (light
passes straight through: no caustic and no shadow) and every smooth mirror
reflectivity 0; and a coverage render in which only those casters emit
(radiance 1, both sides) and nothing else reflects or emits. The mask holds
the pixels that see no caster (coverage < 1e-3) where the reference's
luminance exceeds the caster-free render's by more than 25% of it plus
0.02: where the scene is brighter than it would be with no glass and no
mirror at all. "relMSE caustic" is the same metric over those pixels.

Orientation: caustica's camera puts right = up x forward (FORMAT.md), so a
camera looking along +z with up +y has +x on the image's right; Blender's
(right-handed: right = forward x up) has it on the left. Cycles' images are
mirrored left-right before every comparison. --check-orientation renders a
test scene (a small red sphere up and on the +x side of a grey wall) with
both, locates the sphere in each image and fails unless Cycles' image,
mirrored, puts it where caustica does.

Conversion (caustica's meaning: scenes/FORMAT.md, host/scene/*.cpp,
kernels/lib/material.h and bsdf.h; the scene parsing is
bench/compare_mitsuba.py's):
  * nbounces (scattering events; 1 = direct light only) is Cycles'
    max_bounces + 1 (max_bounces 0 = direct light only), also for the
    diffuse, glossy and transmission limits;
  * camera: vertical fov, box pixel filter of 1 px, thin lens as Cycles'
    circular aperture (f-stop = focal length / diameter) focused on the
    plane at focalDistance;
  * triangles, rectangles, boxes and OBJ meshes are meshes (flat, or with
    the file's normals as custom normals); opaque spheres are Cycles
    point-cloud spheres (analytic); glass spheres are UV-sphere meshes of
    --glass-sphere-segments (256) x 128 quads with exact radial normals
    (APPROXIMATE: surface within 7.5e-5 x radius), because Cycles 5.0.1's
    point-cloud spheres refract wrongly (rays starting inside: the caustic
    under caustics.json's sphere came out as a broad blur unlike caustica's,
    a mesh sphere's matches); cylinders are meshes of --cylinder-segments
    (512) sides with smooth normals plus flat caps: APPROXIMATE, surface
    within 1.9e-5 x radius;
  * emission: an Emission shader of the same radiance, zeroed on back faces
    (Geometry Backfacing) unless the material is twosided, emission
    sampling FRONT; area lights are two such black triangles on the side of
    u x v; backgroundcolor is the world colour (strength 1);
  * Lambertian (ks = 0): Diffuse BSDF (roughness 0); smooth/rough glass:
    Glass BSDF (GGX, roughness = sqrt(alpha)); conductors (isreflective,
    metallic 1): Metallic BSDF with fresnel F82, base colour = F0 and edge
    tint white, which is exactly Schlick's F0 + (1 - F0)(1 - cos)^5, GGX with
    roughness sqrt(alpha) (roughness 0: a mirror). Cycles' GGX has
    height-correlated Smith masking like caustica's;
  * plastic (ks > 0): caustica's Ashikhmin-Shirley coupling of Lambert and
    a GGX layer cannot be expressed (its diffuse term depends on the light's
    angle): the layer is a Metallic F82 lobe of F0 = ks x specularcolor
    (caustica's exact specular term) plus a Diffuse BSDF of colour
    kd x diffuse x (1 - F0) x (1 - (1 - cos_o/2)^5), the same directional
    albedo for every view angle but Lambertian in the light's angle:
    APPROXIMATE;
  * checkerboards are built from Math nodes (square (floor(u s),
    floor(v s)) colour1 where the sum is even); image textures are Image
    Texture nodes (sRGB decoded, linear filtering, repeat), x kd, clamped;
    a sphere's uv is caustica's u = atan2(n.z, n.x) / 2pi, v = acos(-n.y) / pi
    computed in the shader;
  * Cycles' glass does not scale transmitted radiance by 1/eta^2 (caustica
    does); it cancels on leaving a closed object, as every path to a light
    here does;
  * settings: clamping off, light threshold 0, blur_glossy 0, reflective
    and refractive caustics on, light tree on (default), default sampling
    pattern, seed --seed.
"""
import argparse
import hashlib
import json
import math
import os
import re
import resource
import shutil
import struct
import subprocess
import sys
import tempfile
import time
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
VENV_PYTHON = os.path.join(HERE, "cycles", "venv", "bin", "python")
CACHE = os.path.join(HERE, "cycles", "cache")
COMMUNITY = os.path.normpath(os.path.join(ROOT, "..", "shared", "scenes-coursework", "community"))
CONVERTER_VERSION = "2"  # part of the cache key: bump when the conversion changes
DEFAULT_SCENES = [
    "scenes/cornell_box.json@128x128",
    "scenes/cornell_box.json@512x512",
    "scenes/showcase_path.json@320x180",
    "scenes/caustics.json@320x240",
    os.path.join(COMMUNITY, "Kierandon__cpp-raytracer__cornell_box.json") + "@256x256",
    os.path.join(COMMUNITY, "michaelzhang4__raytracer__400_spheres.json") + "@300x200",
]
MIRROR = True  # Cycles' image is caustica's mirrored left-right (checked by --check-orientation)

sys.path.insert(0, HERE)
import compare_mitsuba as cm  # noqa: E402  (scene parsing, PFM; imports only the standard library)


def log(msg):
    print(msg, file=sys.stderr, flush=True)


# ---------------------------------------------------------------- scene -> neutral description


def classify(m):
    """(kind, exact): what a material (cm.read_material) becomes in Cycles."""
    if m["refractive"]:
        return "glass", True
    if m["reflective"]:
        return "conductor", True
    metallic = min(max(m["metallic"], 0.0), 1.0)
    if metallic >= 1.0:
        return "conductor", m["texture"] is None
    spec = [min(max(s * m["ks"], 0.0), 1.0) for s in m["specular"]]
    if max(spec) <= 0.0 and metallic <= 0.0:
        return "lambert", True
    return "plastic", False


class SceneDescription(cm.Converter):
    """A caustica scene as plain data (meshes by material, spheres, camera,
    world) that the Cycles child builds; `notes` and `approximate` say what
    is not exact."""

    def __init__(self, scene_path, cylinder_segments=512, sphere_mesh=0, glass_segments=256):
        self.mi = None
        self.path = scene_path
        self.dir = os.path.dirname(os.path.abspath(scene_path))
        with open(scene_path) as f:
            self.scene = json.load(f)
        self.notes = []
        self.approximate = False
        self.groups = {}
        self.materials = {}
        self.spheres = []
        self.segments = cylinder_segments
        self.sphere_mesh = sphere_mesh
        self.glass_segments = glass_segments

    # Materials: textures resolved to absolute paths; notes per kind.
    def material_record(self, m, base):
        m = dict(m)
        if m["texture"] is not None and not isinstance(m["texture"], dict):
            m["texture"] = os.path.abspath(self.find_asset(str(m["texture"]), base, "textures/"))
        kind, exact = classify(m)
        m["kind"] = kind
        if kind == "plastic":
            spec = [min(max(s * m["ks"], 0.0), 1.0) for s in m["specular"]]
            alpha = m["roughness"] if m["roughness"] >= 0 else math.sqrt(2.0 / (max(m["exponent"], 0.0) + 2.0))
            self.note("plastic (ks x specular %s, GGX alpha %.3g): Schlick GGX lobe exact, Ashikhmin-Shirley diffuse "
                      "coupling replaced by a Lambert lobe of the same directional albedo" % (cm.fmt3(spec), alpha),
                      approximate=True)
        elif kind == "conductor" and not exact:
            self.note("textured metallic material: its texture is left out", approximate=True)
        if isinstance(m["texture"], str):
            self.note("image texture %s: Cycles' bilinear lookup of 8-bit sRGB (caustica filters half floats)"
                      % os.path.basename(m["texture"]))
        if m["metallic"] > 0 and kind == "plastic":
            self.note("metallic %.2g" % m["metallic"], approximate=True)
        if max(m["emission"]) > 0 and m["refractive"]:
            self.note("emissive glass", approximate=True)
        return m

    def add_triangle(self, p, m, uv=None, n=None):
        if cm.length(cm.cross(cm.sub(p[1], p[0]), cm.sub(p[2], p[0]))) <= 0.0:
            return
        if m["texture"] is not None and uv is None:
            uv = [[0, 0], [1, 0], [0, 1]]
        key = (self.material_key(m), uv is not None, n is not None)
        self.groups.setdefault(key, []).append(([list(map(float, q)) for q in p],
                                                 [list(map(float, q[:2])) for q in uv] if uv else None,
                                                 [list(map(float, q)) for q in n] if n else None))

    def add_sphere(self, center, radius, m, base, emitter=None):
        sph = {"center": [float(v) for v in center], "radius": float(radius), "material": m, "mesh": 0}
        if m["refractive"] or self.sphere_mesh:
            # Cycles' point-cloud spheres refract wrongly (a ray that starts
            # inside misses the far side: the caustic below caustics.json's
            # sphere came out blurred): glass spheres are meshes.
            n = self.sphere_mesh or self.glass_segments
            sph["mesh"] = n
            self.note("%s sphere: a %d x %d UV-sphere mesh with exact radial normals (APPROXIMATE; surface "
                      "within %.1e x radius)" % ("glass" if m["refractive"] else "every", n, n // 2,
                                                 1 - math.cos(math.pi / n)), approximate=True)
        self.spheres.append(sph)

    def add_cylinder(self, s, m, base):
        c, a = [float(v) for v in s["center"]], cm.normalize([float(v) for v in s["axis"]])
        r, half = float(s["radius"]), float(s["height"])
        if m["texture"] is not None:
            self.note("textured cylinder: uv not converted", approximate=True)
        helper = [1.0, 0, 0] if abs(a[0]) < 0.9 else [0, 1.0, 0]
        t = cm.normalize(cm.cross(helper, a))
        b = cm.cross(a, t)  # (t, b, a) right-handed
        n = self.segments
        self.note("cylinder: %d-sided mesh with smooth normals and flat caps (APPROXIMATE; surface within "
                  "%.1e x radius)" % (n, 1 - math.cos(math.pi / n)), approximate=True)
        p0, p1 = cm.sub(c, cm.mul(a, half)), cm.add(c, cm.mul(a, half))
        ring = []
        for k in range(n):
            phi = 2 * math.pi * k / n
            d = cm.add(cm.mul(t, math.cos(phi)), cm.mul(b, math.sin(phi)))
            ring.append(d)
        for k in range(n):
            d0, d1 = ring[k], ring[(k + 1) % n]
            q00, q01 = cm.add(p0, cm.mul(d0, r)), cm.add(p0, cm.mul(d1, r))
            q10, q11 = cm.add(p1, cm.mul(d0, r)), cm.add(p1, cm.mul(d1, r))
            # counter-clockwise seen from outside: (q00, q01, q11), (q00, q11, q10)
            self.add_triangle([q00, q01, q11], m, None, [d0, d1, d1])
            self.add_triangle([q00, q11, q10], m, None, [d0, d1, d0])
            down, up = cm.mul(a, -1), a
            self.add_triangle([p0, q01, q00], m, None, [down] * 3)
            self.add_triangle([p1, q10, q11], m, None, [up] * 3)

    def convert(self):
        sc = self.scene
        self.add_shapes()  # compare_mitsuba.Converter's walk, through this class's add_* methods
        for i, l in enumerate(sc["scene"].get("lightsources", [])):
            t = str(l.get("type", "")).lower()
            if t == "arealight":
                u, v = cm.area_light_edges(l)
                c = l["position"]
                a = cm.sub(cm.sub(c, cm.mul(u, 0.5)), cm.mul(v, 0.5))
                b = cm.add(cm.sub(c, cm.mul(v, 0.5)), cm.mul(u, 0.5))
                cc = cm.add(cm.add(c, cm.mul(u, 0.5)), cm.mul(v, 0.5))
                d = cm.add(cm.sub(c, cm.mul(u, 0.5)), cm.mul(v, 0.5))
                m = cm.read_material({"type": "emissive", "color": l["intensity"]})
                self.add_triangle([a, b, cc], m)
                self.add_triangle([a, cc, d], m)
            elif t == "spherelight":
                self.note("sphere light: a point-cloud sphere, found by BSDF sampling only (Cycles samples "
                          "emission on meshes alone): unbiased but noisier")
                self.add_sphere(l["position"], l["radius"],
                                cm.read_material({"type": "emissive", "color": l["intensity"]}), self.dir)
            elif t == "ambient":
                self.note("ambient light ignored (as in caustica's path mode)")
            else:
                raise cm.Unsupported("light type %r" % t)
        if float(sc["camera"].get("exposure", 0)) != 0:
            self.note("camera exposure ignored (both images are linear)")
        meshes = []
        for (mkey, has_uv, has_n), tris in self.groups.items():
            meshes.append({"material": self.material_record(self.materials[mkey], self.dir),
                           "points": [t[0] for t in tris], "uvs": [t[1] for t in tris] if has_uv else None,
                           "normals": [t[2] for t in tris] if has_n else None})
        spheres = [dict(s, material=self.material_record(s["material"], self.dir)) for s in self.spheres]
        cam = self.camera_data()
        if not self.approximate:
            self.notes.insert(0, "faithful conversion")
        return {"meshes": meshes, "spheres": spheres, "camera": cam,
                "background": [float(v) for v in sc["scene"].get("backgroundcolor", [0, 0, 0])],
                "nbounces": int(sc.get("nbounces", 4)), "notes": self.notes, "approximate": self.approximate}

    def camera_data(self):
        cam, top = self.scene["camera"], self.scene
        _, aperture = cm.find_any(cam, ["aperture", "apertureSize", "diameter"])
        if aperture is None:
            aperture = top.get("aperture")
        if not top.get("use_dof", True):
            aperture = None
        pos, at = [float(v) for v in cam["position"]], [float(v) for v in cam["lookAt"]]
        _, focus = cm.find_any(cam, ["focalDistance", "focusDistance", "focusdistance", "focalLength",
                                     "focus_distance"])
        if focus is None:
            focus = top.get("focus_distance", cm.length(cm.sub(at, pos)))
        return {"position": pos, "look_at": at, "up": [float(v) for v in cam["upVector"]], "fov": float(cam["fov"]),
                "aperture": float(aperture) if aperture else 0.0, "focus": float(focus)}


def describe(scene_path, args):
    return SceneDescription(scene_path, args.cylinder_segments, args.sphere_mesh, args.glass_sphere_segments).convert()


# ---------------------------------------------------------------- the Cycles child (runs with bpy)


def cycles_child(job_path):
    """Builds the scene in Blender, renders it with Cycles, writes the films
    as .npy (top row first, NOT mirrored) and a JSON of times."""
    t_start = time.perf_counter()
    import bpy
    import numpy as np
    t_import = time.perf_counter() - t_start
    with open(job_path) as f:
        job = json.load(f)
    desc = job["scene"]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    t0 = time.perf_counter()
    build_blender_scene(bpy, scene, desc, job)
    t_build = time.perf_counter() - t0

    stats = []
    handler = lambda *a: stats.append((time.perf_counter(), str(a[0]) if a else ""))  # noqa: E731
    bpy.app.handlers.render_stats.append(handler)
    # One multilayer (multi-part) EXR: Combined (denoised when denoising is
    # on), Noisy Image (the raw film), the denoising guides, Debug Sample Count.
    scene.render.filepath = job["out"] + ".exr"
    t0 = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    t1 = time.perf_counter()
    wall = t1 - t0

    import OpenEXR
    with OpenEXR.File(job["out"] + ".exr", separate_channels=True) as f:
        ch = {}
        for part in f.parts:
            ch.update(part.channels)
        names = sorted(ch.keys())

        def layer(item):
            got = []
            for c in "RGB":
                k = [n for n in names if n == item + "." + c or n.endswith("." + item + "." + c)]
                if not k:
                    return None
                got.append(np.asarray(ch[k[0]].pixels, dtype=np.float32))
            return np.stack(got, axis=-1)

        combined = layer("Combined")
        noisy = layer("Noisy Image") if job["denoise"] else combined
        counts = None
        k = [n for n in names if "Sample Count" in n]
        if k:
            counts = np.asarray(ch[k[0]].pixels, dtype=np.float32)
    if noisy is None or combined is None:
        raise RuntimeError("films missing from %s: channels %s" % (job["out"] + ".exr", names))
    np.save(job["out"] + "_raw.npy", noisy)
    if job["denoise"]:
        np.save(job["out"] + "_denoised.npy", combined)
    # The stats say "Sample N/M" as the render goes: the largest N is the
    # samples reached; what follows its last increase is the denoising,
    # compositing and writing.
    samples, last = None, None
    for t, text in stats:
        m = re.search(r"Sample (\d+)/(\d+)", text)
        if m and (samples is None or int(m.group(1)) > samples):
            samples, last = int(m.group(1)), t
    started = next((t for t, text in stats if re.search(r"Sample \d+/", text)), None)
    info = {"wall_s": wall, "import_s": t_import, "build_s": t_build, "samples": samples,
            "sync_s": (started - t0) if started else None, "after_s": (t1 - last) if last else None,
            "channels": names,
            "stats_tail": [s for _, s in stats[-4:]], "blender": bpy.app.version_string,
            "sampling_pattern": scene.cycles.sampling_pattern}
    if counts is not None:
        info["sample_count_pass"] = {"mean": float(counts.mean()), "max": float(counts.max()),
                                     "min": float(counts.min())}
    with open(job["out"] + ".json", "w") as f:
        json.dump(info, f, indent=1)


def build_blender_scene(bpy, scene, desc, job):
    import numpy as np
    from mathutils import Matrix

    # ---- render settings
    scene.render.engine = "CYCLES"
    cy = scene.cycles
    cy.device = "CPU"
    scene.render.threads_mode = "FIXED"
    scene.render.threads = int(job["threads"])
    scene.render.resolution_x, scene.render.resolution_y = job["width"], job["height"]
    scene.render.resolution_percentage = 100
    scene.render.pixel_aspect_x = scene.render.pixel_aspect_y = 1
    scene.render.film_transparent = False
    scene.render.use_compositing = False
    scene.render.use_sequencer = False
    scene.render.use_persistent_data = False
    if job.get("seconds"):
        cy.samples = 1 << 24
        cy.time_limit = float(job["seconds"])
    else:
        cy.samples = int(job["samples"])
        cy.time_limit = 0.0
    cy.use_adaptive_sampling = bool(job["adaptive"])
    cy.seed = int(job["seed"])
    cy.use_animated_seed = False
    cy.sample_clamp_direct = 0.0
    cy.sample_clamp_indirect = 0.0
    cy.light_sampling_threshold = 0.0
    cy.use_light_tree = True  # its default since Blender 3.5, set so that the comparison says it
    cy.blur_glossy = 0.0
    cy.caustics_reflective = True
    cy.caustics_refractive = True
    bounces = max(0, desc["nbounces"] - 1)
    cy.max_bounces = bounces
    cy.diffuse_bounces = cy.glossy_bounces = cy.transmission_bounces = bounces
    cy.volume_bounces = 0
    cy.transparent_max_bounces = max(8, bounces)
    cy.min_light_bounces = 0
    cy.min_transparent_bounces = 0
    cy.pixel_filter_type = "BOX"
    cy.filter_width = 1.0
    cy.use_denoising = bool(job["denoise"])
    if job["denoise"]:
        cy.denoiser = "OPENIMAGEDENOISE"
        cy.denoising_input_passes = "RGB_ALBEDO_NORMAL"
        cy.denoising_prefilter = "ACCURATE"
        cy.denoising_use_gpu = False
    vl = scene.view_layers[0]
    vl.cycles.denoising_store_passes = bool(job["denoise"])
    vl.cycles.pass_debug_sample_count = bool(job["adaptive"])
    im = scene.render.image_settings
    im.media_type = "MULTI_LAYER_IMAGE"  # Blender 5: multilayer EXR
    im.file_format = "OPEN_EXR_MULTILAYER"
    im.color_depth = "32"
    im.exr_codec = "ZIP"
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0

    # ---- world
    world = bpy.data.worlds.new("world")
    scene.world = world
    world.use_nodes = True
    bg = world.node_tree.nodes.get("Background") or world.node_tree.nodes.new("ShaderNodeBackground")
    bg.inputs["Color"].default_value = list(desc["background"]) + [1.0]
    bg.inputs["Strength"].default_value = 1.0
    if max(desc["background"]) <= 0:
        world.cycles.sampling_method = "NONE"

    # ---- camera
    c = desc["camera"]
    cam_data = bpy.data.cameras.new("camera")
    cam_data.sensor_fit = "VERTICAL"
    cam_data.lens_unit = "FOV"
    cam_data.angle_y = math.radians(c["fov"])
    cam_data.clip_start = 1e-5
    cam_data.clip_end = 1e9
    fwd = cm.normalize(cm.sub(c["look_at"], c["position"]))
    right = cm.normalize(cm.cross(fwd, c["up"]))  # Blender: right-handed camera
    up = cm.cross(right, fwd)
    cam = bpy.data.objects.new("camera", cam_data)
    cam.matrix_world = Matrix([[right[i], up[i], -fwd[i], c["position"][i]] for i in range(3)] + [[0, 0, 0, 1]])
    if c["aperture"] > 0:
        cam_data.dof.use_dof = True
        cam_data.dof.focus_distance = c["focus"]
        cam_data.dof.aperture_blades = 0
        cam_data.dof.aperture_ratio = 1.0
        # Cycles: aperture radius = 0.5 x (lens mm x 1e-3) / f-stop
        cam_data.dof.aperture_fstop = cam_data.lens * 1e-3 / c["aperture"]
    scene.collection.objects.link(cam)
    scene.camera = cam

    materials = {}

    def material(m, center=None):
        key = json.dumps(m, sort_keys=True) + (json.dumps(center) if center is not None and m["texture"] else "")
        if key not in materials:
            materials[key] = make_material(bpy, m, center, len(materials))
        return materials[key]

    # ---- meshes
    for gi, g in enumerate(desc["meshes"]):
        pts = g["points"]
        verts = [p for tri in pts for p in tri]
        faces = [(3 * k, 3 * k + 1, 3 * k + 2) for k in range(len(pts))]
        me = bpy.data.meshes.new("mesh%d" % gi)
        me.from_pydata(verts, [], faces)
        if g["uvs"]:
            uvl = me.uv_layers.new(name="UVMap")
            flat = np.array([uv for tri in g["uvs"] for uv in tri], dtype=np.float32).ravel()
            uvl.data.foreach_set("uv", flat)  # loops are in vertex order here
        me.update()
        if g["normals"]:
            me.shade_smooth()
            me.normals_split_custom_set([tuple(n) for tri in g["normals"] for n in tri])
        ob = bpy.data.objects.new("mesh%d" % gi, me)
        ob.data.materials.append(material(g["material"]))
        scene.collection.objects.link(ob)

    # ---- mesh spheres (glass, or every sphere with --sphere-mesh): UV spheres
    for gi, s in enumerate(sp for sp in desc["spheres"] if sp["mesh"]):
        n, m = s["mesh"], s["mesh"] // 2
        th = np.pi * np.arange(1, m) / m
        ph = 2 * np.pi * np.arange(n) / n
        dirs = np.stack([np.outer(np.sin(th), np.cos(ph)), np.repeat(-np.cos(th)[:, None], n, 1),
                         np.outer(np.sin(th), np.sin(ph))], -1).reshape(-1, 3)
        dirs = np.concatenate([dirs, [[0, -1, 0], [0, 1, 0]]])
        south, north = len(dirs) - 2, len(dirs) - 1
        idx = lambda j, i: (j - 1) * n + (i % n)  # noqa: E731  ring j = 1 .. m-1
        faces = []
        for i in range(n):
            faces.append((south, idx(1, i + 1), idx(1, i)))  # outward (counter-clockwise seen from outside)
            faces.append((north, idx(m - 1, i), idx(m - 1, i + 1)))
            for j in range(1, m - 1):
                faces.append((idx(j, i), idx(j + 1, i), idx(j + 1, i + 1), idx(j, i + 1)))
        verts = np.asarray(s["center"]) + s["radius"] * dirs
        me = bpy.data.meshes.new("sphere_mesh%d" % gi)
        me.from_pydata(verts.tolist(), [], faces)
        me.update()
        me.shade_smooth()
        me.normals_split_custom_set_from_vertices(dirs.tolist())
        ob = bpy.data.objects.new("sphere_mesh%d" % gi, me)
        ob.data.materials.append(material(s["material"], s["center"]))
        scene.collection.objects.link(ob)

    # ---- spheres: point clouds through a Mesh to Points geometry node group
    if any(not sp["mesh"] for sp in desc["spheres"]):
        ng = bpy.data.node_groups.new("spheres", "GeometryNodeTree")
        ng.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
        sock = ng.interface.new_socket("Material", in_out="INPUT", socket_type="NodeSocketMaterial")
        ng.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
        n = ng.nodes
        gin, gout = n.new("NodeGroupInput"), n.new("NodeGroupOutput")
        m2p = n.new("GeometryNodeMeshToPoints")
        m2p.mode = "VERTICES"
        na = n.new("GeometryNodeInputNamedAttribute")
        na.data_type = "FLOAT"
        na.inputs["Name"].default_value = "radius"
        sm = n.new("GeometryNodeSetMaterial")
        ng.links.new(gin.outputs["Geometry"], m2p.inputs["Mesh"])
        ng.links.new(na.outputs["Attribute"], m2p.inputs["Radius"])
        ng.links.new(m2p.outputs["Points"], sm.inputs["Geometry"])
        ng.links.new(gin.outputs["Material"], sm.inputs["Material"])
        ng.links.new(sm.outputs["Geometry"], gout.inputs["Geometry"])
        groups = {}
        for s in (sp for sp in desc["spheres"] if not sp["mesh"]):
            textured = s["material"]["texture"] is not None
            key = (json.dumps(s["material"], sort_keys=True), tuple(s["center"]) if textured else None)
            groups.setdefault(key, []).append(s)
        for gi, ((_, center), ss) in enumerate(groups.items()):
            me = bpy.data.meshes.new("spheres%d" % gi)
            me.from_pydata([s["center"] for s in ss], [], [])
            attr = me.attributes.new("radius", "FLOAT", "POINT")
            attr.data.foreach_set("value", [s["radius"] for s in ss])
            ob = bpy.data.objects.new("spheres%d" % gi, me)
            mod = ob.modifiers.new("points", "NODES")
            mod.node_group = ng
            mod[sock.identifier] = material(ss[0]["material"], list(center) if center else None)
            scene.collection.objects.link(ob)

    # ---- a glTF file, through Blender's importer
    if desc.get("gltf"):
        import_gltf(bpy, desc["gltf"])


def import_gltf(bpy, path):
    """A glTF file through Blender's own importer (its materials as Blender
    maps them), placed in caustica's coordinates: the importer turns glTF's
    +Y up into Blender's +Z up, a rotation of +90 degrees about X, undone
    here, so a file that a coursework scene places as a "mesh" (in glTF's own
    coordinates) lands where caustica puts it (bench/compare_cycles_gltf.py)."""
    from mathutils import Matrix
    before = set(bpy.data.objects)
    bpy.ops.import_scene.gltf(filepath=path)
    undo = Matrix.Rotation(-math.pi / 2, 4, "X")
    for ob in [o for o in bpy.data.objects if o not in before]:
        if ob.type in ("CAMERA", "LIGHT"):  # the coursework scene's own camera and lights stand
            bpy.data.objects.remove(ob)
        elif ob.parent is None:
            ob.matrix_world = undo @ ob.matrix_world


def make_material(bpy, m, center, index):
    """A Cycles node material for a material record (kernels/lib/material.h)."""
    mat = bpy.data.materials.new("m%d" % index)
    mat.use_nodes = True
    nt = mat.node_tree
    nodes, links = nt.nodes, nt.links
    for nd in list(nodes):
        nodes.remove(nd)
    out = nodes.new("ShaderNodeOutputMaterial")

    def clamp01(c):
        return [min(max(float(v), 0.0), 1.0) for v in c]

    def rgba(c):
        return list(c) + [1.0]

    def math_node(op, a, b=None):
        nd = nodes.new("ShaderNodeMath")
        nd.operation = op
        for i, x in enumerate((a, b)):
            if x is None:
                continue
            if isinstance(x, (int, float)):
                nd.inputs[i].default_value = x
            else:
                links.new(x, nd.inputs[i])
        return nd.outputs[0]

    def uv_socket():
        """(u, v) sockets: the mesh's UVMap, or caustica's sphere mapping."""
        if center is None:
            nd = nodes.new("ShaderNodeUVMap")
            nd.uv_map = "UVMap"
            sep = nodes.new("ShaderNodeSeparateXYZ")
            links.new(nd.outputs["UV"], sep.inputs[0])
            return sep.outputs["X"], sep.outputs["Y"]
        geo = nodes.new("ShaderNodeNewGeometry")
        sub = nodes.new("ShaderNodeVectorMath")
        sub.operation = "SUBTRACT"
        links.new(geo.outputs["Position"], sub.inputs[0])
        sub.inputs[1].default_value = center
        nrm = nodes.new("ShaderNodeVectorMath")
        nrm.operation = "NORMALIZE"
        links.new(sub.outputs[0], nrm.inputs[0])
        sep = nodes.new("ShaderNodeSeparateXYZ")
        links.new(nrm.outputs[0], sep.inputs[0])
        # u = atan2(n.z, n.x) / 2pi wrapped into [0, 1), v = acos(-n.y) / pi
        u = math_node("FRACT", math_node("DIVIDE", math_node("ARCTAN2", sep.outputs["Z"], sep.outputs["X"]),
                                         2 * math.pi))
        v = math_node("DIVIDE", math_node("ARCCOSINE", math_node("MULTIPLY", sep.outputs["Y"], -1.0)), math.pi)
        return u, v

    def diffuse_colour():
        """Socket or constant: clamp(kd x (texture or diffusecolor))."""
        kd = m["kd"]
        tex = m["texture"]
        if tex is None:
            return clamp01([kd * v for v in m["diffuse"]])
        u, v = uv_socket()
        if isinstance(tex, dict):
            s = float(tex.get("scale", 10.0))
            par = math_node("FLOORED_MODULO", math_node("ADD", math_node("FLOOR", math_node("MULTIPLY", u, s)),
                                                        math_node("FLOOR", math_node("MULTIPLY", v, s))), 2.0)
            mix = nodes.new("ShaderNodeMix")
            mix.data_type = "RGBA"
            links.new(par, mix.inputs["Factor"])  # 0: even sum, colour1; 1: odd, colour2
            mix.inputs["A"].default_value = rgba(clamp01([kd * c for c in tex.get("color1", [1, 1, 1])]))
            mix.inputs["B"].default_value = rgba(clamp01([kd * c for c in tex.get("color2", [0, 0, 0])]))
            return mix.outputs["Result"]
        img = nodes.new("ShaderNodeTexImage")
        img.image = bpy.data.images.load(tex, check_existing=True)
        img.interpolation = "Linear"
        img.extension = "REPEAT"
        comb = nodes.new("ShaderNodeCombineXYZ")
        links.new(u, comb.inputs["X"])
        links.new(v, comb.inputs["Y"])
        links.new(comb.outputs[0], img.inputs["Vector"])
        scale = nodes.new("ShaderNodeMix")
        scale.data_type = "RGBA"
        scale.blend_type = "MULTIPLY"
        scale.clamp_result = True
        scale.inputs["Factor"].default_value = 1.0
        links.new(img.outputs["Color"], scale.inputs["A"])
        scale.inputs["B"].default_value = rgba([kd] * 3)
        return scale.outputs["Result"]

    def set_colour(inp, c):
        if isinstance(c, list):
            inp.default_value = rgba(c)
        else:
            links.new(c, inp)

    def metallic_node(f0, alpha):
        nd = nodes.new("ShaderNodeBsdfMetallic")
        nd.distribution = "GGX"
        nd.fresnel_type = "F82"
        set_colour(nd.inputs["Base Color"], f0)
        nd.inputs["Edge Tint"].default_value = (1.0, 1.0, 1.0, 1.0)
        nd.inputs["Roughness"].default_value = math.sqrt(max(alpha, 0.0)) if alpha >= 1e-3 else 0.0
        return nd.outputs[0]

    kind = m["kind"]
    given = m["roughness"] >= 0
    bsdf = None
    if kind == "glass":
        alpha = m["roughness"] if given else 0.0
        if m["ior"] == 1.0:
            bsdf = nodes.new("ShaderNodeBsdfTransparent").outputs[0]
        else:
            nd = nodes.new("ShaderNodeBsdfGlass")
            nd.distribution = "GGX"
            nd.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
            nd.inputs["IOR"].default_value = m["ior"]
            nd.inputs["Roughness"].default_value = math.sqrt(alpha) if alpha >= 1e-3 else 0.0
            bsdf = nd.outputs[0]
    elif kind == "conductor":
        if m["reflective"]:
            f0 = clamp01([m["reflectivity"] * s for s in m["specular"]])
            alpha = m["roughness"] if given else 0.0
        else:  # metallic 1: coloured by the diffuse colour
            f0 = clamp01([m["kd"] * v for v in m["diffuse"]])
            alpha = m["roughness"] if given else math.sqrt(2.0 / (max(m["exponent"], 0.0) + 2.0))
        bsdf = metallic_node(f0, alpha)
    else:
        alpha = m["roughness"] if given else math.sqrt(2.0 / (max(m["exponent"], 0.0) + 2.0))
        diffuse = diffuse_colour()
        spec = clamp01([s * m["ks"] for s in m["specular"]])
        metallic = min(max(m["metallic"], 0.0), 1.0)
        if metallic > 0 and isinstance(diffuse, list):
            spec = [s + (d - s) * metallic for s, d in zip(spec, diffuse)]
            diffuse = [d * (1 - metallic) for d in diffuse]
        dnode = nodes.new("ShaderNodeBsdfDiffuse")
        dnode.inputs["Roughness"].default_value = 0.0
        if kind == "lambert" or max(spec) <= 0:
            set_colour(dnode.inputs["Color"], diffuse)
            lam = dnode.outputs[0]
            is_black = isinstance(diffuse, list) and max(diffuse) <= 0
            bsdf = None if is_black else lam
        else:
            # diffuse x (1 - F0) x (1 - (1 - cos_o / 2)^5): Ashikhmin-Shirley's
            # directional albedo for the view angle (Layer Weight facing = 1 - |cos_o|)
            lw = nodes.new("ShaderNodeLayerWeight")
            lw.inputs["Blend"].default_value = 0.5
            g = math_node("SUBTRACT", 1.0, math_node("POWER", math_node("ADD", 0.5, math_node(
                "MULTIPLY", lw.outputs["Facing"], 0.5)), 5.0))
            # 1 - cos_o / 2 = 1 - (1 - facing) / 2 = 0.5 + facing / 2
            base = nodes.new("ShaderNodeMix")
            base.data_type = "RGBA"
            base.blend_type = "MULTIPLY"
            base.inputs["Factor"].default_value = 1.0
            set_colour(base.inputs["A"], diffuse)
            base.inputs["B"].default_value = rgba([1 - s for s in spec])
            scl = nodes.new("ShaderNodeVectorMath")
            scl.operation = "SCALE"
            links.new(base.outputs["Result"], scl.inputs[0])
            links.new(g, scl.inputs["Scale"])
            links.new(scl.outputs[0], dnode.inputs["Color"])
            add = nodes.new("ShaderNodeAddShader")
            links.new(dnode.outputs[0], add.inputs[0])
            links.new(metallic_node(spec, alpha), add.inputs[1])
            bsdf = add.outputs[0]

    shader = bsdf
    if max(m["emission"]) > 0:
        em = nodes.new("ShaderNodeEmission")
        em.inputs["Color"].default_value = rgba([float(v) for v in m["emission"]])
        em.inputs["Strength"].default_value = 1.0
        emission = em.outputs[0]
        if not m["twosided"]:
            geo = nodes.new("ShaderNodeNewGeometry")
            mix = nodes.new("ShaderNodeMixShader")
            links.new(geo.outputs["Backfacing"], mix.inputs["Fac"])
            links.new(emission, mix.inputs[1])  # front: emission; back: nothing
            emission = mix.outputs[0]
            mat.cycles.emission_sampling = "FRONT"
        else:
            mat.cycles.emission_sampling = "FRONT_BACK"
        if shader is None:
            shader = emission
        else:
            add = nodes.new("ShaderNodeAddShader")
            links.new(shader, add.inputs[0])
            links.new(emission, add.inputs[1])
            shader = add.outputs[0]
    else:
        mat.cycles.emission_sampling = "NONE"
    if shader is not None:
        links.new(shader, out.inputs["Surface"])
    return mat


# ---------------------------------------------------------------- images


def np_mod():
    import numpy as np
    return np


def read_image(path):
    """Linear RGB float32 (H, W, 3), top row first, from .pfm or .exr (main image)."""
    np = np_mod()
    if path.endswith(".pfm"):
        w, h, v = cm.read_pfm(path)
        return np.asarray(v, dtype=np.float32).reshape(h, w, 3)
    return read_exr_layers(path)[""]


def read_exr_layers(path):
    """{layer name ('' for the main image): (H, W, 3)} of an RGB EXR."""
    np = np_mod()
    import OpenEXR
    with OpenEXR.File(path, separate_channels=True) as f:
        ch = {}
        for part in f.parts:
            ch.update(part.channels)
        layers = {}
        for name in ch:
            base, _, c = name.rpartition(".")
            if c in ("R", "G", "B"):
                layers.setdefault(base, {})[c] = np.asarray(ch[name].pixels, dtype=np.float32)
        extra = {name: np.asarray(ch[name].pixels, dtype=np.float32) for name in ch
                 if name.rpartition(".")[2] not in ("R", "G", "B")}
    out = {k: np.stack([v["R"], v["G"], v["B"]], axis=-1) for k, v in layers.items() if len(v) == 3}
    out["_extra"] = extra
    return out


def write_pfm_np(path, img):
    np = np_mod()
    h, w, _ = img.shape
    with open(path, "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (w, h))
        f.write(np.ascontiguousarray(img[::-1], dtype="<f4").tobytes())


def rel_mse(x, ref, mask=None):
    np = np_mod()
    e = (x.astype(np.float64) - ref) ** 2 / (ref.astype(np.float64) ** 2 + 0.01)
    if mask is not None:
        e = e[mask]
    return float(e.mean())


def luminance(img):
    return 0.2126 * img[..., 0] + 0.7152 * img[..., 1] + 0.0722 * img[..., 2]


def to_srgb8(img):
    np = np_mod()
    x = np.clip(np.nan_to_num(img), 0.0, 1.0)
    x = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
    return (x * 255 + 0.5).astype(np.uint8)


def write_png(path, rgb8):
    h, w, _ = rgb8.shape
    raw = b"".join(b"\x00" + rgb8[y].tobytes() for y in range(h))

    def chunk(t, d):
        c = struct.pack(">I", len(d)) + t + d
        return c + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


# ---------------------------------------------------------------- running renderers


def run_timed(cmd, env=None, timeout=None):
    """(CompletedProcess, wall s, child CPU s)."""
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    r = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=timeout)
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    return r, wall, cpu


def caustica_env(args):
    return dict(os.environ, POCL_MAX_PTHREAD_COUNT=str(args.threads))


def wait_for_binary(path):
    for _ in range(120):
        if os.path.isfile(path) and os.access(path, os.X_OK):
            return
        log("waiting for %s (being rebuilt)" % path)
        time.sleep(30)
    sys.exit("%s does not exist" % path)


def caustica_has_denoise(args):
    wait_for_binary(args.caustica)
    r = subprocess.run([args.caustica, "render", "--help"], capture_output=True, text=True)
    return "--denoise" in (r.stdout + r.stderr)


def run_caustica(args, scene, w, h, out, extra, seconds=None, spp=None, seed=1):
    wait_for_binary(args.caustica)
    cmd = [args.caustica, "render", scene, "--mode", "path", "--width", str(w), "--height", str(h), "--seed",
           str(seed), "--exposure", "0", "-o", out, "-q"]
    if seconds is not None:
        cmd[5:5] = ["--time", "%g" % seconds]
    if spp is not None:
        cmd[5:5] = ["--spp", str(spp)]
    cmd += extra
    r, wall, cpu = run_timed(cmd, env=caustica_env(args), timeout=(seconds or 600) * 5 + 600)
    if r.returncode != 0:
        raise RuntimeError("caustica failed (%d): %s\n%s" % (r.returncode, " ".join(cmd), (r.stdout + r.stderr)[-2000:]))
    shown = "POCL_MAX_PTHREAD_COUNT=%d %s" % (args.threads, " ".join(
        os.path.basename(c) if c == out else display_path(c) for c in cmd))
    return {"command": shown, "wall_s": wall, "cpu_s": cpu, "stderr": r.stderr.strip()[-500:]}


def run_cycles(args, desc, w, h, folder, name, adaptive, denoise, seconds=None, samples=None, seed=None):
    """({wall_s, cpu_s, process_s, samples, ...}, raw, denoised or None): images mirrored into caustica's
    orientation."""
    np = np_mod()
    job = {"scene": desc, "width": w, "height": h, "threads": args.threads, "adaptive": adaptive,
           "denoise": denoise, "seconds": seconds, "samples": samples, "seed": args.seed if seed is None else seed,
           "out": os.path.join(folder, name)}
    job_path = os.path.join(folder, name + "_job.json")
    with open(job_path, "w") as f:
        json.dump(job, f)
    cmd = [VENV_PYTHON, os.path.abspath(__file__), "--cycles-child", job_path]
    r, wall, cpu = run_timed(cmd, timeout=(seconds or 3600) * 5 + 600)
    if r.returncode != 0:
        raise RuntimeError("Cycles child failed (%d): %s" % (r.returncode, (r.stdout + r.stderr)[-3000:]))
    with open(job["out"] + ".json") as f:
        info = json.load(f)
    info.update(process_s=wall, cpu_s=cpu)
    raw = np.load(job["out"] + "_raw.npy")
    den = np.load(job["out"] + "_denoised.npy") if denoise else None
    if MIRROR:
        raw = raw[:, ::-1]
        den = den[:, ::-1] if den is not None else None
    return info, np.ascontiguousarray(raw), (np.ascontiguousarray(den) if den is not None else None)


# ---------------------------------------------------------------- references


def scene_hash(path):
    h = hashlib.sha1(CONVERTER_VERSION.encode())
    with open(path, "rb") as f:
        h.update(f.read())
    return h.hexdigest()[:8]


def cache_paths(scene, w, h, spp, renderer):
    stem = os.path.splitext(os.path.basename(scene))[0]
    os.makedirs(CACHE, exist_ok=True)
    name = "%s-%s-%dx%d-%dspp-%s" % (stem, scene_hash(scene), w, h, spp, renderer)
    return os.path.join(CACHE, name + ".pfm"), os.path.join(CACHE, name + ".json")


def cached(scene, w, h, renderer):
    """The cached reference of the most spp, if any: (spp, pfm, json)."""
    if not os.path.isdir(CACHE):
        return None
    stem = os.path.splitext(os.path.basename(scene))[0]
    pat = re.compile(r"^%s-%s-%dx%d-(\d+)spp-%s\.pfm$" % (re.escape(stem), scene_hash(scene), w, h, renderer))
    best = None
    for f in os.listdir(CACHE):
        m = pat.match(f)
        if m and os.path.isfile(os.path.join(CACHE, f[:-4] + ".json")):
            if best is None or int(m.group(1)) > best[0]:
                best = (int(m.group(1)), os.path.join(CACHE, f), os.path.join(CACHE, f[:-4] + ".json"))
    return best


def finish_reference(halves, scene, w, h, spp, renderer, desc, seconds, cpu):
    np = np_mod()
    ref = (halves[0].astype(np.float64) + halves[1]) / 2
    own = float((((halves[0].astype(np.float64) - halves[1]) ** 2) / (ref ** 2 + 0.01)).mean() / 4)
    path, meta = cache_paths(scene, w, h, spp, renderer)
    write_pfm_np(path, ref.astype(np.float32))
    info = {"path": display_path(path), "renderer": desc, "spp": spp, "seconds": seconds, "cpu_s": cpu,
            "own_rel_mse": own, "width": w, "height": h, "scene": display_path(scene),
            "made": time.strftime("%Y-%m-%d %H:%M:%S")}
    with open(meta, "w") as f:
        json.dump(info, f, indent=1)
    return ref.astype(np.float32), info


def reference_spp(rate, args):
    """The multiple of 64 (>= 64) of spp that `rate` (spp per CPU second,
    measured on an equal-time row) fits into --reference-cpu CPU seconds."""
    return max(64, int(rate * args.reference_cpu) // 64 * 64)


def use_cache(scene, w, h, renderer, spp):
    """A cached reference of at least spp, else None."""
    have = cached(scene, w, h, renderer)
    if have and have[0] >= spp:
        with open(have[2]) as f:
            info = json.load(f)
        info["cached"] = True
        return read_image(have[1]), info
    return None


def caustica_reference(args, scene, w, h, folder, rate):
    """rate: spp per second of the equal-time caustica row (sizes the reference)."""
    spp = args.reference_spp or reference_spp(rate, args)
    got = use_cache(scene, w, h, "caustica", spp)
    if got:
        return got
    stem = os.path.basename(scene)
    log("%s %dx%d: caustica reference, %d spp in two halves" % (stem, w, h, spp))
    halves, t, cpu = [], 0.0, 0.0
    for k in range(2):
        out = os.path.join(folder, "ref%d.pfm" % k)
        r = run_caustica(args, scene, w, h, out, ["--no-adaptive"], spp=spp // 2, seed=99 + k)
        t += r["wall_s"]
        cpu += r["cpu_s"]
        halves.append(read_image(out))
        log("  half %d: %.1f s wall, %.1f s CPU" % (k, r["wall_s"], r["cpu_s"]))
    ref, info = finish_reference(halves, scene, w, h, spp, "caustica",
                                 "caustica, --no-adaptive, %d spp (2 x %d, seeds 99 and 100)" % (spp, spp // 2),
                                 t, cpu)
    info["cached"] = False
    return ref, info


def cycles_reference(args, scene, desc, w, h, folder, rate):
    """rate: samples per second of the equal-time Cycles row without adaptive sampling."""
    spp = args.cycles_reference_spp or reference_spp(rate, args)
    got = use_cache(scene, w, h, "cycles", spp)
    if got:
        return got
    log("%s %dx%d: Cycles reference, %d samples in two halves" % (os.path.basename(scene), w, h, spp))
    halves, t, cpu = [], 0.0, 0.0
    for k in range(2):
        info, raw, _ = run_cycles(args, desc, w, h, folder, "cref%d" % k, False, False, samples=spp // 2,
                                  seed=99 + k)
        t += info["wall_s"]
        cpu += info["cpu_s"]
        halves.append(raw)
        log("  half %d: %.1f s wall, %.1f s CPU" % (k, info["wall_s"], info["cpu_s"]))
    ref, info = finish_reference(halves, scene, w, h, spp, "cycles",
                                 "Cycles, adaptive off, no denoising, %d samples (2 x %d, seeds 99 and 100)"
                                 % (spp, spp // 2), t, cpu)
    info["cached"] = False
    return ref, info


# ---------------------------------------------------------------- caustic mask


def caustic_mask(args, scene, w, h, ref, folder):
    """(mask, info): pixels brighter than with no caster at all (see the docstring)."""
    np = np_mod()
    with open(scene) as f:
        sc = json.load(f)
    casters = []
    for s in sc["scene"]["shapes"]:
        m = cm.read_material(s.get("material", {}))
        if (m["refractive"] or m["reflective"]) and m["roughness"] < 1e-3:
            casters.append(s)
    if not casters:
        return None, {"note": "no smooth glass or mirror"}
    free = json.loads(json.dumps(sc))
    cover = json.loads(json.dumps(sc))
    for s in free["scene"]["shapes"]:
        mat = s.setdefault("material", {})
        m = cm.read_material(mat)
        if (m["refractive"] or m["reflective"]) and m["roughness"] < 1e-3:
            if m["refractive"]:
                mat.pop("ior", None)
                mat["refractiveindex"] = 1.0
            else:
                mat["reflectivity"] = 0.0
    cover["scene"]["lightsources"] = []
    cover["scene"]["backgroundcolor"] = [0, 0, 0]
    for s in cover["scene"]["shapes"]:
        m = cm.read_material(s.get("material", {}))
        caster = (m["refractive"] or m["reflective"]) and m["roughness"] < 1e-3
        s["material"] = {"type": "diffuse", "albedo": [0, 0, 0]}
        if caster:
            s["material"] = {"type": "emissive", "color": [1, 1, 1], "twosided": True}
        s.pop("texture", None)
    paths = {}
    for name, d in (("free", free), ("cover", cover)):
        p = os.path.join(os.path.dirname(os.path.abspath(scene)), ".compare_cycles_%s_%d.json" % (name, os.getpid()))
        with open(p, "w") as f:
            json.dump(d, f)
        paths[name] = p
    try:
        key = "%s-%dx%d-%s" % (os.path.splitext(os.path.basename(scene))[0], w, h, scene_hash(scene))
        free_path = os.path.join(CACHE, "mask-free-%s-%dspp.pfm" % (key, args.mask_spp))
        if not os.path.isfile(free_path):
            run_caustica(args, paths["free"], w, h, free_path, ["--no-adaptive", "--caustics", "off"],
                         spp=args.mask_spp, seed=7)
        cover_path = os.path.join(folder, "cover.pfm")
        run_caustica(args, paths["cover"], w, h, cover_path, ["--no-adaptive", "--caustics", "off"], spp=16, seed=7)
    finally:
        for p in paths.values():
            os.remove(p)
    nf = luminance(read_image(free_path))
    cov = read_image(cover_path).max(axis=-1)
    lr = luminance(ref)
    mask = (cov < 1e-3) & (lr > 1.25 * nf + 0.02)
    return mask, {"pixels": int(mask.sum()), "fraction": float(mask.mean()), "free_spp": args.mask_spp,
                  "rule": "no caster seen (coverage < 1e-3) and reference luminance > 1.25 x caster-free + 0.02"}


# ---------------------------------------------------------------- orientation check


def write_orientation_scene(folder):
    """The orientation test scene, 64x64 (a small red sphere up and on the +x
    side of a grey wall, lit by a white background), written to folder; its
    path (bench/compare_mitsuba.py --check-orientation renders it too)."""
    scene = {"nbounces": 2, "rendermode": "pathtracer",
             "camera": {"type": "pinhole", "width": 64, "height": 64, "position": [0, 0, -5], "lookAt": [0, 0, 0],
                        "upVector": [0, 1, 0], "fov": 40},
             "scene": {"backgroundcolor": [1, 1, 1], "lightsources": [], "shapes": [
                 {"type": "rectangle", "v0": [-4, -4, 2], "v1": [4, -4, 2], "v2": [4, 4, 2], "v3": [-4, 4, 2],
                  "material": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
                 {"type": "sphere", "center": [0.9, 0.6, 0], "radius": 0.25,
                  "material": {"type": "diffuse", "albedo": [0.9, 0.05, 0.05]}}]}}
    path = os.path.join(folder, "orientation.json")
    with open(path, "w") as f:
        json.dump(scene, f)
    return path


def check_orientation(args):
    np = np_mod()
    folder = tempfile.mkdtemp(prefix="caustica_cycles_orient_")
    path = write_orientation_scene(folder)
    try:
        out = os.path.join(folder, "c.pfm")
        run_caustica(args, path, 64, 64, out, ["--no-adaptive"], spp=64)
        ci = read_image(out)
        desc = describe(path, args)
        global MIRROR
        keep, MIRROR = MIRROR, False
        try:
            _, bi, _ = run_cycles(args, desc, 64, 64, folder, "b", False, False, samples=64)
        finally:
            MIRROR = keep

        def red_centroid(img):
            red = (img[..., 0] > 2.5 * img[..., 1]) & (img[..., 0] > 0.05)
            ys, xs = np.nonzero(red)
            return (float(xs.mean()), float(ys.mean()), int(red.sum())) if len(xs) else None

        c, b = red_centroid(ci), red_centroid(bi)
        res = {"caustica": c, "cycles_unmirrored": b,
               "expected": "sphere at world (+0.9, +0.6): caustica draws +x on the right (FORMAT.md), up at the top"}
        ok = c is not None and b is not None
        if ok:
            bm = (63 - b[0], b[1])
            res["cycles_mirrored"] = bm
            res["caustica_right_top"] = c[0] > 32 and c[1] < 32
            res["cycles_left_top"] = b[0] < 32 and b[1] < 32
            res["mirrored_match_px"] = math.hypot(bm[0] - c[0], bm[1] - c[1])
            res["unmirrored_match_px"] = math.hypot(b[0] - c[0], b[1] - c[1])
            ok = res["mirrored_match_px"] < 1.5 and res["unmirrored_match_px"] > 10 and res["caustica_right_top"]
            mean_c = float(ci.mean())
            mean_b = float(bi.mean())
            res["image_mean_caustica"], res["image_mean_cycles"] = mean_c, mean_b
        res["ok"] = bool(ok)
        return res
    finally:
        shutil.rmtree(folder, ignore_errors=True)


# ---------------------------------------------------------------- one scene


display_path = cm.display_path  # relative to the repository, also for ../shared/...


def parse_scene_arg(s, args):
    m = re.match(r"^(.*)@(\d+)x(\d+)$", s)
    path, w, h = (m.group(1), int(m.group(2)), int(m.group(3))) if m else (s, None, None)
    if not os.path.isabs(path) and not os.path.isfile(path):
        path = os.path.join(ROOT, path)
    if w is None:
        with open(path) as f:
            cam = json.load(f)["camera"]
        w = args.width or 256
        h = args.height or max(1, round(w * cam.get("height", w) / cam.get("width", w)))
    return path, w, h


def compare_scene(args, spec, has_denoise):
    np = np_mod()
    scene, w, h = parse_scene_arg(spec, args)
    stem = os.path.splitext(os.path.basename(scene))[0]
    res = {"scene": display_path(scene), "name": stem, "width": w, "height": h, "status": "ok", "rows": []}
    folder = tempfile.mkdtemp(prefix="caustica_cycles_")
    t_scene = time.perf_counter()
    try:
        try:
            desc = describe(scene, args)
        except (cm.Unsupported, KeyError, OSError) as e:
            res.update(status="skipped", reason="cannot convert: %s" % e)
            return res
        res["approximate"], res["notes"] = desc["approximate"], desc["notes"]
        rows, images = res["rows"], {}

        # ---- the equal-time rows (their films kept for the metrics below);
        # first a 1-spp caustica render, so that the kernels of this scene's
        # feature set are in caustica's cache (their first build counts
        # against --time)
        run_caustica(args, scene, w, h, os.path.join(folder, "warm.pfm"), ["--no-adaptive"], spp=1)
        t_rows = time.perf_counter()
        out = os.path.join(folder, "caustica_raw.exr")
        c = run_caustica(args, scene, w, h, out, [], seconds=args.seconds, seed=1)
        layers = read_exr_layers(out)
        spp = layers["_extra"].get("spp")
        rows.append({"renderer": "caustica", "mode": "adaptive (default)", "wall_s": c["wall_s"],
                     "cpu_s": c["cpu_s"], "command": c["command"],
                     "spp_mean": float(spp.mean()) if spp is not None else None,
                     "films": ("caustica raw", None)})
        images["caustica raw"] = layers[""]
        log("%s %dx%d: caustica raw: %.2f s" % (stem, w, h, c["wall_s"]))
        if has_denoise:
            out = os.path.join(folder, "caustica_dn.exr")
            c = run_caustica(args, scene, w, h, out, ["--denoise"], seconds=args.seconds, seed=1)
            layers = read_exr_layers(out)
            spp = layers["_extra"].get("spp")
            rows.append({"renderer": "caustica", "mode": "adaptive (default), --denoise", "wall_s": c["wall_s"],
                         "cpu_s": c["cpu_s"], "command": c["command"],
                         "spp_mean": float(spp.mean()) if spp is not None else None,
                         "films": ("caustica --denoise raw (beauty)" if "beauty" in layers else None,
                                   "caustica denoised")})
            if "beauty" in layers:
                images["caustica --denoise raw (beauty)"] = layers["beauty"]
            images["caustica denoised"] = layers[""]
            log("%s %dx%d: caustica --denoise: %.2f s" % (stem, w, h, c["wall_s"]))
        for adaptive in (False, True):
            info, craw, cden = run_cycles(args, desc, w, h, folder, "cy%d" % adaptive, adaptive, True,
                                          seconds=args.seconds)
            mode = "adaptive" if adaptive else "uniform"
            row = {"renderer": "Cycles %s" % info.get("blender", ""), "mode": mode,
                   "wall_s": info["wall_s"], "cpu_s": info["cpu_s"], "process_s": info["process_s"],
                   "build_s": info["build_s"], "import_s": info["import_s"], "sync_s": info.get("sync_s"),
                   "after_s": info.get("after_s"), "samples": info.get("samples"),
                   "sample_count_pass": info.get("sample_count_pass"),
                   "settings": "CPU, %d threads, time_limit %g s, samples 2^24, adaptive %s, seed %d, OIDN "
                               "(RGB_ALBEDO_NORMAL, ACCURATE) with denoising_store_passes"
                               % (args.threads, args.seconds, "on (threshold 0.01)" if adaptive else "off",
                                  args.seed),
                   "films": ("Cycles %s raw" % mode, "Cycles %s denoised" % mode)}
            if row["samples"] and row["sample_count_pass"]:
                row["spp_mean"] = row["samples"] * row["sample_count_pass"]["mean"]
            images["Cycles %s raw" % mode] = craw
            images["Cycles %s denoised" % mode] = cden
            rows.append(row)
            log("%s %dx%d: Cycles %s: %.2f s, %s samples" % (stem, w, h, mode, info["wall_s"], info.get("samples")))
        res["rows_time_s"] = time.perf_counter() - t_rows

        # ---- references, sized from the rows' rates
        t0 = time.perf_counter()
        # rates per CPU second: the machine may be shared, and the budget is CPU time
        c_rate = (rows[0]["spp_mean"] or 16) / max(rows[0]["cpu_s"], 1e-3)
        ref, rinfo = caustica_reference(args, scene, w, h, folder, c_rate)
        res["reference"] = rinfo
        res["reference_time_s"] = time.perf_counter() - t0
        own = None
        want_own = args.cycles_references == "always" or (args.cycles_references == "auto" and (
            desc["approximate"] or (stem == "cornell_box" and (w, h) == (128, 128))))
        if want_own:
            t0 = time.perf_counter()
            u = next(r for r in rows if r["mode"] == "uniform")
            cy_rate = (u["samples"] or 16) / max(u["cpu_s"] - u["import_s"] - u["build_s"], 1e-3)
            own, oinfo = cycles_reference(args, scene, desc, w, h, folder, cy_rate)
            res["cycles_reference"] = oinfo
            res["cycles_reference_time_s"] = time.perf_counter() - t0
            res["cycles_ref_vs_caustica_ref"] = rel_mse(own, ref)
            res["cycles_ref_mean_over_caustica_ref"] = float(own.mean() / ref.mean())
        mask = None
        if args.caustic_mask == "always" or (args.caustic_mask == "auto" and stem == "caustics"):
            t0 = time.perf_counter()
            mask, minfo = caustic_mask(args, scene, w, h, ref, folder)
            minfo["time_s"] = time.perf_counter() - t0
            res["caustic_mask"] = minfo

        # ---- metrics
        def measure(name):
            img = images.get(name) if name else None
            if img is None:
                return {}
            d = {"rel_mse": rel_mse(img, ref), "mean_over_ref": float(img.mean() / ref.mean())}
            if own is not None:
                d["rel_mse_own"] = rel_mse(img, own)
            if mask is not None and mask.any():
                d["rel_mse_caustic"] = rel_mse(img, ref, mask)
            return d

        for row in rows:
            raw_name, dn_name = row.pop("films")
            row["raw"], row["denoised"] = measure(raw_name), measure(dn_name)
            log("%s %dx%d: %s %s: relMSE raw %s denoised %s" % (stem, w, h, row["renderer"], row["mode"],
                                                                fmt(row["raw"].get("rel_mse")),
                                                                fmt(row["denoised"].get("rel_mse"))))
        if args.images:
            images = dict([("reference", ref)] + list(images.items()))
            res["images"] = write_images(args, res, images, folder, mask)
        return res
    finally:
        res["total_time_s"] = time.perf_counter() - t_scene
        shutil.rmtree(folder, ignore_errors=True)


def write_images(args, res, images, folder, mask):
    """Side-by-side tone-mapped strip and `caustica diff --heatmap` per image."""
    np = np_mod()
    os.makedirs(args.images, exist_ok=True)
    stem = "%s-%dx%d" % (res["name"], res["width"], res["height"])
    names = list(images)
    strip = np.concatenate([to_srgb8(images[n]) for n in names], axis=1)
    strip_path = os.path.join(args.images, stem + ".png")
    write_png(strip_path, strip)
    out = {"strip": display_path(strip_path), "panels": names, "heatmaps": {}}
    # run in the temporary folder with short names: the heatmap's title shows them
    ref_name = "%s-reference.pfm" % stem
    write_pfm_np(os.path.join(folder, ref_name), images["reference"])
    for n in names[1:]:
        slug = re.sub(r"[^a-z0-9]+", "_", n.lower()).strip("_")
        name = "%s-%s.pfm" % (stem, slug)
        write_pfm_np(os.path.join(folder, name), images[n])
        hp = os.path.abspath(os.path.join(args.images, "%s-%s-heat.png" % (stem, slug)))
        r = subprocess.run([os.path.abspath(args.caustica), "diff", name, ref_name, "--heatmap", hp], cwd=folder,
                           capture_output=True, text=True)
        if r.returncode == 0:
            out["heatmaps"][n] = display_path(hp)
    if mask is not None:
        mp = os.path.join(args.images, stem + "-caustic-mask.png")
        write_png(mp, np.repeat((mask[..., None] * 255).astype(np.uint8), 3, axis=-1))
        out["mask"] = display_path(mp)
    return out


# ---------------------------------------------------------------- Markdown


def fmt(x, f="%.3e"):
    return f % x if x is not None else "-"


def markdown(args, results, has_denoise):
    out = []
    for r in results:
        out.append("### %s (%dx%d, %g s, %d threads)" % (r["name"], r["width"], r["height"], args.seconds,
                                                         args.threads))
        out.append("")
        if r["status"] != "ok":
            out.append("Skipped: %s." % r["reason"])
            out.append("")
            continue
        out.append(("Conversion: **approximate**: " if r["approximate"] else "Conversion: ") + "; ".join(r["notes"]) + ".")
        ri = r["reference"]
        out.append("")
        out.append("Reference: `%s` (%s%s; its own relMSE ~%.1e)." % (
            ri["path"], ri["renderer"], ", %.0f s wall, %.0f s CPU" % (ri["seconds"], ri.get("cpu_s", 0))
            if ri.get("seconds") else "", ri["own_rel_mse"]))
        own = "cycles_reference" in r
        if own:
            o = r["cycles_reference"]
            out.append("Cycles' own reference: `%s` (%s; its own relMSE ~%.1e); against caustica's: relMSE %.3e, "
                       "mean ratio %.4f." % (o["path"], o["renderer"], o["own_rel_mse"], r["cycles_ref_vs_caustica_ref"],
                                             r["cycles_ref_mean_over_caustica_ref"]))
        caustic = "caustic_mask" in r and r["caustic_mask"].get("pixels")
        if caustic:
            out.append("Caustic region: %d pixels (%.1f%%): %s." % (r["caustic_mask"]["pixels"],
                                                                   100 * r["caustic_mask"]["fraction"],
                                                                   r["caustic_mask"]["rule"]))
        out.append("")
        head = "| renderer | mode | spp / samples | wall s | cpu s | relMSE raw | relMSE denoised | mean / ref |"
        rule = "|---|---|---:|---:|---:|---:|---:|---:|"
        if own:
            head += " raw, own ref | denoised, own ref |"
            rule += "---:|---:|"
        if caustic:
            head += " caustic raw | caustic denoised |"
            rule += "---:|---:|"
        out.append(head)
        out.append(rule)
        for row in r["rows"]:
            if row["renderer"] == "caustica":
                spp = "%.0f (mean)" % row["spp_mean"] if row.get("spp_mean") is not None else "-"
            else:
                spp = "%s" % row.get("samples") if row.get("samples") is not None else "-"
                if row.get("sample_count_pass"):
                    spp = "%s max, %.0f mean" % (spp, row["spp_mean"])
            wall = "%.2f" % row["wall_s"]
            if row.get("after_s") is not None:
                wall += " (%.2f + %.2f + %.2f)" % (row["sync_s"] or 0, row["wall_s"] - (row["sync_s"] or 0) - row["after_s"],
                                                   row["after_s"])
            main = row["denoised"] or row["raw"]
            cells = [row["renderer"], row["mode"], spp, wall, "%.1f" % row["cpu_s"],
                     fmt(row["raw"].get("rel_mse")), fmt(row["denoised"].get("rel_mse")),
                     "%.4f" % main["mean_over_ref"]]
            if own:
                cells += [fmt(row["raw"].get("rel_mse_own")), fmt(row["denoised"].get("rel_mse_own"))]
            if caustic:
                cells += [fmt(row["raw"].get("rel_mse_caustic")), fmt(row["denoised"].get("rel_mse_caustic"))]
            out.append("| " + " | ".join(cells) + " |")
        out.append("")
        vals = [x[k].get("rel_mse") for x in r["rows"] for k in ("raw", "denoised") if x[k].get("rel_mse")]
        if vals and ri["own_rel_mse"] > 0.2 * min(vals):
            out.append("Warning: the reference's own error is %.0f%% of the smallest relMSE measured against it; "
                       "raise --reference-spp or --reference-cpu." % (100 * ri["own_rel_mse"] / min(vals)))
            out.append("")
        out.append("Cycles' wall s is the render call (in brackets: sync and kernel loading until the first sample, "
                   "sampling, and what follows the last sample: OIDN, writing the EXR); caustica's the whole "
                   "process. cpu s: the child's user + system CPU time (threads x wall when the cores were free).")
        out.append("")
        for x in r["rows"]:
            out.append("- %s, %s: %s" % (x["renderer"], x["mode"], "`%s`" % x["command"] if x.get("command") else
                                          x.get("settings", "")))
        out.append("")

        def made(key, tkey):
            i = r.get(key)
            if not i:
                return None
            return "%s %s" % ("cached (made in %.0f s wall, %.0f s CPU)" % (i.get("seconds", 0), i.get("cpu_s", 0))
                              if i.get("cached") else "%.0f s" % r.get(tkey, 0), "")
        parts = ["caustica reference " + made("reference", "reference_time_s")]
        if own:
            parts.append("Cycles reference " + made("cycles_reference", "cycles_reference_time_s"))
        if "caustic_mask" in r:
            parts.append("caustic mask %.0f s" % r["caustic_mask"].get("time_s", 0))
        out.append("Times: the rows %.0f s; %s; the scene %.0f s in all." % (
            r.get("rows_time_s", 0), "; ".join(p.strip() for p in parts), r.get("total_time_s", 0)))
        if r.get("images"):
            out.append("Images: `%s` (panels: %s); heatmaps: %s." % (
                r["images"]["strip"], ", ".join(r["images"]["panels"]),
                ", ".join("`%s`" % v for v in r["images"]["heatmaps"].values())))
        out.append("")
    if not has_denoise:
        out.append("caustica's `--denoise` is not in this build: its denoised rows are left out.")
    out.append("Mitsuba 3: left out (not installed with bpy; no CPU denoiser); see bench/compare_mitsuba.py.")
    return "\n".join(out)


# ---------------------------------------------------------------- main


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "--cycles-child":
        cycles_child(sys.argv[2])
        return
    try:
        import numpy  # noqa: F401
        import OpenEXR  # noqa: F401
    except ImportError:
        if os.path.abspath(sys.executable) != os.path.abspath(VENV_PYTHON) and os.path.isfile(VENV_PYTHON):
            os.execv(VENV_PYTHON, [VENV_PYTHON, os.path.abspath(__file__)] + sys.argv[1:])
        sys.exit("needs numpy and OpenEXR: run with %s (see the docstring)" % display_path(VENV_PYTHON))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="*", help="SCENE.json[@WxH] (default: %s)" % " ".join(
        display_path(s) for s in DEFAULT_SCENES))
    ap.add_argument("--seconds", type=float, default=10.0, help="wall time of every render (default 10)")
    ap.add_argument("--threads", type=int, default=2, help="threads of both renderers (default 2)")
    ap.add_argument("--width", type=int, help="width of scenes given without @WxH (default 256)")
    ap.add_argument("--height", type=int, help="height of scenes given without @WxH (default: the camera's aspect)")
    ap.add_argument("--seed", type=int, default=1, help="Cycles' seed (caustica's is 1)")
    ap.add_argument("--reference-spp", type=int, help="spp of caustica's reference (default: fit --reference-cpu)")
    ap.add_argument("--reference-cpu", type=float, default=360.0,
                    help="CPU seconds for a new caustica reference when --reference-spp is not given (default 360)")
    ap.add_argument("--cycles-reference-spp", type=int,
                    help="samples of Cycles' own references (default: fit --reference-cpu)")
    ap.add_argument("--cycles-references", choices=["auto", "always", "never"], default="auto",
                    help="Cycles' own reference (auto: Cornell box 128^2 and approximate conversions)")
    ap.add_argument("--caustic-mask", choices=["auto", "always", "never"], default="auto",
                    help="relMSE over the caustic region (auto: caustics.json)")
    ap.add_argument("--mask-spp", type=int, default=1024, help="spp of the caster-free render for the mask")
    ap.add_argument("--cylinder-segments", type=int, default=512, help="sides of a cylinder's mesh (default 512)")
    ap.add_argument("--glass-sphere-segments", type=int, default=256,
                    help="segments of a glass sphere's UV mesh (default 256, x 128 rings)")
    ap.add_argument("--sphere-mesh", type=int, default=0,
                    help="N: every sphere a UV mesh of N segments, not a Cycles point-cloud sphere")
    ap.add_argument("--images", help="write tone-mapped strips and heatmaps here")
    ap.add_argument("--json", help="write every number to this file")
    ap.add_argument("--check-orientation", action="store_true", help="only run the orientation check")
    ap.add_argument("--caustica", default=os.path.join(ROOT, "build", "caustica"))
    args = ap.parse_args()
    try:
        os.nice(max(0, 19 - os.nice(0)))  # every render at the lowest priority
    except OSError:
        pass
    if args.check_orientation:
        res = check_orientation(args)
        print(json.dumps(res, indent=1))
        sys.exit(0 if res["ok"] else 1)
    has_denoise = caustica_has_denoise(args)
    log("caustica --denoise: %s" % ("available" if has_denoise else "not in this build (denoised rows left out)"))
    results = []
    for spec in args.scenes or DEFAULT_SCENES:
        results.append(compare_scene(args, spec, has_denoise))
    text = markdown(args, results, has_denoise)
    print(text)
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"settings": vars(args), "caustica_denoise": has_denoise, "scenes": results,
                       "markdown": text}, f, indent=1)


if __name__ == "__main__":
    main()
