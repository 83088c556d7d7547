#!/usr/bin/env python3
"""Write the long-run benchmark model: a small pull-out box (8 quad4 elements, a Coulomb grid at
mid-height) pulled 50 mm in N steps, every step kept. Its steps take about a millisecond each, so
the run's time is mostly what writing its results costs per step (docs/performance.md, "Runs of
thousands of steps").

    python3 scripts/long-run-model.py N > long.toml
    geoslip run long.toml --out long-out
"""

import sys


def model(steps):
    nx, ny = 4, 2

    def node(i, j):
        return 1 + j * (nx + 1) + i

    nodes = ", ".join(f"[{node(i, j)}, {0.1 * i:.1f}, {0.1 * j:.1f}]" for j in range(ny + 1) for i in range(nx + 1))
    elements = []
    for j in range(ny):
        for i in range(nx):
            corners = f"{node(i, j)}, {node(i + 1, j)}, {node(i + 1, j + 1)}, {node(i, j + 1)}"
            elements.append(f'{{ id = {len(elements) + 1}, type = "quad4", nodes = [{corners}], material = "sand" }}')

    def listed(ids):
        return ", ".join(str(n) for n in ids)

    top = ", ".join(f"[{node(i, ny)}, {node(i + 1, ny)}]" for i in range(nx))
    factors = ", ".join(str(k / steps) for k in range(1, steps + 1))
    return "\n".join(
        [
            f'title = "long run, {steps} pull steps"',
            f"nodes = [{nodes}]",
            "elements = [" + ",\n  ".join(elements) + "]",
            "",
            "[units]",
            'length = "m"',
            'force = "kN"',
            "",
            "[materials.soil.sand]",
            "youngs_modulus = 20000.0",
            "poissons_ratio = 0.3",
            "unit_weight = 18.0",
            "",
            "[materials.reinforcement.grid]",
            "axial_stiffness = 1000.0",
            "tension_only = true",
            "",
            "[node_sets]",
            f"base = [{listed(node(i, 0) for i in range(nx + 1))}]",
            f"front = [{listed(node(0, j) for j in range(ny + 1))}]",
            f"back = [{listed(node(nx, j) for j in range(ny + 1))}]",
            "",
            "[edge_sets]",
            f"top = [{top}]",
            "",
            "[[supports]]",
            'set = "base"',
            'fix = ["x", "y"]',
            "",
            "[[supports]]",
            'set = "front"',
            'fix = ["x"]',
            "",
            "[[supports]]",
            'set = "back"',
            'fix = ["x"]',
            "",
            "[[interfaces]]",
            'name = "grid"',
            f'reinforcement = {{ path = [{listed(node(i, 1) for i in range(nx))}], material = "grid" }}',
            'law = { type = "coulomb", shear_stiffness = 5000.0, cohesion = 0.0, friction_angle = 30.0 }',
            "",
            "[[stages]]",
            'name = "surcharge"',
            'loads = [{ type = "edge-traction", edge_set = "top", pressure = 50.0 }]',
            "",
            "[[stages]]",
            'name = "pull-out"',
            f"load_factors = [{factors}]",
            'prescribed = [{ set = "grid.head", ux = -0.05 }]',
            "",
            "[analysis]",
            'scheme = "newton"',
            "",
        ]
    )


if __name__ == "__main__":
    if len(sys.argv) != 2 or not sys.argv[1].isdigit() or int(sys.argv[1]) < 1:
        sys.exit("usage: long-run-model.py N (the number of pull steps, at least 1)")
    sys.stdout.write(model(int(sys.argv[1])))
