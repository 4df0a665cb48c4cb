"""Error against time, uniform and adaptive sampling (docs/python.md).

Renders the Cornell box at 128 x 128 for a time budget with each sampler,
measures every render's relMSE against the converged reference as it goes
(reference=: the same measurements as `caustica render --reference`), and
plots true and estimated relMSE against seconds with matplotlib.

    python3 examples/python/error_vs_time.py --seconds 20 --out docs/python
    python3 examples/python/error_vs_time.py --small --out /tmp   (the tests' size)
"""
import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import caustica  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=20.0, help="time budget of each render")
    parser.add_argument("--small", action="store_true", help="a second each (the tests)")
    parser.add_argument("--out", type=pathlib.Path, default=ROOT / "docs" / "python")
    args = parser.parse_args(argv)
    seconds = 1.0 if args.small else args.seconds
    args.out.mkdir(parents=True, exist_ok=True)

    scene = caustica.load(ROOT / "scenes" / "cornell_box.json")
    reference = ROOT / "tests" / "references" / "cornell_box_128_8192spp.pfm"
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    finals = {}
    for adaptive, colour in ((False, "tab:blue"), (True, "tab:orange")):
        name = "adaptive" if adaptive else "uniform"
        r = caustica.render(scene, width=128, time=seconds, adaptive=adaptive, reference=reference, quiet=True)
        rows = [row for row in r.report if row["relmse"] is not None]
        ax.loglog([row["seconds"] for row in rows], [row["relmse"] for row in rows], "o-", color=colour,
                  label=f"{name}: true relMSE")
        est = [row for row in rows if row["est_relmse"] is not None]
        ax.loglog([row["seconds"] for row in est], [row["est_relmse"] for row in est], "x--", color=colour,
                  alpha=0.7, label=f"{name}: its own estimate")
        finals[name] = (r.spp, r.stats["seconds"], caustica.diff(r, reference), r.error_estimate)
    ax.set_xlabel("seconds")
    ax.set_ylabel("relMSE against the 8192 spp reference")
    ax.set_title("Cornell box 128 x 128: error against time")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(args.out / "error_vs_time.png", dpi=100)
    for name, (spp, secs, true, est) in finals.items():
        print(f"{name}: {spp} spp in {secs:.1f} s, relMSE {true:.3g} (estimated {est:.3g})")
    return finals


if __name__ == "__main__":
    main()
