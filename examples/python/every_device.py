"""The same scene on every OpenCL device present (docs/python.md).

Lists the devices as `caustica devices` does, renders the Cornell box on
each with the same seed, and compares the images: the samples are the
same on every device, so they differ only by floating-point rounding of
the devices' arithmetic. Writes a figure of the images side by side with
their time and their relMSE against the first device's.

    python3 examples/python/every_device.py --out docs/python
    python3 examples/python/every_device.py --small --out /tmp
"""
import argparse
import pathlib
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.image  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

import caustica  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--small", action="store_true", help="a tiny image (the tests)")
    parser.add_argument("--out", type=pathlib.Path, default=ROOT / "docs" / "python")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    width, spp = (32, 4) if args.small else (256, 64)

    scene = caustica.load(ROOT / "scenes" / "cornell_box.json")
    devices = caustica.devices()
    fig, axes = plt.subplots(1, len(devices), figsize=(4 * len(devices), 4.4), squeeze=False)
    results = []
    with tempfile.TemporaryDirectory() as tmp:
        for ax, device in zip(axes[0], devices):
            r = caustica.render(scene, device=device["index"], width=width, spp=spp, seed=7, quiet=True)
            against_first = caustica.diff(r, results[0][1]) if results else 0.0
            results.append((device, r, against_first))
            png = pathlib.Path(tmp) / f"device_{device['index']}.png"
            r.save(png)
            ax.imshow(matplotlib.image.imread(png))
            ax.set_title(f"[{device['index']}] {device['type']}: {device['name'][:28]}\n"
                         f"{r.stats['seconds']:.2f} s, relMSE vs [0] {against_first:.2g}", fontsize=8)
            ax.axis("off")
    fig.tight_layout()
    fig.savefig(args.out / "every_device.png", dpi=100)
    for device, r, against_first in results:
        print(f"[{device['index']}] {device['name']} ({device['platform']}): {r.stats['seconds']:.2f} s, "
              f"{r.stats['rays'] / r.stats['seconds'] / 1e6:.1f} Mrays/s, relMSE against device 0: {against_first:.3g}")
    return results


if __name__ == "__main__":
    main()
