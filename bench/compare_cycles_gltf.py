#!/usr/bin/env python3
"""caustica against Blender's Cycles on glTF 2.0 files, each read by its own
importer (optional; not part of the tests or CI): the glTF material
extensions caustica maps (scenes/FORMAT.md, "glTF 2.0 files": normal maps,
alpha, KHR_materials_clearcoat, _transmission, _volume, _specular) against
what Blender's glTF importer makes of them for Cycles.

Each FILE is placed as a coursework scene's "mesh" (its own coordinates),
seen by the same camera under a uniform white sky (the light a glTF file
without lights gets in caustica), and rendered by both at SPP samples a
pixel (caustica: path mode, 8 bounces; Cycles 5.0.1 CPU with this repo's
settings from bench/compare_cycles.py: no clamping, no glossy blur, a 1 px
box filter, the image mirrored into caustica's orientation). Printed: the
relMSE between the two images (x - y)^2 / (y^2 + 0.01), overall and per
row of the image grid given by --regions (a sample model's rows of
variants), and a strip [caustica | Cycles | |difference| x 4] as PNG.

    bench/cycles/venv/bin/python bench/compare_cycles_gltf.py \\
        ../shared/models/gltf/assimp-tests/ClearCoat-glTF/ClearCoatTest.gltf \\
        --camera 0,0,14 --look-at 0,0,0 --fov 45 --size 320x256 --spp 256 --images out/cycles_gltf
"""
import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import compare_cycles as cc  # noqa: E402


def vec(text):
    return [float(v) for v in text.split(",")]


def wrapper_scene(path, args, folder):
    """The coursework scene caustica renders: the file as a mesh, the camera, a white sky."""
    scene = {"rendermode": "pathtracer", "nbounces": 8,
             "camera": {"type": "pinhole", "width": args.w, "height": args.h, "position": args.camera,
                        "lookAt": args.look_at, "upVector": args.up, "fov": args.fov},
             "scene": {"backgroundcolor": [1, 1, 1], "lightsources": [],
                       "shapes": [{"type": "mesh", "file": os.path.abspath(path)}]}}
    out = os.path.join(folder, os.path.splitext(os.path.basename(path))[0] + "_scene.json")
    with open(out, "w") as f:
        json.dump(scene, f, indent=1)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("files", nargs="+")
    ap.add_argument("--camera", type=vec, default=[0, 0, 10])
    ap.add_argument("--look-at", type=vec, default=[0, 0, 0])
    ap.add_argument("--up", type=vec, default=[0, 1, 0])
    ap.add_argument("--fov", type=float, default=45.0)
    ap.add_argument("--size", default="320x240")
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--regions", type=int, default=1, help="rows of the image reported apart")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--images", default=os.path.join(cc.ROOT, "out", "cycles_gltf"))
    ap.add_argument("--caustica", default=os.path.join(cc.ROOT, "build", "caustica"))
    args = ap.parse_args()
    args.w, args.h = (int(v) for v in args.size.split("x"))
    np = cc.np_mod()
    os.makedirs(args.images, exist_ok=True)
    for path in args.files:
        stem = os.path.splitext(os.path.basename(path))[0]
        scene = wrapper_scene(path, args, args.images)
        ours = os.path.join(args.images, stem + "_caustica.pfm")
        run = cc.run_caustica(args, scene, args.w, args.h, ours, [], spp=args.spp)
        a = cc.read_image(ours)
        desc = {"meshes": [], "spheres": [], "background": [1.0, 1.0, 1.0], "nbounces": 8, "notes": [],
                "approximate": False, "gltf": os.path.abspath(path),
                "camera": {"position": args.camera, "look_at": args.look_at, "up": args.up, "fov": args.fov,
                           "aperture": 0.0, "focus": 1.0}}
        info, b, _ = cc.run_cycles(args, desc, args.w, args.h, args.images, stem + "_cycles", False, False,
                                   samples=args.spp)
        rel = ((a - b) ** 2) / (b ** 2 + 0.01)
        rows = np.array_split(np.arange(args.h), args.regions)
        print("%s at %dx%d, %d spp: relMSE caustica vs Cycles %.4g; by row: %s" % (
            stem, args.w, args.h, args.spp, float(rel.mean()),
            ", ".join("%.3g" % float(rel[r].mean()) for r in rows)))
        print("  caustica: %s (%.1f s); Cycles %s: %.1f s" % (run["command"], run["wall_s"],
                                                              info.get("blender"), info["wall_s"]))
        strip = np.concatenate([a, b, np.abs(a - b) * 4.0], axis=1)
        cc.write_png(os.path.join(args.images, stem + "_strip.png"), cc.to_srgb8(strip))


if __name__ == "__main__":
    main()
