#!/usr/bin/env python3
"""Light sampling measured: time to a given error on `cornell` and `cornell-smoke` under
--light-sampling bsdf, mixture, mis and bdpt, and adaptive sampling under mis (issue #36's first
figures; the error bench's plots are still to come), and on `cornell` with its glass sphere made
white: the light seen through glass is what no light sample can reach.

A reference is rendered under `mis` as two independent halves (seeds 101 and 102); its own
noise (a quarter of the halves' mean squared difference) is subtracted from every measured
mean squared error. Each setting renders at several spp (seed 3); its time is the render's own
summary line (median of RUNS runs); an adaptive row renders with --target-error E (at most
1,024 spp). Writes results/lights.md.

    benches/lights.py [--quick] [--bin target/release/raypool] [--out results/lights.md]
"""
import os
import re
import statistics
import struct
import subprocess
import sys
import tempfile
from datetime import date

QUICK = "--quick" in sys.argv
BIN = sys.argv[sys.argv.index("--bin") + 1] if "--bin" in sys.argv else "target/release/raypool"
OUT = sys.argv[sys.argv.index("--out") + 1] if "--out" in sys.argv else "results/lights.md"
SIDE = 48 if QUICK else 80
REF_SPP = 256 if QUICK else 2048
SCENES = ["cornell", "cornell-smoke", "cornell-white-sphere"]
# A scene made here from a built-in one: (built-in, text replaced, replacement).
DERIVED = {"cornell-white-sphere": ("cornell", 'radius = 90.0\nmaterial = "glass"', 'radius = 90.0\nmaterial = "white"')}
SPPS = {"bsdf": [16, 64, 256, 1024], "mixture": [16, 64, 256], "mis": [4, 16, 64, 256], "bdpt": [4, 16, 64, 256]}
TARGETS = [0.1, 0.05, 0.025]
RUNS = 1 if QUICK else 3
THREADS = "2"


def read_pfm(path):
    with open(path, "rb") as f:
        f.readline()
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        return struct.unpack(("<" if scale < 0 else ">") + "%df" % (w * h * 3), f.read(w * h * 12))


def scene_args(scene, tmp):
    """The flags that name `scene`: a built-in, or a file written for a derived scene."""
    if scene not in DERIVED:
        return ["--scene", scene]
    builtin, old, new = DERIVED[scene]
    text = subprocess.run([BIN, "scene", builtin], capture_output=True, text=True, check=True).stdout
    assert text.count(old) == 1, "the derived scene's text to replace is in %s once" % builtin
    path = os.path.join(tmp, scene + ".toml")
    with open(path, "w") as f:
        f.write(text.replace(old, new))
    return ["--scene-file", path]


def render(scene, light, spp, seed, out, extra=()):
    """Renders `scene` (its flags); `extra` (adaptive flags) replaces --spp with --max-spp."""
    spp_flag = ["--max-spp", str(spp)] if extra else ["--spp", str(spp)]
    args = [BIN, "render", *scene, "--width", str(SIDE), *spp_flag, "--seed", str(seed),
            "--light-sampling", light, "--threads", THREADS, "--out", out, *extra]
    line = subprocess.run(args, capture_output=True, text=True, check=True).stderr
    return float(re.search(r": ([0-9.]+) s,", line).group(1))


def mse(a, b):
    return sum((x - y) ** 2 for x, y in zip(a, b)) / len(a)


def measure(scene, tmp):
    """The rows of one scene: (method, spp or target, seconds, error), and the reference noise."""
    name, scene = scene, scene_args(scene, tmp)
    halves = []
    for seed in (101, 102):
        path = os.path.join(tmp, "%s-ref%d.pfm" % (name, seed))
        render(scene, "mis", REF_SPP // 2, seed, path)
        halves.append(read_pfm(path))
    reference = [(x + y) / 2 for x, y in zip(*halves)]
    ref_noise = mse(*halves) / 4
    runs = [(light, str(spp), spp, ()) for light, spps in SPPS.items() for spp in spps]
    runs += [("mis adaptive", "E = %g" % e, 1024, ("--target-error", str(e))) for e in TARGETS]
    rows = []
    for method, label, spp, extra in runs:
        path = os.path.join(tmp, "%s-%s-%s.pfm" % (name, method.replace(" ", "-"), label.replace(" ", "")))
        light = method.split()[0]
        seconds = statistics.median(render(scene, light, spp, 3, path, extra) for _ in range(RUNS))
        error = max(mse(read_pfm(path), reference) - ref_noise, 0.0)
        rows.append((method, label, seconds, error))
        print(name, method, label, seconds, error, file=sys.stderr)
    return rows, ref_noise


def main():
    tmp = tempfile.mkdtemp()
    cpu = subprocess.run(["sh", "-c", "lscpu | sed -n 's/^Model name: *//p' | head -1"], capture_output=True, text=True).stdout.strip()
    commit = subprocess.run(["git", "describe", "--always", "--dirty=+dirty"], capture_output=True, text=True).stdout.strip()
    md = ["# Light sampling: time to bsdf's error", ""]
    md.append("Command: `benches/lights.py%s` · nproc %d, %s, commit %s, %s" % (" --quick" if QUICK else "", os.cpu_count(), cpu, commit, date.today()))
    md.append("")
    target_spp = SPPS["bsdf"][-1]
    md.append("Each scene at %d × %d, depth 50, Sobol sampler, %s threads; each time the median of %d runs. Error: mean "
              "squared error per channel against a `mis` reference of %d spp (two halves of different seeds), the "
              "reference's own noise subtracted. *efficiency* = error × time (lower is better; constant in spp for an "
              "unbiased estimator whose error falls as 1/spp); *time to bsdf's error* = efficiency ÷ bsdf's error at %d "
              "spp, as a ratio of bsdf's time there. Adaptive rows: `--target-error E`, at most 1,024 spp a pixel."
              % (SIDE, SIDE, THREADS, RUNS, REF_SPP, target_spp))
    md.append("")
    md.append("`cornell-white-sphere` is `cornell` with its glass sphere made of the walls' white (written by this script "
              "from `raypool scene cornell`): what remains of `mis`'s error on `cornell` that the glass causes, paths "
              "that reach the light through the sphere, which no shadow ray can aim at.")
    summary = []
    for scene in SCENES:
        rows, ref_noise = measure(scene, tmp)
        target, bsdf_time = next((e, t) for m, l, t, e in rows if m == "bsdf" and l == str(target_spp))
        md += ["", "## %s (reference noise %.2e)" % (scene, ref_noise), ""]
        md.append("| light sampling | spp | time (s) | MSE | efficiency | time to bsdf's error (× bsdf's) |")
        md.append("|---|---:|---:|---:|---:|---:|")
        best = {}
        for method, label, seconds, error in rows:
            ratio = error * seconds / target / bsdf_time
            md.append("| %s | %s | %.3f | %.3e | %.3e | %.3f |" % (method, label, seconds, error, error * seconds, ratio))
            if not label.isdigit() or int(label) >= 64:
                best.setdefault(method, []).append(ratio)
        for method, ratios in best.items():
            summary.append("- `%s`, %s: **%.3f×** bsdf's time to bsdf's error (median over its rows at ≥ 64 spp or "
                           "its adaptive targets)." % (scene, method, statistics.median(ratios)))
    md += ["", "## Summary", ""] + summary
    with open(OUT, "w") as f:
        f.write("\n".join(md) + "\n")
    print("\n".join(md))


main()
