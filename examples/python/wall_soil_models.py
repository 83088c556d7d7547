"""The 6 m reinforced wall's layer loads with five soil set-ups, beside the Simplified Method.

The wall of examples/reinforced-wall, run in-process five times, each run's T_max per layer taken
from its design checks (``Results.design_checks``):

- reinforced-wall.toml: the backfill Mohr-Coulomb, E = 30 MPa;
- reinforced-wall-compacted.toml: the same, each lift compacted by 8 kPa;
- the plain wall with its backfill made Duncan-Chang (K = 500, n = 0.5, Rf = 0.75, Kb = 250,
  m = 0.25, Kur = 1000, the same strength), without compaction, at tolerances of 1e-5;
- reinforced-wall-hyperbolic.toml: that Duncan-Chang backfill, each lift compacted, at 1e-3;
- reinforced-wall-hardening.toml: hardening-soil backfill, each lift compacted, at 1e-4.

The hyperbolic and hardening-soil runs take looser tolerances than the example's 1e-7; docs/soil.md
(Limitations) says why and how much the loads move with them.

Run (after `pip install ./python` and `pip install matplotlib`; about an hour, most of it the
hardening-soil wall):
    python examples/python/wall_soil_models.py [output.png]
"""

import functools
import pathlib
import sys
import time
import tomllib

import geoslip

ROOT = pathlib.Path(__file__).resolve().parents[2]
WALLS = ROOT / "examples" / "reinforced-wall"


def plain_hyperbolic():
    """reinforced-wall.toml with its backfill made Duncan-Chang, at tolerances of 1e-5."""
    path = WALLS / "reinforced-wall.toml"
    data = tomllib.loads(path.read_text())
    data["mesh"]["file"] = str(WALLS / data["mesh"]["file"])
    fill = data["materials"]["soil"]["backfill"]
    del fill["youngs_modulus"], fill["poissons_ratio"]
    fill["model"] = "duncan-chang"
    fill["hyperbolic"] = {"K": 500.0, "n": 0.5, "Rf": 0.75, "Kb": 250.0, "m": 0.25, "Kur": 1000.0}
    data["analysis"]["force_tolerance"] = 1e-5
    data["analysis"]["displacement_tolerance"] = 1e-5
    return geoslip.Model.from_dict(data, name="reinforced-wall-duncan-chang.json")


def example(name):
    """A function that loads the example model file `name`."""
    return functools.partial(geoslip.Model.load, WALLS / name)


def variants():
    """(label, line style, a function that gives the model)."""
    return [
        ("Mohr–Coulomb", "o-", example("reinforced-wall.toml")),
        ("Mohr–Coulomb, lifts compacted (8 kPa)", "o--", example("reinforced-wall-compacted.toml")),
        ("Duncan–Chang (tolerances 1e-5)", "s-", plain_hyperbolic),
        ("Duncan–Chang, lifts compacted (1e-3)", "s--", example("reinforced-wall-hyperbolic.toml")),
        ("hardening soil, lifts compacted (1e-4)", "^--", example("reinforced-wall-hardening.toml")),
    ]


def main(png):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 5.2))
    simplified = None
    for label, style, model in variants():
        print(f"running: {label}", flush=True)
        started = time.perf_counter()
        results = model().run()
        checks = results.design_checks
        print(f"  {len(results.steps)} steps in {time.perf_counter() - started:.0f} s", flush=True)
        ax.plot(checks["T_max analysis"], checks["depth Z"], style, label=label)
        simplified = checks
        for name, z, t in zip(checks["layer"], checks["depth Z"], checks["T_max analysis"]):
            print(f"  {name}: Z = {z:.1f} m, T_max = {t:.2f} kN/m")
    ax.plot(simplified["T_max simplified"], simplified["depth Z"], "k--", label="Simplified Method, Ka(γz + q)Sv")
    ax.invert_yaxis()
    ax.set_xlabel("largest tension in the layer, T_max [kN/m]")
    ax.set_ylabel("depth below the crest [m]")
    ax.set_title("6 m geogrid wall: layer loads by soil model")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    print(f"figure: {png}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "wall-soil-models.png")
