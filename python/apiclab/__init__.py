"""apiclab from Python: scenes, steps, the state as NumPy arrays (docs/python.md)."""
import csv
import os

from ._apiclab import (  # noqa: F401  (the module's API)
    Simulation,
    SimulationFailed,
    __version__,
    scenes_directory,
    set_threads,
)

__all__ = ["Simulation", "SimulationFailed", "scenes", "set_threads", "scenes_directory",
           "state_by_id", "sweep_table", "__version__"]


def scenes():
    """The shipped scenes' names, as `apiclab list` shows them."""
    return sorted(f[:-5] for f in os.listdir(scenes_directory()) if f.endswith(".json"))


def state_by_id(sim):
    """Copies of the particle arrays ordered by particle id (the storage order changes as the
    fast step sorts the particles; ids do not)."""
    state = vars(sim.state)
    order = state["id"].argsort(kind="stable")
    return {name: array[order] for name, array in state.items()}


def _number(text):
    try:
        return float(text)
    except ValueError:
        return text


def sweep_table(directory, frame=None):
    """DIRECTORY/runs.csv of `apiclab sweep` (one row per run: its axes and metrics,
    docs/sweeps.md). frame=None: a pandas DataFrame when pandas is installed, else a dict of
    column lists; frame=False: always the dict; frame=True: the DataFrame (needs pandas).
    In the dict, cells that read as numbers are floats, the rest strings ('' when empty)."""
    path = os.path.join(os.fspath(directory), "runs.csv")
    if frame is not False:
        try:
            import pandas
        except ImportError:
            if frame:
                raise
        else:
            return pandas.read_csv(path)
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        raise ValueError(f"{path}: empty (no header)")
    header, body = rows[0], rows[1:]
    columns = {name: [_number(r[c]) if c < len(r) and r[c] != "" else ""
                      for r in body] for c, name in enumerate(header)}
    return columns
