"""Order of accuracy of the transfers: a sinusoidal shear flow against its analytic answer.

A periodic box of particles starts with v = (A sin(2 pi y), 0) and no forces worth the name
(E = 1e-12): the exact velocity field never changes, so whatever the particles' velocities lose
is the transfers' error. With the step proportional to dx (fixed CFL), PIC's error falls as
dx (order 1) and APIC's with quadratic weights as dx^2 (order 2). No scene file can state this
initial velocity; it is written from NumPy (APIC's C as the field's gradient).

The particles are Poisson-disk samples (radius dx/2), irregular as in the round trip of
Sec 6.8. On the regular lattice (--lattice, 4 particles a cell) APIC's error falls faster,
about as dx^3 (its quadrature is exact to higher order there); its band is then 2.5-3.5.

    PYTHONPATH=build/python python3 examples/python/convergence.py [--plot convergence.png]
"""
import argparse
import math

import numpy as np

import apiclab

AMPLITUDE = 0.1
BANDS = {"pic": (0.7, 1.3), "apic": (1.5, 2.5)}  # expected fitted orders
LATTICE_BANDS = {"pic": (0.7, 1.3), "apic": (2.5, 3.5)}


def shear_scene(cells, scheme, end, lattice=False):
    dx = 1.0 / cells
    sampling = ({"type": "ppc", "ppc": 4} if lattice else
                {"type": "poisson", "radius": dx / 2, "seed": 1})
    return {
        "name": f"shear-wave-{cells}",
        "dim": 2,
        "domain": {"min": [0, 0], "max": [1, 1], "dx": dx, "boundary": "periodic"},
        "gravity": [0, 0],
        "time": {"end": end, "fps": 1 / end, "dt": {"rule": "fixed", "value": dx}},
        "solver": {"scheme": scheme, "kernel": "quadratic", "integrator": "symplectic"},
        "materials": [{"name": "m", "model": "neo-hookean", "E": 1e-12, "nu": 0.3, "rho": 1}],
        "objects": [{"name": "box", "shape": {"type": "box", "min": [0, 0], "max": [1, 1]},
                     "material": "m", "sampling": sampling}],
    }


def velocity_error(cells, scheme, end, lattice=False):
    """RMS of v_p - v_exact(x_p) over the particles at t = end, relative to the amplitude."""
    sim = apiclab.Simulation(shear_scene(cells, scheme, end, lattice))
    x = sim.state.x
    y = x[:, 1]
    v = np.zeros_like(x)
    v[:, 0] = AMPLITUDE * np.sin(2 * math.pi * y)
    C = np.zeros((len(x), 2, 2))
    C[:, 0, 1] = AMPLITUDE * 2 * math.pi * np.cos(2 * math.pi * y)  # dv_x/dy
    sim.set_state(v=v, C=C if scheme != "pic" else np.zeros_like(C))
    sim.advance(end)
    s = sim.state
    exact = AMPLITUDE * np.sin(2 * math.pi * s.x[:, 1])
    err = np.sqrt(np.mean((s.v[:, 0] - exact) ** 2 + s.v[:, 1] ** 2)) / AMPLITUDE
    return err


def fitted_order(cells, errors):
    """Slope of log(error) against log(dx), least squares."""
    dx = 1.0 / np.asarray(cells, dtype=float)
    return float(np.polyfit(np.log(dx), np.log(errors), 1)[0])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", type=int, nargs="+", default=[16, 32, 64],
                        help="cells per side of each resolution")
    parser.add_argument("--end", type=float, default=0.25, help="time of the comparison (s)")
    parser.add_argument("--lattice", action="store_true",
                        help="particles on the regular lattice instead of Poisson-disk samples")
    parser.add_argument("--plot", help="write the error plot here (needs matplotlib)")
    args = parser.parse_args()
    bands = LATTICE_BANDS if args.lattice else BANDS

    results = {}
    for scheme in bands:
        errors = [velocity_error(n, scheme, args.end, args.lattice) for n in args.cells]
        order = fitted_order(args.cells, errors)
        results[scheme] = (errors, order)
        lo, hi = bands[scheme]
        print(f"{scheme:5s} errors " + " ".join(f"{e:.3e}" for e in errors) +
              f"  fitted order {order:.2f} (expected {lo}-{hi})")
    failed = [s for s, (_, order) in results.items()
              if not bands[s][0] <= order <= bands[s][1]]

    if args.plot:
        try:
            import matplotlib
            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
        except ImportError:
            print("matplotlib is not installed: no plot")
        else:
            dx = [1.0 / n for n in args.cells]
            for scheme, (errors, order) in results.items():
                plt.loglog(dx, errors, "o-", label=f"{scheme} (order {order:.2f})")
            plt.xlabel("dx")
            plt.ylabel("relative RMS velocity error")
            plt.legend()
            plt.savefig(args.plot, dpi=120)
            print(f"wrote {args.plot}")
    if failed:
        raise SystemExit("fitted order outside its band: " + ", ".join(failed))


if __name__ == "__main__":
    main()
