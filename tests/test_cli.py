"""The `airwake` command's own contract: version, help, errors as one clear line."""

import subprocess
import sys

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
