#!/usr/bin/env python3
"""Equal-time comparison of adaptive and uniform sampling in caustica's path
tracer (issue 22; results for docs/adaptive.md; not part of the tests or CI).

For each scene, caustica renders the same image size for the same wall time
(--time) with --no-adaptive (every pixel gets the same samples) and with
--adaptive (after 16 spp each wave's samples go where the film's own error
estimate is: host/render/adaptive_sampling.h), once per seed, the two modes
interleaved (uniform, adaptive, uniform, adaptive, ...) so that drift of the
machine's speed hits both alike. Each render measures itself against a
reference (--reference, --report): the last row of its report is the final
image, whose relMSE (mean over pixels and channels of
(x - ref)^2 / (ref^2 + 0.01)) is the true error, est_relmse the render's own
estimate of it and spp its mean samples per pixel. Per scene the table gives
the mean relMSE over the seeds of each mode, their ratio adaptive / uniform
(below 1: adaptive sampling wins at equal time), the mean over seeds of the
adaptive render's estimate over its true error (1: the estimate that steers
the samples, and that --target-error stops on, is right) and the mean spp
of each mode (adaptive sampling's bookkeeping costs some samples).

    cmake --build build                  # build/caustica
    bench/adaptive_benchmark.py --time 10 --seeds 1 2 3 --size 128x128 \\
        --reference-spp 8192             # these are the defaults

Keep the machine otherwise idle while it runs: both modes get equal wall
time, so any other load skews the comparison. It takes about
scenes x seeds x 2 x (--time + ~2 s of start-up), plus each reference made
for the first time (minutes each at 8192 spp; cached). Progress goes to
stderr; the Markdown table to stdout and to <out-dir>/table.md.

Scenes (--scenes; default all of these, each rendered at --size):
scenes/cornell_box.json, scenes/caustics.json, scenes/showcase_path.json;
`furnace`, a diffuse sphere of albedo (0.5, 0.25, 0.75) under a white sky
(tests/test_path.cpp's kFurnace at 128x128) that this script writes into
bench/adaptive_cache/furnace.json; and three path-traced community scenes,
read where they are in ../shared/scenes-coursework/community/ (never copied
into the repository): Ninteedo__CGRaytracer__glass_spheres_pathtraced,
david14higgins__Pathtracer__area_lighting_pathtracer and
Kierandon__cpp-raytracer__path_dof. A scene that is missing or fails to
render is skipped with a warning that shows the renderer's error.

Reference: a long render, either found in --reference-dir (default
bench/mitsuba/cache/, bench/compare_mitsuba.py's cache: a file
STEM-HASH-WxH-Nspp-RENDERER.pfm with HASH that script's hash of the scene's
current bytes, N >= --reference-spp; a caustica one preferred, as it has no
scene-conversion bias, then a Mitsuba one, the higher N first: at 128x128
this picks the Mitsuba 16384-spp references of cornell_box and caustics and
caustica's of showcase_path), else our own, made once and cached in
bench/adaptive_cache/ under STEM-HASH-WxH-Nspp-caustica.pfm (HASH of the
scene file's bytes) by

    caustica render SCENE --mode path --width W --height H --spp N \\
        --no-adaptive --seed 12345 --report REF.csv -o REF.pfm -q

(caustica converges to Mitsuba's references, so its own long renders are
fair ones). The reference's own noise adds about the same relMSE to both
modes and pulls their ratio towards 1: the notes under the table give it
(the long render's own estimate, or compare_mitsuba.py's half-difference
estimate) and the ratio with it subtracted; raise --reference-spp when it
is more than a few percent of the adaptive error. Scene files that load
meshes or textures are keyed by the JSON's bytes only: clear the cache when
those change. --caustics is left at its default (auto) throughout.

Each run is
    caustica render SCENE --mode path --width W --height H --time T --seed S
        --adaptive|--no-adaptive --reference REF.pfm --report R.csv -o OUT.pfm -q
and the first seed's adaptive run also gets --spp-map MAP.png (--no-spp-maps
leaves it out; a caustica without the option is run again without it, with
a warning). The final relMSE is also recomputed here from OUT.pfm as a check.

Outputs, in --out-dir (default bench/adaptive_results/):
  table.md                 the table and its notes
  STEM.json                every run's numbers, the reference, the summary
  STEM-error.png           `caustica plot` of the first seed's two reports
                           (true relMSE solid, estimate dashed, against time)
  STEM-spp.png             the adaptive first-seed run's samples-per-pixel map
  reports/STEM-MODE-seedS.csv  every run's error report
Images and references stay in bench/adaptive_cache/ (ignored by git).
--dry-run prints the commands without running or writing anything.
"""
import argparse
import hashlib
import json
import math
import os
import re
import shlex
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from compare_mitsuba import read_pfm, rel_mse, scene_hash as mitsuba_scene_hash  # noqa: E402 (stdlib only)

CACHE = os.path.join(HERE, "adaptive_cache")
COMMUNITY = os.path.join(ROOT, "..", "shared", "scenes-coursework", "community")
COMMUNITY_SCENES = [
    "Ninteedo__CGRaytracer__glass_spheres_pathtraced.json",
    "david14higgins__Pathtracer__area_lighting_pathtracer.json",
    "Kierandon__cpp-raytracer__path_dof.json",
]
DEFAULT_SCENES = (["scenes/cornell_box.json", "scenes/caustics.json", "scenes/showcase_path.json", "furnace"] +
                  [os.path.join(COMMUNITY, s) for s in COMMUNITY_SCENES])
REFERENCE_SEED = 12345
MODES = ("uniform", "adaptive")

# tests/test_path.cpp's kFurnace at 128 x 128: every path leaves the convex
# sphere after one bounce weighted by the albedo exactly.
FURNACE_JSON = """{"nbounces": 8, "rendermode": "pathtracer",
  "camera": {"type": "pinhole", "width": 128, "height": 128, "position": [0, 0, -4], "lookAt": [0, 0, 0],
             "upVector": [0, 1, 0], "fov": 45},
  "scene": {"backgroundcolor": [1, 1, 1],
    "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1,
                "material": {"type": "diffuse", "albedo": [0.5, 0.25, 0.75]}}]}}
"""


def log(msg):
    print(msg, file=sys.stderr, flush=True)


def warn(msg):
    log("WARNING: " + msg)


def rel(path):
    """The path relative to the repository root (commands run there), or
    absolute when it is outside the root's parent folder."""
    r = os.path.relpath(os.path.abspath(path), ROOT)
    return r if not r.startswith(os.pardir + os.sep + os.pardir) else os.path.abspath(path)


def quote(cmd):
    return " ".join(shlex.quote(str(c)) for c in cmd)


def finite_or_none(v):
    return v if isinstance(v, (int, float)) and math.isfinite(v) else None


def mean(values):
    values = [v for v in values if v is not None]
    return sum(values) / len(values) if values else None


def output_tail(text, lines=15):
    return "\n".join("    " + l for l in text.strip().splitlines()[-lines:])


# ---------------------------------------------------------------- error reports


def read_report(path):
    """(header dict, rows as dicts of floats or None): host/app/error_report.h's format."""
    header, columns, rows = {}, None, []
    with open(path) as f:
        for line in f:
            line = line.rstrip("\r\n")
            if columns is None:
                if line.startswith("#"):
                    key, sep, value = line[1:].strip().partition(": ")
                    if sep:
                        header[key] = value
                    continue
                columns = line.split(",")
                continue
            if not line:
                continue
            fields = line.split(",")
            rows.append({c: (float(v) if v else None) for c, v in zip(columns, fields)})
    if columns is None or not rows:
        raise ValueError("%s: no rows (not a finished caustica error report)" % path)
    for needed in ("seconds", "spp", "est_relmse", "relmse"):
        if needed not in columns:
            raise ValueError("%s: no '%s' column in %s" % (path, needed, ",".join(columns)))
    return header, rows


# ---------------------------------------------------------------- scenes


class Scene:
    def __init__(self, stem, path, data, optional):
        self.stem, self.path, self.data, self.optional = stem, path, data, optional
        self.hash = hashlib.sha1(data).hexdigest()[:8]


def resolve_scenes(args):
    scenes, stems = [], set()
    for spec in args.scenes:
        optional = os.path.abspath(spec).startswith(os.path.abspath(COMMUNITY) + os.sep)
        if spec == "furnace":
            path, data = os.path.join(CACHE, "furnace.json"), FURNACE_JSON.encode()
            if not args.dry_run:
                os.makedirs(CACHE, exist_ok=True)
                if not os.path.isfile(path) or open(path, "rb").read() != data:
                    with open(path, "wb") as f:
                        f.write(data)
        else:
            path = spec if os.path.isfile(spec) else os.path.join(ROOT, spec)
            if not os.path.isfile(path):
                where = " (../shared is absent?)" if optional else ""
                warn("scene %s not found%s: skipped" % (spec, where))
                args.skipped.append((os.path.splitext(os.path.basename(spec))[0], "not found"))
                continue
            with open(path, "rb") as f:
                data = f.read()
        stem = os.path.splitext(os.path.basename(path))[0]
        base, k = stem, 2
        while stem in stems:
            stem, k = "%s_%d" % (base, k), k + 1
        stems.add(stem)
        scenes.append(Scene(stem, path, data, optional))
    return scenes


# ---------------------------------------------------------------- running caustica


def run(args, cmd, what, warn_on_failure=True):
    """(returncode, combined output, seconds); in --dry-run only prints."""
    print("$ " + quote(cmd), file=sys.stderr if not args.dry_run else sys.stdout, flush=True)
    if args.dry_run:
        return 0, "", 0.0
    t0 = time.perf_counter()
    p = subprocess.run(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    seconds = time.perf_counter() - t0
    if p.returncode != 0 and warn_on_failure:
        warn("%s failed (exit status %d):\n%s" % (what, p.returncode, output_tail(p.stdout)))
    return p.returncode, p.stdout, seconds


def size_args(args):
    return ["--width", str(args.width), "--height", str(args.height)]


# ---------------------------------------------------------------- references


def find_existing_reference(args, scene):
    """(path, info) of a reference in --reference-dir for this scene's bytes, or None."""
    if not args.reference_dir or not os.path.isdir(args.reference_dir):
        return None
    h = mitsuba_scene_hash(scene.path) if os.path.isfile(scene.path) else None
    pattern = re.compile(r"^%s-%s-%dx%d-(\d+)spp-(caustica|mitsuba)\.pfm$" %
                         (re.escape(scene.stem), h, args.width, args.height))
    found = []
    for name in os.listdir(args.reference_dir):
        m = pattern.match(name)
        if m and int(m.group(1)) >= args.reference_spp:
            found.append((m.group(2) != "caustica", -int(m.group(1)), name))
    if not found:
        return None
    name = sorted(found)[0][2]
    path = os.path.join(args.reference_dir, name)
    info = {"path": rel(path), "made_by": "bench/compare_mitsuba.py"}
    meta = path[:-4] + ".json"
    if os.path.isfile(meta):
        with open(meta) as f:
            m = json.load(f)
        for k in ("renderer", "spp", "seconds", "made"):
            if k in m:
                info[k] = m[k]
        if "own_rel_mse" in m:
            info["own_relmse"] = m["own_rel_mse"]
            info["own_relmse_how"] = "half difference"
    return path, info


def make_reference(args, scene):
    """(path, info) of this scene's reference: found, cached or rendered now; None on failure."""
    existing = find_existing_reference(args, scene)
    if existing:
        log("%s: reference %s" % (scene.stem, existing[1]["path"]))
        return existing
    name = "%s-%s-%dx%d-%dspp-caustica" % (scene.stem, scene.hash, args.width, args.height, args.reference_spp)
    path, meta_path = os.path.join(CACHE, name + ".pfm"), os.path.join(CACHE, name + ".json")
    if os.path.isfile(path) and os.path.isfile(meta_path):
        with open(meta_path) as f:
            info = json.load(f)
        info.update(path=rel(path), cached=True)
        log("%s: reference %s (cached)" % (scene.stem, info["path"]))
        return path, info
    tmp_pfm, tmp_csv = os.path.join(CACHE, name + ".tmp.pfm"), os.path.join(CACHE, name + ".tmp.csv")
    cmd = [args.caustica, "render", rel(scene.path), "--mode", "path"] + size_args(args) + [
        "--spp", str(args.reference_spp), "--no-adaptive", "--seed", str(REFERENCE_SEED),
        "--report", rel(tmp_csv), "-o", rel(tmp_pfm), "-q"]
    log("%s: making the reference (%d spp, cached once made)" % (scene.stem, args.reference_spp))
    rc, out, seconds = run(args, cmd, "%s: the reference render" % scene.stem)
    if args.dry_run:
        return path, {"path": rel(path), "dry_run": True}
    if rc != 0:
        return None
    info = {"path": rel(path), "cached": False, "made_by": "bench/adaptive_benchmark.py",
            "renderer": "caustica, %d spp uniform, seed %d" % (args.reference_spp, REFERENCE_SEED),
            "spp": args.reference_spp, "seconds": seconds, "scene": rel(scene.path), "scene_sha1_8": scene.hash,
            "command": quote(cmd), "made": time.strftime("%Y-%m-%d %H:%M:%S")}
    try:
        _, rows = read_report(tmp_csv)
        info["own_relmse"] = finite_or_none(rows[-1]["est_relmse"])
        info["own_relmse_how"] = "its own estimate"
    except (OSError, ValueError) as e:
        warn("%s: cannot read the reference's report: %s" % (scene.stem, e))
    os.replace(tmp_pfm, path)
    with open(meta_path, "w") as f:
        json.dump(info, f, indent=1)
    if os.path.exists(tmp_csv):
        os.remove(tmp_csv)
    log("%s: reference made in %.0f s" % (scene.stem, seconds))
    return path, info


# ---------------------------------------------------------------- one scene


def render_run(args, scene, ref_path, ref_values, mode, seed):
    """The run's numbers (a dict), or None when the render failed."""
    tag = "%s-%s-seed%d" % (scene.stem, mode, seed)
    report = os.path.join(args.out_dir, "reports", tag + ".csv")
    image = os.path.join(CACHE, "runs", tag + ".pfm")
    spp_map = os.path.join(CACHE, "runs", tag + "-spp.png")
    want_map = args.spp_maps and mode == "adaptive" and seed == args.seeds[0]
    for attempt in (want_map, False) if want_map else (False,):
        cmd = [args.caustica, "render", rel(scene.path), "--mode", "path"] + size_args(args) + [
            "--time", "%g" % args.time, "--seed", str(seed), "--" + ("adaptive" if mode == "adaptive" else "no-adaptive"),
            "--reference", rel(ref_path), "--report", rel(report), "-o", rel(image), "-q"]
        if attempt:
            cmd += ["--spp-map", rel(spp_map)]
        for stale in (report, image, spp_map):
            if not args.dry_run and os.path.exists(stale):
                os.remove(stale)
        rc, out, wall = run(args, cmd, "%s: %s seed %d" % (scene.stem, mode, seed), warn_on_failure=not attempt)
        if rc != 0 and attempt and "spp-map" in out:
            first = out.strip().splitlines()[0] if out.strip() else "no message"
            warn("caustica rejected --spp-map (%s): running again without it, and no spp maps from now on" % first)
            args.spp_maps = False
            continue
        if rc != 0 and attempt:
            warn("%s: %s seed %d failed (exit status %d):\n%s" % (scene.stem, mode, seed, rc, output_tail(out)))
        break
    if args.dry_run:
        return {"mode": mode, "seed": seed, "command": quote(cmd)}
    if rc != 0:
        return None
    header, rows = read_report(report)
    last = rows[-1]
    r = {"mode": mode, "seed": seed, "relmse": finite_or_none(last["relmse"]),
         "est_relmse": finite_or_none(last["est_relmse"]), "spp": int(last["spp"]), "seconds": last["seconds"],
         "process_seconds": wall, "mse": finite_or_none(last.get("mse")), "mae": finite_or_none(last.get("mae")),
         "report": rel(report), "image": rel(image), "command": quote(cmd),
         "device": header.get("device"), "report_mode": header.get("mode")}
    if not (header.get("mode") or "").endswith(" " + mode):
        warn("%s: the report's mode is '%s', not %s sampling" % (tag, header.get("mode"), mode))
    if attempt:
        if os.path.isfile(spp_map):
            r["spp_map"] = rel(spp_map)
        else:
            warn("%s: --spp-map was accepted but %s was not written" % (tag, rel(spp_map)))
    # The report's last row is the final image: recompute its relMSE here.
    try:
        w, h, values = read_pfm(image)
        r["relmse_check"] = rel_mse(values, ref_values)
        if r["relmse"] and abs(r["relmse_check"] - r["relmse"]) > 1e-3 * r["relmse"]:
            warn("%s: relMSE %.6g from %s, but the report's last row says %.6g" %
                 (tag, r["relmse_check"], rel(image), r["relmse"]))
    except (OSError, ValueError, SystemExit) as e:
        warn("%s: cannot check the image: %s" % (tag, e))
    if abs(r["seconds"] - args.time) > 0.1 * args.time:
        warn("%s: ran %.2f s for --time %g" % (tag, r["seconds"], args.time))
    log("  %-9s seed %d: relMSE %.4g (estimate %s), %d spp, %.2f s" %
        (mode, seed, r["relmse"] or float("nan"), "%.4g" % r["est_relmse"] if r["est_relmse"] else "-", r["spp"],
         r["seconds"]))
    return r


def summarise(runs, ref_info):
    s = {}
    for mode in MODES:
        rs = [r for r in runs if r["mode"] == mode]
        s[mode] = {
            "relmse_mean": mean([r["relmse"] for r in rs]),
            "est_relmse_mean": mean([r["est_relmse"] for r in rs]),
            "est_over_true_mean": mean([r["est_relmse"] / r["relmse"] if r["est_relmse"] and r["relmse"] else None
                                        for r in rs]),
            "spp_mean": mean([r["spp"] for r in rs]),
            "seconds_mean": mean([r["seconds"] for r in rs]),
            # relMSE x seconds is constant for an unbiased renderer: equal time exactly.
            "relmse_x_seconds_mean": mean([r["relmse"] * r["seconds"] if r["relmse"] is not None else None
                                           for r in rs]),
        }
    u, a = s["uniform"], s["adaptive"]
    s["ratio"] = a["relmse_mean"] / u["relmse_mean"] if u["relmse_mean"] and a["relmse_mean"] is not None else None
    s["ratio_time_normalised"] = (a["relmse_x_seconds_mean"] / u["relmse_x_seconds_mean"]
                                  if u["relmse_x_seconds_mean"] and a["relmse_x_seconds_mean"] is not None else None)
    by_seed = {}
    for r in runs:
        by_seed.setdefault(r["seed"], {})[r["mode"]] = r["relmse"]
    s["ratio_per_seed"] = {str(k): v["adaptive"] / v["uniform"] for k, v in by_seed.items()
                           if v.get("uniform") and v.get("adaptive") is not None}
    own = ref_info.get("own_relmse")
    if own is not None and s["ratio"] is not None and u["relmse_mean"] > own:
        # Reference noise adds (about) its own relMSE to both: subtract it.
        s["ratio_reference_noise_removed"] = max(a["relmse_mean"] - own, 0.0) / (u["relmse_mean"] - own)
    return s


def git_commit():
    try:
        head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=ROOT, capture_output=True, text=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=ROOT,
                               capture_output=True, text=True).stdout.strip()
        return head + (" (with uncommitted changes)" if dirty else "") if head else None
    except OSError:
        return None


def bench_scene(args, scene):
    log("== %s (%s)" % (scene.stem, rel(scene.path)))
    made = make_reference(args, scene)
    if made is None:
        args.skipped.append((scene.stem, "the reference render failed"))
        return None
    ref_path, ref_info = made
    ref_values = None
    if not args.dry_run:
        w, h, ref_values = read_pfm(ref_path)
        if (w, h) != (args.width, args.height):
            warn("%s: reference %s is %dx%d, not %dx%d: skipped" % (scene.stem, rel(ref_path), w, h, args.width,
                                                                   args.height))
            args.skipped.append((scene.stem, "reference of the wrong size"))
            return None
    runs = []
    for seed in args.seeds:
        for mode in MODES:  # interleaved: drift of the machine hits both modes
            r = render_run(args, scene, ref_path, ref_values, mode, seed)
            if r is None:
                args.skipped.append((scene.stem, "%s seed %d failed to render" % (mode, seed)))
                return None
            runs.append(r)
    first = [os.path.join(args.out_dir, "reports", "%s-%s-seed%d.csv" % (scene.stem, m, args.seeds[0]))
             for m in MODES]
    plot = os.path.join(args.out_dir, scene.stem + "-error.png")
    rc, _, _ = run(args, [args.caustica, "plot"] + [rel(p) for p in first] + ["-o", rel(plot)],
                   "%s: the plot" % scene.stem)
    spp_png = os.path.join(args.out_dir, scene.stem + "-spp.png")
    if args.dry_run:
        if args.spp_maps:
            print("$ cp %s %s" % (quote([rel(os.path.join(CACHE, "runs", "%s-adaptive-seed%d-spp.png" %
                                                           (scene.stem, args.seeds[0])))]), quote([rel(spp_png)])))
        return None
    result = {
        "scene": rel(scene.path), "stem": scene.stem, "scene_sha1_8": scene.hash,
        "width": args.width, "height": args.height, "time": args.time, "seeds": args.seeds,
        "reference": ref_info, "runs": runs, "summary": summarise(runs, ref_info),
        "plot": rel(plot) if rc == 0 and os.path.isfile(plot) else None, "spp_map": None,
        "caustica": rel(args.caustica) if os.path.isabs(args.caustica) else args.caustica,
        "commit": git_commit(), "made": time.strftime("%Y-%m-%d %H:%M:%S"),
        "command": quote([rel(sys.argv[0])] + sys.argv[1:]),
    }
    maps = [r["spp_map"] for r in runs if r.get("spp_map")]
    if maps:
        shutil.copyfile(os.path.join(ROOT, maps[0]), spp_png)
        result["spp_map"] = rel(spp_png)
    with open(os.path.join(args.out_dir, scene.stem + ".json"), "w") as f:
        json.dump(result, f, indent=1)
    return result


# ---------------------------------------------------------------- table


def fmt(v, spec):
    return spec % v if v is not None else "-"


def markdown(args, results):
    lines = ["| scene | time s | uniform relMSE | adaptive relMSE | adaptive/uniform | est/true (adaptive) "
             "| mean spp uniform | mean spp adaptive |",
             "|---|---|---|---|---|---|---|---|"]
    for res in results:
        s = res["summary"]
        u, a = s["uniform"], s["adaptive"]
        lines.append("| %s | %s / %s | %s | %s | %s | %s | %s | %s |" % (
            res["stem"], fmt(u["seconds_mean"], "%.1f"), fmt(a["seconds_mean"], "%.1f"),
            fmt(u["relmse_mean"], "%.3g"), fmt(a["relmse_mean"], "%.3g"), fmt(s["ratio"], "%.3f"),
            fmt(a["est_over_true_mean"], "%.2f"), fmt(u["spp_mean"], "%.0f"), fmt(a["spp_mean"], "%.0f")))
    seeds = " ".join(str(s) for s in args.seeds)
    notes = ["",
             "%dx%d, --time %g s, seeds %s; means over the seeds. \"time s\": the renders' measured seconds "
             "(uniform / adaptive). adaptive/uniform < 1: adaptive sampling has the lower error at equal time. "
             "est/true: the adaptive render's own relMSE estimate over its true relMSE." %
             (args.width, args.height, args.time, seeds), ""]
    for res in results:
        s, ref = res["summary"], res["reference"]
        own = ref.get("own_relmse")
        parts = ["reference %s (%s)" % (ref["path"], ref.get("renderer", "?"))]
        if own is not None:
            parts.append("its own relMSE ~%.2g (%s)" % (own, ref.get("own_relmse_how", "")))
        if s.get("ratio_reference_noise_removed") is not None:
            parts.append("ratio without it %.3f" % s["ratio_reference_noise_removed"])
        if s.get("ratio_time_normalised") is not None:
            parts.append("ratio of relMSE x seconds %.3f" % s["ratio_time_normalised"])
        if s.get("ratio_per_seed"):
            parts.append("per seed " + ", ".join("%.3f" % v for v in s["ratio_per_seed"].values()))
        notes.append("- %s: %s." % (res["stem"], "; ".join(parts)))
        if own is not None and s["adaptive"]["relmse_mean"] and own > 0.05 * s["adaptive"]["relmse_mean"]:
            notes.append("  (the reference's noise is %.0f%% of the adaptive error: raise --reference-spp)" %
                         (100 * own / s["adaptive"]["relmse_mean"]))
    for stem, why in args.skipped:
        notes.append("- %s: skipped (%s)." % (stem, why))
    notes.append("")
    notes.append("Made by `%s` (caustica %s)." % (quote([rel(sys.argv[0])] + sys.argv[1:]),
                                                  results[0]["commit"] if results and results[0]["commit"] else "?"))
    return "\n".join(lines + notes) + "\n"


# ---------------------------------------------------------------- main


def main():
    p = argparse.ArgumentParser(description="Adaptive against uniform sampling at equal wall time "
                                            "(see the module docstring).")
    p.add_argument("--scenes", nargs="+", default=DEFAULT_SCENES,
                   help="scene JSON files, or 'furnace' for the generated furnace scene (default: the 7 listed above)")
    p.add_argument("--time", type=float, default=10.0, help="seconds per render (default 10)")
    p.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3], help="seeds (default 1 2 3)")
    p.add_argument("--size", default="128x128", help="WxH (default 128x128)")
    p.add_argument("--reference-spp", type=int, default=8192,
                   help="spp of our own references; the least a --reference-dir one may have (default 8192)")
    p.add_argument("--reference-dir", default=os.path.join(HERE, "mitsuba", "cache"),
                   help="existing references, compare_mitsuba.py's naming (default bench/mitsuba/cache; '' for none)")
    p.add_argument("--caustica", default=os.path.join(ROOT, "build", "caustica"),
                   help="the caustica binary (default build/caustica)")
    p.add_argument("--out-dir", default=os.path.join(HERE, "adaptive_results"),
                   help="results folder (default bench/adaptive_results)")
    p.add_argument("--spp-maps", action=argparse.BooleanOptionalAction, default=True,
                   help="--spp-map on the first seed's adaptive run (default on)")
    p.add_argument("--dry-run", action="store_true", help="print the commands, run and write nothing")
    args = p.parse_args()
    m = re.fullmatch(r"(\d+)[xX](\d+)", args.size)
    if not m or int(m.group(1)) < 1 or int(m.group(2)) < 1:
        p.error("--size %s: expected WxH, e.g. 128x128" % args.size)
    args.width, args.height = int(m.group(1)), int(m.group(2))
    if args.time <= 0 or args.reference_spp < 1:
        p.error("--time and --reference-spp must be positive")
    if len(set(args.seeds)) != len(args.seeds):
        p.error("--seeds: each seed once")
    if os.sep in args.caustica:  # a path (else a name on PATH): commands run from the repository root
        full = os.path.abspath(args.caustica)
        args.caustica = "./" + rel(full) if full.startswith(ROOT + os.sep) else full
        if not args.dry_run and not os.access(full, os.X_OK):
            sys.exit("%s: no caustica binary there (cmake --build build, or --caustica PATH)" % args.caustica)
    args.skipped = []
    if not args.dry_run:
        for d in (CACHE, os.path.join(CACHE, "runs"), args.out_dir, os.path.join(args.out_dir, "reports")):
            os.makedirs(d, exist_ok=True)
        ignore = os.path.join(CACHE, ".gitignore")
        if not os.path.isfile(ignore):
            with open(ignore, "w") as f:
                f.write("*\n")

    results = []
    for scene in resolve_scenes(args):
        try:
            res = bench_scene(args, scene)
        except (OSError, ValueError) as e:
            warn("%s: %s: skipped" % (scene.stem, e))
            args.skipped.append((scene.stem, str(e)))
            res = None
        if res:
            results.append(res)
    if args.dry_run:
        return 0
    table = markdown(args, results)
    print(table, end="")
    with open(os.path.join(args.out_dir, "table.md"), "w") as f:
        f.write(table)
    log("results in %s/" % rel(args.out_dir))
    return 0 if results else 1


if __name__ == "__main__":
    sys.exit(main())
