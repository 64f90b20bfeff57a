"""PIC, FLIP and APIC continued from one state, compared step by step.

The rotating disk (Jiang et al. 2017, Sec 6.1) runs with APIC to t0; three clones then switch
to PIC, FLIP and APIC and run on side by side. PIC loses energy and angular momentum in every
G2P, FLIP loses less, APIC keeps the angular momentum to round-off. Each step's diagnostics
come from the same columns as the CSV; every column beyond the base ones (the per-stage
conservation ledger, when a --set turns it on) is summed over the steps as well.

    PYTHONPATH=build/python python3 examples/python/schemes_from_one_state.py
"""
import argparse

import numpy as np

import apiclab

BASE = {"step", "t", "dt", "kinetic", "kinetic_grid", "potential", "total", "px", "py", "pz",
        "Lx", "Ly", "Lz", "newton_iters", "cg_iters", "residual", "wall_s", "dt_limit"}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default="rotating-disk")
    parser.add_argument("--t0", type=float, default=0.25, help="time of the shared state (s)")
    parser.add_argument("--steps", type=int, default=40, help="steps after the switch")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help="scene overrides, as apiclab run --set")
    args = parser.parse_args()

    start = apiclab.Simulation(args.scene, set=args.set)
    start.advance(args.t0)
    initial = start.measure()
    e0, l0 = initial["total"][0], initial["Lz"][0]
    print(f"{args.scene} at t = {start.time:.4f} s after {start.steps} APIC steps: "
          f"E = {e0:.6e}, Lz = {l0:.6e}")

    print(f"{'scheme':6s} {'dE/E0':>12s} {'dLz/Lz0':>12s}")
    for scheme in ("pic", "flip", "apic"):
        sim = start.clone()
        sim.clear_diagnostics()
        sim.set_scheme(scheme)
        for _ in range(args.steps):
            sim.step()
        d = sim.diagnostics()
        print(f"{scheme:6s} {(d['total'][-1] - e0) / e0:12.3e} {(d['Lz'][-1] - l0) / l0:12.3e}")
        for name in d:
            if name not in BASE and not isinstance(d[name], list):
                print(f"       {name}: sum over the steps {float(np.sum(d[name])):.3e}")


if __name__ == "__main__":
    main()
