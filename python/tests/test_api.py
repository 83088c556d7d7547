"""geoslip from Python against the geoslip command on the same files.

Reference: the command-line program (`GEOSLIP_CLI`, or target/debug/geoslip) run on the same model
file: the Python API runs the same engine in-process, so its history and fields must be the CLI's,
to 1e-12 of each column's largest value (the CLI's CSV files hold 11 significant digits; a
different build of the same code may differ in the last bits of what is round-off, 1e-16 kPa).
"""

import _thread
import csv
import json
import os
import pathlib
import signal
import subprocess
import tomllib

import numpy as np
import pytest

import geoslip

ROOT = pathlib.Path(__file__).resolve().parents[2]
PAPER = ROOT / "examples" / "paper-pullout-clay.toml"


def cli():
    exe = os.environ.get("GEOSLIP_CLI", str(ROOT / "target" / "debug" / "geoslip"))
    if not os.path.exists(exe):
        pytest.skip(f"no geoslip command at {exe} (set GEOSLIP_CLI)")
    return exe


def assert_same(cli_text, values, what, scale=None):
    """The CLI's column (text) against the API's numbers: to 1e-12 of `scale` (the column's largest
    value when not given), and within the CLI's 11 significant digits of each."""
    expected = np.array([float(t) for t in cli_text])
    values = np.asarray(values, dtype=float)
    assert expected.shape == values.shape, what
    scale = max(scale or np.abs(expected).max(initial=0.0), 1e-300)
    bound = 1e-12 * scale + 5e-11 * np.abs(expected)
    worst = np.abs(values - expected) - bound
    assert (worst <= 0).all(), f"{what}: {values[worst > 0][:3]} against {expected[worst > 0][:3]}"


@pytest.fixture(scope="module")
def cli_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("cli")
    subprocess.run([cli(), "run", "-q", "--csv", "--solver", "faer", "--out", str(out), str(PAPER)], check=True)
    return out


@pytest.fixture(scope="module")
def dict_run():
    data = tomllib.loads(PAPER.read_text())
    return geoslip.Model.from_dict(data, name="paper-pullout-clay.json").run(solver="faer")


def test_a_model_from_a_dict_gives_the_cli_history(cli_run, dict_run):
    with open(cli_run / "history.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    h = dict_run.history["grid.head (x)"]
    assert len(rows) == len(h["reaction"]) == 61
    assert_same([r["displacement [m]"] for r in rows], h["displacement"], "displacement")
    assert_same([r["reaction [kN/m]"] for r in rows], h["reaction"], "reaction")
    assert dict_run.completed
    assert dict_run.events == geoslip.Results.open(cli_run).events


def test_every_field_array_has_the_cli_csv_values(cli_run, dict_run):
    for index in (0, 30, 60):
        step = dict_run.steps[index]
        stage = "stage-1-surcharge" if index == 0 else "stage-2-pull-out"
        folder = cli_run / stage / f"step-{(index if index else 1):03d}"
        with open(folder / "interface.csv", newline="") as f:
            rows = list(csv.reader(f))
        header, rows = rows[0], rows[1:]
        col = {name.split(" ")[0]: k for k, name in enumerate(header)}
        p = step["interface"]
        assert len(rows) == len(p["tau"])
        assert [int(row[col["slave_node"]]) for row in rows] == list(p["node"])
        assert [row[col["state"]] for row in rows] == p["state"]
        # the stresses to 1e-12 of the largest σn (τ is round-off, 1e-16 kPa, under the surcharge)
        # and slips and displacements to 1e-12 of the largest displacement
        stress = np.abs(p["sigma_n"]).max()
        length = np.abs(step["nodes"]["u"]).max()
        for name, scale in (("tributary", None), ("lambda", None), ("sigma_n", None), ("tau", stress), ("slip", length)):
            assert_same([row[col[name]] for row in rows], p[name], f"step {index} {name}", scale)
        with open(folder / "bar_forces.csv", newline="") as f:
            bars = list(csv.DictReader(f))
        # bar forces to 1e-12 of the largest force per width the step carries (its multipliers)
        force = max(np.abs(p["lambda"]).max(), np.abs(step["bars"]["T"]).max())
        assert_same([b["T [kN/m]"] for b in bars], step["bars"]["T"], f"step {index} T", force)
        with open(folder / "displacements.csv", newline="") as f:
            nodes = list(csv.DictReader(f))
        assert [int(n["node"]) for n in nodes] == list(step["nodes"]["id"])
        assert_same([n["ux [m]"] for n in nodes], step["nodes"]["u"][:, 0], f"step {index} ux", length)
        assert_same([n["uy [m]"] for n in nodes], step["nodes"]["u"][:, 1], f"step {index} uy", length)
        assert step["soil"]["stress"].shape[1] == 4


def test_a_results_folder_opens_as_the_same_history(cli_run, dict_run):
    opened = geoslip.Results.open(cli_run)
    a, b = opened.history["grid.head (x)"], dict_run.history["grid.head (x)"]
    np.testing.assert_allclose(a["reaction"], b["reaction"], rtol=1e-10)
    assert len(opened.steps) == 61
    np.testing.assert_allclose(opened.steps[-1]["interface"]["tau"], dict_run.steps[-1]["interface"]["tau"], rtol=1e-9, atol=1e-12)


def test_a_duncan_chang_soil_from_a_dict_runs_as_the_cli(tmp_path):
    # the paper's pull-out with its soil made hyperbolic (docs/model-format.md, Materials)
    data = tomllib.loads(PAPER.read_text())
    soil = data["materials"]["soil"]["soil"]
    del soil["youngs_modulus"], soil["poissons_ratio"]
    soil.update(
        model="duncan-chang",
        cohesion=5.0,
        friction_angle=30.0,
        hyperbolic={"K": 300.0, "n": 0.5, "Rf": 0.8, "Kb": 150.0, "m": 0.25, "Kur": 600.0, "delta_phi": 2.0},
    )
    model_file = tmp_path / "hyperbolic.json"
    model_file.write_text(json.dumps(data))
    out = tmp_path / "cli"
    subprocess.run([cli(), "run", "-q", "--csv", "--solver", "faer", "--out", str(out), str(model_file)], check=True)
    run = geoslip.Model.from_dict(data, name="hyperbolic.json").run(solver="faer")
    with open(out / "history.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    h = run.history["grid.head (x)"]
    # (cutbacks add steps: as many rows as the CLI's, and at least the model's 61)
    assert len(rows) == len(h["reaction"]) >= 61
    assert_same([r["reaction [kN/m]"] for r in rows], h["reaction"], "reaction")
    assert run.completed


def test_a_hardening_soil_from_a_dict_runs_as_the_cli(tmp_path):
    # tests/fuzz-seeds/hardening-soil-lifts.toml: hardening soil placed in a lift, compacted, loaded
    # and unloaded (docs/model-format.md, Materials), from a dict and by the CLI
    seed = ROOT / "tests" / "fuzz-seeds" / "hardening-soil-lifts.toml"
    data = tomllib.loads(seed.read_text())
    assert data["materials"]["soil"]["fill"]["model"] == "hardening-soil"
    out = tmp_path / "cli"
    subprocess.run([cli(), "run", "-q", "--csv", "--solver", "faer", "--out", str(out), str(seed)], check=True)
    run = geoslip.Model.from_dict(data, name="hardening.json").run(solver="faer")
    folder = geoslip.Results.open(out)
    assert len(run.steps) == len(folder.steps) and run.completed
    assert_same(folder.steps[-1]["bars"]["T"], run.steps[-1]["bars"]["T"], "T")
    assert run.steps[-1]["soil"]["stress"].shape[1] == 4
    with pytest.raises(geoslip.ModelError, match=r"materials\.soil\.fill\.hardening\.m"):
        data["materials"]["soil"]["fill"]["hardening"]["m"] = 1.5
        geoslip.Model.from_dict(data, name="hardening.json").run()


def test_a_wall_s_design_checks_come_back_as_arrays(tmp_path):
    # the wall of tests/fuzz-seeds/design-wall.toml from a dict, against the CLI's folder
    # (docs/design-checks.md)
    data = tomllib.loads((ROOT / "tests" / "fuzz-seeds" / "design-wall.toml").read_text())
    out = tmp_path / "cli"
    subprocess.run([cli(), "run", "-q", "--solver", "faer", "--out", str(out), str(ROOT / "tests" / "fuzz-seeds" / "design-wall.toml")], check=True)
    run = geoslip.Model.from_dict(data, name="design-wall.json").run(solver="faer")
    folder = geoslip.Results.open(out)
    checks = run.design_checks
    assert checks["layer"] == folder.design_checks["layer"] == ["grid-2", "grid-1"]
    for key in ("depth Z", "T_max analysis", "T_max simplified", "Pr", "CDR pull-out"):
        assert_same(folder.design_checks[key], checks[key], key)
    assert np.all(checks["T_max analysis"] > 0) and np.all(checks["CDR pull-out"] > 1)
    assert geoslip.Model.load(PAPER).run(solver="faer").design_checks is None


def test_a_compacted_lift_from_a_dict_runs_its_compaction_stages(tmp_path):
    # tests/fuzz-seeds/duncan-chang-lifts.toml: a lift of Duncan–Chang soil compacted with 8 kPa
    # (docs/soil.md, Compaction), from a dict and by the CLI
    seed = ROOT / "tests" / "fuzz-seeds" / "duncan-chang-lifts.toml"
    data = tomllib.loads(seed.read_text())
    assert data["stages"][1]["compaction"] == {"pressure": 8.0, "material": "fill"}
    out = tmp_path / "cli"
    subprocess.run([cli(), "run", "-q", "--solver", "faer", "--out", str(out), str(seed)], check=True)
    run = geoslip.Model.from_dict(data, name="lifts.json").run(solver="faer")
    stages = [s["stage"] for s in run.summary["steps"]]
    assert "lift: compaction" in stages and "lift: compaction removed" in stages
    cli_stages = [s["stage"] for s in geoslip.Results.open(out).summary["steps"]]
    assert stages == cli_stages and run.completed


def test_a_dynamic_stage_from_a_dict_gives_the_cli_motion_as_arrays(tmp_path):
    # tests/fuzz-seeds/shaken-block.toml: a block shaken by an inline base motion, then loaded
    # statically (docs/dynamics.md), from a dict and by the CLI
    seed = ROOT / "tests" / "fuzz-seeds" / "shaken-block.toml"
    data = tomllib.loads(seed.read_text())
    assert data["stages"][1]["dynamic"]["record"] == ["crest"]
    out = tmp_path / "cli"
    subprocess.run([cli(), "run", "-q", "--solver", "faer", "--out", str(out), str(seed)], check=True)
    run = geoslip.Model.from_dict(data, name="shaken.json").run(solver="faer")
    folder = geoslip.Results.open(out)
    motion = run.motion
    assert motion["stage"] == folder.motion["stage"] == ["shaking"] * 4
    assert np.allclose(motion["time"], [0.05, 0.1, 0.15, 0.2])
    for key in ("ground ax", "crest ux relative", "crest ax absolute", "liner mean slip"):
        assert_same(folder.motion[key], motion[key], key)
    # the base's acceleration is the record's, 0.4 g at 0.05 s and -0.4 g at 0.1 s
    assert np.allclose(motion["ground ax"][:2], [0.4 * 9.80665, -0.4 * 9.80665])
    times = [s.get("time") for s in run.summary["steps"]]
    assert times[0] is None and times[1:5] == pytest.approx([0.05, 0.1, 0.15, 0.2]) and times[5] is None
    assert geoslip.Model.load(PAPER).run(solver="faer").motion is None


def test_a_bad_model_raises_with_the_field_path():
    data = tomllib.loads(PAPER.read_text())
    data["materials"]["soil"]["soil"]["youngs_modulus"] = -5.0
    model = geoslip.Model.from_dict(data, name="bad.json")
    problems = model.check()
    assert any("materials.soil.soil.youngs_modulus" in p and "bad.json" in p for p in problems), problems
    with pytest.raises(geoslip.ModelError, match=r"materials\.soil\.soil\.youngs_modulus"):
        model.run()
    with pytest.raises(geoslip.ModelError, match="missing field `units`"):
        geoslip.Model.from_dict({"title": "no units"})
    with pytest.raises(ValueError, match="solver"):
        geoslip.Model.load(PAPER).run(solver="gauss")


def test_an_interrupted_run_keeps_its_completed_steps(tmp_path):
    seen = []

    def progress(stage, step, load_factor):
        seen.append((stage, step))
        if stage == "pull-out" and step == 3:
            _thread.interrupt_main()  # as Ctrl-C would

    # Python installs its Ctrl-C handler only when SIGINT is not ignored at start-up, and a shell
    # ignores SIGINT in the commands it starts in the background: install it here
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with pytest.raises(KeyboardInterrupt) as stopped:
            geoslip.Model.load(PAPER).run(solver="faer", out=tmp_path, progress=progress)
    finally:
        signal.signal(signal.SIGINT, previous)
    results = stopped.value.results
    assert not results.completed
    # the surcharge step and the pull-out's first three: the step in which Ctrl-C came is complete
    assert len(results.steps) == 4 == len(seen)
    assert len(results.history["grid.head (x)"]["reaction"]) == 4
    # and the results folder says so, with those steps written
    summary = geoslip.Results.open(tmp_path)
    assert len(summary.history["grid.head (x)"]["reaction"]) == 4
    assert "stopped after 4 completed steps" in (tmp_path / "summary.json").read_text()
