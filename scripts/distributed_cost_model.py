#!/usr/bin/env python3
"""Communication-cost model of data-parallel training (docs/distributed.md): efficiency at K ranks."""
import argparse
import math

PARAMETERS = 3.69e6  # paper_network at width 128 (docs/model-format.md)


def step_comm_seconds(ranks, bandwidth_bytes, latency_s, bn_layers, bn_channels):
    """Seconds of communication in one step: ring allreduce of the gradients plus the
    latency-bound batch-norm sums (2 in the forward pass, 1 in the backward, per layer)."""
    if ranks == 1:
        return 0.0
    gradient_bytes = 4 * PARAMETERS
    ring = 2 * (ranks - 1) / ranks * gradient_bytes / bandwidth_bytes + 2 * (ranks - 1) * latency_s
    bn_bytes = 8 * (2 * bn_channels + 1)
    tree = 2 * math.ceil(math.log2(ranks)) * (latency_s + bn_bytes / bandwidth_bytes)
    return ring + 3 * bn_layers * tree


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--compute", type=float, nargs="+", default=[0.1, 8.0],
                   help="seconds of computation per step on one rank (its rows of the batch)")
    p.add_argument("--latency-us", type=float, default=5.0, help="per-message latency")
    p.add_argument("--bn-layers", type=int, default=29, help="batch-norm layers (paper_network: 2 + 2 x 11 + 2 x 2 + 1)")
    p.add_argument("--bn-channels", type=int, default=128, help="channels of each (the width)")
    a = p.parse_args()
    networks = [("1 Gb/s", 1e9 / 8), ("10 Gb/s", 10e9 / 8), ("100 Gb/s", 100e9 / 8),
                ("400 Gb/s", 400e9 / 8)]
    print(f"gradient bytes per step: {4 * PARAMETERS / 1e6:.2f} MB; latency {a.latency_us} us")
    for compute in a.compute:
        print(f"\ncompute {compute} s per step per rank (weak scaling: rows per rank fixed)")
        print("| network | " + " | ".join(f"K={k}" for k in (8, 64, 512)) + " |")
        print("| --- | --- | --- | --- |")
        for name, bw in networks:
            cells = []
            for k in (8, 64, 512):
                comm = step_comm_seconds(k, bw, a.latency_us * 1e-6, a.bn_layers, a.bn_channels)
                cells.append(f"{compute / (compute + comm):.1%} ({comm * 1e3:.0f} ms)")
            print(f"| {name} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
