"""An initial condition no scene file can state: a bar released from a stretch field.

A free elastic bar (no gravity, no walls near it) starts in the shape of its first free-free
mode, u(X) = (-(a L / pi) cos(pi (X - X0) / L), 0): each particle is moved by u and given the
deformation gradient F = I + grad u (stretched on one half, squeezed on the other, free at both
ends), at rest. Released, it rings: the energy moves between elastic and kinetic while the total
stays (symplectic Euler, APIC). A measured displacement field or particles from another code's
output go in the same way, through set_state.

    PYTHONPATH=build/python python3 examples/python/custom_initial_condition.py [--png bar.png]
"""
import argparse
import math

import numpy as np

import apiclab

X0, LENGTH, Y0, HEIGHT = 0.2, 0.6, 0.45, 0.1


def bar_scene(end):
    return {
        "name": "ringing-bar",
        "dim": 2,
        "domain": {"min": [0, 0], "max": [1, 1], "dx": 0.02, "boundary": "slip"},
        "gravity": [0, 0],
        "time": {"end": end, "fps": 24, "dt": {"rule": "elastic", "nu": 0.5}},
        "solver": {"scheme": "apic", "kernel": "quadratic", "integrator": "symplectic"},
        "materials": [{"name": "rubber", "model": "neo-hookean", "E": 20, "nu": 0.3,
                       "rho": 1}],
        "objects": [{"name": "bar",
                     "shape": {"type": "box", "min": [X0, Y0], "max": [X0 + LENGTH, Y0 + HEIGHT]},
                     "material": "rubber", "sampling": {"type": "ppc", "ppc": 4}}],
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--end", type=float, default=1.0, help="time to run to (s)")
    parser.add_argument("--amplitude", type=float, default=0.05, help="largest strain a")
    parser.add_argument("--png", help="write the last frame's picture here")
    args = parser.parse_args()

    sim = apiclab.Simulation(bar_scene(args.end))
    s = sim.state
    k = math.pi / LENGTH
    X = s.x.copy()
    x = X.copy()
    x[:, 0] -= args.amplitude / k * np.cos(k * (X[:, 0] - X0))
    F = np.repeat(np.eye(2)[None], len(X), axis=0)
    F[:, 0, 0] += args.amplitude * np.sin(k * (X[:, 0] - X0))  # 1 + d u_x / d X
    sim.set_state(x=x, F=F)

    first = sim.measure()
    e0 = first["total"][0]
    print(f"ringing bar: {sim.particle_count} particles, elastic energy {first['potential'][0]:.4e} J")
    print(f"{'t':>6s} {'kinetic':>11s} {'potential':>11s} {'total/E0':>9s}")

    def frame(sim):
        m = sim.measure()
        print(f"{sim.time:6.3f} {m['kinetic'][0]:11.4e} {m['potential'][0]:11.4e} "
              f"{m['total'][0] / e0:9.4f}")

    sim.run_to(args.end, frame)
    d = sim.diagnostics()
    print(f"{sim.steps} steps; largest kinetic energy {d['kinetic'].max():.4e} J")
    if args.png:
        try:
            image = sim.snapshot(640, 480)
        except RuntimeError as e:  # no EGL or OSMesa on this machine
            print(f"no picture: {e}")
        else:
            write_png(args.png, image)
            print(f"wrote {args.png}")


def write_png(path, rgba):
    """A plain PNG writer (zlib), so that the example needs no imaging package."""
    import struct
    import zlib

    h, w, _ = rgba.shape
    raw = b"".join(b"\0" + rgba[y].tobytes() for y in range(h))

    def chunk(tag, data):
        return (struct.pack(">I", len(data)) + tag + data +
                struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF))

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


if __name__ == "__main__":
    main()
