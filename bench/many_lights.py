#!/usr/bin/env python3
"""Many lights (issue 42, docs/many_lights.md): the light tree against the
power CDF (and uniform picking, what Mitsuba 3 does by default) at equal
time, on generated scenes, through the Python module.

    PYTHONPATH=build/python /usr/bin/python3 bench/many_lights.py --seconds 10 --reference-seconds 120 --out /tmp/ml

Scenes (built here as dicts, written to --out as JSON for the CLI):
  lights_1000      a room lit by 1,000 small rectangle lights on its ceiling and walls
  triangles_10000  the same room with a wall of 10,000 emissive triangles (screens)
  street_1000, street_16  a street between facades with that many lamps (sphere lights) along it
  lights_1, lights_4, lights_16, lights_64   the room with that many ceiling lights (the threshold)
For each: a reference rendered with the tree for --reference-seconds, then
each sampler for --seconds with another seed; relMSE against the reference,
samples per pixel reached, and the tree's build time (-v). Prints a
Markdown table; writes the images as PNG.
"""
import argparse
import json
import pathlib
import random
import subprocess
import sys
import time

import numpy as np

import caustica

ROOT = pathlib.Path(__file__).resolve().parents[1]


def room(width, height):
    walls = [
        {"type": "rectangle", "corner1": [-5, 0, -5], "corner2": [5, 0, 5], "material": {"diffusecolor": [0.6, 0.6, 0.6]}},
        {"type": "rectangle", "v0": [-5, 0, 5], "v1": [5, 0, 5], "v2": [5, 4, 5], "v3": [-5, 4, 5],
         "material": {"diffusecolor": [0.5, 0.5, 0.55]}},
        {"type": "rectangle", "v0": [-5, 0, -5], "v1": [-5, 0, 5], "v2": [-5, 4, 5], "v3": [-5, 4, -5],
         "material": {"diffusecolor": [0.6, 0.3, 0.25]}},
        {"type": "rectangle", "v0": [5, 0, 5], "v1": [5, 0, -5], "v2": [5, 4, -5], "v3": [5, 4, 5],
         "material": {"diffusecolor": [0.25, 0.5, 0.3]}},
        {"type": "rectangle", "v0": [-5, 4, -5], "v1": [-5, 4, 5], "v2": [5, 4, 5], "v3": [5, 4, -5],
         "material": {"diffusecolor": [0.7, 0.7, 0.7]}},
        {"type": "sphere", "center": [-1.5, 0.8, 1], "radius": 0.8, "material": {"diffusecolor": [0.8, 0.8, 0.8]}},
        {"type": "sphere", "center": [1.5, 0.6, 0], "radius": 0.6,
         "material": {"diffusecolor": [0.3, 0.4, 0.8], "specularcolor": [0.5, 0.5, 0.5], "roughness": 0.2}},
    ]
    return {
        "nbounces": 4, "rendermode": "path",
        "camera": {"type": "pinhole", "width": width, "height": height, "position": [0, 2, -4.8],
                   "lookAt": [0, 1.6, 0], "upVector": [0, 1, 0], "fov": 65},
        "scene": {"backgroundcolor": [0, 0, 0], "lightsources": [], "shapes": walls},
    }


def ceiling_lights(count, rng, total_power=120.0):
    lights = []
    for _ in range(count):
        colour = [rng.uniform(0.3, 1.0) for _ in range(3)]
        scale = rng.uniform(0.2, 1.0) * total_power / count / 0.01  # radiance of a 0.1 x 0.1 light
        lights.append({"type": "arealight", "position": [rng.uniform(-4.8, 4.8), 3.99, rng.uniform(-4.8, 4.8)],
                       "intensity": [scale * c / 3.14159 for c in colour], "size": [0.1, 0.1],
                       "u": [1, 0, 0], "v": [0, 0, 1]})
    return lights


def wall_lights(count, rng, total_power=60.0):
    lights = []
    for _ in range(count):
        colour = [rng.uniform(0.3, 1.0) for _ in range(3)]
        scale = rng.uniform(0.2, 1.0) * total_power / count / 0.01
        # On the side walls, facing into the room.
        side = rng.choice([-1, 1])
        lights.append({"type": "arealight", "position": [side * 4.99, rng.uniform(0.5, 3.5), rng.uniform(-4.5, 4.5)],
                       "intensity": [scale * c / 3.14159 for c in colour], "size": [0.1, 0.1],
                       "u": [0, 1, 0], "v": [0, 0, side]})
    return lights


def screen_wall(count, rng):
    """`count` emissive triangles (count / 2 quads) on the back wall, as screens."""
    quads = count // 2
    cols = int(np.ceil(np.sqrt(quads * 2.5)))
    rows = int(np.ceil(quads / cols))
    vertices, indices, shapes = [], [], []
    w, h = 9.0 / cols, 3.0 / rows
    for q in range(quads):
        x0 = -4.5 + (q % cols) * w
        y0 = 0.5 + (q // cols) * h
        e = [rng.uniform(0.0, 1.0) ** 3 * 6.0 for _ in range(3)]
        base = len(vertices)
        vertices += [[x0, y0, 4.99], [x0, y0 + 0.9 * h, 4.99], [x0 + 0.9 * w, y0 + 0.9 * h, 4.99], [x0 + 0.9 * w, y0, 4.99]]
        shapes.append({"type": "mesh", "vertices": vertices[base:base + 4], "indices": [[0, 1, 2], [0, 2, 3]],
                       "material": {"emission": e, "kd": 0}})
    return shapes


def street(width, height, lamps, rng):
    """A street 2 m per lamp long between two facades, lamps on both sides:
    each point is lit by the lamps near it (where a tree pays)."""
    length = lamps * 1.0
    shapes = [
        {"type": "rectangle", "corner1": [-6, 0, -2], "corner2": [6, 0, length], "material": {"diffusecolor": [0.4, 0.4, 0.4]}},
        {"type": "rectangle", "v0": [-6, 0, -2], "v1": [-6, 0, length], "v2": [-6, 12, length], "v3": [-6, 12, -2],
         "material": {"diffusecolor": [0.6, 0.5, 0.4]}},
        {"type": "rectangle", "v0": [6, 0, length], "v1": [6, 0, -2], "v2": [6, 12, -2], "v3": [6, 12, length],
         "material": {"diffusecolor": [0.5, 0.5, 0.6]}},
    ]
    lights = []
    for i in range(lamps):
        side = -4.5 if i % 2 == 0 else 4.5
        warm = rng.uniform(0.7, 1.0)
        lights.append({"type": "spherelight", "position": [side, 4.0, (i // 2) * 2.0 + rng.uniform(-0.3, 0.3)],
                       "radius": 0.08, "intensity": [120 * warm, 100 * warm, 70 * warm]})
    return {
        "nbounces": 4, "rendermode": "path",
        "camera": {"type": "pinhole", "width": width, "height": height, "position": [0, 1.7, -1.5],
                   "lookAt": [0, 1.5, 10], "upVector": [0, 1, 0], "fov": 60},
        "scene": {"backgroundcolor": [0, 0, 0], "lightsources": lights, "shapes": shapes},
    }


def scenes(width, height):
    rng = random.Random(42)
    out = {}
    d = room(width, height)
    d["scene"]["lightsources"] = ceiling_lights(700, rng) + wall_lights(300, rng)
    out["lights_1000"] = d
    d = room(width, height)
    d["scene"]["lightsources"] = ceiling_lights(4, rng, total_power=20.0)
    d["scene"]["shapes"] = d["scene"]["shapes"] + screen_wall(10000, rng)
    out["triangles_10000"] = d
    out["street_1000"] = street(width, height, 1000, rng)
    out["street_16"] = street(width, height, 16, rng)
    for n in (1, 4, 16, 64):
        d = room(width, height)
        d["scene"]["lightsources"] = ceiling_lights(n, rng)
        out[f"lights_{n}"] = d
    return out


def measure(name, d, args):
    scene = caustica.load_dict(d, name=name)
    counts = scene.counts
    reference = caustica.render(scene, light_sampler="tree", time=args.reference_seconds, seed=1000, quiet=True)
    rows = []
    for sampler in ("tree", "power", "uniform"):
        errors, spps = [], []
        for seed in range(args.seeds):
            r = caustica.render(scene, light_sampler=sampler, time=args.seconds, seed=seed, quiet=True)
            errors.append(caustica.diff(r, reference))
            spps.append(r.spp)
            if seed == 0:
                r.save(args.out / f"{name}_{sampler}.png")
        rows.append((sampler, float(np.mean(errors)), float(np.mean(spps))))
    reference.save(args.out / f"{name}_reference.png")
    json_path = args.out / f"{name}.json"
    json_path.write_text(json.dumps(d, default=lambda a: a.tolist()))
    # The tree's build time, from the CLI's -v.
    build = subprocess.run([str(ROOT / "build" / "caustica"), "render", str(json_path), "--spp", "1", "-v",
                            "--light-sampler", "tree", "-o", str(args.out / "v.pfm")], capture_output=True, text=True)
    return counts, reference.spp, rows, build.stderr


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--reference-seconds", type=float, default=120.0)
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--width", type=int, default=160)
    ap.add_argument("--height", type=int, default=120)
    ap.add_argument("--only", default="", help="comma-separated scene names")
    ap.add_argument("--out", type=pathlib.Path, default=pathlib.Path("/tmp/many_lights"))
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    print(f"# {time.strftime('%Y-%m-%d')}, {args.width}x{args.height}, {args.seconds} s a render "
          f"(mean of {args.seeds} seeds), references {args.reference_seconds} s with the tree")
    print("| scene | sampler | spp | relMSE | vs power |")
    print("|---|---|---|---|---|")
    for name, d in scenes(args.width, args.height).items():
        if args.only and name not in args.only.split(","):
            continue
        counts, ref_spp, rows, verbose = measure(name, d, args)
        power = dict((s, e) for s, e, _ in rows)["power"]
        for sampler, error, spp in rows:
            print(f"| {name} | {sampler} | {spp:.0f} | {error:.3g} | {error / power:.2f}x |", flush=True)
        tree_line = [l for l in verbose.splitlines() if "light tree" in l or "light sampler" in l]
        sys.stderr.write(f"{name}: {counts}, reference {ref_spp} spp; {' / '.join(tree_line)}\n")


if __name__ == "__main__":
    main()
