#!/usr/bin/env python3
"""List the module imports of geoslip's sources and fail on an import circle or on a core module
that imports the model file format.

    python3 scripts/check-imports.py [--list]

Every `crate::…`, `super::…` and `self::…` path in the code of `src/` (comments and strings left
out) is resolved to the module file it names. It then checks:
- no circle between files (a file's `mod` declarations are not imports; its `use` of a child is);
- no circle between the top-level modules (`analysis`, `model`, `interface`, …, `mesh.rs`);
- only `model`, `output`, `cli`, `meshgen` and `calibration` import `model::file`, the serde types of the file
  format: the core reads the checked model, or types of its own that the file format re-uses;
- `output` does not import `linsol`: the results are written from the analysis's values, and the
  run's statistics come through `analysis`.
With --list it prints the top-level modules in layers (each imports only the ones below it) and
every file's imports. Exits with 1 and names the circle or the import when a check fails.
"""

import os
import re
import sys

SRC = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src")
MAY_IMPORT_FILE_FORMAT = {"model", "output", "cli", "meshgen", "calibration"}


def module_files():
    """module path (tuple) -> file path, for every .rs under src/ but the binaries."""
    mods = {}
    for root, _, files in os.walk(SRC):
        for f in files:
            if not f.endswith(".rs"):
                continue
            path = os.path.join(root, f)
            rel = os.path.relpath(path, SRC)[:-3].split(os.sep)
            if rel[0] == "bin" or rel == ["main"]:
                continue
            if rel == ["lib"]:
                key = ()
            elif rel[-1] == "mod":
                key = tuple(rel[:-1])
            else:
                key = tuple(rel)
            mods[key] = path
    return mods


def code_of(path):
    """The file's text without comments, string literals and #[cfg(test)] modules."""
    text = open(path, encoding="utf-8").read()
    cut = re.search(r"#\[cfg\(test\)\]\s*mod \w+", text)
    if cut:
        text = text[: cut.start()]
    text = re.sub(r"//[^\n]*", "", text)
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    text = re.sub(r'(?<!\w)r#*"(?:.|\n)*?"#*', '""', text)
    text = re.sub(r'"(?:\\.|[^"\\])*"', '""', text, flags=re.S)
    return text


def use_paths(code):
    """Every path a file names: `use` trees expanded, and inline `crate::a::b` paths."""
    paths = []
    for m in re.finditer(r"\buse\s+([^;]+);", code):
        paths.extend(expand(m.group(1).replace("\n", " ")))
    for m in re.finditer(r"(?<![\w:])((?:crate|super|self)(?:::\w+)+)", code):
        paths.append(m.group(1).split("::"))
    return paths


def expand(tree):
    """`a::{b, c::{d, e}}` -> [[a, b], [a, c, d], [a, c, e]]."""
    tree = tree.strip()
    if tree.startswith("pub "):
        tree = tree[4:].strip()
    depth, i = 0, 0
    brace = None
    for i, ch in enumerate(tree):
        if ch == "{" and depth == 0:
            brace = i
            break
    if brace is None:
        return [[p.strip() for p in tree.split(" as ")[0].split("::") if p.strip()]]
    prefix = [p for p in tree[:brace].split("::") if p.strip()]
    inner = tree[brace + 1: tree.rindex("}")]
    parts, depth, start = [], 0, 0
    for i, ch in enumerate(inner):
        if ch == "{":
            depth += 1
        elif ch == "}":
            depth -= 1
        elif ch == "," and depth == 0:
            parts.append(inner[start:i])
            start = i + 1
    parts.append(inner[start:])
    out = []
    for part in parts:
        if part.strip():
            for sub in expand(part):
                out.append(prefix + sub)
    return out


def resolve(path, here, mods):
    """The module a path names (its longest prefix that is a module), or None (external)."""
    if not path:
        return None
    if path[0] == "crate":
        base, rest = (), path[1:]
    elif path[0] in ("super", "self"):
        # the file's own module is `here` (a mod.rs is its folder's module): `super` climbs one
        base, rest = here, path
        while rest and rest[0] in ("super", "self"):
            if rest[0] == "super":
                base = base[:-1]
            rest = rest[1:]
    elif here + (path[0],) in mods:
        # a child module named without `self::` (`use law::ShearLaw` in interface/mod.rs)
        base, rest = here, path
    else:
        return None
    best = base if base in mods else None
    for k in range(1, len(rest) + 1):
        if base + tuple(rest[:k]) in mods:
            best = base + tuple(rest[:k])
    return best


def find_cycle(graph):
    """A cycle in a directed graph as a list of nodes, or None."""
    colour, stack = {}, []

    def visit(n):
        colour[n] = 1
        stack.append(n)
        for m in sorted(graph.get(n, ())):
            if colour.get(m) == 1:
                return stack[stack.index(m):] + [m]
            if colour.get(m) is None:
                found = visit(m)
                if found:
                    return found
        stack.pop()
        colour[n] = 2
        return None

    for n in sorted(graph):
        if colour.get(n) is None:
            found = visit(n)
            if found:
                return found
    return None


def layers(graph):
    """Top-level modules in layers from the top: each imports only modules in layers below it."""
    remaining = set(graph)
    out = []
    while remaining:
        top = sorted(n for n in remaining if not any(n in graph[m] for m in remaining if m != n))
        if not top:
            return out + [sorted(remaining)]
        out.append(top)
        remaining -= set(top)
    return out


def name(key):
    return "::".join(key) if key else "crate (lib.rs)"


def main():
    listing = "--list" in sys.argv
    mods = module_files()
    files = {}
    for key, path in mods.items():
        targets = set()
        for p in use_paths(code_of(path)):
            t = resolve(p, key, mods)
            if t is not None and t != key and t != ():
                # a parent module named only as a path prefix (super::Type from a child) is an
                # import of that parent; a child named by its parent is an import of the child
                targets.add(t)
        files[key] = targets
    failures = []
    cycle = find_cycle(files)
    if cycle:
        failures.append("import circle between files: " + " -> ".join(name(k) for k in cycle))
    top = {}
    for key, targets in files.items():
        if not key:
            continue
        top.setdefault(key[0], set()).update(t[0] for t in targets if t and t[0] != key[0])
    cycle = find_cycle(top)
    if cycle:
        failures.append("import circle between top-level modules: " + " -> ".join(cycle))
    for key, targets in sorted(files.items()):
        if key and key[0] not in MAY_IMPORT_FILE_FORMAT and ("model", "file") in targets:
            failures.append(f"{name(key)} imports model::file: the core must not depend on the file format")
        if key and key[0] == "output" and any(t and t[0] == "linsol" for t in targets):
            failures.append(f"{name(key)} imports linsol: output writes what the analysis hands it")
    if listing:
        print("top-level modules, in layers from the top (each imports only modules below it):")
        for i, layer in enumerate(layers(top)):
            print(f"  {i + 1}. {', '.join(layer)}")
        print()
        for key in sorted(files):
            if files[key]:
                print(f"{name(key)} -> {', '.join(sorted(name(t) for t in files[key]))}")
    for f in failures:
        print("error: " + f)
    if not failures:
        print(f"{len(files)} module files, {sum(len(t) for t in files.values())} imports: no circle, "
              "no core module importing model::file")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
