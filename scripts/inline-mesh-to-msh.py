#!/usr/bin/env python3
"""Write a model file's inline mesh as a Gmsh .msh (format 4.1, ASCII) beside a copy of the model
that names it: the same nodes and elements under the same ids, one physical surface per soil
material, everything else (sets, interfaces, stages) left inline.

    python3 scripts/inline-mesh-to-msh.py MODEL.toml OUT_STEM
    # writes OUT_STEM.msh and OUT_STEM.toml

For timing the `.msh` import against the inline mesh (docs/performance.md, issue #39). Handles the
linear elements (tri3, quad4) and models whose `nodes = [...]` is one line, as
`geoslip bench --pullout --write-models` writes them.
"""
import sys
import tomllib

GMSH_TYPE = {"tri3": 2, "quad4": 3}


def main(model_path, stem):
    text = open(model_path, encoding="utf-8").read()
    model = tomllib.loads(text)
    nodes = model["nodes"]
    materials = sorted({e["material"] for e in model["elements"]})
    surface = {m: k + 1 for k, m in enumerate(materials)}
    xs = [n[1] for n in nodes]
    ys = [n[2] for n in nodes]
    out = [
        "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n",
        f"$PhysicalNames\n{len(materials)}\n",
        "".join(f'2 {surface[m]} "{m}"\n' for m in materials),
        "$EndPhysicalNames\n",
        f"$Entities\n0 0 {len(materials)} 0\n",
        "".join(f"{surface[m]} {min(xs)} {min(ys)} 0 {max(xs)} {max(ys)} 0 1 {surface[m]} 0\n" for m in materials),
        "$EndEntities\n",
    ]
    # every node in the first surface's block (a node belongs to one entity in a .msh)
    ids = [n[0] for n in nodes]
    out.append(f"$Nodes\n1 {len(nodes)} {min(ids)} {max(ids)}\n2 1 0 {len(nodes)}\n")
    out.append("".join(f"{i}\n" for i in ids))
    out.append("".join(f"{x!r} {y!r} 0\n" for _, x, y in nodes))
    out.append("$EndNodes\n")
    by_block = {}
    for e in model["elements"]:
        by_block.setdefault((surface[e["material"]], GMSH_TYPE[e["type"]]), []).append(e)
    element_ids = [e["id"] for e in model["elements"]]
    out.append(f"$Elements\n{len(by_block)} {len(element_ids)} {min(element_ids)} {max(element_ids)}\n")
    for (tag, kind), elements in sorted(by_block.items()):
        out.append(f"2 {tag} {kind} {len(elements)}\n")
        out.append("".join(f"{e['id']} {' '.join(map(str, e['nodes']))}\n" for e in elements))
    out.append("$EndElements\n")
    with open(stem + ".msh", "w", encoding="utf-8") as f:
        f.write("".join(out))

    # the model without its inline mesh, naming the .msh
    lines = text.split("\n")
    kept, skipping = [], False
    for line in lines:
        if line.startswith("nodes = [["):
            continue
        if line == "[[elements]]":
            skipping = True
            continue
        if skipping:
            if line.startswith("[") and line != "[[elements]]":
                skipping = False
            else:
                continue
        kept.append(line)
    first_table = next(k for k, line in enumerate(kept) if line.startswith("["))
    mesh = ["[mesh]", f'file = "{stem.split("/")[-1]}.msh"',
            "materials = { " + ", ".join(f'{m} = "{m}"' for m in materials) + " }", ""]
    with open(stem + ".toml", "w", encoding="utf-8") as f:
        f.write("\n".join(kept[:first_table] + mesh + kept[first_table:]))


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
