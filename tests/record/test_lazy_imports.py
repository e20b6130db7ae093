"""The daemon's import graph stays light: pandas (~100 MB RSS, slow start) is only for
flight tables, never for ingest and recording."""

import subprocess
import sys


def test_daemon_and_recorder_do_not_import_pandas():
    code = (
        "import sys, importlib, pkgutil\n"
        "import airwake.daemon as d, airwake.record, airwake.record.reader\n"
        "for m in pkgutil.iter_modules(d.__path__):\n"
        "    importlib.import_module('airwake.daemon.' + m.name)\n"
        "print(sorted(k for k in ('pandas', 'torch', 'matplotlib') if k in sys.modules))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_flight_table_names_still_import_from_the_package():
    from airwake.record import FlightTableError, load_flight_table

    assert load_flight_table.__module__ == "airwake.record.flight_table"
    assert issubclass(FlightTableError, Exception)
