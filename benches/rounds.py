#!/usr/bin/env python3
"""Before/after and sampler against sampler, in one run: paired ratios of raypool binaries.

Each round runs every (binary, sampler) pair on every scene, in an order rotated from round
to round, and the medians of the per-round ratios are printed: the first binary's time over
each other's (above 1 = the other is faster), and each binary's Sobol time over its
independent time (its sampler's price per sample). Absolute times drift by 10-50% on a shared
machine; ratios taken within a round cancel most of it. `final` renders 600 x 400, the other
scenes 400 wide; the flags after `--` go to every render.

    git worktree add ../today e9d8d27 && (cd ../today && cargo build --release)
    benches/rounds.py 11 today=../today/target/release/raypool now=target/release/raypool \\
        -- --spp 16 --threads 1 --mode serial

Options before the binaries: --scenes final,paper1 (default: the five scenes).
"""
import os
import re
import statistics
import subprocess
import sys
import tempfile

SAMPLERS = ["sobol", "independent"]


def main(argv):
    if "--" not in argv or len(argv) < 3 or not argv[0].isdigit() or int(argv[0]) < 1:
        sys.exit(__doc__)
    rounds, rest = int(argv[0]), argv[1:]
    scenes = ["final", "paper1", "paper2", "paper3", "three-spheres"]
    if rest[0] == "--scenes":
        scenes, rest = rest[1].split(","), rest[2:]
    split = rest.index("--")
    binaries = [arg.split("=", 1) for arg in rest[:split]]
    if not binaries or any(len(b) != 2 for b in binaries):
        sys.exit("rounds.py: name each binary as NAME=PATH, before the --")
    flags = rest[split + 1:]
    out = os.path.join(tempfile.mkdtemp(), "x.pfm")

    def seconds(binary, scene, sampler):
        size = ["--width", "600", "--height", "400"] if scene == "final" else ["--width", "400"]
        command = [binary, "render", "--scene", scene, *size, *flags, "--sampler", sampler, "--out", out]
        try:
            run = subprocess.run(command, capture_output=True, text=True)
        except OSError as error:
            sys.exit(f"rounds.py: cannot run {binary}: {error.strerror}")
        found = re.search(r"([0-9.]+) s,", run.stderr + run.stdout)
        if run.returncode != 0 or not found:
            sys.exit(f"{' '.join(command)}: {run.stderr.strip()}")
        return float(found.group(1))

    combos = [(name, path, sampler) for name, path in binaries for sampler in SAMPLERS]
    times = {}
    for r in range(rounds):
        for scene in scenes:
            k = r % len(combos)
            for name, path, sampler in combos[k:] + combos[:k]:
                times[r, scene, name, sampler] = seconds(path, scene, sampler)
        print(f"round {r + 1}/{rounds} done", file=sys.stderr, flush=True)

    def summary(ratios):
        return f"{statistics.median(ratios):.3f} ({min(ratios):.3f}-{max(ratios):.3f})"

    names = [name for name, _ in binaries]
    print(f"{rounds} rounds; final 600 x 400, others 400 wide; {' '.join(flags)}")
    for scene in scenes:
        for sampler in SAMPLERS:
            for name in names[1:]:
                ratios = [times[r, scene, names[0], sampler] / times[r, scene, name, sampler] for r in range(rounds)]
                print(f"{scene:14} {sampler:12} {names[0]} / {name}: {summary(ratios)}")
        for name in names:
            ratios = [times[r, scene, name, "sobol"] / times[r, scene, name, "independent"] for r in range(rounds)]
            medians = [statistics.median(times[r, scene, name, s] for r in range(rounds)) for s in SAMPLERS]
            print(f"{scene:14} sobol/indep  {name}: {summary(ratios)}, medians {medians[0]:.3f} s / {medians[1]:.3f} s")


if __name__ == "__main__":
    main(sys.argv[1:])
