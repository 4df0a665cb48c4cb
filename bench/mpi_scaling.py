#!/usr/bin/env python3
"""Distributed rendering's scaling (issues 23 and 40; results for
docs/distributed.md; not part of the tests or CI).

Time to reach a target error with 1 and 2 (--most-ranks: more) MPI ranks of
one PoCL thread each (POCL_MAX_PTHREAD_COUNT=1 per rank), against one
process of as many PoCL threads: the Cornell box at 512x512 and the showcase
(scenes/showcase_path.json: glass and metal spheres, with the photon pass as
`--caustics auto` decides), with the defaults: adaptive sampling (the ranks
share every wave; --uniform adds --no-adaptive). Each run renders with
--target-error E (the film's own relMSE estimate, taken on rank 0 from the
ranks' summed film) and reports its render time (rank 0's, reductions and
weight refreshes included), the spp reached and the estimate there. Runs
stop at slightly different spp (after whole waves), so each time is
normalised to the target: the error falls as 1 / spp, so t_norm = t *
estimate / target is the time the run would have taken to reach exactly E.
Efficiency at N = t_norm(1) / (N * t_norm(N)) (1: perfect).

Then the cost of one reduction (the ranks' films summed on rank 0: each
rank reads its film from the device, the 128-bit sums and the half buffer
go through MPI_Reduce with an integer op, rank 0 restores the sum) and of
one adaptive weight refresh (the colour sums and ray counts summed on every
rank with MPI_Allreduce, the weights computed on each) for a 1920x1080 film
on 2 ranks, and the model of efficiency at 16 and 64 ranks for a 1920x1080
render of one minute (docs/distributed.md derives it):

    t_reduce(R) = t_read + ceil(log2 R) * t_mpi(2) + t_restore
    (t_mpi measured after a barrier: the wait for the slowest rank is apart)
    t_refresh(R) = t_refresh(2) + (ceil(log2 R) - 1) * 2 * t_mpi(2) * b_w / b_r
    (a tree all-reduce: up and down every level, b_w / b_r the share of
    bytes a refresh sums: colour and rays, not the aux values)
    efficiency(R) = 60 / (60 + k * t_reduce(R) + w * t_refresh(R) + t_imbalance)

k reductions (1 with --spp or --time; with only a target error the
sparse monitor's measurements: one at 16 passes, then where the estimate
projects the target, at most 4x apart, about 2 + log4(passes / 16); with
a report, log2 of the passes + 1), w weight refreshes (one at 16 passes,
then at every quarter's growth: 1 + log(passes / 16) / log(1.25)),
t_imbalance at most one wave on one rank (the last; a wave is shared by
all, so its share of a pass).

    cmake --build build --target caustica    # caustica built with MPI
    bench/mpi_scaling.py                     # defaults: --target 0.005 0.01

Keep the machine otherwise idle: the ranks and threads share its cores.
It takes about 3 to 5 minutes on 2 cores (--repeat 3: 10). Progress goes to
stderr, the Markdown tables to stdout.
"""
import argparse
import math
import os
import re
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BINARY = os.path.join(ROOT, "build", "caustica")
SCENES = [("cornell box 512x512", "scenes/cornell_box.json", ["--width", "512", "--height", "512"]),
          ("showcase 480x270", "scenes/showcase_path.json", ["--width", "480", "--height", "270"])]
MPI_ENV = {"OMPI_MCA_btl": "self,vader", "OMPI_MCA_btl_vader_single_copy_mechanism": "none"}


def mpirun(ranks):
    args = ["mpirun", "--oversubscribe", "-np", str(ranks)]
    if os.geteuid() == 0:
        args.insert(1, "--allow-run-as-root")
    return args


def run(cmd, threads, out):
    env = dict(os.environ, POCL_MAX_PTHREAD_COUNT=str(threads), **MPI_ENV)
    t0 = time.monotonic()
    p = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=600)
    wall = time.monotonic() - t0
    text = p.stdout + p.stderr
    if p.returncode != 0:
        sys.exit(f"failed ({p.returncode}): {' '.join(cmd)}\n{text}")
    m = re.search(r"wrote \S+ \(\d+x\d+, (\d+) spp\) in ([0-9.]+) s, estimated relMSE ([0-9.e+-]+)", text)
    if not m:
        sys.exit(f"no result line in: {' '.join(cmd)}\n{text}")
    r = re.search(r"summed on rank 0 in (\d+) reductions, ([0-9.]+) s \(film reads ([0-9.]+) s, waiting for ranks "
                  r"([0-9.]+) s, MPI ([0-9.]+) s, restore ([0-9.]+) s\)", text)
    w = re.search(r"weights refreshed (\d+) times from the summed film, ([0-9.]+) s .*MPI ([0-9.]+) s.*waiting "
                  r"([0-9.]+) s", text)
    return {"spp": int(m.group(1)), "seconds": float(m.group(2)), "estimate": float(m.group(3)), "wall": wall,
            "reductions": int(r.group(1)) if r else 0, "reduce_s": float(r.group(2)) if r else 0.0,
            "read_s": float(r.group(3)) if r else 0.0, "wait_s": float(r.group(4)) if r else 0.0,
            "mpi_s": float(r.group(5)) if r else 0.0, "restore_s": float(r.group(6)) if r else 0.0,
            "refreshes": int(w.group(1)) if w else 0, "refresh_s": float(w.group(2)) if w else 0.0,
            "refresh_mpi_s": float(w.group(3)) if w else 0.0, "refresh_wait_s": float(w.group(4)) if w else 0.0}


UNIFORM = []  # ["--no-adaptive"] with --uniform


def render_cmd(scene, size, extra):
    return [BINARY, "render", os.path.join(ROOT, scene), "--mode", "path"] + UNIFORM + [
        "-v", "-o", "/tmp/caustica_mpi_scaling.pfm"] + size + extra


def scaling(name, scene, size, target, repeat, most):
    """Each configuration `repeat` times, the configurations interleaved (so
    that drift in the machine's speed hits all alike); a row is the run of
    median normalised time."""
    configs = [("process", 1)] + [c for n in range(2, most + 1) for c in (("ranks", n), ("threads", n))]
    runs = {c: [] for c in configs}
    for attempt in range(repeat):
        for kind, n in configs:
            base = render_cmd(scene, size, ["--target-error", str(target)])
            cmd = mpirun(n) + base if kind == "ranks" else base
            threads = 1 if kind == "ranks" else n
            print(f"[mpi_scaling] {name}: {n} {kind} ({attempt + 1}/{repeat}) ...", file=sys.stderr, flush=True)
            r = run(cmd, threads, None)
            r["kind"], r["n"] = kind, n
            r["t_norm"] = r["seconds"] * r["estimate"] / target
            runs[(kind, n)].append(r)
    rows = [sorted(runs[c], key=lambda r: r["t_norm"])[(repeat - 1) // 2] for c in configs]
    one = rows[0]["t_norm"]
    if repeat > 1:
        for c in configs:
            effs = ", ".join(f"{one / (c[1] * r['t_norm']):.2f}" for r in runs[c])
            print(f"[mpi_scaling] {name}: {c[1]} {c[0]}: efficiency of each run against the median 1-thread "
                  f"run: {effs}", file=sys.stderr)
    print(f"\n### {name}, target relMSE {target}" + (f", medians of {repeat} runs" if repeat > 1 else "") + "\n")
    print("| run | spp | estimated relMSE | render s | wall s | normalised s | efficiency | reductions (s) | "
          "weight refreshes (s; waiting for the slowest rank before them) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        label = "1 process, 1 thread" if r["kind"] == "process" else (
            f"{r['n']} ranks x 1 thread" if r["kind"] == "ranks" else f"1 process, {r['n']} threads")
        eff = one / (r["n"] * r["t_norm"])
        red = f"{r['reductions']} ({r['reduce_s']:.3f})" if r["reductions"] else "-"
        ref = f"{r['refreshes']} ({r['refresh_s']:.3f}, waiting {r['refresh_wait_s']:.3f})" if r["refreshes"] else "-"
        print(f"| {label} | {r['spp']} | {r['estimate']:.4g} | {r['seconds']:.2f} | {r['wall']:.2f} | "
              f"{r['t_norm']:.2f} | {eff:.2f} | {red} | {ref} |")
    return rows


def reduction_cost():
    """One reduction (a 2-spp render's last) and, unless --uniform, one
    weight refresh (an 18-spp render's first, at 16 passes) of a 1920x1080
    film on 2 ranks of 1 thread each."""
    print("[mpi_scaling] 1920x1080 reduction on 2 ranks ...", file=sys.stderr, flush=True)
    size = ["--width", "1920", "--height", "1080"]
    r = run(mpirun(2) + render_cmd("scenes/cornell_box.json", size, ["--spp", "2"]), 1, None)
    film_mb = 1920 * 1080 * 3 * 16 * 2 / 1e6  # 128-bit sums, the combined sum and the half
    print(f"\n### One reduction of a 1920x1080 film ({film_mb:.0f} MB of sums) on 2 ranks\n")
    print("| film reads s | waiting for the other rank s | MPI s | restore s | total s |")
    print("|---|---|---|---|---|")
    print(f"| {r['read_s']:.3f} | {r['wait_s']:.3f} | {r['mpi_s']:.3f} | {r['restore_s']:.3f} | {r['reduce_s']:.3f} |")
    r["refresh_local_s"] = r["refresh_mpi_s"] = 0.0
    if not UNIFORM:
        print("[mpi_scaling] 1920x1080 weight refresh on 2 ranks (18 spp, about a minute) ...", file=sys.stderr,
              flush=True)
        w = run(mpirun(2) + render_cmd("scenes/cornell_box.json", size, ["--spp", "18"]), 1, None)
        n = max(1, w["refreshes"])
        r["refresh_mpi_s"] = w["refresh_mpi_s"] / n
        r["refresh_local_s"] = (w["refresh_s"] - w["refresh_mpi_s"]) / n
        print(f"\nOne adaptive weight refresh of that film on 2 ranks (colour sums and ray counts all-reduced, "
              f"weights on every rank): {r['refresh_local_s'] + r['refresh_mpi_s']:.3f} s, of which MPI "
              f"{r['refresh_mpi_s']:.3f} s ({w['refreshes']} in an 18-spp render).")
    return r


def model(red, pass_s):
    """Efficiency of a one-minute 1920x1080 render on R ranks (docs/distributed.md).

    Collectives: tree = every level of a binomial tree moves the whole
    film (pessimistic: a reduce ceil(log2 R) times t_mpi(2), an all-reduce
    as many); pipelined = Open MPI's segmented reduce or ring all-reduce for
    large messages, about one transfer of the film (an all-reduce 2 (R - 1)
    / R of one, which is 1 at 2 ranks). The MPI times are this VM's (shared
    memory without single copy) or scaled to an assumed 12.5 GB/s network
    (100 Gbit/s). Imbalance: the last wave on one rank (2 passes at 1080p,
    shared by the ranks). k reductions: 1 for --spp/--time; for a target
    error the sparse monitor's (one at 16 passes, then where the estimate
    projects the target, at most 4x apart: about 2 + ceil(log4(passes /
    16))). w weight refreshes: at 16 passes, then every quarter's growth."""
    film_bytes = 1920 * 1080 * 3 * 16 * 2
    vm_bandwidth = film_bytes / max(1e-6, red["mpi_s"])
    print(f"\nThis VM's reduction moved {film_bytes / 1e6:.0f} MB in {red['mpi_s']:.3f} s: "
          f"{vm_bandwidth / 1e9:.2f} GB/s.")
    for net, scale in (("this VM's shared memory (measured)", 1.0),
                       ("a 12.5 GB/s network (100 Gbit/s; assumed)", vm_bandwidth / 12.5e9)):
        for label, pass_time in ((f"this CPU's 1-thread 1080p pass, {pass_s:.2f} s (measured)", pass_s),
                                 ("a 0.1 s 1080p pass (a GPU; assumed)", 0.1)):
            print(f"\n### Modelled efficiency, 1920x1080, one minute, adaptive sampling; MPI over {net}; "
                  f"passes: {label}\n")
            print("| ranks | passes | w | t_refresh s, tree / pipelined | t_reduce s, tree / pipelined | "
                  "--spp or --time, tree / pipelined | --target-error (k reductions), tree / pipelined |")
            print("|---|---|---|---|---|---|---|")
            for ranks in (2, 16, 64):
                levels = math.ceil(math.log2(ranks))
                mpi = red["mpi_s"] * scale
                fixed = red["read_s"] + red["restore_s"]
                tree, pipe = fixed + levels * mpi, fixed + mpi
                refresh_mpi = red["refresh_mpi_s"] * scale
                w_tree = red["refresh_local_s"] + levels * refresh_mpi
                w_pipe = red["refresh_local_s"] + 2 * (ranks - 1) / ranks * refresh_mpi
                passes = max(2.0, ranks * 60 / pass_time)
                imbalance = 2 * pass_time / ranks
                w = 0 if not red["refresh_local_s"] else 1 + int(math.log(max(1.0, passes / 16)) / math.log(1.25))
                k_sparse = 2 + max(0, math.ceil(math.log(max(1.0, passes / 16), 4)))
                eff = lambda n, t, wt: 60 / (60 + n * t + w * wt + imbalance)
                print(f"| {ranks} | {passes:.0f} | {w} | {w_tree:.3f} / {w_pipe:.3f} | {tree:.3f} / {pipe:.3f} | "
                      f"{eff(1, tree, w_tree):.3f} / {eff(1, pipe, w_pipe):.3f} | "
                      f"{eff(k_sparse, tree, w_tree):.3f} / {eff(k_sparse, pipe, w_pipe):.3f} (k = {k_sparse}) |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--target", type=float, nargs=2, default=[0.005, 0.01],
                    help="target relMSE of the Cornell box and the showcase")
    ap.add_argument("--skip-scaling", action="store_true", help="only the reduction cost and the model")
    ap.add_argument("--repeat", type=int, default=1, help="runs of each configuration (interleaved); rows are medians")
    ap.add_argument("--scenes", nargs="*", choices=["cornell", "showcase"], default=["cornell", "showcase"])
    ap.add_argument("--skip-model", action="store_true", help="no 1080p reduction and model")
    ap.add_argument("--most-ranks", type=int, default=2, help="ranks (and threads) up to this many")
    ap.add_argument("--uniform", action="store_true", help="--no-adaptive (every pixel alike)")
    args = ap.parse_args()
    if args.uniform:
        UNIFORM.append("--no-adaptive")
    if not os.path.exists(BINARY):
        sys.exit(f"{BINARY}: build caustica first (with MPI: libopenmpi-dev)")
    if not args.skip_scaling:
        for (name, scene, size), target, key in zip(SCENES, args.target, ["cornell", "showcase"]):
            if key in args.scenes:
                scaling(name, scene, size, target, max(1, args.repeat), max(2, args.most_ranks))
    if args.skip_model:
        return
    red = reduction_cost()
    # A 1080p pass on one thread: the 2-spp render on 2 ranks traced 2
    # passes' samples, half on each, in its time less the reduction.
    model(red, max(1e-3, red["seconds"] - red["reduce_s"] + red["wait_s"]))


if __name__ == "__main__":
    main()
