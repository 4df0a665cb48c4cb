#!/usr/bin/env python3
"""How honest caustica's error estimate is where light is rare (issue 45;
the figures of docs/error.md; not part of the tests or CI).

For each scene and each way of rendering it, caustica renders the scene
once per seed up to --spp samples per pixel (the photon pass forced on:
--pm-spp; the Cornell box: --cornell-spp), measuring itself against a
long path-traced reference (`reference=`, the rows of `Render.report`: at
2, 4, 8, ... spp the true relMSE, the film's point estimate and its 90%
upper bound, host/render/error_estimate.h). From those rows:

  * ratios.csv: every row of every seed (scene, variant, seed, spp, truth,
    estimate, bound), the truth less the reference's own noise: the
    per-sample variance of path tracing alone (the `pt` renders' last
    rows, mean over seeds: the reference is path traced) over the
    reference's spp;
  * summary.md: per scene, variant and spp, the median truth over seeds,
    the median and range of estimate / truth, the share of seeds whose
    bound covers the truth, and the median bound / truth;
  * split.md: for each variant at its last spp, the true error split
    into the path tracer's variance, the photon map's variance and the
    bias (mean over seeds less the reference, less its own variance and
    the reference's noise: the path tracer is unbiased, so it is the photon
    map's, or the mass of paths no seed found), next to the same split of
    the estimate (the photon map's share is its `caustics_variance`, the
    rest the half buffer's); every term is sum (x / (ref^2 + 0.01)) /
    (3 pixels), so the shares add up to the truth's mean over seeds (less
    the reference's noise);
  * SCENE.png: estimate / truth and bound / truth against spp, a point per
    seed and the median, for each variant (gnuplot).

    cmake --build build --target caustica_python   # build/python/caustica
    /usr/bin/python3 bench/error_honesty.py        # docs/error.md's run (16 seeds; about 30 min on 2 cores)

Scenes (--scenes): stiff_ground and caustics (their references are
committed in tests/references/), cornell_box (the same), and `community`,
../shared/scenes-coursework/community/Ninteedo__CGRaytracer__initial_scene.json
in path mode (glass and mirror balls on a table under a small sphere
light; read from ../shared, never copied), whose reference this script
renders once (--community-reference-spp, path tracing alone, uniform) and
caches in bench/error_cache/. Variants (--variants): `defaults` (adaptive
sampling, caustics auto), `pt` (--caustics off --no-adaptive: path
tracing alone) and `pm` (--caustics on --no-adaptive: the photon pass every
pass).
"""
import argparse
import csv
import math
import os
import subprocess
import sys
from collections import defaultdict

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "build", "python"))
import caustica  # noqa: E402

EPS = 0.01  # metrics.h's kRelMseEpsilon
COMMUNITY = os.path.join(ROOT, "..", "shared", "scenes-coursework", "community",
                         "Ninteedo__CGRaytracer__initial_scene.json")
SCENES = {
    "stiff_ground": dict(scene="scenes/stiff_ground.json", size=(72, 48),
                         reference="tests/references/stiff_ground_pt_72x48.pfm", reference_spp=262144),
    "caustics": dict(scene="scenes/caustics.json", size=(64, 48),
                     reference="tests/references/caustics_pt_64x48.pfm", reference_spp=131072),
    "community": dict(scene=COMMUNITY, size=(72, 48), reference=None, reference_spp=None, mode="path"),
    "cornell_box": dict(scene="scenes/cornell_box.json", size=(128, 128),
                        reference="tests/references/cornell_box_128_8192spp.pfm", reference_spp=8192),
}
VARIANTS = {  # pt first: its renders measure the reference's own noise for all three
    "pt": dict(caustics="off", adaptive=False),
    "defaults": {},
    "pm": dict(caustics="on", adaptive=False),
}


def read_pfm(path):
    with open(path, "rb") as f:
        if f.readline().strip() != b"PF":
            raise ValueError(f"{path}: not a colour PFM")
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.fromfile(f, dtype="<f4" if scale < 0 else ">f4").reshape(h, w, 3)
    return data[::-1].astype(np.float64)  # PFM rows run bottom to top


def community_reference(args):
    cache = os.path.join(ROOT, "bench", "error_cache")
    os.makedirs(cache, exist_ok=True)
    w, h = SCENES["community"]["size"]
    path = os.path.join(cache, f"community_pt_{w}x{h}_{args.community_reference_spp}spp.pfm")
    if not os.path.exists(path):
        print(f"rendering the community scene's reference ({args.community_reference_spp} spp) to {path}",
              file=sys.stderr)
        scene = caustica.load(COMMUNITY)
        caustica.render(scene, mode="path", width=w, height=h, spp=args.community_reference_spp, seed=4242,
                        caustics="off", adaptive=False, error_estimate=False, output=path, quiet=True)
    return path, args.community_reference_spp


def run(args, name, config, variant, seed, reference_path):
    scene = caustica.load(os.path.join(ROOT, config["scene"]) if not os.path.isabs(config["scene"])
                          else config["scene"])
    w, h = config["size"]
    spp = spp_of(args, name, variant)
    options = dict(width=w, height=h, spp=spp, seed=seed, reference=reference_path, quiet=True)
    if "mode" in config:
        options["mode"] = config["mode"]
    options.update(VARIANTS[variant])
    return caustica.render(scene, **options)


def spp_of(args, name, variant):
    if name == "cornell_box":
        return args.cornell_spp
    return args.pm_spp if variant == "pm" else args.spp


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--scenes", nargs="+", default=list(SCENES))
    parser.add_argument("--variants", nargs="+", default=list(VARIANTS))
    parser.add_argument("--seeds", type=int, default=16)
    parser.add_argument("--spp", type=int, default=4096, help="defaults and pt: samples per pixel")
    parser.add_argument("--pm-spp", type=int, default=1024, help="pm (the photon pass every pass costs most)")
    parser.add_argument("--cornell-spp", type=int, default=1024)
    parser.add_argument("--community-reference-spp", type=int, default=65536)
    parser.add_argument("--out-dir", default=os.path.join(ROOT, "bench", "error_honesty"))
    args = parser.parse_args()
    os.makedirs(args.out_dir, exist_ok=True)

    rows = []            # (scene, variant, seed, spp, truth, estimate, bound)
    split_lines = []
    for name in args.scenes:
        config = SCENES[name]
        if name == "community":
            if not os.path.exists(COMMUNITY):
                print(f"skipping {name}: {COMMUNITY} is missing", file=sys.stderr)
                continue
            reference_path, reference_spp = community_reference(args)
        else:
            reference_path = os.path.join(ROOT, config["reference"])
            reference_spp = config["reference_spp"]
        reference = read_pfm(reference_path)
        weight = 1.0 / (reference * reference + EPS)
        values = reference.size
        reference_noise, noise_image = None, None  # the reference's own relMSE and per-pixel variance
        for variant in sorted(args.variants, key=list(VARIANTS).index):
            if name == "cornell_box" and variant != "defaults":
                continue  # no caustics: the variants render the same thing
            images, caustic_images, variances, caustic_variances = [], [], [], []
            reports, per_sample = [], []
            for seed in range(args.seeds):
                print(f"{name} {variant} seed {seed}", file=sys.stderr)
                r = run(args, name, config, variant, seed, reference_path)
                aovs = r.aovs
                reports.append(r.report)
                # Each pixel's per-sample variance: its mean's variance at
                # the last row times its spp.
                per_sample.append(aovs["variance"][..., None] * aovs["spp"][..., None])
                images.append(r.image.astype(np.float64))
                variances.append(aovs["variance"][..., None].astype(np.float64))
                if "caustics" in aovs:
                    caustic_images.append(aovs["caustics"].astype(np.float64))
                    caustic_variances.append(aovs["caustics_variance"][..., None].astype(np.float64))
            # The reference's own noise: path tracing's per-sample variance
            # over the reference's spp (without pt renders, this variant's).
            if reference_noise is None or variant == "pt":
                noise_image = np.mean(per_sample, axis=0) / reference_spp
                reference_noise = float(np.sum(noise_image * weight)) / values
            for seed, report in enumerate(reports):
                for row in report:
                    if row["est_relmse"] is None or row["relmse"] is None:
                        continue
                    truth = max(row["relmse"] - reference_noise, 1e-30)
                    rows.append((name, variant, seed, row["spp"], truth, row["est_relmse"], row["est_relmse_bound"]))
            if len(images) >= 2:
                split_lines.append(split_line(name, variant, spp_of(args, name, variant), reference, noise_image, weight,
                                              values, images, caustic_images, variances, caustic_variances))

    with open(os.path.join(args.out_dir, "ratios.csv"), "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(["scene", "variant", "seed", "spp", "truth", "estimate", "bound"])
        out.writerows(rows)
    summary = summarise(rows)
    with open(os.path.join(args.out_dir, "summary.md"), "w") as f:
        f.write(summary)
    with open(os.path.join(args.out_dir, "split.md"), "w") as f:
        f.write("| scene | variant | spp | truth | PT variance | PM variance | bias^2 | estimate | its PT share | "
                "its PM share |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n")
        f.write("".join(split_lines))
    print(summary)
    print("".join(split_lines))
    plot(rows, args.out_dir)


def split_line(name, variant, spp, reference, noise_image, weight, values, images, caustic_images, variances,
               caustic_variances):
    k = len(images)
    images = np.array(images)
    term = lambda x: float(np.sum(x * weight)) / values  # noqa: E731
    truth = np.mean([term((im - reference) ** 2) for im in images]) - term(noise_image)
    if caustic_images:
        caustics = np.array(caustic_images)
        paths = images - caustics
        pt_var, pm_var = term(paths.var(0, ddof=1)), term(caustics.var(0, ddof=1))
        est_pm = np.mean([term(v) for v in caustic_variances])
    else:
        pt_var, pm_var, est_pm = term(images.var(0, ddof=1)), 0.0, 0.0
    # Summed before the clamp: a clamp per pixel would count every pixel's
    # noise above 0 as bias.
    bias2 = max(term((images.mean(0) - reference) ** 2 - images.var(0, ddof=1) / k - noise_image), 0.0)
    est_all = np.mean([term(v) for v in variances])
    return (f"| {name} | {variant} | {spp} | {truth:.3g} | {pt_var:.3g} | {pm_var:.3g} | {bias2:.3g} | "
            f"{est_all:.3g} | {est_all - est_pm:.3g} | {est_pm:.3g} |\n")


def summarise(rows):
    groups = defaultdict(list)
    for scene, variant, seed, spp, truth, estimate, bound in rows:
        groups[(scene, variant, spp)].append((truth, estimate, bound))
    lines = ["| scene | variant | spp | seeds | median truth | estimate / truth: median [min, max] | "
             "bound covers | median bound / truth |", "|---|---|---:|---:|---:|---|---:|---:|"]
    past16 = defaultdict(lambda: [0, 0])
    for (scene, variant, spp), values in sorted(groups.items()):
        truth = np.array([v[0] for v in values])
        ratio = np.array([v[1] for v in values]) / truth
        bound = np.array([v[2] for v in values]) / truth
        lines.append(f"| {scene} | {variant} | {spp} | {len(values)} | {np.median(truth):.3g} | "
                     f"{np.median(ratio):.2f} [{ratio.min():.2f}, {ratio.max():.2f}] | "
                     f"{np.mean(bound >= 1.0):.0%} | {np.median(bound):.2f} |")
        if spp > 16:
            past16[(scene, variant)][0] += int(np.sum(bound >= 1.0))
            past16[(scene, variant)][1] += len(values)
    lines.append("")
    lines.append("| scene | variant | rows past 16 spp | bound covers |")
    lines.append("|---|---|---:|---:|")
    for (scene, variant), (covered, total) in sorted(past16.items()):
        lines.append(f"| {scene} | {variant} | {total} | {covered} ({covered / total:.0%}) |")
    return "\n".join(lines) + "\n"


def plot(rows, out_dir):
    by_scene = defaultdict(list)
    for row in rows:
        by_scene[row[0]].append(row)
    colours = {"defaults": "#0072b2", "pt": "#d55e00", "pm": "#009e73"}
    for scene, scene_rows in by_scene.items():
        blocks, plots = [], []
        for variant in colours:
            vr = [r for r in scene_rows if r[1] == variant]
            if not vr:
                continue
            for kind, column, style in (("estimate", 5, "pt 7 ps 0.5"), ("bound", 6, "pt 2 ps 0.6")):
                name = f"${variant}_{kind}"
                pts = "\n".join(f"{r[3]} {r[column] / r[4]:.6g}" for r in vr)
                blocks.append(f"{name} << EOD\n{pts}\nEOD\n")
                med = defaultdict(list)
                for r in vr:
                    med[r[3]].append(r[column] / r[4])
                mname = f"{name}_median"
                mpts = "\n".join(f"{spp} {np.median(v):.6g}" for spp, v in sorted(med.items()))
                blocks.append(f"{mname} << EOD\n{mpts}\nEOD\n")
                plots.append(f"{name} using 1:2 with points {style} lc rgb '{colours[variant]}' notitle")
                dash = "dt 1" if kind == "estimate" else "dt 2"
                plots.append(f"{mname} using 1:2 with lines lw 2 {dash} lc rgb '{colours[variant]}' "
                             f"title '{variant}: {kind} / truth (median)'")
        script = (f"set terminal pngcairo size 820,560\nset output '{os.path.join(out_dir, scene + '.png')}'\n"
                  "set logscale xy\nset xlabel 'samples per pixel'\nset ylabel 'estimated / true relMSE'\n"
                  "set format x '%g'\nset format y '%g'\nset grid\nset key outside bottom center horizontal\n"
                  f"set title '{scene}: points are seeds, lines their median; 1 = exact' noenhanced\n" +
                  "".join(blocks) +
                  "plot " + ", \\\n  ".join(plots + ["1 with lines lc rgb '#000000' lw 1 notitle"]) + "\n")
        subprocess.run(["gnuplot"], input=script.encode(), check=True)


if __name__ == "__main__":
    main()
