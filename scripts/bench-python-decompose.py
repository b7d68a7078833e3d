#!/usr/bin/env python3
"""Times the Python module's facetool.decompose on one photo in a loop, in one process (no process
start, the model loaded once): every layer, and each `--layers` list given.

  PYTHONPATH=build/python scripts/bench-python-decompose.py [PHOTO] [--repeats 20]
      [--layers normal --layers albedo,normal ...] [--rounds 3]

The photo is decoded once (facetool.read_image) and the array decomposed; the first call of each
list is a warm-up and left out. Lists run interleaved (A B A B ...) for --rounds rounds, so that
every figure comes from the same minutes; per list it prints the median and the fastest ms per
photo over all timed calls, and the ratio of medians to every layer's. Figures only: nothing is
asserted (the machine may be shared; the load average is printed beside them).
"""

import argparse
import os
import statistics
import time

import facetool


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("photo", nargs="?", default=os.path.join(here, "..", "examples", "photos", "grace_hopper_512x512.jpg"))
    parser.add_argument("--repeats", type=int, default=20, help="timed calls per list per round")
    parser.add_argument("--rounds", type=int, default=3, help="interleaved rounds over the lists")
    parser.add_argument("--layers", action="append", default=[],
                        help="a comma-separated list of layers (albedo, normal, visibility, shading, reconstruction); repeatable")
    parser.add_argument("--backend", default="cpu")
    args = parser.parse_args()
    if args.repeats < 1 or args.rounds < 1:
        parser.error("--repeats and --rounds must be at least 1")

    lists = [None] + [[name.strip() for name in text.split(",")] for text in args.layers]
    label = {0: "every layer"}
    for i, layers in enumerate(lists[1:], 1):
        label[i] = "layers=" + ",".join(layers)

    start = time.perf_counter()
    model = facetool.load_model(backend=args.backend)
    image = facetool.read_image(args.photo)
    print(f"model loaded in {time.perf_counter() - start:.2f} s; photo {image.shape[1]}x{image.shape[0]} "
          f"({os.path.basename(args.photo)}), {args.rounds} round(s) x {args.repeats} call(s) per list")
    for layers in lists:  # warm-up: kernels, caches, the detector's models
        model.decompose(image, layers=layers)
    times = {i: [] for i in range(len(lists))}
    for _ in range(args.rounds):
        for i, layers in enumerate(lists):
            for _ in range(args.repeats):
                t = time.perf_counter()
                model.decompose(image, layers=layers)
                times[i].append(1e3 * (time.perf_counter() - t))
    base = statistics.median(times[0])
    for i in range(len(lists)):
        median = statistics.median(times[i])
        print(f"{label[i]:40s} median {median:7.1f} ms, fastest {min(times[i]):7.1f} ms per photo, "
              f"{median / base:.2f}x every layer's")
    print("load average (1, 5, 15 min): " + ", ".join(f"{v:.2f}" for v in os.getloadavg()))


if __name__ == "__main__":
    main()
