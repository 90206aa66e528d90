#!/usr/bin/env python3
"""Manifold next-event estimation measured (issue #36): `cornell` at 80 x 80 under `bsdf`
(1,024 spp) and under `mis` before and after manifold samples (256 spp), seeds 3, 4 and 5,
the two `mis` binaries alternated seed by seed. Error: mean squared error per channel against a
`mis` reference of 2 x 2,048 spp (seeds 101 and 102, the after binary), its own noise
subtracted; also split between the pixels whose footprint sees the glass ball and the rest
(as benches/bdpt_split.py). Time: each render's own summary line, median of the three seeds.
*time to bsdf's error* = error x time / (bsdf's error x bsdf's time). Writes results/mnee.md.
With --roulette, two more rows: `bsdf` (1,024 spp) and `mis` after (256 spp) with `--roulette`,
to show what Russian roulette does to each side of the ratio.

    benches/mnee.py --before OLD_BIN --after NEW_BIN [--out results/mnee.md] [--roulette]
"""
import math, os, re, statistics, struct, subprocess, sys, tempfile
from datetime import date

arg = lambda name, default=None: sys.argv[sys.argv.index(name) + 1] if name in sys.argv else default
BEFORE, AFTER, OUT = arg("--before"), arg("--after"), arg("--out", "results/mnee.md")
W, SEEDS = 80, (3, 4, 5)


def read_pfm(path):
    with open(path, "rb") as f:
        f.readline(); w, h = map(int, f.readline().split()); scale = float(f.readline())
        d = struct.unpack(("<" if scale < 0 else ">") + "%df" % (w * h * 3), f.read(w * h * 12))
    return [v for y in range(h) for v in d[(h - 1 - y) * w * 3:(h - y) * w * 3]]  # top row first


ROWS = [("bsdf", AFTER, "bsdf", 1024, []), ("mis before", BEFORE, "mis", 256, []), ("mis after", AFTER, "mis", 256, [])]
if "--roulette" in sys.argv:
    ROWS += [("bsdf --roulette", AFTER, "bsdf", 1024, ["--roulette"]), ("mis after --roulette", AFTER, "mis", 256, ["--roulette"])]


def render(binary, light, spp, seed, out, extra=()):
    line = subprocess.run([binary, "render", "--scene", "cornell", "--width", str(W), "--spp", str(spp), "--seed",
                           str(seed), "--light-sampling", light, "--threads", "2", "--out", out, *extra],
                          capture_output=True, text=True, check=True).stderr
    return float(re.search(r": ([0-9.]+) s,", line).group(1))


def sees_glass(x, y):
    """Whether the camera ray through pixel point (x, y) (from the top left) meets the ball."""
    o, c, r = (278.0, 278.0, -800.0), (190.0, 90.0, 190.0), 90.0
    d = [569.2 - 7.28 * x - o[0], 569.2 - 7.28 * y - o[1], -o[2]]
    n = math.sqrt(sum(v * v for v in d)); d = [v / n for v in d]
    oc = [o[k] - c[k] for k in range(3)]; b = sum(oc[k] * d[k] for k in range(3))
    return b * b - (sum(v * v for v in oc) - r * r) > 0


GLASS = [any(sees_glass(i + (a + 0.5) / 5, j + (b + 0.5) / 5) for a in range(5) for b in range(5))
         for j in range(W) for i in range(W)]


def split(f):
    e = [0.0, 0.0]
    for k in range(W * W):
        e[0 if GLASS[k] else 1] += sum(f(k, ch) for ch in range(3))
    return [v / (3 * W * W) for v in e]


tmp = tempfile.mkdtemp()
halves = []
for seed in (101, 102):
    render(AFTER, "mis", 2048, seed, "%s/ref%d.pfm" % (tmp, seed)); halves.append(read_pfm("%s/ref%d.pfm" % (tmp, seed)))
ref = [(a + b) / 2 for a, b in zip(*halves)]
noise = split(lambda k, ch: (halves[0][3 * k + ch] - halves[1][3 * k + ch]) ** 2 / 4)
rows = {}
for seed in SEEDS:
    for name, binary, light, spp, extra in ROWS:
        t = render(binary, light, spp, seed, "%s/img.pfm" % tmp, extra); img = read_pfm("%s/img.pfm" % tmp)
        e = split(lambda k, ch: (img[3 * k + ch] - ref[3 * k + ch]) ** 2)
        rows.setdefault(name, []).append((t, [x - n for x, n in zip(e, noise)]))
        print(name, seed, t, e, file=sys.stderr)
cpu = subprocess.run(["sh", "-c", "lscpu | sed -n 's/^Model name: *//p' | head -1"], capture_output=True, text=True).stdout.strip()
commit = subprocess.run(["git", "describe", "--always", "--dirty=+dirty"], capture_output=True, text=True).stdout.strip()
md = ["| setting | spp | time (s) | MSE | from glass pixels | from the rest | time to bsdf's error (x bsdf's) |",
      "|---|---:|---:|---:|---:|---:|---:|"]
stats = {}
for name, _, _, spp, _ in ROWS:
    t = statistics.median(r[0] for r in rows[name])
    g = statistics.mean(r[1][0] for r in rows[name]); rest = statistics.mean(r[1][1] for r in rows[name])
    stats[name] = (t, g + rest)
    md.append("| %s | %d | %.3f | %.3e | %.2e | %.2e | %s |" % (name, spp, t, g + rest, g, rest, "%.3f"))
base = stats["bsdf"][0] * stats["bsdf"][1]
md[2:] = [line % (stats[row[0]][0] * stats[row[0]][1] / base) for line, row in zip(md[2:], ROWS)]
head = ["Command: `benches/mnee.py --before %s --after %s` · nproc %d, %s, commit %s, %s" %
        (BEFORE, AFTER, os.cpu_count(), cpu, commit, date.today()), "",
        "cornell, 80 x 80, depth 50, Sobol, 2 threads; seeds %s, medians of their times, means of their errors; "
        "reference mis 2 x 2,048 spp (noise %.2e glass, %.2e rest, subtracted)." % (SEEDS, *noise), ""]
print("\n".join(head + md))
with open(OUT, "w") as f:
    f.write("\n".join(head + md) + "\n")
