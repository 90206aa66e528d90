#!/usr/bin/env python3
"""Light sampling measured: time to a given error on `cornell` under --light-sampling bsdf,
mixture and mis (issue #36's first figures; the full error bench is still to come).

A reference is rendered under `mis` as two independent halves (seeds 101 and 102); its own
noise (a quarter of the halves' mean squared difference) is subtracted from every measured
mean squared error. Each setting renders at several spp (seed 3); its time is the render's own
summary line (median of RUNS runs). Writes results/lights.md.

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
SPPS = {"bsdf": [16, 64, 256, 1024], "mixture": [16, 64, 256], "mis": [4, 16, 64, 256]}
RUNS = 1 if QUICK else 3
THREADS = "2"


def read_pfm(path):
    with open(path, "rb") as f:
        f.readline()
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        return struct.unpack(("<" if scale < 0 else ">") + "%df" % (w * h * 3), f.read(w * h * 12))


def render(light, spp, seed, out):
    args = [BIN, "render", "--scene", "cornell", "--width", str(SIDE), "--spp", str(spp), "--seed", str(seed),
            "--light-sampling", light, "--threads", THREADS, "--out", out]
    line = subprocess.run(args, capture_output=True, text=True, check=True).stderr
    return float(re.search(r": ([0-9.]+) s,", line).group(1))


def mse(a, b):
    return sum((x - y) ** 2 for x, y in zip(a, b)) / len(a)


def main():
    tmp = tempfile.mkdtemp()
    halves = []
    for seed in (101, 102):
        path = os.path.join(tmp, "ref%d.pfm" % seed)
        render("mis", REF_SPP // 2, seed, path)
        halves.append(read_pfm(path))
    reference = [(x + y) / 2 for x, y in zip(*halves)]
    ref_noise = mse(*halves) / 4
    rows = []
    for light, spps in SPPS.items():
        for spp in spps:
            path = os.path.join(tmp, "%s-%d.pfm" % (light, spp))
            seconds = statistics.median(render(light, spp, 3, path) for _ in range(RUNS))
            error = max(mse(read_pfm(path), reference) - ref_noise, 0.0)
            rows.append((light, spp, seconds, error))
            print(light, spp, seconds, error, file=sys.stderr)
    # Error falls as 1/spp (unbiased Monte Carlo): the time each setting needs to reach bsdf's
    # error at its largest spp, from its own best-measured efficiency (error x time).
    target_spp = SPPS["bsdf"][-1]
    target = next(e for l, s, t, e in rows if l == "bsdf" and s == target_spp)
    bsdf_time = next(t for l, s, t, e in rows if l == "bsdf" and s == target_spp)
    cpu = subprocess.run(["sh", "-c", "lscpu | sed -n 's/^Model name: *//p' | head -1"], capture_output=True, text=True).stdout.strip()
    nproc = os.cpu_count()
    commit = subprocess.run(["git", "describe", "--always", "--dirty=+dirty"], capture_output=True, text=True).stdout.strip()
    md = ["# Light sampling on `cornell`: time to bsdf's error", ""]
    md.append("Command: `benches/lights.py%s` · nproc %d, %s, commit %s, %s" % (" --quick" if QUICK else "", nproc, cpu, commit, date.today()))
    md.append("")
    md.append("`cornell` at %d × %d, depth 50, Sobol sampler, %s threads; each time the median of %d runs. Error: mean squared "
              "error per channel against a `mis` reference of %d spp (two halves of different seeds), the reference's own "
              "noise (%.2e) subtracted. *efficiency* = error × time (lower is better; constant in spp for an unbiased "
              "estimator); *time to bsdf's error* = efficiency ÷ bsdf's error at %d spp, as a ratio of bsdf's time there."
              % (SIDE, SIDE, THREADS, RUNS, REF_SPP, ref_noise, target_spp))
    md.append("")
    md.append("| light sampling | spp | time (s) | MSE | efficiency | time to bsdf's error (× bsdf's) |")
    md.append("|---|---:|---:|---:|---:|---:|")
    best = {}
    for light, spp, seconds, error in rows:
        eff = error * seconds
        ratio = eff / target / bsdf_time
        md.append("| %s | %d | %.3f | %.3e | %.3e | %.3f |" % (light, spp, seconds, error, eff, ratio))
        if spp >= 64:
            best.setdefault(light, []).append(ratio)
    md.append("")
    for light, ratios in best.items():
        md.append("- `%s`: median over its runs of ≥ 64 spp, **%.3f×** bsdf's time to bsdf's error." % (light, statistics.median(ratios)))
    with open(OUT, "w") as f:
        f.write("\n".join(md) + "\n")
    print("\n".join(md))


main()
