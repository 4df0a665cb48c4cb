#!/usr/bin/env python3
"""How much any sample allocation could gain on a scene: the bound behind
docs/adaptive.md's figures (issue 22; not part of the tests or CI).

Adaptive sampling lowers the image's relMSE at equal samples by at most what
a perfect allocation would: with each pixel's true per-sample relative
variance v_i known, Neyman's n_i ~ sqrt(v_i) gives relMSE
(mean sqrt v)^2 / mean v times uniform's. How uneven a scene's noise is
decides that bound, whatever the estimator. This script measures v_i from
many uniform renders against a long reference, and prints, at equal samples
(adaptive relMSE / uniform relMSE, lower is better):

  own pixel, ideal     n ~ sqrt(v_i) from each pixel's own true variance
                       (no unbiased renderer can use it: a count that
                       follows its own samples biases the mean,
                       host/render/adaptive_sampling.h)
  own pixel, floor     the same with the floor of a quarter of the mean count
  neighbours (ours)    caustica's rule fed the true variance: each pixel's
                       weight from its neighbours' 5x5 mean (without
                       itself), dilated 3x3, floor a quarter of the mean
  share of the error   in the worst 1% and 10% of the pixels

The renders take `caustica render SCENE --mode path --no-adaptive --spp N
--seed S` for S = 1..--seeds, cached in bench/adaptive_cache/oracle/. The
sample mean of v_i over a few dozen seeds is noisy where the noise is
fireflies, which makes the own-pixel bounds optimistic (their square roots
of noisy values spread more than the truth).

    bench/adaptive_oracle.py scenes/showcase_path.json \\
        --reference bench/mitsuba/cache/showcase_path-...-16384spp-caustica.pfm
"""
import argparse
import math
import os
import struct
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def read_pfm(path):
    with open(path, "rb") as f:
        if f.readline().strip() != b"PF":
            sys.exit(f"{path}: not a colour PFM")
        width, height = map(int, f.readline().split())
        scale = float(f.readline())
        data = f.read()
    count = width * height * 3
    if len(data) < 4 * count:
        sys.exit(f"{path}: {len(data)} bytes of pixels, expected {4 * count}")
    return width, height, struct.unpack(("<" if scale < 0 else ">") + f"{count}f", data[: 4 * count])


def neighbours_mean(v, width, height, radius):
    """Each pixel's mean of v over the (2 radius + 1)^2 box around it, less itself."""
    out = [0.0] * len(v)
    for y in range(height):
        for x in range(width):
            total, n = 0.0, 0
            for yy in range(max(0, y - radius), min(height, y + radius + 1)):
                for xx in range(max(0, x - radius), min(width, x + radius + 1)):
                    if yy != y or xx != x:
                        total += v[yy * width + xx]
                        n += 1
            out[y * width + x] = total / max(1, n)
    return out


def dilate(v, width, height, radius):
    out = [0.0] * len(v)
    for y in range(height):
        for x in range(width):
            out[y * width + x] = max(
                v[yy * width + xx]
                for yy in range(max(0, y - radius), min(height, y + radius + 1))
                for xx in range(max(0, x - radius), min(width, x + radius + 1)))
    return out


def water_fill(weights, floor_share):
    """Counts (mean 1) max(floor_share, lambda w): the allocation's shape."""
    lo, hi = 0.0, 1.0
    mean = lambda lam: sum(max(floor_share, lam * w) for w in weights) / len(weights)
    while mean(hi) < 1.0:
        hi *= 2.0
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        (lo, hi) = (mid, hi) if mean(mid) < 1.0 else (lo, mid)
    return [max(floor_share, hi * w) for w in weights]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--reference", required=True, help="a long render of the scene at --size (PFM)")
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--seeds", type=int, default=32)
    ap.add_argument("--size", default="128x128")
    ap.add_argument("--caustica", default=os.path.join(ROOT, "build", "caustica"))
    ap.add_argument("--rules", action="store_true", help="also compare the guards' variants (see above)")
    args = ap.parse_args()
    width, height = map(int, args.size.split("x"))
    cache = os.path.join(HERE, "adaptive_cache", "oracle")
    os.makedirs(cache, exist_ok=True)
    stem = os.path.splitext(os.path.basename(args.scene))[0]
    rw, rh, ref = read_pfm(args.reference)
    if (rw, rh) != (width, height):
        sys.exit(f"{args.reference}: {rw}x{rh}, not --size {args.size}")
    pixels = width * height
    v = [0.0] * pixels  # per-sample relative variance, summed over channels
    per_render = []  # each render's own v (its squared error x spp), for --rules
    for seed in range(1, args.seeds + 1):
        out = os.path.join(cache, f"{stem}-{args.size}-{args.spp}spp-seed{seed}.pfm")
        if not os.path.exists(out):
            cmd = [args.caustica, "render", args.scene, "--mode", "path", "--no-adaptive", "--width", str(width),
                   "--height", str(height), "--spp", str(args.spp), "--seed", str(seed), "-o", out, "-q"]
            print(" ".join(cmd), file=sys.stderr)
            subprocess.run(cmd, check=True, stderr=subprocess.DEVNULL)
        _, _, img = read_pfm(out)
        own_v = [0.0] * pixels
        for i in range(pixels):
            t = 0.0
            for c in range(3):
                r = ref[3 * i + c]
                d = img[3 * i + c] - r
                t += d * d / (r * r + 0.01)
            own_v[i] = t * args.spp
            v[i] += t * args.spp / args.seeds
        if args.rules:
            per_render.append(own_v)
    mean_v = sum(v) / pixels

    def ratio(counts):  # relMSE against uniform's at the same total
        m = sum(counts) / pixels
        return sum(v[i] * m / counts[i] for i in range(pixels) if counts[i] > 0) / pixels / mean_v

    own = [math.sqrt(x) + 1e-30 for x in v]
    ours = dilate([math.sqrt(x) for x in neighbours_mean(v, width, height, 2)], width, height, 1)
    ranked = sorted(v, reverse=True)
    print(f"{stem} {args.size}, {args.seeds} uniform renders of {args.spp} spp; adaptive / uniform relMSE at "
          f"equal samples:")
    print(f"  own pixel, ideal      {ratio(own):.3f}")
    print(f"  own pixel, floor 1/4  {ratio(water_fill(own, 0.25)):.3f}")
    print(f"  neighbours (ours)     {ratio(water_fill([w + 1e-30 for w in ours], 0.25)):.3f}")
    print(f"  share of the error    worst 1% of pixels {sum(ranked[: pixels // 100]) / sum(v):.2f}, "
          f"worst 10% {sum(ranked[: pixels // 10]) / sum(v):.2f}")
    if args.rules:
        print("  rule variants (filter radius, dilation radius, floor): true v / v from one render")
        for box, grow, floor in [(2, 1, 0.25), (2, 1, 0.1), (2, 0, 0.1), (1, 1, 0.1), (1, 0, 0.1), (3, 1, 0.1)]:
            def rule(values):
                w = [math.sqrt(max(0.0, x)) for x in neighbours_mean(values, width, height, box)]
                if grow:
                    w = dilate(w, width, height, grow)
                return water_fill([x + 1e-30 for x in w], floor)
            split = []
            for k in range(min(4, len(per_render))):
                rest = [(v[i] * args.seeds - per_render[k][i]) / (args.seeds - 1) for i in range(pixels)]
                counts = rule(per_render[k])
                m = sum(counts) / pixels
                split.append(sum(rest[i] * m / counts[i] for i in range(pixels)) / sum(rest))
            print(f"    r={box} dilate={grow} floor={floor:<5} {ratio(rule(v)):.3f} / {sum(split) / len(split):.3f}")


if __name__ == "__main__":
    main()
