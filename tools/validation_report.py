#!/usr/bin/env python3
"""The fracture validation report: docs/VALIDATION.md's results, made from the runs' own files.

    tools/validation_report.py [--results DIR] [--check]

1. Every run folder under DIR (default results/validation, what tools/run_validations.sh
   writes) that finished is archived into docs/validation/NAME/: its errors.csv,
   errors_cohesive_beam.csv, measured.csv, analytic.csv, cohesive_beam.csv, run.toml and
   scenario_as_run.toml (small text files; a later run of the same NAME replaces them).
2. From docs/validation/*/ alone it draws docs/validation/NAME.svg (measured, LEFM's closed
   form stage by stage, beam theory with the cohesive zone) and writes, between the markers
   <!-- results:begin --> and <!-- results:end --> of docs/VALIDATION.md, one section per
   test: the plot, the error table per stage against both references (the judged one with
   its bounds and verdict), the command, the commit and the wall time.

--check makes nothing: it exits 1 if docs/VALIDATION.md differs from what the archived runs
give (CI runs it, so that the report is never edited by hand).
"""

import argparse
import csv
import math
import shutil
import sys
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DOC = ROOT / "docs" / "VALIDATION.md"
ARCHIVE = ROOT / "docs" / "validation"
BEGIN, END = "<!-- results:begin -->", "<!-- results:end -->"
KEPT = ["errors.csv", "errors_cohesive_beam.csv", "measured.csv", "analytic.csv",
        "cohesive_beam.csv", "run.toml", "scenario_as_run.toml"]

# The order of the report: the full runs of the paper's material, then any other archived run.
ORDER = ["dcb", "enf", "mmb_20", "mmb_50", "mmb_80"]
STAGE_NAMES = {"1": "I", "2": "II", "3": "III", "4": "IV", "peak": "peak"}


def read_csv(path):
    if not path.exists():
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def archive(results):
    """Copies each finished run's small files into docs/validation/NAME/."""
    copied = []
    for run in sorted(p for p in results.iterdir() if (p / "run.toml").exists()):
        manifest = tomllib.loads((run / "run.toml").read_text())
        if manifest.get("status") != "finished" or not (run / "errors.csv").exists():
            print(f"validation_report: {run} did not finish; not archived", file=sys.stderr)
            continue
        target = ARCHIVE / run.name
        if target.exists():
            shutil.rmtree(target)
        target.mkdir(parents=True)
        for name in KEPT:
            if (run / name).exists():
                shutil.copy2(run / name, target / name)
        copied.append(run.name)
    return copied


def plot(name, folder, svg):
    import matplotlib
    matplotlib.use("Agg")
    matplotlib.rcParams["svg.hashsalt"] = "cleave"  # the same SVG for the same data
    matplotlib.rcParams["svg.fonttype"] = "none"
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.0, 4.2))
    measured = read_csv(folder / "measured.csv")
    windowed = bool(measured) and "load_instant_N" in measured[0]
    if windowed:
        # The instantaneous values under the window means: what the load cell's average hides.
        ax.plot([number(r["delta_instant_mm"]) for r in measured],
                [number(r["load_instant_N"]) for r in measured],
                color="0.6", lw=0.7, label="cleave, instantaneous (one step a row)")
    if measured:
        ax.plot([number(r["delta_mm"]) for r in measured], [number(r["load_N"]) for r in measured],
                color="black", lw=1.6,
                label="cleave (lattice), mean over each row's steps" if windowed
                else "cleave (lattice)")
    analytic = read_csv(folder / "analytic.csv")
    for stage in sorted({r["stage"] for r in analytic}):
        rows = [r for r in analytic if r["stage"] == stage]
        ax.plot([number(r["delta_mm"]) for r in rows], [number(r["load_N"]) for r in rows],
                ls="--", lw=1.2, label=f"LEFM, stage {STAGE_NAMES.get(stage, stage)}")
    czm = read_csv(folder / "cohesive_beam.csv")
    if czm:
        ax.plot([number(r["delta_mm"]) for r in czm], [number(r["load_N"]) for r in czm],
                color="tab:red", lw=1.0, alpha=0.8, label="beam theory with the cohesive zone")
    ax.set_xlabel("opening at the loaded end Δ (mm)" if not name.startswith("enf")
                  else "load-point deflection Δ (mm)")
    ax.set_ylabel("load P (N)")
    ax.set_title(name)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    fig.savefig(svg, metadata={"Date": None, "Creator": None})
    plt.close(fig)


def percent(x):
    return "—" if math.isnan(x) else f"{100 * x:.2f} %"


def bounds(row):
    parts = [f"{key} {100 * number(row[col]):g} %" for key, col in
             (("mean", "mean_bound"), ("max", "max_bound"), ("slope", "slope_bound"))
             if row.get(col)]
    return ", ".join(parts)


def table(rows, judged):
    out = ["| stage | Δ range (mm) | points | mean error | largest error | slope error |"
           + (" bounds | pass |" if judged else ""),
           "| --- | --- | --- | --- | --- | --- |" + (" --- | --- |" if judged else "")]
    for r in rows:
        stage = STAGE_NAMES.get(r["stage"], r["stage"])
        if r["stage"] == "peak":
            span = f"{number(r['from_mm']):.3f} (reference {number(r['to_mm']):.3f})"
        else:
            span = f"{number(r['from_mm']):.3f}–{number(r['to_mm']):.3f}"
        line = (f"| {stage} | {span} | {r['points']} | {percent(number(r['mean_rel_error']))} | "
                f"{percent(number(r['max_rel_error']))} | {percent(number(r['slope_rel_error']))} |")
        if judged:
            line += f" {bounds(r) or '—'} | {r['pass']} |"
        out.append(line)
    return "\n".join(out)


def section(name, folder):
    manifest = tomllib.loads((folder / "run.toml").read_text())
    facts, prov = manifest.get("facts", {}), manifest.get("provenance", {})
    reference = facts.get("reference", "lefm")
    errors = read_csv(folder / "errors.csv")
    zerrors = read_csv(folder / "errors_cohesive_beam.csv")
    wall = number(facts.get("wall_seconds"))
    threads = facts.get("threads", "?")
    verdict = "**PASS**" if facts.get("validation") == "pass" else "**FAIL**"
    lines = [f"### {name}", "",
             f"{facts.get('test', '?')}; judged against "
             + ("beam theory with the cohesive zone" if reference == "cohesive_beam"
                else "LEFM's closed forms") + f": {verdict}.", "",
             f"- command: `cleave validate {prov.get('scenario', '?')}`",
             f"- commit: `{prov.get('cleave_version', '?')}`",
             f"- wall time: {wall / 60:.1f} min ({facts.get('steps', '?')} steps, "
             f"{facts.get('steps_per_second', '?')} steps/s, {threads} thread{'' if threads == '1' else 's'}; "
             f"{facts.get('bodies', '?')} cubes, {facts.get('links', '?')} links)",
             f"- peak load {number(facts.get('peak_load_N')):.4g} N "
             f"(LEFM {number(facts.get('closed_form_peak_N')):.4g} N); kinetic energy at most "
             f"{facts.get('kinetic_over_work_max', '?')} of the external work after 5 % of the run",
             "", f"![{name}: load-deflection](validation/{name}.svg)", ""]
    first, second = ((zerrors, errors) if reference == "cohesive_beam" else (errors, zerrors))
    names = {"cohesive": "beam theory with the cohesive zone", "lefm": "LEFM (eqs 59-70)"}
    judged_name = names["cohesive"] if reference == "cohesive_beam" else names["lefm"]
    other_name = names["lefm"] if reference == "cohesive_beam" else names["cohesive"]
    lines += [f"Against {judged_name}, judged:", "", table(first, True), ""]
    if second:
        lines += [f"Against {other_name}, for comparison:", "", table(second, False), ""]
    return "\n".join(lines)


def summary_row(name, folder):
    manifest = tomllib.loads((folder / "run.toml").read_text())
    facts, prov = manifest.get("facts", {}), manifest.get("provenance", {})
    ref = "cohesive beam" if facts.get("reference") == "cohesive_beam" else "LEFM"
    return (f"| [{name}](#{name.replace('_', '_')}) | {ref} | {facts.get('validation', '?')} | "
            f"{number(facts.get('wall_seconds')) / 60:.1f} min | `{prov.get('cleave_version', '?')}` |")


def report():
    folders = {p.name: p for p in ARCHIVE.iterdir() if (p / "run.toml").exists()} if ARCHIVE.exists() else {}
    names = [n for n in ORDER if n in folders] + sorted(n for n in folders if n not in ORDER)
    missing = [n for n in ORDER if n not in folders]
    total = sum(number(tomllib.loads((folders[n] / "run.toml").read_text())["facts"].get("wall_seconds"))
                for n in names)
    parts = [BEGIN,
             "<!-- made by tools/validation_report.py from docs/validation/*/: do not edit by hand -->",
             "", "| test | judged against | verdict | wall time | commit |",
             "| --- | --- | --- | --- | --- |"]
    parts += [summary_row(n, folders[n]) for n in names]
    parts += ["", f"Wall time of the runs above, one after another: {total / 3600:.2f} h."]
    if missing:
        parts += ["", "Not run yet at full resolution: " + ", ".join(f"`{n}`" for n in missing) + "."]
    for n in names:
        parts += ["", section(n, folders[n])]
    parts += ["", END]
    return "\n".join(parts)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--results", type=Path, default=ROOT / "results" / "validation")
    parser.add_argument("--check", action="store_true",
                        help="exit 1 if docs/VALIDATION.md is not what the archived runs give")
    args = parser.parse_args()
    doc = DOC.read_text()
    if BEGIN not in doc or END not in doc:
        print(f"validation_report: {DOC} lacks the markers {BEGIN} / {END}", file=sys.stderr)
        return 2
    if not args.check:
        ARCHIVE.mkdir(parents=True, exist_ok=True)
        if args.results.exists():
            for name in archive(args.results):
                print(f"archived {args.results / name} -> {ARCHIVE / name}")
        for folder in sorted(p for p in ARCHIVE.iterdir() if (p / "run.toml").exists()):
            plot(folder.name, folder, ARCHIVE / f"{folder.name}.svg")
    head, rest = doc.split(BEGIN, 1)
    tail = rest.split(END, 1)[1]
    new = head + report() + tail
    if args.check:
        if new != doc:
            print("validation_report: docs/VALIDATION.md differs from the archived runs in "
                  "docs/validation/; run tools/validation_report.py", file=sys.stderr)
            return 1
        print("docs/VALIDATION.md matches the archived runs")
        return 0
    DOC.write_text(new)
    print(f"wrote {DOC}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
