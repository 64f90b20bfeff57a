"""`import apiclab` against `apiclab run` and its own promises (docs/python.md, docs/testing.md).

Run by ctest (python_tests) with APICLAB (the executable) and PYTHONPATH (BUILD/python) set.
"""
import csv
import gc
import glob
import json
import os
import signal
import subprocess
import sys
import threading

import numpy as np
import pytest

import apiclab

APICLAB = os.environ.get("APICLAB", "apiclab")
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENE = "rotating-disk"
# 100 steps of 1 ms, explicit: a second or less.
SETS = ["solver.integrator=symplectic", 'time.dt={"rule":"fixed","value":0.001}',
        "time.end=0.1"]


def run_csv(tmp_path, sets):
    """`apiclab run` of SCENE: its diagnostics columns and its last dump, by particle id."""
    csv_path, dump = tmp_path / "run.csv", tmp_path / "dump"
    args = [APICLAB, "run", SCENE, "--quiet", "--threads", "1", "--csv", str(csv_path),
            "--dump", str(dump)]
    for s in sets:
        args += ["--set", s]
    subprocess.run(args, check=True)
    with open(csv_path) as f:
        rows = list(csv.DictReader(f))
    frames = sorted(glob.glob(str(dump / "frame_*.csv")))
    with open(frames[-1]) as f:
        particles = list(csv.DictReader(f))
    return rows, particles


def check_same_as_run(sim, rows, particles):
    d = sim.diagnostics()
    assert len(rows) == sim.steps + 1 == 101  # the first state's row, then one per step
    for name in rows[0]:
        if name == "wall_s":
            continue
        got = d[name]
        want = [r[name] for r in rows]
        if isinstance(got, list):
            assert got == want, name
        else:  # the CSV's 17 digits read back to the same double
            assert np.array_equal(got, np.array(want, dtype=float)), name
    s = apiclab.state_by_id(sim)
    assert [int(p["id"]) for p in particles] == list(s["id"])
    for axis, name in enumerate("xy"):
        assert np.array_equal(s["x"][:, axis], [float(p[name]) for p in particles])
        assert np.array_equal(s["v"][:, axis], [float(p["v" + name]) for p in particles])


def test_scene_by_name_and_as_dict_match_run_bit_for_bit(tmp_path):
    apiclab.set_threads(1)
    rows, particles = run_csv(tmp_path, SETS)
    by_name = apiclab.Simulation(SCENE, set=SETS)
    by_name.run_to(by_name.end_time)
    check_same_as_run(by_name, rows, particles)
    with open(os.path.join(apiclab.scenes_directory(), SCENE + ".json")) as f:
        scene = json.load(f)
    as_dict = apiclab.Simulation(scene, set=dict(s.split("=", 1) for s in SETS))
    for _ in range(100):
        as_dict.step()
    check_same_as_run(as_dict, rows, particles)


def run_error(args):
    r = subprocess.run([APICLAB, "run", SCENE, "--t-end", "0.01", "--quiet", *args],
                       capture_output=True, text=True)
    assert r.returncode == 2
    return r.stderr.strip()


@pytest.mark.parametrize("key,value", [("materials.0.E", "-5"), ("solver.scheme", "picc"),
                                       ("solver.shceme", "pic"), ("time.fps", "fast")])
def test_bad_keys_and_values_raise_the_registries_messages(key, value):
    with pytest.raises(ValueError) as e:
        apiclab.Simulation(SCENE, set={key: value})
    message = str(e.value)
    assert key.split(".")[-1] in message
    assert message in run_error(["--set", f"{key}={value}"])


def test_bad_scene_and_precision_raise():
    with pytest.raises(ValueError, match="no such scene"):
        apiclab.Simulation("no-such-scene")
    with pytest.raises(ValueError, match="precision"):
        apiclab.Simulation(SCENE, precision="half")
    with pytest.raises(ValueError):
        apiclab.Simulation({"name": "x", "dim": 2, "colour": 1})


def test_writing_v_and_c_is_the_setup_s_state():
    spinning = apiclab.Simulation(SCENE, set=SETS)
    still = apiclab.Simulation(SCENE, set=SETS + ["objects.0.angular_velocity=0"])
    assert not np.any(still.state.v)
    still.set_state(v=spinning.state.v, C=spinning.state.C)
    for _ in range(10):
        spinning.step()
        still.step()
    for name in ("x", "v", "F", "C"):
        assert np.array_equal(getattr(spinning.state, name), getattr(still.state, name)), name


def test_moving_x_across_blocks_steps_as_the_moved_scene():
    shift = 8 * 0.03125  # eight cells: two sorting blocks
    small = SETS + ["objects.0.shape.radius=0.15"]
    here = apiclab.Simulation(SCENE, set=small)
    there = apiclab.Simulation(SCENE, set=small + [f"objects.0.shape.center=[{0.5 - shift}, 0.5]"])
    for _ in range(5):
        here.step()
        there.step()
    assert np.array_equal(here.state.id, there.state.id)
    assert np.allclose(here.state.x - [shift, 0], there.state.x, rtol=0, atol=1e-12)
    here.set_state(**{n: getattr(there.state, n) for n in ("x", "v", "F", "C")})
    assert "outside the active box" in here._partition_conflict()
    here.step()
    there.step()
    assert here._partition_conflict() == ""  # the step sorted the moved particles again
    for _ in range(10):
        here.step()
        there.step()
    for name in ("x", "v", "F", "C"):
        assert np.allclose(getattr(here.state, name), getattr(there.state, name),
                           rtol=0, atol=1e-12), name


def test_bad_writes_raise_and_change_nothing():
    sim = apiclab.Simulation(SCENE, set=SETS)
    x = sim.state.x.copy()
    with pytest.raises(ValueError, match="outside the domain"):
        sim.set_state(v=np.zeros_like(x), x=x + 2)
    with pytest.raises(ValueError, match="shape"):
        sim.set_state(v=np.zeros((3, 2)))
    with pytest.raises(ValueError, match="not finite"):
        sim.set_state(v=np.full_like(x, np.nan))
    with pytest.raises(ValueError, match="not a writable"):
        sim.set_state(id=np.zeros(len(x)))
    assert np.array_equal(sim.state.x, x)
    assert np.any(sim.state.v)
    with pytest.raises(ValueError):
        sim.state.x[0, 0] = 0.5  # views are read-only: writes go through set_state


def test_a_state_array_outlives_its_simulation():
    sim = apiclab.Simulation(SCENE, set=SETS)
    sim.step()
    x, F = sim.state.x, sim.state.F
    expected = x.copy()
    del sim
    gc.collect()
    assert np.array_equal(x, expected)
    assert F.shape[1:] == (2, 2) and np.all(np.isfinite(F))


def test_diagnostics_clone_grid_and_scheme():
    sim = apiclab.Simulation(SCENE, set=SETS)
    sim.advance(0.01)
    copy = sim.clone()
    copy.set_scheme("pic")
    copy.advance(0.02)
    assert sim.steps == 10 and copy.steps == 20 and sim.scheme == "apic" and copy.scheme == "pic"
    assert len(copy.diagnostics()["t"]) == 21 and len(sim.diagnostics()["t"]) == 11
    g = sim.grid()
    assert g["mass"].ndim == 2 and g["velocity"].shape == g["mass"].shape + (2,)
    assert abs(g["mass"].sum() - sim.state.mass.sum()) < 1e-12 * sim.state.mass.sum()
    with pytest.raises(ValueError, match="scheme"):
        sim.set_scheme("picc")


def test_float_precision_views_and_writes():
    sim = apiclab.Simulation(SCENE, set=SETS, precision="float")
    assert sim.precision == "float" and sim.state.x.dtype == np.float32
    sim.set_state(v=np.zeros(sim.state.v.shape), C=np.zeros(sim.state.C.shape))  # float64 given
    sim.step()
    assert sim.state.v.dtype == np.float32 and not np.any(sim.state.v)


def test_a_method_without_particles_gives_its_grids():
    sim = apiclab.Simulation("eol-spin")
    sim.step()
    layers = sim.grid()
    assert sim.method == "eol" and sim.scheme is None and sim.particle_count == 0
    assert layers and all(f.shape == layers[0]["nodes"] for f in layers[0]["fields"].values())
    with pytest.raises(ValueError, match="no particles"):
        sim.state
    with pytest.raises(ValueError, match="double precision only"):
        apiclab.Simulation("eol-spin", precision="float")


def test_steps_release_the_gil_and_refuse_a_second_thread():
    sim = apiclab.Simulation(SCENE, set=SETS[:2])
    stepping = threading.Thread(target=sim.advance, args=(0.3,))
    refused = 0
    stepping.start()
    while stepping.is_alive():  # this thread runs while the other one steps
        try:
            sim.state
        except RuntimeError as e:
            assert "another thread" in str(e)
            refused += 1
    stepping.join()
    assert refused > 0 and sim.time == 0.3


def test_ctrl_c_in_run_to_raises_between_steps():
    sim = apiclab.Simulation(SCENE, set=SETS[:2])
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            sim.run_to(1000.0)
    finally:
        timer.cancel()
        timer.join()
    assert 0 < sim.time < 1000 and sim.steps + 1 == len(sim.diagnostics()["t"])
    sim.step()  # the state is whole: it steps on


def test_blow_up_raises_simulation_failed():
    # Symplectic Euler at ten times the elastic step limit.
    sim = apiclab.Simulation(SCENE, set=["solver.integrator=symplectic",
                                         'time.dt={"rule":"fixed","value":0.01}'])
    with pytest.raises(apiclab.SimulationFailed, match="blew up"):
        sim.run_to(sim.end_time)
    steps = sim.steps
    with pytest.raises(apiclab.SimulationFailed):
        sim.step()
    assert sim.steps == steps


def test_snapshot_is_an_image():
    sim = apiclab.Simulation(SCENE, set=SETS)
    try:
        image = sim.snapshot(96, 64)
    except RuntimeError as e:
        pytest.skip(f"no offscreen context: {e}")
    assert image.shape == (64, 96, 4) and image.dtype == np.uint8
    assert (image[:, :, 0] < 200).sum() > 50  # particles drawn


def test_sweep_table_as_columns(tmp_path):
    (tmp_path / "runs.csv").write_text("id,solver.scheme,outcome,final_energy\n"
                                       "0,apic,completed,1.5\n1,pic,blew_up,\n")
    t = apiclab.sweep_table(tmp_path, frame=False)
    assert t["solver.scheme"] == ["apic", "pic"] and t["final_energy"] == [1.5, ""]


@pytest.mark.parametrize("example,args", [
    ("convergence.py", ["--cells", "8", "16", "32", "--end", "0.125"]),
    ("schemes_from_one_state.py", ["--t0", "0.02", "--steps", "5"]),
    ("custom_initial_condition.py", ["--end", "0.05"]),
])
def test_examples_run(example, args):
    path = os.path.join(ROOT, "examples", "python", example)
    r = subprocess.run([sys.executable, path, *args], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr
