"""The `airwake` command's own contract: version, help, errors as one clear line."""

import json
import os
import subprocess
import sys
from pathlib import Path

import airwake
from airwake.cli import build_parser, main
from airwake.errors import AirwakeError


def test_version_flag_prints_package_version(capsys):
    try:
        main(["--version"])
    except SystemExit as exc:
        assert exc.code == 0
    assert capsys.readouterr().out.strip() == f"airwake {airwake.__version__}"


def test_console_script_runs_in_a_fresh_process():
    # the installed entry point must import without side effects (no torch at import time)
    out = subprocess.run(
        [sys.executable, "-c", "import sys, airwake.cli as c; sys.exit(c.main(['--help']))"],
        capture_output=True, text=True, check=True,
    )
    assert "bench" in out.stdout
    # the console script itself (its own wrapper), sys.modules read as it exits
    out = subprocess.run([str(Path(sys.executable).with_name("airwake")), "--help"],
                         capture_output=True, text=True, check=True, env={
                             **os.environ, "PYTHONPROFILEIMPORTTIME": "1"})
    imported = {line.split("|")[-1].strip().split(".")[0]
                for line in out.stderr.splitlines() if line.startswith("import time:")}
    assert "airwake" in imported and not imported & set(HEAVY_PACKAGES)


def test_user_error_becomes_one_line_and_status_2(monkeypatch, capsys):
    real_build = build_parser

    def build_with_failing_command():
        parser = real_build()
        sub = next(a for a in parser._actions if a.dest == "command")

        def boom(_args):
            raise AirwakeError("file 'x.csv': column 'p_rad_s' missing")

        sub.add_parser("boom-test").set_defaults(func=boom)
        return parser

    monkeypatch.setattr("airwake.cli.build_parser", build_with_failing_command)
    assert main(["boom-test"]) == 2
    err = capsys.readouterr().err
    assert err == "airwake boom-test: error: file 'x.csv': column 'p_rad_s' missing\n"


def test_bare_command_group_prints_help_and_fails(capsys):
    assert main([]) == 2
    assert "usage: airwake" in capsys.readouterr().err


# What `airwake --help`, `airwake X --help` and an argument error must not load: each of
# these takes 0.3-3 s to import on the build machine, and a command people type twenty
# times a day must answer at once (issue 22; the wall time is the bench's `cli_help_s`).
HEAVY_PACKAGES = ("torch", "numba", "scipy", "pandas", "pyarrow", "matplotlib", "dask")

_EVERY_HELP_AND_USAGE_ERROR = r"""
import argparse, contextlib, io, json, sys
from airwake.cli import build_parser, main

HEAVY = set(sys.argv[1].split(","))

def leaves(parser, path):
    yield path, parser
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield from leaves(sub, path + [name])

def heavy_loaded():
    return sorted({m.split(".")[0] for m in sys.modules} & HEAVY)

calls = []
for path, parser in leaves(build_parser(), []):
    calls.append(path + ["--help"])
    calls.append(path + ["--no-such-option"])
    if any(a.required for a in parser._actions):
        calls.append(path)  # a required argument missing
report = []
for argv in calls:
    with contextlib.redirect_stdout(io.StringIO()) as out, \
            contextlib.redirect_stderr(io.StringIO()) as err:
        try:
            status = main(argv)
        except SystemExit as exc:
            status = exc.code
    report.append({"argv": argv, "status": status, "heavy": heavy_loaded(),
                   "said": len(out.getvalue()) + len(err.getvalue())})
print(json.dumps(report))
"""


def test_help_and_usage_errors_import_no_heavy_package():
    # every command and sub-command's --help, an unknown option, a missing argument: one
    # fresh interpreter, modules checked after each call (the first offender is named)
    out = subprocess.run([sys.executable, "-c", _EVERY_HELP_AND_USAGE_ERROR,
                          ",".join(HEAVY_PACKAGES)], capture_output=True, text=True, check=True)
    report = json.loads(out.stdout)
    argvs = [r["argv"] for r in report]
    for needed in (["--help"], ["daemon", "--help"], ["sim", "run", "--help"],
                   ["model", "diagnose", "--help"], ["nets", "train", "--help"],
                   ["bench", "--help"], ["export"], ["calibrate", "--no-such-option"]):
        assert needed in argvs
    for r in report:
        assert r["status"] in (0, 2), r  # help: 0; argparse's usage error: 2
        assert r["said"] > 0, r
        assert r["heavy"] == [], f"airwake {' '.join(r['argv'])} imported {r['heavy']}"



def test_a_library_warning_is_one_line_and_the_command_goes_on(monkeypatch, capsys):
    # e.g. a flight table's implausible column the command does not read (FlightTableWarning)
    import warnings

    from airwake.record.flight_table import FlightTableWarning

    real_build = build_parser

    def build_with_warning_command():
        parser = real_build()
        sub = next(a for a in parser._actions if a.dest == "command")

        def warn(_args):
            warnings.warn(FlightTableWarning("f.csv: column 'x_m_s' has 2 value(s) ..."),
                          stacklevel=1)
            print("done")

        sub.add_parser("warn-test").set_defaults(func=warn)
        return parser

    monkeypatch.setattr("airwake.cli.build_parser", build_with_warning_command)
    assert main(["warn-test"]) == 0
    out = capsys.readouterr()
    assert out.err == "airwake warn-test: warning: f.csv: column 'x_m_s' has 2 value(s) ...\n"
    assert out.out == "done\n"
