"""A material parameter swept, the images shown as a grid (docs/python.md).

Builds a scene as a Python dict (a metal sphere and a glass sphere on a
floor under an area light, the floor an inline NumPy mesh), renders it for
each GGX roughness, and lays the images out with matplotlib. The display
curve is the renderer's own (ACES, gamma 2.2, as a .png output gets it):
each render is saved as a .png and read back.

    python3 examples/python/material_sweep.py --out docs/python
    python3 examples/python/material_sweep.py --small --out /tmp
"""
import argparse
import pathlib
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.image  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import caustica  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]


def scene_dict(roughness, width, height):
    floor = np.array([[-4, 0, -4], [4, 0, -4], [4, 0, 4], [-4, 0, 4]], np.float32)
    return {
        "nbounces": 8,
        "rendermode": "path",
        "camera": {"type": "pinhole", "width": width, "height": height, "position": [0, 1.4, -4.2],
                   "lookAt": [0, 0.6, 0], "upVector": [0, 1, 0], "fov": 40},
        "scene": {
            "backgroundcolor": [0.05, 0.05, 0.08],
            "lightsources": [{"type": "arealight", "position": [0, 3.5, -1], "intensity": [6, 6, 6],
                              "size": [2, 2]}],
            "shapes": [
                {"type": "sphere", "center": [-0.65, 0.6, 0], "radius": 0.6,
                 "material": {"type": "metal", "specularcolor": [0.95, 0.7, 0.4], "roughness": roughness}},
                {"type": "sphere", "center": [0.65, 0.6, 0], "radius": 0.6,
                 "material": {"type": "dielectric", "refractiveindex": 1.5, "roughness": roughness}},
                {"type": "mesh", "vertices": floor, "indices": np.array([[0, 2, 1], [0, 3, 2]], np.int32),
                 "material": {"diffusecolor": [0.6, 0.6, 0.6]}},
            ],
        },
    }


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--small", action="store_true", help="tiny images (the tests)")
    parser.add_argument("--out", type=pathlib.Path, default=ROOT / "docs" / "python")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    width, height, spp = (48, 32, 8) if args.small else (240, 160, 256)
    roughnesses = [0.0, 0.05, 0.15, 0.3, 0.5, 0.8]

    fig, axes = plt.subplots(2, 3, figsize=(9.6, 4.6))
    renders = []
    with tempfile.TemporaryDirectory() as tmp:
        for ax, alpha in zip(axes.flat, roughnesses):
            r = caustica.render(caustica.load_dict(scene_dict(alpha, width, height)), spp=spp, seed=1, quiet=True)
            png = pathlib.Path(tmp) / f"roughness_{alpha}.png"
            r.save(png)
            ax.imshow(matplotlib.image.imread(png))
            ax.set_title(f"roughness {alpha}: est. relMSE {r.error_estimate:.2g}", fontsize=9)
            ax.axis("off")
            renders.append(r)
    fig.suptitle(f"GGX roughness swept on gold and glass ({spp} spp each)")
    fig.tight_layout()
    fig.savefig(args.out / "material_sweep.png", dpi=100)
    for alpha, r in zip(roughnesses, renders):
        print(f"roughness {alpha}: {r.stats['seconds']:.2f} s, mean {r.image.mean():.4f}")
    return renders


if __name__ == "__main__":
    main()
