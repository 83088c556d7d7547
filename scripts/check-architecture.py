#!/usr/bin/env python3
"""Check that docs/architecture.md names every source file under src/, and names no file that
does not exist.

    python3 scripts/check-architecture.py

Every `.rs` file under `src/` (the binaries included) must be named in docs/architecture.md by its
path relative to `src/`: literally (`analysis/equilibrium/solve.rs`), through a brace group
(`linsol/condensed/{kept,fallback}.rs` names `linsol/condensed/kept.rs` and
`linsol/condensed/fallback.rs`), or, for a folder's `mod.rs` only, as the folder with a trailing
slash inside code (`analysis/equilibrium/` names `analysis/equilibrium/mod.rs`). A leading `src/`
is allowed. It then checks the other way: every `.rs` path the page names must exist, under `src/`
when its first folder is one of `src/`'s (or it is a file there), otherwise from the repository's
root (`python/src/lib.rs`, `build.rs`). Exits with 1 and lists the files not named and the names
that point at nothing; prints one line when both hold.
"""

import os
import re
import sys

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
SRC = os.path.join(ROOT, "src")
DOC = os.path.join(ROOT, "docs", "architecture.md")

# the characters of a path token; a comma belongs to it only inside a brace group
PATH_CHARS = re.compile(r"[\w./{}*-]")


def source_files():
    """Every .rs file under src/, as a path relative to src/ with `/` separators."""
    files = set()
    for root, _, names in os.walk(SRC):
        for name in names:
            if name.endswith(".rs"):
                files.add(os.path.relpath(os.path.join(root, name), SRC).replace(os.sep, "/"))
    return files


def tokens(text):
    """Path-like tokens of a text: runs of path characters, commas kept inside `{…}`."""
    out, current, depth = [], [], 0
    for ch in text:
        if ch == "{":
            depth += 1
            current.append(ch)
        elif ch == "}" and depth > 0:
            depth -= 1
            current.append(ch)
        elif PATH_CHARS.match(ch) or (ch == "," and depth > 0):
            current.append(ch)
        elif depth > 0 and ch == " ":
            # `{a, b}`: a space after a comma inside a group
            continue
        else:
            if current:
                out.append("".join(current))
            current, depth = [], 0
    if current:
        out.append("".join(current))
    return out


def expand(token):
    """`a/{b,c}.rs` -> [`a/b.rs`, `a/c.rs`]; several groups expand in turn."""
    m = re.search(r"\{([^{}]*)\}", token)
    if not m:
        return [token]
    result = []
    for part in m.group(1).split(","):
        result.extend(expand(token[: m.start()] + part.strip() + token[m.end():]))
    return result


def code_text(doc):
    """The page's code: fenced blocks and inline `…` spans."""
    parts = re.findall(r"^```[^\n]*\n(.*?)^```", doc, flags=re.S | re.M)
    prose = re.sub(r"^```[^\n]*\n.*?^```", "", doc, flags=re.S | re.M)
    parts.extend(re.findall(r"`([^`\n]+)`", prose))
    return "\n".join(parts)


def clean(name):
    name = name.rstrip(".")
    while name.startswith("./"):
        name = name[2:]
    return name


def names_in(doc, src_dirs):
    """(.rs names as written with their expansions, folders named with a trailing slash)."""
    rs, folders = [], set()
    for token in tokens(doc):
        for name in map(clean, expand(token)):
            # (`.rs` alone, or a pattern such as `*.rs`, names no file)
            if name.endswith(".rs") and not re.search(r"(^|/)\.rs$|\*", name):
                rs.append((token, name))
    for token in tokens(code_text(doc)):
        for name in map(clean, expand(token)):
            if name.endswith("/"):
                if name.startswith("src/"):
                    name = name[4:]
                if name.split("/")[0] in src_dirs:
                    folders.add(name)
    return rs, folders


def main():
    files = source_files()
    src_dirs = {f.split("/")[0] for f in files if "/" in f}
    try:
        doc = open(DOC, encoding="utf-8").read()
    except OSError as e:
        print(f"error: cannot read {os.path.relpath(DOC, ROOT)}: {e.strerror}")
        return 1
    rs, folders = names_in(doc, src_dirs)
    named, stale = set(), []
    for token, name in rs:
        relative = name[4:] if name.startswith("src/") else name
        under_src = name.startswith("src/") or relative in files or relative.split("/")[0] in src_dirs
        if under_src and relative in files:
            named.add(relative)
        elif under_src:
            stale.append((token, "src/" + relative))
        elif not os.path.isfile(os.path.join(ROOT, name)):
            stale.append((token, f"{name} (neither src/{name} nor {name} in the repository)"))
    stale = list(dict.fromkeys(stale))
    for folder in folders:
        if folder + "mod.rs" in files:
            named.add(folder + "mod.rs")
    missing = sorted(files - named)
    if missing:
        print(f"error: {len(missing)} source files under src/ are not named in docs/architecture.md:")
        for f in missing:
            print(f"  {f}")
    if stale:
        print(f"error: docs/architecture.md names {len(stale)} .rs files that do not exist:")
        for token, path in stale:
            print(f"  {path}" + (f"  (from `{token}`)" if "{" in token else ""))
    if missing or stale:
        return 1
    print(f"{len(files)} source files under src/, every one named in docs/architecture.md; "
          f"all {len({n for _, n in rs})} .rs names in it exist")
    return 0


if __name__ == "__main__":
    sys.exit(main())
