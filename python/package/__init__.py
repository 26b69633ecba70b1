"""igms from Python: scenes, the server's step, the dynamics kernels, logs and sweeps.

    import igms
    sim = igms.Simulation(igms.Scene.load("scenes/box_slide.yaml"))
    sim.step(500)                      # without the GIL
    sim.q, sim.v                       # read-only views, no copies
    sim.body("box").pose               # 4 x 4, world <- body
    sim.contacts()                     # a structured array: bodies, point, normal, impulse, depth
    sim.hands.push(tip=[0.3, 0, 0.1])  # as the bus would bring it, checked by the server's input gate
    model = igms.Model.from_urdf("models/puma560.urdf")
    model.rnea(q, v, a)

The package also holds the LCM message types (igms.robot_state_t, ...), as lcm-gen made them.
docs/python.md walks through it; igms.sweep (igms-sweep) runs many scenarios on Ray.
"""
import importlib as _importlib
import pkgutil as _pkgutil

# The message types: every *_t module lcm-gen wrote here.
for _m in _pkgutil.iter_modules(__path__):
    if _m.name.endswith("_t"):
        globals()[_m.name] = getattr(_importlib.import_module("." + _m.name, __name__), _m.name)

try:
    from ._igms import (Log, Model, ModelError, Scene, SceneError, LogError, SimulationDiverged, resimulate,
                        run_scenario)
except ModuleNotFoundError as _e:  # the message types alone (a build without the module)
    if _e.name != __name__ + "._igms":
        raise
else:
    from .simulation import Body, Hands, Simulation  # noqa: F401

__all__ = ["Scene", "Simulation", "Model", "Log", "resimulate", "run_scenario", "sweep", "SceneError", "ModelError",
           "LogError", "SimulationDiverged", "Body", "Hands"]


def sweep(spec, out="out/sweep", address=None, workers=None, progress=True, base_dir="."):
    """Runs a sweep spec (a dict or a YAML file's path) on Ray and writes DIR/results.parquet; see igms.sweeps."""
    from .sweeps import run_sweep
    return run_sweep(spec, out, address=address, workers=workers, progress=progress, base_dir=base_dir)
