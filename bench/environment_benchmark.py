#!/usr/bin/env python3
"""Equal-time error of environment-map importance sampling (issue 24).

A Lambertian floor (albedo 0.5) under a 64 x 32 map: radiance 1 everywhere
but one "sun" texel of 1e5 (the map of tests/test_environment.cpp's
ImportanceSamplingBeatsBsdfSamplingOnASun). Every floor point's radiance is
then known in closed form, 0.5 / pi x (pi x 1 + the sun texel's cosine-
weighted solid angle x (1e5 - 1)), so the error needs no reference render.
The same scene is rendered for the same wall time with the map importance
sampled (the default) and sampled uniformly over the sphere
("importance": false), both combined with BSDF sampling by MIS, over a few
seeds; the script prints each relMSE and their ratio.

    bench/environment_benchmark.py [--caustica build/caustica] [--time 2] [--seeds 3]

Timings depend on the machine: the numbers in docs/environment.md say
which they came from.
"""
import argparse
import math
import os
import re
import struct
import subprocess
import tempfile

W, H, SUN_X, SUN_Y, SUN, SKY = 64, 32, 20, 9, 1e5, 1.0


def write_pfm(path, width, height, rgb):
    with open(path, "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (width, height))
        for y in range(height - 1, -1, -1):  # bottom row first
            f.write(struct.pack("<%df" % (3 * width), *rgb[3 * width * y: 3 * width * (y + 1)]))


def read_pfm(path):
    with open(path, "rb") as f:
        data = f.read()
    parts = data.split(b"\n", 3)
    width, height = map(int, parts[1].split())
    values = struct.unpack("<%df" % (3 * width * height), parts[3][: 12 * width * height])
    return values


def texel_irradiance(x, y, radiance):
    t0, t1 = math.pi * y / H, math.pi * (y + 1) / H
    return radiance * (2 * math.pi / W) * 0.5 * (math.sin(t1) ** 2 - math.sin(t0) ** 2)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--caustica", default="build/caustica")
    ap.add_argument("--time", type=float, default=2.0, help="seconds per render")
    ap.add_argument("--seeds", type=int, default=3)
    a = ap.parse_args()
    folder = tempfile.mkdtemp(prefix="caustica_env_bench_")
    rgb = [SKY] * (3 * W * H)
    for c in range(3):
        rgb[3 * (SUN_Y * W + SUN_X) + c] = SUN
    map_path = os.path.join(folder, "sun.pfm")
    write_pfm(map_path, W, H, rgb)
    expected = 0.5 / math.pi * (math.pi * SKY + texel_irradiance(SUN_X, SUN_Y, SUN - SKY))
    results = {}
    for importance in ("true", "false"):
        scene = os.path.join(folder, "floor_%s.json" % importance)
        with open(scene, "w") as f:
            f.write("""{"nbounces": 1, "rendermode": "pathtracer",
 "camera": {"type": "pinhole", "width": 64, "height": 64, "position": [0, 6, 0], "lookAt": [0, 0, 0],
            "upVector": [0, 0, 1], "fov": 60},
 "scene": {"environment": {"file": "%s", "importance": %s},
  "shapes": [{"type": "rectangle", "v0": [-50, 0, -50], "v1": [-50, 0, 50], "v2": [50, 0, 50], "v3": [50, 0, -50],
              "material": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}}]}}""" % (map_path, importance))
        errors, spps = [], []
        # One sample first, so that the timed renders find the kernels built and cached.
        subprocess.run([a.caustica, "render", scene, "--spp", "1", "-o", os.path.join(folder, "warm.pfm")],
                       capture_output=True, check=True)
        for seed in range(a.seeds):
            out = os.path.join(folder, "out.pfm")
            run = subprocess.run([a.caustica, "render", scene, "--spp", "1000000", "--time", str(a.time),
                                  "--seed", str(seed), "-o", out], capture_output=True, text=True, check=True)
            values = read_pfm(out)
            errors.append(sum((v - expected) ** 2 for v in values) / (expected ** 2 * len(values)))
            found = re.search(r"wrote .*\(\d+x\d+, ([\d.]+) spp\)", run.stdout + run.stderr)
            spps.append((found.group(1) if found else "?") + " spp")
        results[importance] = sum(errors) / len(errors)
        print("importance %-5s: relMSE %.4g over %d seeds at %.1f s each (%s)" %
              (importance, results[importance], a.seeds, a.time, ", ".join(spps)))
    print("uniform / importance sampling at equal time: %.0fx" % (results["false"] / results["true"]))


if __name__ == "__main__":
    main()
