#!/usr/bin/env python3
"""Prints a scene of 2,000 small sphere lights (radius 0.03) over a floor and a red ball, plus two
overlapping larger ones: the case where a shadow ray's density lookup cost as much as the shadow
ray (results/perf.md, fourteenth pass). Seeded, so the same file every time.

    benches/many_lights.py > /tmp/many-lights.toml
    target/release/raypool render --scene-file /tmp/many-lights.toml --width 300 --spp 16 --threads 1
"""
import random

random.seed(5)
print("""[camera]
lookfrom = [0.0, 3.0, 9.0]
lookat = [0.0, 1.0, 0.0]
vup = [0.0, 1.0, 0.0]
vfov = 40.0
focus_dist = 9.2

[background]
kind = "black"

[materials]
floor = { kind = "lambertian", albedo = [0.6, 0.6, 0.6] }
red = { kind = "lambertian", albedo = [0.7, 0.2, 0.2] }
lamp = { kind = "diffuse_light", emit = [4.0, 3.5, 3.0] }

[[quad]]
q = [-10.0, 0.0, -10.0]
u = [0.0, 0.0, 20.0]
v = [20.0, 0.0, 0.0]
material = "floor"

[[sphere]]
center = [0.0, 1.0, 0.0]
radius = 1.0
material = "red"
""")
for _ in range(2000):
    x, z, y = random.uniform(-6, 6), random.uniform(-6, 6), random.uniform(2.5, 5)
    print('[[sphere]]\ncenter = [%.4f, %.4f, %.4f]\nradius = 0.03\nmaterial = "lamp"\n' % (x, y, z))
for x in (2.0, 2.1):
    print('[[sphere]]\ncenter = [%.1f, 1.5, 1.0]\nradius = 0.2\nmaterial = "lamp"\n' % x)
