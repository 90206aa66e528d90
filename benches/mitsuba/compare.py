#!/usr/bin/env python3
"""Compares raypool's renders with the Mitsuba 3 references of `references.py` (issue #55).

For each scene, raypool renders the same scene file Mitsuba rendered (results/references/NAME.toml)
at 64 x 64 with N independent seeds, under each light sampling asked for (`mis`, the default, and
`bsdf`); the mean over seeds is compared with Mitsuba's mean, for the whole image and for each
8 x 8 block, on the average of the three channels:

    bias = (raypool mean - Mitsuba mean) / Mitsuba mean
    z    = (raypool mean - Mitsuba mean) / sqrt(SE_raypool^2 + SE_mitsuba^2)

each standard error taken from the spread of the independent seeds' means (of the region), on
both sides, never from the pixels of one image. The detectable bias of a region is 4.5 combined
standard errors over its Mitsuba mean for a block (the threshold a block must pass: |z| <= 4.5 over
64 blocks), 4 for the whole image. Writes (replaces) its section in results/accuracy-mitsuba.md.

    python3 benches/mitsuba/compare.py                        # the committed run: 16 seeds x 512 spp,
                                                              # mis and bsdf, 6 min on 2 cores
    python3 benches/mitsuba/compare.py --seeds 4 --spp 64 --out /tmp/quick.md   # a quick look
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shlex
import subprocess
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import references as R  # noqa: E402

# Scene -> raypool runs compared with its reference: (label, raypool's scene arguments).
RUNS = {
    "cornell-white": [("cornell, white diffuse ball", ["--scene-file", "{refs}/cornell-white.toml"])],
    "cornell": [
        ('cornell, glass `fresnel = "exact"`', ["--scene-file", "{refs}/cornell.toml"]),
        ("built-in cornell (Schlick glass)", ["--scene", "cornell"]),
    ],
    "cornell-smoke": [("built-in cornell-smoke", ["--scene-file", "{refs}/cornell-smoke.toml"])],
}


def rel(path: str) -> str:
    return os.path.relpath(path, R.ROOT)


def render_raypool(binary: str, scene_args: list[str], seed: int, spp: int, size: int, extra: list[str], out: str) -> None:
    cmd = [binary, "render", *scene_args, "--width", str(size), "--height", str(size), "--spp", str(spp), "--seed", str(seed), "--out", out, *extra]
    subprocess.run(cmd, check=True, cwd=R.ROOT, capture_output=True)


def stats(r_values: np.ndarray, m_values: np.ndarray):
    """Means and standard errors over seeds (axis 0) of both sides, the bias, its SE and z."""
    r, m = r_values.mean(axis=0), m_values.mean(axis=0)
    se_r = r_values.std(axis=0, ddof=1) / math.sqrt(len(r_values))
    se_m = m_values.std(axis=0, ddof=1) / math.sqrt(len(m_values))
    se = np.sqrt(se_r**2 + se_m**2)
    with np.errstate(divide="ignore", invalid="ignore"):
        return {"r": r, "m": m, "se_r": se_r, "se_m": se_m, "bias": (r - m) / m, "se_bias": se / m, "z": (r - m) / se}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenes", nargs="*", default=list(RUNS), choices=list(RUNS))
    ap.add_argument("--seeds", type=int, default=16, help="raypool's independent renders N")
    ap.add_argument("--spp", type=int, default=512)
    ap.add_argument("--first-seed", type=int, default=1, help="raypool's seeds first .. first+N-1")
    ap.add_argument("--light-sampling", nargs="*", default=["mis", "bsdf"])
    ap.add_argument("--raypool", default=R.RAYPOOL)
    ap.add_argument("--refs", default=R.OUT_DIR, help="where references.py wrote the references")
    ap.add_argument("--out", default=os.path.join(R.ROOT, "results", "accuracy-mitsuba.md"))
    ap.add_argument("--commit", default=None, help="the commit the binary was built from, if not HEAD's sources")
    ap.add_argument("--only", nargs="*", default=None, help="only the runs whose label contains one of these")
    args = ap.parse_args()
    if args.seeds < 8:
        print("warning: under 8 seeds, the standard errors (and so every z) are unreliable", file=sys.stderr)

    size, block = R.SIZE, R.BLOCK
    started = time.time()
    rows, notes = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.scenes:
            info = json.load(open(os.path.join(args.refs, f"{name}-mitsuba.json")))
            m_mean = R.read_pfm(os.path.join(args.refs, f"{name}-mitsuba.pfm"))
            assert m_mean.shape == (size, size, 3)
            m_blocks = np.array(info["per_seed"]["blocks"])
            m_image = np.array(info["per_seed"]["image"])
            assert np.allclose(m_blocks.mean(axis=0), R.blocks(m_mean.mean(axis=2)), rtol=1e-4, atol=1e-6)
            for label, scene_args in RUNS[name]:
                if args.only and not any(o in label for o in args.only):
                    continue
                refs = rel(args.refs) if args.refs.startswith(R.ROOT) else args.refs
                scene_args = [a.replace("{refs}", refs) for a in scene_args]
                for ls in args.light_sampling:
                    extra = ["--light-sampling", ls, "--depth", str(info["max_depth"])]
                    t0 = time.time()
                    r_blocks, r_image, r_sum = [], [], np.zeros((size, size, 3))
                    for seed in range(args.first_seed, args.first_seed + args.seeds):
                        out = os.path.join(tmp, "x.pfm")
                        try:
                            render_raypool(args.raypool, scene_args, seed, args.spp, size, extra, out)
                        except subprocess.CalledProcessError as e:
                            notes.append(f"{label}, `{ls}`: raypool refused it: {e.stderr.decode().strip()}")
                            break
                        img = R.read_pfm(out)
                        r_sum += img
                        grey = img.mean(axis=2)
                        r_blocks.append(R.blocks(grey, block))
                        r_image.append(grey.mean())
                    else:
                        took = time.time() - t0
                        whole = stats(np.array(r_image), m_image)
                        per = stats(np.array(r_blocks), m_blocks)
                        # Blocks Mitsuba sees black (none at depth 50) are left out of the figures.
                        lit = np.where(per["m"] > 0, per["m"], np.nan)
                        absz = np.abs(per["z"])
                        worst = np.unravel_index(np.nanargmax(absz), absz.shape)
                        detect = 4.5 * per["se_bias"]
                        # The image mean per channel, for the record.
                        r_ch = r_sum.reshape(-1, 3).mean(axis=0) / args.seeds
                        m_ch = m_mean.reshape(-1, 3).mean(axis=0)
                        rows.append(
                            {
                                "scene": name,
                                "label": label,
                                "ls": ls,
                                "cmd": " ".join(shlex.quote(a) for a in scene_args),
                                "bias": float(whole["bias"]),
                                "se": float(whole["se_bias"]),
                                "z": float(whole["z"]),
                                "worst_z": float(per["z"][worst]),
                                "worst_at": (int(worst[1]) * block, int(worst[0]) * block),
                                "worst_bias": float(per["bias"][worst]),
                                "worst_se": float(per["se_bias"][worst]),
                                "over45": int((absz > 4.5).sum()),
                                "blocks": int(np.isfinite(lit).sum()),
                                "detect_image": float(4 * whole["se_bias"]),
                                "detect_median": float(np.nanmedian(detect)),
                                "detect_max": float(np.nanmax(detect)),
                                "se_sides": (float(np.nanmedian(per["se_r"] / lit)), float(np.nanmedian(per["se_m"] / lit))),
                                "channels": ((r_ch - m_ch) / m_ch).tolist(),
                                "seconds": took,
                                "blocks_bias": per["bias"],
                                "blocks_z": per["z"],
                            }
                        )
                        row = rows[-1]
                        print(
                            f"{label} [{ls}]: whole {100 * row['bias']:+.2f}% +- {100 * row['se']:.2f}% (z {row['z']:+.1f}); "
                            f"worst block z {row['worst_z']:+.1f} at {row['worst_at']} ({100 * row['worst_bias']:+.2f}% +- {100 * row['worst_se']:.2f}%); "
                            f"detectable {100 * row['detect_median']:.1f}% (median block), {100 * row['detect_max']:.1f}% (worst); median block SE raypool {100 * row['se_sides'][0]:.2f}%, Mitsuba {100 * row['se_sides'][1]:.2f}%; {took:.0f} s",
                            flush=True,
                        )
    write_section(args, rows, notes, time.time() - started)


def git_head(commit: str | None) -> str:
    """The commit the binary was built from: `--commit`, or HEAD, marked when the sources that
    make the binary (src/, pool/, Cargo.*) have uncommitted changes."""
    if commit:
        return commit
    try:
        head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=R.ROOT, capture_output=True, text=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--", "src", "pool", "Cargo.toml", "Cargo.lock"], cwd=R.ROOT, capture_output=True, text=True).stdout.strip()
        return head + (" with uncommitted changes in src/ or pool/" if dirty else "")
    except OSError:
        return "unknown"


def write_section(args, rows, notes, seconds) -> None:
    refs = {}
    for name in args.scenes:
        refs[name] = json.load(open(os.path.join(args.refs, f"{name}-mitsuba.json")))
    cmd = "python3 benches/mitsuba/compare.py " + " ".join(
        f"--{k.replace('_', '-')} {' '.join(map(str, v)) if isinstance(v, list) else v}"
        for k, v in [("seeds", args.seeds), ("spp", args.spp), ("first_seed", args.first_seed), ("light_sampling", args.light_sampling), ("scenes", args.scenes)]
    ) + (f" --commit {args.commit}" if args.commit else "")
    lines = [
        "## raypool against Mitsuba 3 references (64 x 64)",
        "",
        f"Command: `{cmd}` (after `python3 benches/mitsuba/references.py`, whose settings each reference's JSON records).",
        f"Machine: {R.machine()}. raypool built from: `{git_head(args.commit)}`. Date: {time.strftime('%Y-%m-%d')}. "
        f"Mitsuba {refs[args.scenes[0]]['mitsuba']} (`scalar_rgb`). Compare step: {seconds / 60:.1f} min.",
        "",
        "Both sides at depth 50 (raypool `--depth 50` = Mitsuba `max_depth = 50`), conventions in "
        "[references/README.md](references/README.md). Figures on the average of the three channels; "
        "bias = (raypool − Mitsuba) / Mitsuba, its standard error and z from both sides' independent "
        "seeds. Detectable bias: 4 combined standard errors of the whole image, 4.5 of a block "
        "(median block, and the block where it is largest). The built-in cornell's glass reflects by "
        "Schlick's approximation and Mitsuba's by the Fresnel equations: that row is not like for like "
        "and is expected to differ in the ball's blocks (how well it is seen measures the comparison's "
        "power); the `fresnel = \"exact\"` row is the like-for-like one.",
        "",
        "| scene | raypool | light sampling | raypool seeds × spp | Mitsuba seeds × spp | whole image: bias ± SE | z | worst 8 × 8 block: z (x, y), bias ± SE | blocks over 4.5 | detectable: image / median block / worst block |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for row in rows:
        ref = refs[row["scene"]]
        m_seeds = ref["seeds"][1] - ref["seeds"][0] + 1
        x, y = row["worst_at"]
        lines.append(
            f"| {row['scene']} | {row['label']} (`{row['cmd']}`) | `{row['ls']}` | {args.seeds} × {args.spp} (seeds {args.first_seed}–{args.first_seed + args.seeds - 1}) "
            f"| {m_seeds} × {ref['spp']} (seeds {ref['seeds'][0]}–{ref['seeds'][1]}) "
            f"| {100 * row['bias']:+.2f}% ± {100 * row['se']:.2f}% | {row['z']:+.1f} "
            f"| {row['worst_z']:+.1f} ({x}–{x + 7}, {y}–{y + 7}), {100 * row['worst_bias']:+.2f}% ± {100 * row['worst_se']:.2f}% "
            f"| {row['over45']} / {row['blocks']} | {100 * row['detect_image']:.2f}% / {100 * row['detect_median']:.1f}% / {100 * row['detect_max']:.1f}% |"
        )
    lines += ["", "Whole image per channel, bias (raypool − Mitsuba) / Mitsuba:", "", "| scene | raypool | light sampling | R | G | B |", "|---|---|---|---|---|---|"]
    for row in rows:
        lines.append(f"| {row['scene']} | {row['label']} | `{row['ls']}` | " + " | ".join(f"{100 * c:+.2f}%" for c in row["channels"]) + " |")
    for row in rows:
        bad = np.argwhere(np.abs(row["blocks_z"]) > 4.5)
        if len(bad):
            lines.append("")
            lines.append(
                f"{row['scene']}, {row['label']}, `{row['ls']}`: blocks over |z| 4.5 (x, y: bias, z): "
                + "; ".join(f"({c * 8}, {r * 8}: {100 * row['blocks_bias'][r, c]:+.1f}%, {row['blocks_z'][r, c]:+.1f})" for r, c in bad)
                + "."
            )
    for note in notes:
        lines.append("")
        lines.append(note)
    section = "\n".join(lines) + "\n"
    head = "# raypool against independent references (Mitsuba 3)\n\n"
    existing = open(args.out).read() if os.path.exists(args.out) else head
    marker = "## raypool against Mitsuba 3 references (64 x 64)"
    if marker in existing:
        before, _, after = existing.partition(marker)
        nxt = after.find("\n## ")
        existing = before + section + (after[nxt + 1 :] if nxt >= 0 else "")
    else:
        existing = existing.rstrip("\n") + "\n\n" + section
    with open(args.out, "w") as f:
        f.write(existing)
    print(f"wrote {rel(args.out) if args.out.startswith(R.ROOT) else args.out}")


if __name__ == "__main__":
    main()
