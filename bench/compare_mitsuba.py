#!/usr/bin/env python3
"""Equal-time comparison of caustica's path tracer with Mitsuba 3 (optional;
not part of the tests or CI).

Converts a caustica scene of triangles with diffuse or emissive materials
(scenes/cornell_box.json) into a Mitsuba scene, renders it with both for the
same wall time on the same number of threads, and prints each image's relMSE
against a reference render (rel MSE = mean over pixels and channels of
(x - ref)^2 / (ref^2 + 0.01)).

    pip install mitsuba
    build/caustica render scenes/cornell_box.json --spp 2048 --seed 7 -o ref.pfm
    bench/compare_mitsuba.py scenes/cornell_box.json --reference ref.pfm --seconds 10

Mitsuba's variant: llvm_ad_rgb when DRJIT_LIBLLVM_PATH names a libLLVM it
runs on (Debian 12's own 14/15 abort inside LLVM), else scalar_rgb; --variant
overrides; the table says which. Mitsuba's look_at puts up x forward on the image's left,
caustica's on the right, so Mitsuba's image is mirrored before comparing.
Conventions mapped: caustica's nbounces (scattering events) is Mitsuba's
max_depth - 1; an emissive triangle is a one-sided area emitter on its
counter-clockwise side in both; diffuse surfaces reflect on both sides in
caustica, so Mitsuba's are wrapped in "twosided".
"""
import argparse
import json
import os
import struct
import subprocess
import sys
import tempfile
import time


def read_pfm(path):
    with open(path, "rb") as f:
        data = f.read()
    header, dims, scale, rest = data.split(b"\n", 3)
    w, h = map(int, dims.split())
    little = float(scale) < 0
    values = struct.unpack(("<" if little else ">") + "%df" % (w * h * 3), rest[: w * h * 12])
    rows = [values[y * w * 3 : (y + 1) * w * 3] for y in range(h)]
    rows.reverse()  # PFM stores the bottom row first
    return w, h, [v for row in rows for v in row]


def rel_mse(image, reference):
    return sum((a - b) ** 2 / (b * b + 0.01) for a, b in zip(image, reference)) / len(reference)


def pick_variant(mi, requested):
    # llvm_ad_rgb aborts the process inside LLVM on Debian 12's libLLVM 14/15
    # (not an exception one could catch), so it is used only when asked for
    # or when DRJIT_LIBLLVM_PATH points at a newer libLLVM.
    variant = requested or ("llvm_ad_rgb" if os.environ.get("DRJIT_LIBLLVM_PATH") else "scalar_rgb")
    mi.set_variant(variant)
    return variant


def to_mitsuba(scene, mi, width, height, spp, folder, sampler):
    cam = scene["camera"]
    groups = {}
    for shape in scene["scene"]["shapes"]:
        if shape["type"] != "triangle":
            sys.exit("compare_mitsuba.py converts triangle scenes only")
        m = shape.get("material", {})
        key = json.dumps(m, sort_keys=True)
        groups.setdefault(key, []).append((shape["v0"], shape["v1"], shape["v2"]))
    d = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": int(scene.get("nbounces", 4)) + 1},
        "sensor": {
            "type": "perspective",
            "fov_axis": "y",
            "fov": float(cam["fov"]),
            "to_world": mi.ScalarTransform4f().look_at(
                origin=cam["position"], target=cam["lookAt"], up=cam["upVector"]
            ),
            "film": {"type": "hdrfilm", "width": width, "height": height, "rfilter": {"type": "box"}},
            "sampler": {"type": sampler, "sample_count": spp},
        },
    }
    for i, (key, tris) in enumerate(groups.items()):
        m = json.loads(key)
        path = os.path.join(folder, "group%d.obj" % i)
        with open(path, "w") as f:
            for t in tris:
                for v in t:
                    f.write("v %g %g %g\n" % tuple(v))
            for k in range(len(tris)):
                f.write("f %d %d %d\n" % (3 * k + 1, 3 * k + 2, 3 * k + 3))
        shape = {"type": "obj", "filename": path, "face_normals": True}
        albedo = m.get("albedo", m.get("diffusecolor", [0.8, 0.8, 0.8]))
        if "emission" in m:
            shape["emitter"] = {"type": "area", "radiance": {"type": "rgb", "value": m["emission"]}}
            shape["bsdf"] = {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0, 0, 0]}}
        else:
            # caustica's opaque surfaces reflect on both sides; Mitsuba's only on the front.
            shape["bsdf"] = {"type": "twosided",
                             "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": albedo}}}
        d["shape%d" % i] = shape
    return d


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene")
    ap.add_argument("--reference", required=True, help="a long render of the scene (.pfm)")
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--variant", default="", help="Mitsuba variant (default: see above)")
    ap.add_argument("--mitsuba-sampler", default="multijitter",
                    help="Mitsuba's sampler: multijitter (default; stratified for any count), independent, ...")
    ap.add_argument("--caustica", default=os.path.join(os.path.dirname(__file__), "..", "build", "caustica"))
    args = ap.parse_args()

    import drjit as dr
    import mitsuba as mi

    variant = pick_variant(mi, args.variant)
    dr.set_thread_count(args.threads)
    with open(args.scene) as f:
        scene = json.load(f)
    w, h, reference = read_pfm(args.reference)
    folder = tempfile.mkdtemp(prefix="caustica_mitsuba_")

    # Mitsuba: its rate from a short render, then the spp that fills the time.
    probe_spp = 4
    m_scene = mi.load_dict(to_mitsuba(scene, mi, w, h, probe_spp, folder, args.mitsuba_sampler))
    t0 = time.time()
    mi.render(m_scene, spp=probe_spp)
    rate = probe_spp / (time.time() - t0)
    spp = max(1, int(rate * args.seconds))
    m_scene = mi.load_dict(to_mitsuba(scene, mi, w, h, spp, folder, args.mitsuba_sampler))
    t0 = time.time()
    image = mi.render(m_scene, spp=spp)
    m_seconds = time.time() - t0
    m_path = os.path.join(folder, "mitsuba.pfm")
    mi.Bitmap(image).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32).write(m_path)
    _, _, flat = read_pfm(m_path)
    # Mirror each row: Mitsuba's look_at is left-handed with respect to ours.
    m_values = []
    for y in range(h):
        row = flat[y * w * 3 : (y + 1) * w * 3]
        for x in reversed(range(w)):
            m_values.extend(row[3 * x : 3 * x + 3])

    # caustica: the same time limit and threads.
    out = os.path.join(folder, "caustica.pfm")
    env = dict(os.environ, POCL_MAX_PTHREAD_COUNT=str(args.threads))
    t0 = time.time()
    subprocess.run([args.caustica, "render", args.scene, "--time", str(args.seconds), "--width", str(w), "-q",
                    "-o", out, "--seed", "1"], check=True, env=env)
    c_seconds = time.time() - t0
    _, _, c_values = read_pfm(out)

    m_err, c_err = rel_mse(m_values, reference), rel_mse(c_values, reference)
    # Unbiased Monte Carlo: relMSE x time is constant, so the products
    # compare the two at exactly equal time even where the runs' times
    # differ a little (caustica's includes its process start and scene load).
    print("| renderer | wall s | spp | relMSE vs reference | relMSE x s |")
    print("|---|---:|---:|---:|---:|")
    print("| Mitsuba %s (%s, %s, %d threads) | %.2f | %d | %.3e | %.3e |" % (
        mi.__version__, variant, args.mitsuba_sampler, args.threads, m_seconds, spp, m_err, m_err * m_seconds))
    print("| caustica (PoCL, %d threads, --time %g) | %.2f | - | %.3e | %.3e |" % (
        args.threads, args.seconds, c_seconds, c_err, c_err * c_seconds))
    print("caustica / Mitsuba relMSE at equal time: %.2f" % ((c_err * c_seconds) / (m_err * m_seconds)))


if __name__ == "__main__":
    main()
