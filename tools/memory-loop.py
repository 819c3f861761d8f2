#!/usr/bin/env python3
# measurement: resident memory across a long loop of renders in one Python process (docs/python.md). Run: target/pyvenv/bin/python tools/memory-loop.py [--renders 1000] [SCENE]
"""Resident memory across a long loop of renders in one Python process.

Loads one scene and renders N small jobs (different seeds and cameras, every AOV, so that
each render allocates and frees its film, AOVs and numpy arrays), printing the resident set
size after 10 renders and after N. A leak of even a few KiB per render shows as growth
between the two. A measurement, not a test: docs/instancing.md quotes its figure.

    target/pyvenv/bin/python tools/memory-loop.py [--renders 1000] [SCENE]
"""

import argparse
import math
import os
import time

import glint


def rss_mib() -> float:
    """Current resident set size of this process (Linux /proc), MiB."""
    with open("/proc/self/statm") as f:
        pages = int(f.read().split()[1])
    return pages * os.sysconf("SC_PAGE_SIZE") / 2**20


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", nargs="?", help="glTF file (default: the demo scene)")
    parser.add_argument("--renders", type=int, default=1000)
    parser.add_argument("--width", type=int, default=64)
    parser.add_argument("--height", type=int, default=36)
    parser.add_argument("--spp", type=int, default=4)
    args = parser.parse_args()
    scene = glint.load(args.scene)
    lo, hi = scene.bounds
    centre = [(a + b) / 2 for a, b in zip(lo, hi)]
    radius = max(b - a for a, b in zip(lo, hi))
    start = time.perf_counter()
    after_10 = None
    for i in range(args.renders):
        # A turntable: a new camera each render.
        angle = i * 0.0628
        position = (centre[0] + 1.5 * radius * math.sin(angle), centre[1] + 0.3 * radius,
                    centre[2] + 1.5 * radius * math.cos(angle))
        img = scene.render(width=args.width, height=args.height, spp=args.spp, seed=i,
                           camera={"position": position, "target": tuple(centre)},
                           aovs=list(glint.AOVS))
        assert img["radiance"].shape == (args.height, args.width, 3)
        del img
        if i + 1 == 10:
            after_10 = rss_mib()
    end = rss_mib()
    seconds = time.perf_counter() - start
    print(f"{scene.label}: {args.renders} renders of {args.width}x{args.height} at {args.spp} spp "
          f"with all AOVs in {seconds:.1f} s")
    print(f"RSS after 10 renders: {after_10:.1f} MiB; after {args.renders}: {end:.1f} MiB "
          f"({end - after_10:+.1f} MiB)")


if __name__ == "__main__":
    main()
