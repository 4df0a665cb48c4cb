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
  gltf_interior_10000  a glTF 2.0 room lit only by a wall of 10,000 emissive triangles (64 materials)
  sponza_256, sponza_4  the converted Sponza (glTF) lit by that many coloured sphere lights
                   (each with a twin, sponza_N_obj, over the OBJ it came from: for the peers' converters)
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


def gltf_interior(width, height, triangles, rng):
    """The room as a glTF 2.0 file: walls, two boxes, and a wall of
    `triangles` emissive triangles (screens: quads of 64 emissive
    materials), lit by those alone; written with tools/make_gltf_example.py's
    Builder."""
    sys.path.insert(0, str(ROOT / "tools"))
    from make_gltf_example import Builder, cube, quat
    b = Builder()
    grey = b.material({"name": "wall", "pbrMetallicRoughness": {"baseColorFactor": [0.6, 0.6, 0.6, 1],
                                                                 "metallicFactor": 0.0, "roughnessFactor": 1.0}})
    red = b.material({"name": "red wall", "pbrMetallicRoughness": {"baseColorFactor": [0.6, 0.3, 0.25, 1],
                                                                   "metallicFactor": 0.0, "roughnessFactor": 1.0}})
    metal = b.material({"name": "metal", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.8, 0.6, 1],
                                                                  "metallicFactor": 1.0, "roughnessFactor": 0.3}})
    quads = {
        grey: [[[-5, 0, -5], [-5, 0, 5], [5, 0, 5], [5, 0, -5]],     # floor (up)
               [[-5, 4, -5], [5, 4, -5], [5, 4, 5], [-5, 4, 5]],     # ceiling (down)
               [[-5, 0, 5], [-5, 4, 5], [5, 4, 5], [5, 0, 5]],       # back wall (toward -z)
               [[5, 0, 5], [5, 4, 5], [5, 4, -5], [5, 0, -5]]],      # right wall
        red: [[[-5, 0, -5], [-5, 4, -5], [-5, 4, 5], [-5, 0, 5]]],   # left wall
    }
    roots = []
    for material, qs in quads.items():
        pos = [v for q in qs for v in q]
        idx = [k for i in range(len(qs)) for k in (4 * i, 4 * i + 1, 4 * i + 2, 4 * i, 4 * i + 2, 4 * i + 3)]
        roots.append(b.node({"mesh": b.mesh(pos, None, None, idx, material)}))
    cp, cn, cu, ci = cube()
    roots.append(b.node({"mesh": b.mesh(cp, cn, cu, ci, metal), "translation": [-1.5, 0.8, 1.0],
                         "rotation": quat((0, 1, 0), 25), "scale": [0.8, 0.8, 0.8]}))
    roots.append(b.node({"mesh": b.mesh(cp, cn, cu, ci, grey), "translation": [1.6, 0.5, -0.5],
                         "rotation": quat((0, 1, 0), -15), "scale": [0.5, 0.5, 0.5]}))
    # The screens: `triangles` / 2 quads on the back wall, facing into the
    # room (one-sided, as glTF's emission is), each of one of 64 emissive
    # materials (a spread of brightness and colour).
    screens = [b.material({"name": "screen %d" % k, "emissiveFactor": [rng.uniform(0.0, 1.0) ** 3 for _ in range(3)],
                           "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0.0},
                           "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 20.0}}})
               for k in range(64)]
    n_quads = triangles // 2
    cols = int(np.ceil(np.sqrt(n_quads * 2.5)))
    rows = int(np.ceil(n_quads / cols))
    w, h = 9.0 / cols, 3.0 / rows
    by_material = {}
    for q in range(n_quads):
        x0, y0 = -4.5 + (q % cols) * w, 0.5 + (q // cols) * h
        by_material.setdefault(rng.randrange(64), []).append(
            [[x0, y0, 4.99], [x0, y0 + 0.9 * h, 4.99], [x0 + 0.9 * w, y0 + 0.9 * h, 4.99], [x0 + 0.9 * w, y0, 4.99]])
    for k, qs in sorted(by_material.items()):
        pos = [v for q in qs for v in q]
        idx = [i for j in range(len(qs)) for i in (4 * j, 4 * j + 1, 4 * j + 2, 4 * j, 4 * j + 2, 4 * j + 3)]
        roots.append(b.node({"mesh": b.mesh(pos, None, None, idx, screens[k], index_type=5125)}))
    b.doc["extensionsUsed"] = ["KHR_materials_emissive_strength"]
    b.doc["cameras"] = [{"type": "perspective",
                         "perspective": {"yfov": 1.13, "aspectRatio": width / height, "znear": 0.05}}]
    # glTF cameras look down their -z: this one turned about y to face the screens.
    roots.append(b.node({"camera": 0, "matrix": [-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, -1, 0, 0, 2.0, -4.8, 1]}))
    return b.gltf(roots)


def sponza(width, height, lights, rng, mesh):
    """The converted Sponza (../shared/models/gltf/converted/sponza; `mesh`
    names it or the OBJ it was converted from, for the peers' converters)
    lit by `lights` coloured sphere lights through the nave and arcades."""
    sources = []
    for _ in range(lights):
        hue = rng.random()
        colour = [max(0.0, min(1.0, abs(hue * 6 - 3) - 1)), max(0.0, min(1.0, 2 - abs(hue * 6 - 2))),
                  max(0.0, min(1.0, 2 - abs(hue * 6 - 4)))]
        colour = [0.15 + 0.85 * c for c in colour]
        position = [rng.uniform(-13.0, 13.0), rng.uniform(0.3, 10.0), rng.uniform(-3.6, 3.6)]
        sources.append({"type": "spherelight", "position": position, "radius": 0.05,
                        "intensity": [40.0 * c for c in colour]})
    return {
        "nbounces": 4, "rendermode": "path",
        "camera": {"type": "pinhole", "width": width, "height": height, "position": [-12.0, 1.8, 0.3],
                   "lookAt": [4.0, 4.5, 0.0], "upVector": [0, 1, 0], "fov": 70},
        "scene": {"backgroundcolor": [0, 0, 0], "lightsources": sources,
                  "shapes": [{"type": "mesh", "file": str(mesh)}]},
    }


SHARED = ROOT.parent / "shared" / "models"


def scenes(width, height, out_dir):
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
    interior = out_dir / "gltf_interior_10000.gltf"
    interior.write_bytes(gltf_interior(width, height, 10000, rng))
    out["gltf_interior_10000"] = interior
    if (SHARED / "gltf" / "converted" / "sponza" / "sponza.gltf").exists():
        for n in (256, 4):
            state = rng.getstate()
            out[f"sponza_{n}"] = sponza(width, height, n, rng, SHARED / "gltf" / "converted" / "sponza" / "sponza.gltf")
            rng.setstate(state)  # the peers' twin: the same lights over the OBJ the glTF was converted from
            out[f"sponza_{n}_obj"] = sponza(width, height, n, rng, SHARED / "sponza-dabrovic" / "sponza.obj")
    return out


def measure(name, d, args):
    scene = caustica.load(d) if isinstance(d, pathlib.Path) else caustica.load_dict(d, name=name)
    counts = scene.counts
    # The size given (a glTF file's own camera would make its image 800 px wide).
    size = dict(width=args.width, height=args.height)
    reference = caustica.render(scene, light_sampler="tree", time=args.reference_seconds, seed=1000, quiet=True, **size)
    rows = []
    for sampler in ("tree", "power", "uniform"):
        errors, spps = [], []
        for seed in range(args.seeds):
            r = caustica.render(scene, light_sampler=sampler, time=args.seconds, seed=seed, quiet=True, **size)
            errors.append(caustica.diff(r, reference))
            spps.append(r.spp)
            if seed == 0:
                r.save(args.out / f"{name}_{sampler}.png")
        rows.append((sampler, float(np.mean(errors)), float(np.mean(spps))))
    reference.save(args.out / f"{name}_reference.png")
    json_path = d if isinstance(d, pathlib.Path) else args.out / f"{name}.json"
    if not isinstance(d, pathlib.Path):
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
    ap.add_argument("--write-only", action="store_true",
                    help="write the scenes (JSON, glTF) to --out and stop (bench/compare_mitsuba.py renders them)")
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    print(f"# {time.strftime('%Y-%m-%d')}, {args.width}x{args.height}, {args.seconds} s a render "
          f"(mean of {args.seeds} seeds), references {args.reference_seconds} s with the tree")
    print("| scene | sampler | spp | relMSE | vs power |")
    print("|---|---|---|---|---|")
    for name, d in scenes(args.width, args.height, args.out).items():
        if name.endswith("_obj"):  # the peers' twin (--write-only)
            (args.out / f"{name}.json").write_text(json.dumps(d))
            continue
        if args.write_only:
            if not isinstance(d, pathlib.Path):
                (args.out / f"{name}.json").write_text(json.dumps(d))
            continue
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
