"""Flight campaigns on dask.distributed: many flights through export, calibration, wind
estimation, wind maps and model reports, merged into one airwake map per relative wind
heading (docs/campaigns.md).

    from airwake.campaign import load_campaign, run_campaign
    campaign = load_campaign("campaign.toml")      # validated up front (CampaignError)
    run = run_campaign(campaign, "results/")        # LocalCluster; scheduler="tcp://..."
    run.summary                                     # summary.parquet as a DataFrame

One module per concern: `spec` (the campaign file), `plan` (tasks and their content
addresses), `store` (the result store), `steps` (each step through the public API of its
command), `runner` (one task where it runs), `cluster` (LocalCluster or a scheduler, the
worker warm-up plugin), `execute` (the run on Dask), `display` (live progress), `merge`
(the merged map per heading), `results` (summary.parquet, index.html).
"""

from airwake.campaign.errors import CampaignError

__all__ = ["CampaignError", "load_campaign", "run_campaign"]


def __getattr__(name):
    # lazy: `airwake --help` imports the package without Dask
    if name == "load_campaign":
        from airwake.campaign.spec import load_campaign

        return load_campaign
    if name == "run_campaign":
        from airwake.campaign.execute import run_campaign

        return run_campaign
    raise AttributeError(name)
