"""strider.fuzzy.Engine against pyfuzzylite on pyfuzzylite's own example engines: the largest
difference of their outputs and the time each takes for arrays of 100,000 inputs.

    target/python-venv/bin/python python/bench/fuzzylite_speed.py [--inputs 100000] [--engines mamdani/laundry.fll …]

pyfuzzylite evaluates whole NumPy arrays too (fuzzylite 8's vectorized `Engine.process`); it is
fed pieces of 10,000 inputs so that its centroid's (inputs × resolution) arrays stay small.
`--scalar K` also times pyfuzzylite the way most code calls it, one input at a time (K inputs,
scaled to the whole array). Set RAYON_NUM_THREADS=1 to time strider on one core.
"""

from __future__ import annotations

import argparse
import glob
import os
import time

import fuzzylite as fl
import numpy as np

import strider
from strider.fuzzy import Engine

PIECE = 10_000


def pyfuzzylite_process(engine, xs, n):
    outs = {v.name: np.empty(n) for v in engine.output_variables}
    for start in range(0, n, PIECE):
        for v in engine.input_variables:
            v.value = xs[v.name][start : start + PIECE]
        engine.process()
        for v in engine.output_variables:
            outs[v.name][start : start + PIECE] = np.broadcast_to(np.asarray(v.value, dtype=float), (min(PIECE, n - start),))
    return outs


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--inputs", type=int, default=100_000)
    parser.add_argument("--engines", nargs="*")
    parser.add_argument("--scalar", type=int, default=0, help="inputs pyfuzzylite evaluates one at a time")
    args = parser.parse_args()
    root = os.path.join(os.path.dirname(fl.__file__), "examples")
    paths = sorted(glob.glob(os.path.join(root, "**", "*.fll"), recursive=True))
    if args.engines:
        paths = [os.path.join(root, e) for e in args.engines]
    rng = np.random.default_rng(1)
    header = f"{'engine':45} {'max |diff|':>10} {'pyfuzzylite s':>13} {'strider s':>10} {'ratio':>7}"
    print(header + (f" {'1-by-1 s':>10} {'ratio':>7}" if args.scalar else ""))
    ratios, scalar_ratios = [], []
    for path in paths:
        name = os.path.relpath(path, root)
        text = open(path).read()
        try:
            ours = Engine.from_fll(text, file=name)
        except strider.StriderError as e:
            print(f"{name:45} not loaded: {e}")
            continue
        theirs = fl.FllImporter().from_string(text)
        xs = {v.name: rng.uniform(v.minimum, v.maximum, args.inputs) for v in theirs.input_variables}
        clock = time.perf_counter()
        want = pyfuzzylite_process(theirs, xs, args.inputs)
        t_theirs = time.perf_counter() - clock
        ours.process({k: xs[k][:1000] for k in ours.inputs})  # warm up
        best = float("inf")
        for _ in range(3):
            clock = time.perf_counter()
            got = ours.process({k: xs[k] for k in ours.inputs})
            best = min(best, time.perf_counter() - clock)
        diff = max(
            float(np.nanmax(np.abs(want[k] - got[k]), initial=0.0)) if np.array_equal(np.isnan(want[k]), np.isnan(got[k])) else np.inf
            for k in want
        )
        ratios.append(t_theirs / best)
        line = f"{name:45} {diff:10.2g} {t_theirs:13.3f} {best:10.4f} {t_theirs / best:6.0f}×"
        if args.scalar:
            clock = time.perf_counter()
            for i in range(args.scalar):
                for v in theirs.input_variables:
                    v.value = float(xs[v.name][i])
                theirs.process()
                [np.asarray(v.value, dtype=float).item() for v in theirs.output_variables]
            t_one = (time.perf_counter() - clock) * args.inputs / args.scalar
            scalar_ratios.append(t_one / best)
            line += f" {t_one:10.1f} {t_one / best:6.0f}×"
        print(line)
    for label, r in (("vectorized", ratios), ("one by one", scalar_ratios)):
        if r:
            print(f"{label}: strider faster by min {min(r):.0f}×, median {np.median(r):.0f}×, max {max(r):.0f}× over {len(r)} engines")


if __name__ == "__main__":
    main()
