"""A campaign on a 2-worker LocalCluster loses nothing when a worker is killed mid-run:
every result equals a serial run's, one broken flight fails alone (its traceback in the
summary), and a re-run recomputes only what failed."""

import os
import signal

import pandas as pd
import pytest
from airwake.campaign import load_campaign, run_campaign
from airwake.campaign.cluster import open_client
from campaigns import assert_same_results, broken_flight, outputs, write_campaign


@pytest.mark.slow
def test_killed_worker_loses_no_result_and_a_failed_flight_stops_only_itself(sim_campaign,
                                                                              tmp_path):
    broken = broken_flight(sim_campaign, tmp_path / "broken")
    camp = load_campaign(write_campaign(tmp_path / "campaign.toml", sim_campaign,
                                        extra=[{"path": str(broken)}]))
    assert len(camp.flights) == 7 and camp.betas == [0.0, 15.0]
    serial = run_campaign(camp, tmp_path / "serial", workers=0, show=False)

    killed = {}
    with open_client(workers=2, dashboard_address="127.0.0.1:0") as client:
        first_workers = set(client.scheduler_info(n_workers=-1)["workers"])

        def kill_a_busy_worker(rec):
            # after the first estimate, SIGKILL a worker that is running a task
            if killed or rec["step"] != "estimate" or rec["status"] != "done":
                return
            busy = {w: keys for w, keys in client.processing().items() if keys}
            if not busy:
                return
            addr = sorted(busy)[0]
            pid = client.run(os.getpid, workers=[addr])[addr]
            os.kill(pid, signal.SIGKILL)
            killed.update(worker=addr, tasks=list(busy[addr]))

        run = run_campaign(camp, tmp_path / "dask", client=client, show=False,
                           on_record=kill_a_busy_worker)
    assert killed, "no worker was busy after the first estimate"
    assert killed["worker"] in first_workers
    assert run.ran == len(run.plan.tasks)

    # every result, equal to the serial run's (tables to the bit)
    assert_same_results(outputs(serial), outputs(run))

    # the broken flight failed in its estimate, its map was skipped; nothing else failed
    s = run.summary.set_index("flight")
    assert s.loc["beta0_broken", "status"] == "failed"
    assert s.loc["beta0_broken", "failed_step"] == "estimate"
    assert "acc_x_m_s2" in s.loc["beta0_broken", "error"]
    assert "Traceback" in s.loc["beta0_broken", "traceback"]
    assert (s.drop(index="beta0_broken")["status"] == "done").all()
    assert (s.loc[s["role"] == "flight"].drop(index="beta0_broken")["map_cells"] > 0).all()
    merged = pd.read_parquet(run.out / "merged.parquet").set_index("beta_deg")
    assert list(merged["flights"]) == [3, 3]  # beta 0: three good flights, the broken left out
    assert (merged["status"] == "done").all()

    # a re-run finds every finished result in the store and retries only the failure
    again = run_campaign(camp, tmp_path / "dask", workers=0, show=False)
    retried = {r["subject"] for r in again.records.values() if not r.get("cached")}
    assert retried == {"beta0_broken"}  # its estimate failed again, its map skipped
    assert again.records[run.plan.by_subject["beta 0"]["merge"]]["cached"]
    assert sum(1 for r in again.records.values() if r["status"] == "done"
               and r.get("cached")) == sum(1 for r in run.records.values()
                                           if r["status"] == "done")
