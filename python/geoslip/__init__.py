"""geoslip from Python: soil-geosynthetic interfaces that slip a lot.

The engine runs in this process (the same code as the ``geoslip`` command, compiled into this
module), with the GIL released while it iterates::

    import geoslip
    model = geoslip.Model.load("examples/paper-pullout-clay.toml")   # or Model.from_dict({...})
    assert model.check() == []
    results = model.run(solver="auto")             # out="folder" keeps the CLI's results folder
    force = results.history["grid.head (x)"]["reaction"]

    fit = geoslip.calibrate("lab/direct-shear.toml")   # or a dict in the calibration file's schema
    print(fit.parameters["friction_angle"].interval, fit.law_block)

Errors are exceptions whose message names the file, the field and the entity: ``ModelError`` for a
model that cannot be read or checked, ``RunError`` for a run that fails (no equilibrium, a singular
system); either carries the completed steps as ``.results``. Ctrl-C stops a run at its next
converged step and raises ``KeyboardInterrupt`` with the completed steps as ``.results``.
``CalibrationError`` is raised by ``calibrate`` for curves it cannot read or parameters the data
cannot identify. See docs/python.md and docs/calibration.md.
"""

import csv as _csv
import json as _json
import os as _os

import numpy as _np

from ._geoslip import Model as _Model, ModelError, RunError, CalibrationError, backends
from ._geoslip import calibrate as _calibrate

__all__ = ["Model", "Results", "ModelError", "RunError", "CalibrationError", "Calibration", "calibrate", "backends"]


class Model:
    """A model file, parsed; ``check()`` lists its problems, ``run()`` runs it."""

    def __init__(self, inner):
        self._inner = inner

    @staticmethod
    def load(path):
        """Read a model file (TOML, or JSON when it ends in .json)."""
        return Model(_Model.load(_os.fspath(path)))

    @staticmethod
    def from_dict(data, name="model.json"):
        """A model from a dict in the model file's schema (as ``geoslip schema`` prints it);
        ``name`` names it in messages."""
        return Model(_Model.from_json(_json.dumps(data, allow_nan=True), name))

    @property
    def source(self):
        return self._inner.source

    def check(self):
        """Every problem the check found, as ``geoslip check`` prints them; [] when fine."""
        return list(self._inner.check())

    def run(self, solver="auto", out=None, progress=None):
        """Run every stage and return its ``Results``. ``solver``: auto, mumps, umfpack, faer or
        dense; ``out``: a results folder to write as ``geoslip run --out`` does (None: a temporary
        one); ``progress(stage, step, load_factor)`` is called after each converged step."""
        try:
            raw = self._inner.run(solver, None if out is None else _os.fspath(out), progress)
        except BaseException as e:  # noqa: B902 - re-raised with the completed steps wrapped
            partial = getattr(e, "results", None)
            if isinstance(partial, dict):
                e.results = Results(partial)
            raise
        return Results(raw)


class Results:
    """A run's results: ``history`` (per prescribed target, its ``displacement`` and ``reaction``
    per converged step, as history.csv), ``steps`` (each converged step's fields as NumPy arrays:
    ``nodes``, ``bars``, ``interface``, ``soil``), ``events``, ``summary`` (summary.json),
    ``completed``, and for a model with a ``[design]`` table ``design_checks`` (per layer, from the
    top: ``layer`` names and NumPy arrays of design-checks.csv's columns, keyed by their names
    without units, for example ``"T_max analysis"``, ``"T_max simplified"``, ``"CDR pull-out"``;
    docs/design-checks.md), else None; for a model with dynamic stages ``motion`` (per time step:
    ``stage`` names and NumPy arrays of motion.csv's columns keyed by their names without units, for
    example ``"time"``, ``"ground ax"``, ``"crest ax absolute"``, ``"liner mean slip"``;
    docs/dynamics.md), else None."""

    def __init__(self, raw):
        self.design_checks = _design_checks(raw.get("design_checks_csv"))
        self.motion = _columns(raw.get("motion_csv"), "stage")
        self.history = raw["history"]
        self.steps = raw["steps"]
        self.factors_of_safety = raw.get("factors_of_safety", [])
        self.summary = _json.loads(raw.get("summary_json") or "{}")
        self.events = list(self.summary.get("events", []))
        self.completed = bool(raw.get("completed", False))
        self.units = raw.get("units", {})

    def __repr__(self):
        return "<geoslip.Results: {} steps{}, targets {}>".format(
            len(self.steps), "" if self.completed else " (stopped early)", ", ".join(self.history) or "none"
        )

    @staticmethod
    def open(folder):
        """The results of a folder written by ``geoslip run`` (history.csv and summary.json; each
        step's fields when it was run with ``--csv``)."""
        folder = _os.fspath(folder)
        history = {}
        with open(_os.path.join(folder, "history.csv"), newline="") as f:
            reader = _csv.reader(f)
            header = next(reader)
            for row in reader:
                key = "{} ({})".format(row[3], row[4])
                h = history.setdefault(key, {"stage": [], "step": [], "load_factor": [], "displacement": [], "reaction": []})
                h["stage"].append(row[0])
                h["step"].append(int(row[1]))
                h["load_factor"].append(float(row[2]))
                h["displacement"].append(float(row[5]))
                h["reaction"].append(float(row[6]))
        for h in history.values():
            for k in ("step", "load_factor", "displacement", "reaction"):
                h[k] = _np.array(h[k])
        summary = "{}"
        path = _os.path.join(folder, "summary.json")
        if _os.path.exists(path):
            with open(path) as f:
                summary = f.read()
        steps = []
        for stage_dir in sorted(d for d in _os.listdir(folder) if d.startswith("stage-")):
            for step_dir in sorted(d for d in _os.listdir(_os.path.join(folder, stage_dir)) if d.startswith("step-")):
                steps.append(_read_step_csv(_os.path.join(folder, stage_dir, step_dir)))
        raw = {"history": history, "steps": steps, "summary_json": summary,
               "completed": _json.loads(summary).get("status") == "completed"}
        for name, key in (("design-checks.csv", "design_checks_csv"), ("motion.csv", "motion_csv")):
            path = _os.path.join(folder, name)
            if _os.path.exists(path):
                with open(path) as f:
                    raw[key] = f.read()
        return Results(raw)


def _design_checks(text):
    """design-checks.csv as ``layer`` (names) and a NumPy array per column, keyed by its name
    without the unit."""
    return _columns(text, "layer")


def _columns(text, first):
    """A CSV file whose first column holds names (``first``) and the others numbers: the names as a
    list, each other column as a NumPy array (a blank cell as NaN), keyed by its header without the
    unit; None without the file."""
    if not text:
        return None
    reader = _csv.reader(text.splitlines())
    header = next(reader)
    rows = list(reader)
    table = {}
    for k, name in enumerate(header):
        key = name.split(" [")[0]
        column = [r[k] for r in rows]
        table[key] = column if k == 0 else _np.array([float(v) if v != "" else _np.nan for v in column])
    return table


def _read_table(path):
    with open(path, newline="") as f:
        reader = _csv.reader(f)
        header = next(reader)
        rows = list(reader)
    return header, rows


def _column(header, rows, starts, kind=float):
    k = next(i for i, h in enumerate(header) if h == starts or h.startswith(starts + " "))
    return [kind(r[k]) for r in rows]


def _read_step_csv(folder):
    """One step's fields from the CSV files ``geoslip run --csv`` writes."""
    step = {"folder": folder}
    path = _os.path.join(folder, "interface.csv")
    if _os.path.exists(path):
        h, rows = _read_table(path)
        step["interface"] = {
            "interface": _column(h, rows, "interface", str),
            "face": _column(h, rows, "face", str),
            "node": _np.array(_column(h, rows, "slave_node", int)),
            "x": _np.array([_column(h, rows, "x"), _column(h, rows, "y")]).T,
            "state": _column(h, rows, "state", str),
            "tributary": _np.array(_column(h, rows, "tributary")),
            "lambda": _np.array(_column(h, rows, "lambda")),
            "sigma_n": _np.array(_column(h, rows, "sigma_n")),
            "tau": _np.array(_column(h, rows, "tau")),
            "bearing": _np.array(_column(h, rows, "bearing")),
            "dilation": _np.array(_column(h, rows, "dilation")),
            "slip": _np.array(_column(h, rows, "slip")),
        }
    path = _os.path.join(folder, "bar_forces.csv")
    if _os.path.exists(path):
        h, rows = _read_table(path)
        step["bars"] = {"id": _np.array(_column(h, rows, "bar", int)), "T": _np.array(_column(h, rows, "T"))}
    return step


class Parameter:
    """One parameter of a fitted law: ``value`` (in ``unit``), and for a fitted one its
    ``standard_error`` and 95 % ``interval`` (``None`` for a parameter held under ``fixed``)."""

    def __init__(self, raw):
        self.name = raw["name"]
        self.unit = raw["unit"]
        self.value = raw["value"]
        self.fitted = raw["fitted"]
        self.standard_error = raw["standard_error"]
        self.interval = None if raw["interval"] is None else tuple(raw["interval"])

    def __repr__(self):
        if self.fitted:
            return (f"Parameter({self.name} = {self.value:.6g} {self.unit} ± {self.standard_error:.3g}, "
                    f"95 %: {self.interval[0]:.6g} … {self.interval[1]:.6g})")
        return f"Parameter({self.name} = {self.value:.6g} {self.unit}, fixed)"


class Calibration:
    """A fitted law: ``parameters`` (name -> ``Parameter``), ``correlation`` (NumPy, over
    ``fitted``, in that order), ``law`` (a dict for an interface's ``law`` in a model dict),
    ``law_block`` (the TOML line to paste), ``curves`` (per curve: ``condition`` [kPa], ``x`` [m],
    ``measured``, ``modelled``, ``smooth_x``, ``smooth_y`` as NumPy arrays), ``warnings``,
    ``weighted_rms``, ``points``, ``degrees_of_freedom``."""

    def __init__(self, raw):
        self.test = raw["test"]
        self.law_name = raw["law"]
        self.parameters = {p["name"]: Parameter(p) for p in raw["parameters"]}
        self.fitted = list(raw["fitted"])
        self.correlation = _np.array(raw["correlation"], dtype=float)
        self.law = raw["law_spec"]
        self.law_block = raw["law_block"]
        self.warnings = list(raw["warnings"])
        self.weighted_rms = raw["weighted_rms"]
        self.points = raw["points"]
        self.degrees_of_freedom = raw["degrees_of_freedom"]
        self.curves = [
            {k: (_np.asarray(v, dtype=float) if isinstance(v, list) else v) for k, v in c.items()}
            for c in raw["curves"]
        ]

    def __repr__(self):
        return f"Calibration({self.law_name}: " + ", ".join(repr(p) for p in self.parameters.values()) + ")"


def calibrate(spec, out=None, name="calibration.json"):
    """Fit an interface law to measured curves, as ``geoslip calibrate`` does. ``spec``: a
    calibration file (TOML) or a dict in its schema (``test``, ``data``, ``law``, optional
    ``initial``, ``fixed``, ``pull_out``; see docs/calibration.md), whose ``data`` is taken from the
    current folder (``name`` names it in messages). ``out``: a folder for the report, the plots and
    the law block. Raises ``CalibrationError`` naming what is wrong, or the parameters the data
    cannot identify."""
    out = None if out is None else _os.fspath(out)
    if isinstance(spec, dict):
        raw = _calibrate(name, _json.dumps(spec), out)
    else:
        raw = _calibrate(_os.fspath(spec), None, out)
    return Calibration(_json.loads(raw))
