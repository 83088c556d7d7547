"""Peak pull-out force of a geogrid against its embedded length and the surcharge.

A parameter study as engineers script them: one model per (embedded length, surcharge), built as a
Python dict in the model file's schema (a 1.2 m x 0.6 m sand box meshed here as 24 x 12 quad4,
the grid embedded at mid-height from the front wall, Coulomb interface phi = 30 deg, c = 0), run
in-process by geoslip, and the peak force plotted against the length, one line per surcharge,
beside the fully sliding limit 2 (q + gamma h) tan(phi) L.

Run (after `pip install ./python` and `pip install matplotlib`):
    python examples/python/parameter_study.py [output.png]
"""

import math
import sys

import geoslip

LENGTH, HEIGHT, NX, NY = 1.2, 0.6, 24, 12
GAMMA, PHI = 18.0, 30.0


def pullout_box(embedded, surcharge, pull=0.04, steps=20):
    """The model dict: sand box, grid embedded from the front wall over `embedded` metres."""
    h = LENGTH / NX
    node = lambda i, j: 1 + j * (NX + 1) + i  # noqa: E731
    nodes = [[node(i, j), i * h, j * HEIGHT / NY] for j in range(NY + 1) for i in range(NX + 1)]
    elements = [
        {"id": 1 + j * NX + i, "type": "quad4", "material": "sand",
         "nodes": [node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)]}
        for j in range(NY) for i in range(NX)
    ]
    mid = NY // 2
    cells = round(embedded / h)
    return {
        "title": f"pull-out box, L = {embedded} m, q = {surcharge} kPa",
        "units": {"length": "m", "force": "kN"},
        "materials": {
            "soil": {"sand": {"youngs_modulus": 30000.0, "poissons_ratio": 0.3, "unit_weight": GAMMA}},
            "reinforcement": {"grid": {"axial_stiffness": 2500.0}},
        },
        "nodes": nodes,
        "elements": elements,
        "node_sets": {
            "floor": [node(i, 0) for i in range(NX + 1)],
            "front": [node(0, j) for j in range(NY + 1)],
            "back": [node(NX, j) for j in range(NY + 1)],
        },
        "edge_sets": {"top": [[node(i + 1, NY), node(i, NY)] for i in range(NX)]},
        "supports": [
            {"set": "floor", "fix": ["x", "y"]},
            {"set": "front", "fix": ["x"]},
            {"set": "back", "fix": ["x"]},
        ],
        "interfaces": [{
            "name": "grid",
            "reinforcement": {"path": [node(i, mid) for i in range(cells + 1)], "material": "grid", "mode": "embedded"},
            "law": {"type": "coulomb", "shear_stiffness": 10000.0, "cohesion": 0.0, "friction_angle": PHI},
        }],
        "stages": [
            {"name": "confinement", "load_factors": [1.0],
             "loads": [{"type": "gravity"}, {"type": "edge-traction", "edge_set": "top", "pressure": surcharge}]},
            {"name": "pull-out", "load_factors": [(k + 1) / steps for k in range(steps)],
             "prescribed": [{"set": "grid.head", "ux": -pull}]},
        ],
    }


def peak_force(embedded, surcharge):
    model = geoslip.Model.from_dict(pullout_box(embedded, surcharge), name=f"box-{embedded}-{surcharge}.json")
    problems = model.check()
    if problems:
        raise SystemExit("\n".join(problems))
    results = model.run()
    return max(abs(r) for r in results.history["grid.head (x)"]["reaction"])


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "parameter-study.png"
    lengths = [0.4, 0.6, 0.8, 1.0]
    surcharges = [25.0, 50.0, 100.0]
    table = {q: [peak_force(L, q) for L in lengths] for q in surcharges}
    print("embedded length [m]: " + "  ".join(f"{L:6.2f}" for L in lengths))
    for q, peaks in table.items():
        print(f"q = {q:5.1f} kPa, peak [kN/m]: " + "  ".join(f"{p:6.2f}" for p in peaks))

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.5))
    tan = math.tan(math.radians(PHI))
    for q, peaks in table.items():
        line, = ax.plot(lengths, peaks, "o-", label=f"geoslip, q = {q:g} kPa")
        limit = [2 * (q + GAMMA * HEIGHT / 2) * tan * L for L in lengths]
        ax.plot(lengths, limit, "--", color=line.get_color(), alpha=0.6)
    ax.plot([], [], "k--", alpha=0.6, label="2 (q + γh) tan φ L (whole grid sliding)")
    ax.set_xlabel("embedded length L [m]")
    ax.set_ylabel("peak pull-out force [kN/m]")
    ax.set_title("Geogrid pull-out: peak force against embedded length and surcharge")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print(f"plot: {out}")


if __name__ == "__main__":
    main()
