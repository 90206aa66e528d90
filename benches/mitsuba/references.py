#!/usr/bin/env python3
"""Independent references for raypool's lit scenes, rendered by Mitsuba 3 (issue #55, item 3).

Converts raypool's scene files (TOML, as `raypool scene NAME` prints them) into Mitsuba 3 scenes
(Python dicts for `mi.load_dict`, variant `scalar_rgb`) and renders each at 64 x 64 with K
independent seeds (`mi.render(..., seed=k)`); stores the per-pixel mean and the standard error of
that mean over the seeds as PFMs, plus each seed's 8 x 8-block and whole-image means (JSON), in
results/references/. `benches/mitsuba/compare.py` compares raypool's renders with them.

    python3 benches/mitsuba/references.py                   # the committed references: every scene,
                                                            # 16 seeds x 1,024 spp (7 min on 2 cores)
    python3 benches/mitsuba/references.py --scenes cornell-white --seeds 8 --spp 256 --out-dir /tmp/refs
    python3 benches/mitsuba/references.py --check-camera    # depth 1 against the exact image

Conventions, each read from raypool's source and checked by rendering both programs (see
results/references/README.md: orientation, depth 1 and 2), so that both compute the same integral:

| what | raypool | Mitsuba 3 as written here |
|---|---|---|
| camera | `lookfrom`, `lookat`, `vup`, `vfov` = vertical field of view in degrees; pinhole when `aperture = 0` (src/tracer/camera.rs) | `perspective`, `to_world = look_at(lookfrom, lookat, vup)`, `fov = vfov`, `fov_axis = 'y'`; aperture 0 only (a lens is refused) |
| image rows | row 0 at the top; its PFM writer stores rows bottom-to-top, as the format says (src/files/output.rs) | `mi.render` gives row 0 at the top; `write_pfm` below stores bottom-to-top. Image right is world -x for the Cornell camera in both (checked by `--check`: no flip) |
| pixel filter | each sample uniform in its pixel square, pixel = plain mean (camera.rs) | `hdrfilm` with `rfilter = box` (radius 0.5: a sample lands in its own pixel only), `independent` sampler |
| quad | `q + a u + b v`, a, b in [0, 1]; front = `u x v` (src/tracer/geometry/quad.rs) | `rectangle` ([-1, 1]^2, normal +z) with `to_world` columns `u/2, v/2, unit(u x v), q + u/2 + v/2`: its normal is `u x v` (asserted) |
| lights | `diffuse_light`: radiance `emit` from the front face only; absorbs what arrives (`albedo` 0) (src/tracer/shading/material.rs) | `area` emitter (one-sided, emits along the shape's normal) on the rectangle above, and a black `diffuse` BSDF (Mitsuba's default BSDF would reflect 50%) |
| lambertian | two-sided: the normal faces the ray (a Cornell wall's `u x v` points out of the room) | `twosided` around `diffuse` (Mitsuba's `diffuse` is black from behind) |
| glass | `dielectric`, `ior` relative to outside; Schlick's reflectance by default, `fresnel = "exact"` for the Fresnel equations | `dielectric`, `int_ior = ior`, `ext_ior = 1.0`: always exact Fresnel, so the reference stands for raypool's `fresnel = "exact"`. (Mitsuba scales radiance by 1/eta^2 entering and eta^2 leaving: the same for every path that enters and leaves the ball) |
| box | six outward quads between `min` and `max` (`box_faces`), placed by rotate_x, then rotate_y, then rotate_z (degrees, counter-clockwise seen from +axis), then translate (src/scenes/world.rs, src/tracer/math/transform.rs) | the same six quads, transformed here by the same matrices, each a `rectangle`; so the boxes stand on the floor at y = 0 exactly as raypool places them |
| medium | the book's constant medium: inside a closed boundary, free flights of density `d`, isotropic phase, `albedo` scattered (object.rs `Medium::hit`); the boundary itself is invisible | the boundary's faces with a `null` BSDF and `interior` = `homogeneous` (`sigma_t = d`, `albedo`, isotropic phase), integrator `volpath`. A face lying in the plane of an opaque quad (a smoke box's bottom on the floor) is left out: the floor closes the volume, and a null face coplanar with the floor would let paths slip through it or leave the medium on the floor |
| depth | `--depth N`: at most N rays per path, camera ray included (depth 1 = only what the camera sees; default 50) | `max_depth = N` (1 = directly visible emitters only; 2 = direct light). A medium scattering counts as a bounce in both; a null face counts in neither (raypool has none) |
| roulette | off by default (`--roulette` unbiased) | Mitsuba's default `rr_depth = 5`: unbiased, changes noise only |
| background | `kind = "black"` | no environment emitter |
| colour | linear RGB, three independent channels | `scalar_rgb`: RGB reflectances and radiances used as given (no spectral upsampling) |

Not converted (raises): textures (Perlin noise, images), motion blur (`center1`), fuzzy metal,
hollow spheres, meshes, groups, a lens, a sky. So `next-week` (Perlin marble, an image-textured
planet, a moving sphere, 1,000 spheres in an instance) has no reference.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import subprocess
import sys
import tempfile
import time
import tomllib

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
OUT_DIR = os.path.join(ROOT, "results", "references")
RAYPOOL = os.path.join(ROOT, "target", "release", "raypool")
SIZE = 64
BLOCK = 8

# name -> (how its TOML is made from a built-in scene, whether Mitsuba needs volpath)
SCENES = {
    # The cleanest comparison: cornell with its glass ball replaced by a white diffuse one.
    "cornell-white": ("cornell", "white-ball"),
    # cornell with the glass Mitsuba has (exact Fresnel); raypool renders this file, and
    # its built-in cornell (Schlick) is compared with it too, to show Schlick's difference.
    "cornell": ("cornell", "exact-glass"),
    "cornell-smoke": ("cornell-smoke", None),
}


# ---------------------------------------------------------------------------------------------
# PFM (rows stored bottom-to-top, as the format and raypool's writer do; arrays top row first)


def read_pfm(path: str) -> np.ndarray:
    with open(path, "rb") as f:
        data = f.read()
    fields, at = [], 0
    while len(fields) < 4:
        while data[at : at + 1].isspace():
            at += 1
        start = at
        while not data[at : at + 1].isspace():
            at += 1
        fields.append(data[start:at].decode())
    at += 1
    assert fields[0] == "PF", f"{path}: not a colour PFM"
    w, h, scale = int(fields[1]), int(fields[2]), float(fields[3])
    pixels = np.frombuffer(data[at:], dtype="<f4" if scale < 0 else ">f4").reshape(h, w, 3)
    return pixels[::-1].astype(np.float64)  # top row first


def write_pfm(path: str, image: np.ndarray) -> None:
    h, w, _ = image.shape
    with open(path, "wb") as f:
        f.write(f"PF\n{w} {h}\n-1.0\n".encode())
        f.write(np.ascontiguousarray(image[::-1], dtype="<f4").tobytes())


# ---------------------------------------------------------------------------------------------
# Scene files


def scene_toml(builtin: str, variant: str | None, raypool: str = RAYPOOL) -> str:
    """The TOML both programs render: `raypool scene BUILTIN`, edited for the variant."""
    text = subprocess.run([raypool, "scene", builtin], check=True, capture_output=True, text=True).stdout
    if variant == "white-ball":
        # The [[sphere]] table's material (the glass ball) becomes the walls' white.
        head, sep, tail = text.partition("[[sphere]]")
        assert sep and 'material = "glass"' in tail, "cornell's ball is not where expected"
        text = head + sep + tail.replace('material = "glass"', 'material = "white"', 1)
        text = text.replace('[materials.glass]\nkind = "dielectric"\nior = 1.5\n\n', "")
    elif variant == "exact-glass":
        old = '[materials.glass]\nkind = "dielectric"\nior = 1.5\n'
        assert old in text, "cornell's glass is not written as expected"
        text = text.replace(old, old + 'fresnel = "exact"\n')
    else:
        assert variant is None, variant
    return text


def rot(axis: int, degrees: float) -> np.ndarray:
    """raypool's rotation matrices (transform.rs): counter-clockwise seen from +axis."""
    r = math.radians(degrees)
    # raypool's exact_sin_cos makes quarter turns exact; so do these roundings.
    s, c = math.sin(r), math.cos(r)
    if degrees % 90 == 0:
        s, c = round(s), round(c)
    if axis == 0:
        return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    if axis == 1:
        return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def placement(spec: dict | None):
    """(R, t) of a `transform` table: rotate x, then y, then z, then translate (world.rs)."""
    if not spec:
        return np.eye(3), np.zeros(3)
    r = rot(2, spec.get("rotate_z", 0.0)) @ rot(1, spec.get("rotate_y", 0.0)) @ rot(0, spec.get("rotate_x", 0.0))
    return r, np.array(spec.get("translate", [0.0, 0.0, 0.0]), dtype=float)


def box_faces(a, b):
    """raypool's `box_faces` (quad.rs): six (q, u, v), each facing outwards."""
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    d = hi - lo
    dx, dy, dz = np.array([d[0], 0, 0]), np.array([0, d[1], 0]), np.array([0, 0, d[2]])
    return [
        (np.array([lo[0], lo[1], hi[2]]), dx, dy),  # front, +z
        (np.array([hi[0], lo[1], hi[2]]), -dz, dy),  # right, +x
        (np.array([hi[0], lo[1], lo[2]]), -dx, dy),  # back, -z
        (lo.copy(), dz, dy),  # left, -x
        (np.array([lo[0], hi[1], hi[2]]), dx, -dz),  # top, +y
        (lo.copy(), dx, dz),  # bottom, -y
    ]


def rectangle(q, u, v, **extra) -> dict:
    """Mitsuba's rectangle covering raypool's quad (q, u, v), facing u x v."""
    import mitsuba as mi

    q, u, v = (np.asarray(x, dtype=float) for x in (q, u, v))
    n = np.cross(u, v)
    assert abs(np.dot(u, v)) <= 1e-9 * np.dot(u, u) ** 0.5 * np.dot(v, v) ** 0.5, "not a rectangle"
    n = n / np.linalg.norm(n)
    c = q + 0.5 * u + 0.5 * v
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = 0.5 * u, 0.5 * v, n, c
    to_world = mi.ScalarTransform4f(m.tolist())
    # Mitsuba's normal is the inverse transpose applied to +z: check it is u x v.
    normal = np.array(to_world.inverse_transpose @ mi.ScalarPoint4f(0, 0, 1, 0))[:3]
    assert np.dot(normal / np.linalg.norm(normal), n) > 1 - 1e-6
    return {"type": "rectangle", "to_world": to_world, **extra}


def coplanar(face, quads) -> bool:
    """Whether the face (q, u, v) lies in the plane of one of `quads`."""
    q, u, v = face
    n = np.cross(u, v)
    n /= np.linalg.norm(n)
    for q2, u2, v2 in quads:
        n2 = np.cross(u2, v2)
        n2 /= np.linalg.norm(n2)
        scale = max(1.0, np.abs(q2).max(), np.abs(q).max())
        if abs(abs(np.dot(n, n2)) - 1) < 1e-9 and abs(np.dot(q - q2, n2)) < 1e-9 * scale:
            return True
    return False


def to_mitsuba(scene: dict, width: int, height: int, spp: int, depth: int, integrator: str | None = None) -> dict:
    """The Mitsuba 3 scene (a dict for `mi.load_dict`) of a raypool scene (parsed TOML)."""
    import mitsuba as mi

    known = {"camera", "background", "materials", "quad", "box", "sphere", "medium", "textures"}
    unknown = set(scene) - known
    if unknown:
        raise ValueError(f"not converted: {sorted(unknown)}")
    if scene.get("textures"):
        raise ValueError("textures are not converted")
    if scene.get("background", {}).get("kind", "black") != "black":
        raise ValueError("only a black background is converted")
    cam = scene["camera"]
    if cam.get("aperture", 0.0) != 0.0:
        raise ValueError("only a pinhole camera (aperture 0) is converted")

    def material(ref) -> tuple[dict, dict | None]:
        """(bsdf, emitter or None) of a material reference."""
        spec = scene["materials"][ref] if isinstance(ref, str) else ref
        kind = spec["kind"]
        rgb = lambda c: {"type": "rgb", "value": [float(x) for x in c]}  # noqa: E731
        if kind == "lambertian":
            if "albedo" not in spec or spec.get("texture"):
                raise ValueError("textured lambertian is not converted")
            return {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": rgb(spec["albedo"])}}, None
        if kind == "dielectric":
            return {"type": "dielectric", "int_ior": float(spec["ior"]), "ext_ior": 1.0}, None
        if kind == "diffuse_light":
            albedo = float(spec.get("albedo", 0.0))
            bsdf = {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": rgb([albedo] * 3)}}
            return bsdf, {"type": "area", "radiance": rgb(spec["emit"])}
        if kind == "metal" and spec.get("fuzz", 0.0) == 0.0:
            # raypool's mirror reflects `albedo` at every angle: a conductor of no material.
            return {"type": "conductor", "material": "none", "specular_reflectance": rgb(spec["albedo"])}, None
        raise ValueError(f"material {spec} is not converted")

    out: dict = {"type": "scene"}
    depth = int(depth)
    media = scene.get("medium", [])
    out["integrator"] = {"type": integrator or ("volpath" if media else "path"), "max_depth": depth}
    out["sensor"] = {
        "type": "perspective",
        "to_world": mi.ScalarTransform4f().look_at(origin=cam["lookfrom"], target=cam["lookat"], up=cam["vup"]),
        "fov": float(cam["vfov"]),
        "fov_axis": "y",
        "near_clip": 1e-2,
        "far_clip": 1e6,
        "film": {
            "type": "hdrfilm",
            "width": width,
            "height": height,
            "rfilter": {"type": "box"},
            "pixel_format": "rgb",
            "sample_border": False,
        },
        "sampler": {"type": "independent", "sample_count": spp},
    }
    opaque_quads = []
    count = 0

    def add(shape: dict):
        nonlocal count
        out[f"shape{count:03d}"] = shape
        count += 1

    def add_quad(q, u, v, ref):
        bsdf, emitter = material(ref)
        extra = {"bsdf": bsdf}
        if emitter:
            extra["emitter"] = emitter
        add(rectangle(q, u, v, **extra))
        opaque_quads.append((np.asarray(q, float), np.asarray(u, float), np.asarray(v, float)))

    for quad in scene.get("quad", []):
        add_quad(quad["q"], quad["u"], quad["v"], quad["material"])
    for box in scene.get("box", []):
        r, t = placement(box.get("transform"))
        for q, u, v in box_faces(np.array(box["min"], float), np.array(box["max"], float)):
            add_quad(r @ q + t, r @ u, r @ v, box["material"])
    for sphere in scene.get("sphere", []):
        if "center1" in sphere:
            raise ValueError("moving spheres are not converted")
        if sphere["radius"] <= 0:
            raise ValueError("hollow spheres are not converted")
        bsdf, emitter = material(sphere["material"])
        shape = {"type": "sphere", "center": [float(x) for x in sphere["center"]], "radius": float(sphere["radius"]), "bsdf": bsdf}
        if emitter:
            shape["emitter"] = emitter
        add(shape)
    for k, medium in enumerate(media):
        boundary = medium["boundary"]
        name = f"medium{k}"
        out[name] = {
            "type": "homogeneous",
            "sigma_t": float(medium["density"]),
            "albedo": {"type": "rgb", "value": [float(x) for x in medium["albedo"]]},
            "scale": 1.0,
            "phase": {"type": "isotropic"},
        }
        r, t = placement(medium.get("transform"))
        if boundary["kind"] == "sphere":
            c = r @ np.array(boundary["center"], float) + t
            add({"type": "sphere", "center": c.tolist(), "radius": float(boundary["radius"]), "bsdf": {"type": "null"}, "interior": {"type": "ref", "id": name}})
            continue
        for q, u, v in box_faces(np.array(boundary["min"], float), np.array(boundary["max"], float)):
            face = (r @ q + t, r @ u, r @ v)
            if coplanar(face, opaque_quads):
                continue
            add(rectangle(*face, bsdf={"type": "null"}, interior={"type": "ref", "id": name}))
    return out


# ---------------------------------------------------------------------------------------------
# The camera check: at depth 1 an image is the lights' emission times the share of each pixel
# their projection covers, which is computed here exactly (each quad's corners projected by
# raypool's camera formulas, the polygon clipped to every pixel square). Both programs must
# give it; a flipped, shifted or rescaled image, or a wrong field of view, would not.


def project(cam: dict, width: int, height: int, points) -> list[tuple[float, float]]:
    """Pixel coordinates (x right, y down, from the top-left corner) of world points: raypool's
    `Camera::pixel_of` without the rounding."""
    c = np.array(cam["lookfrom"], float)
    w = c - np.array(cam["lookat"], float)
    focus = np.linalg.norm(w)
    w /= focus
    u = np.cross(cam["vup"], w)
    u /= np.linalg.norm(u)
    v = np.cross(w, u)
    vh = 2 * math.tan(math.radians(cam["vfov"]) / 2) * focus
    vw = vh * width / height
    du, dv = vw * u / width, -vh * v / height
    corner = c - focus * w - 0.5 * (vw * u - vh * v)
    out = []
    for p in points:
        to = np.asarray(p, float) - c
        on_film = c + to * (focus / np.dot(to, -w)) - corner
        out.append((np.dot(on_film, du) / np.dot(du, du), np.dot(on_film, dv) / np.dot(dv, dv)))
    return out


def clipped_area(poly, x0, x1, y0, y1) -> float:
    """Area of a convex polygon inside the rectangle [x0, x1] x [y0, y1] (Sutherland-Hodgman)."""
    edges = [(0, x0, 1), (0, x1, -1), (1, y0, 1), (1, y1, -1)]
    for axis, at, sign in edges:
        out = []
        for i in range(len(poly)):
            a, b = poly[i - 1], poly[i]
            ina, inb = sign * (a[axis] - at) >= 0, sign * (b[axis] - at) >= 0
            if ina != inb:
                t = (at - a[axis]) / (b[axis] - a[axis])
                out.append(tuple(a[k] + t * (b[k] - a[k]) for k in range(2)))
            if inb:
                out.append(b)
        poly = out
        if not poly:
            return 0.0
    x, y = np.array([p[0] for p in poly]), np.array([p[1] for p in poly])
    return 0.5 * abs(np.dot(x, np.roll(y, 1)) - np.dot(y, np.roll(x, 1)))


def exact_depth1(scene: dict, size: int) -> np.ndarray:
    """The exact depth-1 image (channels' average) of a scene whose lights are unoccluded quads."""
    image = np.zeros((size, size))
    for quad in scene.get("quad", []):
        ref = quad["material"]
        spec = scene["materials"][ref] if isinstance(ref, str) else ref
        if spec["kind"] != "diffuse_light":
            continue
        q, u, v = (np.array(quad[k], float) for k in "quv")
        if np.dot(np.cross(u, v), np.array(scene["camera"]["lookfrom"], float) - q) <= 0:
            continue  # the camera sees its back, which is black
        poly = project(scene["camera"], size, size, [q, q + u, q + u + v, q + v])
        grey = float(np.mean(spec["emit"]))
        for j in range(size):
            for i in range(size):
                image[j, i] += grey * clipped_area(poly, i, i + 1, j, j + 1)
    return image


def check_camera(names, raypool: str, size: int) -> None:
    """Depth 1: the exact image's mean against Mitsuba's (32 seeds x 256 spp) and raypool's
    (8 seeds x 256 spp), each with its standard error, and both images' largest pixel error."""
    import mitsuba as mi

    for name in names:
        builtin, variant = SCENES[name]
        text = scene_toml(builtin, variant, raypool)
        scene = tomllib.loads(text)
        exact = exact_depth1(scene, size)
        m = [img.mean(axis=2) for img in render_mitsuba(to_mitsuba(scene, size, size, 256, 1), range(1, 33), 256)]
        r = []
        with tempfile.TemporaryDirectory() as tmp:
            with open(os.path.join(tmp, "s.toml"), "w") as f:
                f.write(text)
            for seed in range(1, 9):
                out = os.path.join(tmp, "x.pfm")
                subprocess.run([raypool, "render", "--scene-file", os.path.join(tmp, "s.toml"), "--width", str(size), "--height", str(size), "--spp", "256", "--seed", str(seed), "--depth", "1", "--out", out], check=True, capture_output=True)
                r.append(read_pfm(out).mean(axis=2))
        e = exact.mean()
        for who, images in (("Mitsuba", m), ("raypool", r)):
            means = [x.mean() for x in images]
            mean, se = np.mean(means), np.std(means, ddof=1) / math.sqrt(len(means))
            worst = np.abs(np.mean(images, axis=0) - exact).max()
            print(f"{name} depth 1, {who} ({len(images)} seeds x 256 spp): image mean {mean:.6f} +- {se:.6f} "
                  f"against exact {e:.6f}: {100 * (mean / e - 1):+.3f}% (z {(mean - e) / se:+.1f}); largest pixel error {worst:.3f}", flush=True)


# ---------------------------------------------------------------------------------------------
# Rendering


def blocks(image: np.ndarray, block: int = BLOCK) -> np.ndarray:
    """Means of each block x block square of a (h, w) array: (h/block, w/block)."""
    h, w = image.shape
    return image.reshape(h // block, block, w // block, block).mean(axis=(1, 3))


def render_mitsuba(scene_dict: dict, seeds: range, spp: int) -> list[np.ndarray]:
    import mitsuba as mi

    scene = mi.load_dict(scene_dict)
    images = []
    for seed in seeds:
        images.append(np.array(mi.render(scene, seed=seed, spp=spp), dtype=np.float64)[:, :, :3])
    return images


def summarise(images: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray, dict]:
    """Mean, standard error of the mean per pixel, and each seed's block and image means
    (of the channels' average)."""
    stack = np.stack(images)
    mean = stack.mean(axis=0)
    se = stack.std(axis=0, ddof=1) / math.sqrt(len(images))
    grey = stack.mean(axis=3)
    per_seed = {
        "blocks": [blocks(g).round(9).tolist() for g in grey],
        "image": [float(g.mean()) for g in grey],
        "channels": [[float(c) for c in img.reshape(-1, 3).mean(axis=0)] for img in images],
    }
    return mean, se, per_seed


def machine() -> str:
    model = "unknown CPU"
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
        model = next(line.split(":", 1)[1].strip() for line in out.splitlines() if line.startswith("Model name"))
    except (OSError, StopIteration):
        pass
    return f"{os.cpu_count()} CPUs (`nproc`), {model}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenes", nargs="*", default=list(SCENES), choices=list(SCENES))
    ap.add_argument("--seeds", type=int, default=16, help="independent renders K (default 16)")
    ap.add_argument("--spp", type=int, default=1024, help="samples per pixel of each render (default 1024)")
    ap.add_argument("--first-seed", type=int, default=1000, help="seeds first-seed .. first-seed+K-1")
    ap.add_argument("--depth", type=int, default=50, help="raypool's --depth = Mitsuba's max_depth")
    ap.add_argument("--size", type=int, default=SIZE)
    ap.add_argument("--raypool", default=RAYPOOL, help="raypool binary (for `raypool scene`)")
    ap.add_argument("--out-dir", default=OUT_DIR)
    ap.add_argument("--check-camera", action="store_true", help="only the depth-1 check against the exact image")
    args = ap.parse_args()

    import mitsuba as mi

    mi.set_variant("scalar_rgb")
    if args.check_camera:
        check_camera([n for n in args.scenes if n != "cornell"], args.raypool, args.size)
        return
    os.makedirs(args.out_dir, exist_ok=True)
    for name in args.scenes:
        builtin, variant = SCENES[name]
        text = scene_toml(builtin, variant, args.raypool)
        toml_path = os.path.join(args.out_dir, f"{name}.toml")
        with open(toml_path, "w") as f:
            f.write(text)
        scene = tomllib.loads(text)
        seeds = range(args.first_seed, args.first_seed + args.seeds)
        start = time.time()
        images = render_mitsuba(to_mitsuba(scene, args.size, args.size, args.spp, args.depth), seeds, args.spp)
        took = time.time() - start
        mean, se, per_seed = summarise(images)
        write_pfm(os.path.join(args.out_dir, f"{name}-mitsuba.pfm"), mean)
        write_pfm(os.path.join(args.out_dir, f"{name}-mitsuba-se.pfm"), se)
        info = {
            "scene": name,
            "scene_file": f"results/references/{name}.toml",
            "mitsuba": mi.__version__,
            "variant": "scalar_rgb",
            "size": [args.size, args.size],
            "spp": args.spp,
            "seeds": [seeds.start, seeds.stop - 1],
            "max_depth": args.depth,
            "integrator": "volpath" if scene.get("medium") else "path",
            "seconds": round(took, 1),
            "machine": machine(),
            "date": time.strftime("%Y-%m-%d"),
            "per_seed": per_seed,
        }
        with open(os.path.join(args.out_dir, f"{name}-mitsuba.json"), "w") as f:
            json.dump(info, f, indent=1)
        g, gse = mean.mean(), math.sqrt(np.var(per_seed["image"], ddof=1) / len(images))
        print(f"{name}: {len(images)} seeds x {args.spp} spp in {took:.0f} s; image mean {g:.5f} +- {gse:.5f}", flush=True)


if __name__ == "__main__":
    sys.exit(main())
