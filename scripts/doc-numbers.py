#!/usr/bin/env python3
"""Every number the README and docs quote from a geoslip run, produced by the runs themselves.

A document marks a number it quotes from a run as

    <!-- number: ID -->12.84<!-- /number -->

and a table or list made from runs as

    <!-- numbers: ID -->
    | ... |
    <!-- /numbers -->

This script runs the models (each once), computes every ID below, and compares. With --write it
puts the computed text in place; without, it fails (exit 1) where a document and a run disagree,
and where a document marks an ID that no run produces. The numbers are formatted to the digits
the documents state, so "disagree" means beyond those digits.

    python3 scripts/doc-numbers.py [--geoslip PATH] [--measured DIR] [--write] [--keep DIR] [--list]

  --geoslip PATH  the geoslip binary (default: target/release/geoslip, then target/debug/geoslip)
  --measured DIR  also the numbers the tests recorded: a test quoting its own run writes each
                  number to DIR/ID when GEOSLIP_DOC_NUMBERS=DIR (tests/common/mod.rs, doc_number);
                  scripts/test-all.sh runs the tests so, then this script with --measured
  --write         rewrite the marked text in README.md and docs/*.md with the runs' numbers
  --keep DIR      run into DIR (kept) instead of a temporary folder
  --list          print every number the runs give, by ID

The runs (about two minutes with a release build):
  clay-segment, clay-nearest-node, clay-mortar
      examples/paper-pullout-clay.toml with each re-association rule (docs/reassociation.md)
  lab-series
      examples/lab-pullout/lab-pullout.toml: three airbag pressures, meshed by Gmsh (README)
  wall
      examples/reinforced-wall/reinforced-wall.toml and reinforced-wall-compacted.toml (README,
      docs/soil.md)
  results-readback
      the segment run's CSV files give what docs/results.md's h5py / meshio example prints
"""

import argparse
import csv
import json
import math
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DOCUMENTS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
INLINE = re.compile(r"<!-- number: ([\w.-]+) -->(.*?)<!-- /number -->")
BLOCK = re.compile(r"<!-- numbers: ([\w.-]+) -->\n(.*?)<!-- /numbers -->", re.S)

CLAY = ROOT / "examples/paper-pullout-clay.toml"
RULES = ["segment", "nearest-node", "mortar"]


def run(geoslip, model, out, *args):
    if out.exists():
        shutil.rmtree(out)
    done = subprocess.run([str(geoslip), "run", str(model), "--out", str(out), "-q", *args],
                          capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"doc-numbers: {model.name} failed (exit {done.returncode}):\n{done.stderr}")
    return out


def history(out):
    """The pull-out stage's |reaction| at the head, by step (1 step = 1 mm in the clay model)."""
    forces = {}
    with open(out / "history.csv", newline="") as f:
        for row in csv.DictReader(f):
            if row["stage"] == "pull-out":
                forces[int(row["step"])] = abs(float(row["reaction [kN/m]"]))
    return forces


def event_step(summary, text):
    """The pull-out step of the first event containing `text`, or None."""
    for event in summary["events"]:
        if text in event and 'stage "pull-out"' in event:
            return int(re.search(r"step (\d+)", event).group(1))
    return None


def sigma_n(out, step):
    """σn on the grid's upper face at a pull-out step, over the points in contact whose tributary
    length is a whole spacing h, within 10 % (not the head's or the tail's half, nor a point clipped
    at the front):
    mean, population standard deviation, min and max."""
    path = out / "stage-2-pull-out" / f"step-{step:03d}" / "interface.csv"
    with open(path, newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["interface"] == "grid" and r["face"] == "upper"]
    # (the spacing h, stretched with the grid: the median of the points' lengths)
    h = statistics.median(float(r["tributary [m]"]) for r in rows)
    values = [float(r["sigma_n [kPa]"]) for r in rows
              if r["state"] == "active" and 0.9 * h < float(r["tributary [m]"]) < 1.1 * h]
    return statistics.fmean(values), statistics.pstdev(values), min(values), max(values)


def percent(a, b, digits=2):
    d = 100 * (a - b) / b
    text = f"{d:+.{digits}f} %".replace("-", "−")
    zero = f"{0:.{digits}f} %"
    return zero if text in ("+" + zero, "−" + zero) else text


def clay_numbers(geoslip, work):
    numbers = {}
    runs = {}
    for rule in RULES:
        model = work / f"clay-{rule}.toml"
        text = CLAY.read_text()
        text, n = re.subn(r'(?m)^reassociation = "segment"', f'reassociation = "{rule}"', text)
        if n != 1:
            sys.exit("doc-numbers: examples/paper-pullout-clay.toml no longer sets reassociation = \"segment\"")
        model.write_text(text)
        out = run(geoslip, model, work / f"clay-{rule}", "--csv", "--no-restart")
        summary = json.loads((out / "summary.json").read_text())
        forces = history(out)
        peak_step = max(forces, key=forces.get)
        runs[rule] = (out, summary, forces)
        key = f"clay-{rule}"
        numbers[f"{key}.slip-starts"] = f"{event_step(summary, 'slip starts')} mm"
        slides = event_step(summary, "every interface point in contact slides")
        numbers[f"{key}.all-slide"] = f"{slides} mm" if slides else "no step"
        numbers[f"{key}.peak-at"] = f"{peak_step} mm"
        numbers[f"{key}.peak"] = f"{forces[peak_step]:.2f} kN/m"
        numbers[f"{key}.reassociations"] = re.search(r"(\d+) in all", (out / "report.md").read_text()).group(1)
        numbers[f"{key}.iterations"] = str(sum(s["iterations"] for s in summary["steps"]))
        numbers[f"{key}.analyses"] = str(summary["solver_stats"]["analyses"])
        numbers[f"{key}.set-aside"] = str(sum(
            any("set aside" in c for c in s["state_changes"]) for s in summary["steps"]))
        numbers[f"{key}.sd-60"] = f"{sigma_n(out, 60)[1]:.1f} kPa"
        numbers[f"{key}.max-60"] = f"{sigma_n(out, 60)[3]:.0f} kPa"
    (_, _, seg), (_, _, nn), (_, _, mo) = (runs[r] for r in RULES)
    rows = ["| head displacement [mm] | segment [kN/m] | nearest-node [kN/m] | difference | mortar [kN/m] | difference |",
            "|---:|---:|---:|---:|---:|---:|"]
    for mm in range(5, 61, 5):
        rows.append(f"| {mm} | {seg[mm]:.3f} | {nn[mm]:.3f} | {percent(nn[mm], seg[mm])} | {mo[mm]:.3f} | "
                    f"{percent(mo[mm], seg[mm])} |")
    numbers["clay-forces"] = "\n".join(rows) + "\n"
    rows = ["| step (head displacement) | segment [kPa] | nearest-node [kPa] | mortar [kPa] |", "|---|---|---|---|"]
    for step in (20, 40, 60):
        cells = [" / ".join([f"{m:.1f}", f"{s:.1f}", f"{lo:.1f}", f"{hi:.1f}"])
                 for (m, s, lo, hi) in (sigma_n(runs[r][0], step) for r in RULES)]
        rows.append(f"| {step} ({step} mm) | " + " | ".join(cells) + " |")
    numbers["clay-sigma-n"] = "\n".join(rows) + "\n"
    return numbers


def readback_numbers(clay_segment):
    """What docs/results.md's Python example prints after the clay run, from the same run's CSV
    files: the steps written, the largest |ux| of the last step, the peak pull-out force, and the
    first four points of the grid's upper face in the last step."""
    steps = sorted(step for stage in clay_segment.glob("stage-*") for step in stage.glob("step-*"))
    with open(steps[-1] / "displacements.csv", newline="") as f:
        ux = max(abs(float(r["ux [m]"])) for r in csv.DictReader(f))
    peak = max(history(clay_segment).values())
    with open(steps[-1] / "interface.csv", newline="") as f:
        upper = [r for r in csv.DictReader(f) if r["interface"] == "grid" and r["face"] == "upper"]
    points = ", ".join(f"({round(float(r['x [m]']), 3)}, {round(float(r['tau [kPa]']), 2)})" for r in upper[:4])
    return {"results-readback": ("```text\n"
                                 f"{len(steps)} steps; at step {len(steps)} the largest |ux| is {ux:.4f} m\n"
                                 f"peak pull-out force {peak:.2f} kN/m\n"
                                 f"tau along the grid's upper face: [{points}] ...\n```\n")}


def measured_numbers(folder):
    """The numbers the tests recorded (one file an ID)."""
    return {path.name: path.read_text() for path in sorted(Path(folder).iterdir()) if path.is_file()}


def lab_numbers(geoslip, work):
    out = run(geoslip, ROOT / "examples/lab-pullout/lab-pullout.toml", work / "lab-series")
    series = json.loads((out / "series.json").read_text())
    length = series["pullout"]["embedded_length"]
    below = []
    for case in series["cases"]:
        q = case["value"]
        peak = next(p["reaction"] for p in case["peaks"] if p["label"] == "grid.head")
        ideal = 2 * (q + 18.0 * 0.3) * math.tan(math.radians(30)) * length
        below.append(100 * (1 - abs(peak) / ideal))
    return {
        "lab-series.friction-angle": f"{series['envelope']['apparent_friction_angle_deg']:.1f}°",
        "lab-series.below": f"{min(below):.1f}–{max(below):.1f} %",
    }


def wall_numbers(geoslip, work):
    out = run(geoslip, ROOT / "examples/reinforced-wall/reinforced-wall.toml", work / "wall",
              "--csv", "--keep", "events", "--no-restart")
    stages = sorted((p for p in out.iterdir() if p.is_dir() and p.name.startswith("stage-")),
                    key=lambda p: int(p.name.split("-")[1]))
    steps = sorted(p for p in stages[-1].iterdir() if p.name.startswith("step-"))
    with open(steps[-1] / "bar_forces.csv", newline="") as f:
        bars = list(csv.DictReader(f))
    force, y = "T [kN/m]", "y_mid [m]"
    layers = {}
    for b in bars:
        level = round(float(b[y]), 6)
        layers[level] = max(layers.get(level, -math.inf), float(b[force]))
    fe = sum(layers.values())
    ka = math.tan(math.pi / 4 - math.radians(34) / 2) ** 2
    simplified = sum(ka * (18.0 * (6.0 - (0.6 * k - 0.3)) + 10.0) * 0.6 for k in range(1, 11))
    # the same wall with every lift compacted: each layer's T_max beside the plain run's and the
    # Simplified Method's (design-checks.csv of both runs)
    compacted = run(geoslip, ROOT / "examples/reinforced-wall/reinforced-wall-compacted.toml",
                    work / "wall-compacted", "--keep", "events", "--no-restart")
    plain_rows, compacted_rows = design_checks(out), design_checks(compacted)
    rows = ["| layer | depth Z [m] | T_max, lifts placed [kN/m] | T_max, lifts compacted [kN/m] | change | "
            "Simplified Method [kN/m] |", "|---|---:|---:|---:|---:|---:|"]
    for p, c in zip(plain_rows, compacted_rows):
        # (the change from the loads as the table prints them: MUMPS's ordering differs from one run
        # to the next, and with it the last digits, which could tip a change computed unrounded)
        t_p, t_c = round(float(p["T_max analysis"]), 2), round(float(c["T_max analysis"]), 2)
        rows.append(f"| {p['layer']} | {float(p['depth Z']):.1f} | {t_p:.2f} | {t_c:.2f} | {percent(t_c, t_p, 1)} | "
                    f"{float(p['T_max simplified']):.2f} |")
    sum_p = sum(float(r["T_max analysis"]) for r in plain_rows)
    sum_c = sum(float(r["T_max analysis"]) for r in compacted_rows)
    return {
        "wall.sum-t-max": f"{fe:.1f} kN/m",
        "wall.simplified": f"{simplified:.1f}",
        "wall.fraction": f"{100 * fe / simplified:.0f} %",
        "wall.compaction": "\n".join(rows) + "\n",
        "wall.compaction-sum": f"{sum_c:.1f} kN/m against {sum_p:.1f} kN/m ({percent(sum_c, sum_p, 0)})",
    }


def design_checks(out):
    """The rows of a run's design-checks.csv, from the top layer down, keyed by column name
    without its unit."""
    with open(out / "design-checks.csv", newline="") as f:
        rows = list(csv.reader(f))
    keys = [h.split(" [")[0] for h in rows[0]]
    return [dict(zip(keys, r)) for r in rows[1:]]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--geoslip")
    parser.add_argument("--measured")
    parser.add_argument("--write", action="store_true")
    parser.add_argument("--keep")
    parser.add_argument("--list", action="store_true", help="print every ID and its number")
    args = parser.parse_args()
    geoslip = Path(args.geoslip) if args.geoslip else next(
        (p for p in [ROOT / "target/release/geoslip", ROOT / "target/debug/geoslip"] if p.exists()), None)
    if geoslip is None or not geoslip.exists():
        sys.exit("doc-numbers: no geoslip binary: build one (cargo build --release) or pass --geoslip")

    with tempfile.TemporaryDirectory() as tmp:
        work = Path(args.keep) if args.keep else Path(tmp)
        work.mkdir(parents=True, exist_ok=True)
        numbers = {}
        for produce in (clay_numbers, lab_numbers, wall_numbers):
            numbers.update(produce(geoslip, work))
        numbers.update(readback_numbers(work / "clay-segment"))
    if args.measured:
        numbers.update(measured_numbers(args.measured))

    if args.list:
        for key, value in numbers.items():
            print(f"{key}: {value}" if "\n" not in value else f"{key}:\n{value}")
    wrong, unknown, marked = [], [], 0
    for doc in DOCUMENTS:
        text = doc.read_text()
        new = text

        def marked_text(kind, opening, closing, describe):
            """The replacement of one marked place: the run's text between the document's marks."""
            def replace(m):
                nonlocal marked
                marked += 1
                want = numbers.get(m.group(1))
                if want is None:
                    unknown.append(f"{doc.relative_to(ROOT)}: {kind} {m.group(1)}")
                    return m.group(0)
                if m.group(2) != want:
                    wrong.append(f"{doc.relative_to(ROOT)}: {m.group(1)}: {describe(m.group(2), want)}")
                return f"{opening.format(m.group(1))}{want}{closing}"
            return replace

        inline = marked_text("number", "<!-- number: {} -->", "<!-- /number -->",
                             lambda doc_text, run: f"the document says {doc_text!r}, the run {run!r}")
        block = marked_text("numbers", "<!-- numbers: {} -->\n", "<!-- /numbers -->",
                            lambda doc_text, run: "the document's block differs from the run's:\n"
                                                  f"--- document\n{doc_text}--- run\n{run}")
        new = INLINE.sub(inline, new)
        new = BLOCK.sub(block, new)
        if args.write and new != text:
            doc.write_text(new)
    for line in unknown:
        print(f"doc-numbers: no run produces {line}")
    if unknown and not args.measured:
        print("doc-numbers: numbers quoted from a test's run need --measured DIR, after the tests ran with "
              "GEOSLIP_DOC_NUMBERS=DIR")
    if args.write:
        print(f"doc-numbers: {marked} marked numbers and blocks, {len(wrong)} rewritten")
        return 1 if unknown else 0
    for line in wrong:
        print(f"doc-numbers: {line}")
    print(f"doc-numbers: {marked} marked numbers and blocks, {len(wrong)} differ from the runs")
    return 1 if wrong or unknown else 0


if __name__ == "__main__":
    sys.exit(main())
