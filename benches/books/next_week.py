#!/usr/bin/env python3
"""raypool's next-week scene with the book's own numbers: reads `raypool scene next-week` on
stdin and the output of book_numbers.cc (400 box heights, then 1,000 sphere centres) from the
file named first, and prints the scene with those heights and centres. With a second argument
(a PNG of the book's earthmap.jpg, beside the scene file) the planet becomes the book's earth.

    raypool scene next-week | next_week.py numbers.txt [earthmap.png] > next-week-book.toml
"""
import re
import sys


def main():
    numbers = open(sys.argv[1]).read().split("\n")
    heights = [n for n in numbers[:400]]
    centres = [n.split() for n in numbers[400:1400]]
    assert len(heights) == 400 and all(len(c) == 3 for c in centres), "book_numbers.cc's output is short"
    earth = sys.argv[2] if len(sys.argv) > 2 else None
    header, boxes, spheres, out = None, 0, 0, []
    for line in sys.stdin.read().split("\n"):
        if line.startswith("["):
            header = line
        elif header == "[[box]]" and line.startswith("max = "):
            x, _, z = re.match(r"max = \[(.*)\]", line).group(1).split(", ")
            line = f"max = [{x}, {heights[boxes]}, {z}]"
            boxes += 1
        elif header == "[[group.sphere]]" and line.startswith("center = "):
            line = "center = [{}]".format(", ".join(centres[spheres]))
            spheres += 1
        elif earth and 'builtin = "planet"' in line:
            line = line.replace('builtin = "planet"', f'path = "{earth}"')
        out.append(line)
    assert boxes == 400 and spheres == 1000, f"raypool's next-week changed: {boxes} boxes, {spheres} small spheres"
    print("\n".join(out), end="")


if __name__ == "__main__":
    main()
