#!/usr/bin/env python3
"""Where a render's error lies (issue #58): `cornell` at the error bench's setting (96 x 96,
Sobol, edge points, depth 50), SEEDS renders of SPP samples each, every pixel's squared error
against the error bench's `bsdf` reference (2 x 8,192 spp, cached by `cargo bench --bench error
-- --only lights` under target/error-reference/), the reference's own noise taken out. Prints
the mean squared error, the share of it held by the worst 1% of pixels and by the worst 50,
and the worst pixels (row, column from the top left; their error over the mean). Flags after
`--` go to every render (e.g. `-- --roulette`). Results: results/mnee.md.

    benches/error_where.py target/release/raypool [--spp 64] [--seeds 4] [-- render flags]
"""
import os, re, struct, subprocess, sys, tempfile

REFERENCE = "target/error-reference/cornell-bsdf-sobol-96x96-8192-{}.pfm"
W = 96


def read_pfm(path):
    with open(path, "rb") as f:
        f.readline(); w, h = map(int, f.readline().split()); scale = float(f.readline())
        d = struct.unpack(("<" if scale < 0 else ">") + "%df" % (w * h * 3), f.read(w * h * 12))
    return [d[(h - 1 - y) * w * 3:(h - y) * w * 3] for y in range(h)]  # top row first


def main():
    args, extra = (sys.argv[1:], [])
    if "--" in args:
        args, extra = args[:args.index("--")], args[args.index("--") + 1:]
    arg = lambda name, default: int(args[args.index(name) + 1]) if name in args else default
    binary, spp, seeds = args[0], arg("--spp", 64), arg("--seeds", 4)
    if not all(os.path.exists(REFERENCE.format(k)) for k in "ab"):
        sys.exit("no reference: run `cargo bench --bench error -- --only lights` first")
    a, b = read_pfm(REFERENCE.format("a")), read_pfm(REFERENCE.format("b"))
    # The reference is the mean of two halves; its noise per channel is (a - b)^2 / 4.
    ref = [[(x + y) / 2 for x, y in zip(ra, rb)] for ra, rb in zip(a, b)]
    noise = sum((x - y) ** 2 / 4 for ra, rb in zip(a, b) for x, y in zip(ra, rb)) / (W * W * 3)
    per_pixel = [[0.0] * W for _ in range(W)]
    times = []
    with tempfile.TemporaryDirectory() as tmp:
        for seed in range(1, seeds + 1):
            out = os.path.join(tmp, f"{seed}.pfm")
            line = subprocess.run([binary, "render", "--scene", "cornell", "--width", str(W), "--spp", str(spp),
                                   "--seed", str(seed), "--threads", "1", "--mode", "serial", "--out", out, *extra],
                                  capture_output=True, text=True, check=True).stderr
            times.append(float(re.search(r": ([0-9.]+) s,", line).group(1)))
            image = read_pfm(out)
            for y in range(W):
                for x in range(W):
                    e = sum((image[y][3 * x + c] - ref[y][3 * x + c]) ** 2 for c in range(3)) / 3
                    per_pixel[y][x] += e / seeds
    flat = sorted(((per_pixel[y][x], y, x) for y in range(W) for x in range(W)), reverse=True)
    total = sum(e for e, _, _ in flat)
    mse = total / (W * W) - noise
    print(f"{seeds} seeds x {spp} spp, {' '.join(extra) or 'defaults'}: mean time {sum(times) / seeds:.3f} s, "
          f"MSE {mse:.3e} (reference noise {noise:.2e} taken out)")
    print(f"worst 1% of pixels: {sum(e for e, _, _ in flat[:W * W // 100]) / total:.1%} of the squared error; "
          f"worst 50: {sum(e for e, _, _ in flat[:50]) / total:.1%}")
    print("worst pixels (row, column, error / mean):",
          ", ".join(f"({y}, {x}, {e / (total / (W * W)):.0f})" for e, y, x in flat[:10]))


if __name__ == "__main__":
    main()
