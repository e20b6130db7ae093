"""Model versus measurement: compare · where · diagnose · add · report (MISSION.md §3.6).

    an = analyse(model, "flight.parquet")                 # step 1: residuals, metrics
    where = breakdown(an)                                 # step 2: regimes, spectra, tests
    diag = diagnose(model, "flight.parquet")              # step 3: ranked candidate effects
    added = add_effect(model, "ground_effect", "flight.parquet", out="model2.toml")  # step 4
    write_report("flight.parquet", model, "report_dir")   # step 5: HTML + PNG

Every step reads only measured columns (never `truth_*`, never the table's metadata) and
uses the same analysis band and start-up cut (`AnalysisSettings`). docs/model-discrepancy.md
walks through them on a simulated flight.
"""

from airwake.discrepancy.errors import DiscrepancyError
from airwake.discrepancy.settings import AnalysisSettings

__all__ = ["AnalysisSettings", "DiscrepancyError"]
