"""The README is executed: its tour's commands and its Python snippet, as written, in a fresh
folder, and the figures its comments give against what the commands print."""

import os
import pathlib
import re
import signal
import subprocess
import sys
import time
import tomllib

ROOT = pathlib.Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text()


def code_blocks(after):
    """The fenced code blocks of the README's section that starts with `after`."""
    section = README.split(after, 1)[1].split("\n## ", 1)[0]
    return re.findall(r"```(\w*)\n(.*?)```", section, re.S)


def tour():
    """(command, comment) for each line of the tour's shell block."""
    lines = []
    for line in code_blocks("## A 30-second tour")[0][1].splitlines():
        command, _, comment = line.partition(" #")
        if command.strip():
            lines.append((command.strip(), comment.strip()))
    return lines


def figure(text, pattern):
    """The number `pattern` captures in `text`, with half a unit of its last digit."""
    m = re.search(pattern, text)
    assert m, f"no match for {pattern!r} in: {text[-3000:]}"
    digits = m.group(1)
    places = len(digits.split(".")[1]) if "." in digits else 0
    return float(digits), 0.5 * 10.0 ** -places


def check_figures(comment, output, pairs):
    """Each (README pattern, output pattern): the printed figure within the text's precision."""
    for in_text, in_output in pairs:
        said, tolerance = figure(comment, in_text)
        got, _ = figure(output, in_output)
        assert abs(got - said) <= tolerance * (1 + 1e-9), f"README says {said} ({comment}), the run printed {got}"


def environment():
    env = dict(os.environ)
    env["PATH"] = str(pathlib.Path(env["CLEAVE_BINARY"]).parent) + os.pathsep + env["PATH"]
    # Open MPI refuses root without these; the README says to add --allow-run-as-root as root.
    env["OMPI_ALLOW_RUN_AS_ROOT"] = "1"
    env["OMPI_ALLOW_RUN_AS_ROOT_CONFIRM"] = "1"
    return env


def shell(command, cwd, env):
    done = subprocess.run(command, shell=True, cwd=cwd, env=env, capture_output=True, text=True, timeout=1500)
    output = done.stdout + done.stderr
    assert done.returncode == 0, f"`{command}` exited {done.returncode}:\n{output[-4000:]}"
    return output


def manifest(folder):
    with open(folder / "run.toml", "rb") as f:
        return tomllib.load(f)


def test_the_tour_runs_as_written_and_prints_the_figures_it_gives(tmp_path):
    (tmp_path / "scenarios").symlink_to(ROOT / "scenarios")
    env = environment()
    commands = tour()
    assert len(commands) >= 10, commands
    (run, run_comment), (restart, _) = commands[0], commands[1]
    assert run.startswith("cleave run ") and restart.startswith("cleave restart ")

    # The first run, stopped by Ctrl-C once its dynamics have begun (the restart line is
    # "after Ctrl-C"): it says how to continue, and the restart ends it.
    result = tmp_path / "results" / "brazilian_fracture"
    started = subprocess.Popen("exec " + run, shell=True, cwd=tmp_path, env=env, stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True)
    deadline = time.monotonic() + 600
    while not list((result / "frames").glob("bodies_*.vtp")) and time.monotonic() < deadline:
        time.sleep(0.05)
    started.send_signal(signal.SIGINT)  # as Ctrl-C does
    said = started.communicate(timeout=600)[0]
    assert started.returncode == 128 + signal.SIGINT, said[-3000:]
    assert "continue it with: cleave restart results/brazilian_fracture" in said, said[-3000:]
    output = shell(restart, tmp_path, env)
    assert manifest(result)["status"] == "finished"
    check_figures(run_comment, output, [(r"strength ([\d.]+) Pa", r"= ([\d.]+) Pa\s*\n"),
                                        (r"(\d+) bonds broken", r"cracks\s+(\d+) intergranular"),
                                        (r"(\d+) grains split", r"cracks\s+\d+ intergranular[^,\n]*, (\d+) transgranular")])

    for command, comment in commands[2:]:
        output = shell(command, tmp_path, env)
        if command.startswith("cleave sweep"):
            fit = manifest(tmp_path / "results" / "brazilian_fracture_sweep")["facts"]["weibull_modulus"]
            check_figures(comment, f"m = {fit}", [(r"Weibull modulus ([\d.]+)", r"m = ([\d.]+)")])
            assert "Weibull fit of 10 strengths" in output
        elif command.startswith("cleave validate"):
            assert "PASS" in comment and "PASS" in output and "FAIL" not in output, output[-3000:]
        elif command.startswith("mpirun"):
            one = manifest(result)["facts"]["final_state_hash"]
            assert manifest(tmp_path / "results" / "bf_mpi")["facts"]["final_state_hash"] == one
        elif command.startswith("cleave measure elastic"):
            check_figures(comment, output, [(r"E ([\d.]+) GPa", r"(?m)^  E = ([\d.]+) GPa"),
                                            (r"nu ([\d.]+)", r"(?m)^  E = [\d.]+ GPa, nu = ([\d.]+)")])
        elif command.startswith("cleave measure flexural"):
            check_figures(comment, output, [(r"sigma_f ([\d.]+) MPa", r"(?m)^  sigma_f = ([\d.]+) MPa")])


def test_the_python_snippet_runs_as_written_and_loads_along_the_axis_it_says(tmp_path):
    (tmp_path / "scenarios").symlink_to(ROOT / "scenarios")
    blocks = [text for lang, text in code_blocks("## A 30-second tour") if lang == "python"]
    assert len(blocks) == 1
    done = subprocess.run([sys.executable, "-c", blocks[0]], cwd=tmp_path, env=dict(os.environ),
                          capture_output=True, text=True, timeout=1500)
    assert done.returncode == 0, done.stderr[-4000:]
    assert (tmp_path / "ld.png").stat().st_size > 10000
    assert manifest(tmp_path / "results" / "bf")["status"] == "finished"
    # The snippet sets the top platen to 1e-4 m/s down y: its travel along its load axis
    # over the loading stage's rows grows at that rate.
    rows = (tmp_path / "results" / "bf" / "load_displacement.csv").read_text().splitlines()
    head = rows[0].split(",")
    t, d, stage = head.index("time_s"), head.index("top_displacement_m"), head.index("stage")
    loading = [r.split(",") for r in rows[1:] if r.split(",")[stage] == "loading"]
    (t0, d0), (t1, d1) = [(float(r[t]), float(r[d])) for r in (loading[len(loading) // 2], loading[-1])]
    assert abs((d1 - d0) / (t1 - t0) - 1e-4) < 1e-9
