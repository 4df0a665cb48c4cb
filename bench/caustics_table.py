#!/usr/bin/env python3
"""The photon pass on real scenes (issue 19): a benchmark table for docs/caustics.md.

For every official and community coursework scene (../shared/scenes-coursework,
read in place), path mode at W x H for S seconds with `--caustics auto` and
`--caustics off`: samples per pixel, the photon pass's share of render time
(host time tracing and gathering photon maps; the inline gathers inside the
shade stage are not in it), the estimated relMSE of each, how far past the
time limit the render ended, and what `auto` decided. Then equal-time error
against a long reference for scenes/caustics.json, scenes/caustics_point.json
and scenes/stiff_ground.json, and the official scene.json and mirror_image.json
(point lights: their caustics are the photon map's alone) (auto, on, off).
Prints Markdown.

  bench/caustics_table.py [--seconds 10] [--width 240 --height 160]
                          [--reference-seconds 240] [--only SUBSTRING]

Timings are wall time on this machine: run it with nothing else running.
"""
import argparse
import os
import platform
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.path.join(os.path.dirname(ROOT), "shared", "scenes-coursework")

WROTE = re.compile(r"wrote \S+ \((\d+)x(\d+), (\d+) spp\) in ([\d.]+) s(?:, estimated relMSE ([\d.e+-]+))?"
                   r"(?:, relMSE against the reference ([\d.e+-]+))?")
PHOTONS = re.compile(r"photons: (\d+) maps in ([\d.]+) s \(([\d.]+)% of the render\)")
FEATURES = re.compile(r"photon-pass=(yes|no) \(([^)]*)\)")
DECISION = re.compile(r"caustics auto: (.*)")


def run(binary, args):
    p = subprocess.run([binary] + args, capture_output=True, text=True)
    return p.returncode, p.stderr


def warm_up(binary, scene, mode, size):
    """One pass first, so that the timed render finds its kernels compiled
    (PoCL compiles a kernel's work-group function at its first launch)."""
    with tempfile.TemporaryDirectory() as tmp:
        run(binary, ["render", scene, "--mode", "path", "--width", str(size[0]), "--height", str(size[1]),
                     "--spp", "2", "--caustics", mode, "-q", "-o", os.path.join(tmp, "out.pfm")])


def render(binary, scene, mode, seconds, size, extra=()):
    warm_up(binary, scene, mode, size)
    with tempfile.TemporaryDirectory() as tmp:
        args = ["render", scene, "--mode", "path", "--width", str(size[0]), "--height", str(size[1]),
                "--time", str(seconds), "--caustics", mode, "-v", "-o", os.path.join(tmp, "out.pfm")] + list(extra)
        rc, err = run(binary, args)
    out = {"rc": rc, "error": None}
    if rc != 0:
        lines = [l for l in err.splitlines() if l.strip()]
        out["error"] = lines[-1] if lines else "exit %d" % rc
        return out
    m = WROTE.search(err)
    out["spp"] = int(m.group(3))
    out["seconds"] = float(m.group(4))
    out["estimate"] = float(m.group(5)) if m.group(5) else None
    out["true"] = float(m.group(6)) if m.group(6) else None
    p = PHOTONS.search(err)
    out["photon_share"] = float(p.group(3)) if p else 0.0
    out["maps"] = int(p.group(1)) if p else 0
    f = FEATURES.search(err)
    out["feature"] = f.groups() if f else ("?", "?")
    out["decisions"] = DECISION.findall(err)
    return out


def decision_summary(r):
    if r["feature"][0] != "yes":
        return "left out (%s)" % r["feature"][1]
    text = " ".join(r["decisions"])
    if "off after" in text:
        return "off after the first map" if "no map interval" in text else "off: caustic < 0.1% of the light"
    every = re.findall(r"every (\d+) pass", text)  # the latest: the errors' balance, if it came
    if every:
        return "kept, a map every %s pass%s" % (every[-1], "" if every[-1] == "1" else "es")
    return "on"


def fmt(x, spec="%.3g"):
    return "-" if x is None else spec % x


def machine():
    model = "?"
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return "%s, %d threads (PoCL pthread), %s" % (model, os.cpu_count() or 0, platform.platform())


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--binary", default=os.environ.get("CAUSTICA_BIN", os.path.join(ROOT, "build", "caustica")))
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--width", type=int, default=240)
    ap.add_argument("--height", type=int, default=160)
    ap.add_argument("--reference-seconds", type=float, default=240.0)
    ap.add_argument("--only", default="", help="only scenes whose file name contains this")
    ap.add_argument("--skip-corpus", action="store_true")
    ap.add_argument("--skip-references", action="store_true")
    a = ap.parse_args()
    size = (a.width, a.height)
    tolerance = max(0.5, 0.05 * a.seconds)

    print("Machine: %s. `bench/caustics_table.py --seconds %g --width %d --height %d`.\n" %
          (machine(), a.seconds, a.width, a.height))
    if not a.skip_corpus:
        scenes = []
        for sub in ("official", "community"):
            d = os.path.join(SHARED, sub)
            if os.path.isdir(d):
                scenes += [os.path.join(d, f) for f in sorted(os.listdir(d)) if f.endswith(".json")]
        scenes = [s for s in scenes if a.only in os.path.basename(s)]
        print("| scene | spp auto | spp off | auto / off | photon pass share | est. relMSE auto | est. relMSE off "
              "| past the limit (auto, off) | auto decided |")
        print("|---|---|---|---|---|---|---|---|---|")
        worst_ratio, worst_late = None, 0.0
        for scene in scenes:
            name = os.path.basename(scene)[:-5]
            auto = render(a.binary, scene, "auto", a.seconds, size)
            if auto["error"]:
                print("| %s | does not load: %s |||||||| " % (name, auto["error"].replace("|", "/")[:90]))
                continue
            off = render(a.binary, scene, "off", a.seconds, size)
            ratio = auto["spp"] / off["spp"] if off.get("spp") else None
            late = (auto["seconds"] - a.seconds, off["seconds"] - a.seconds)
            worst_late = max(worst_late, *late)
            if auto["feature"][0] == "yes" and ratio is not None:
                worst_ratio = ratio if worst_ratio is None else min(worst_ratio, ratio)
            print("| %s | %d | %d | %s | %s | %s | %s | %+.2f s, %+.2f s | %s |" %
                  (name, auto["spp"], off["spp"], fmt(ratio, "%.2f"), "%.1f%%" % auto["photon_share"],
                   fmt(auto["estimate"]), fmt(off["estimate"]), late[0], late[1], decision_summary(auto)))
            sys.stdout.flush()
        print("\nLowest auto / off where the pass was compiled: %s; latest end past the %g s limit: %+.2f s "
              "(bound %.2f s).\n" % (fmt(worst_ratio, "%.2f"), a.seconds, worst_late, tolerance))

    if a.skip_references:
        return
    print("Equal time (%g s each) against a long reference (`--caustics on --time %g --seed 99`; the photon map's "
          "bias is in it, its noise adds to every row alike):\n" % (a.seconds, a.reference_seconds))
    print("| scene | mode | spp | est. relMSE | relMSE vs reference |")
    print("|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for scene in ("caustics.json", "caustics_point.json", "stiff_ground.json", "official/scene.json",
                      "official/mirror_image.json"):
            path = (os.path.join(SHARED, scene) if scene.startswith("official/") else
                    os.path.join(ROOT, "scenes", scene))
            if not os.path.exists(path):
                continue
            ref = os.path.join(tmp, os.path.basename(scene) + ".pfm")
            rc, err = run(a.binary, ["render", path, "--mode", "path", "--width", str(size[0]), "--height",
                                     str(size[1]), "--time", str(a.reference_seconds), "--caustics", "on",
                                     "--seed", "99", "--no-error-estimate", "-q", "-o", ref])
            if rc != 0:
                print("| %s | reference failed: %s ||||" % (scene, err.strip().splitlines()[-1]))
                continue
            for mode in ("auto", "on", "off"):
                r = render(a.binary, path, mode, a.seconds, size, ["--reference", ref])
                print("| %s | %s | %d | %s | %s |" % (scene, mode, r["spp"], fmt(r["estimate"]), fmt(r["true"])))
                sys.stdout.flush()


if __name__ == "__main__":
    main()
