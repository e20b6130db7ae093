"""Where a campaign runs: a Dask LocalCluster on this machine, or an existing cluster.

    with open_client(workers=None, scheduler=None) as client:   # LocalCluster, one worker
        ...                                                       # per core, one thread each
    with open_client(scheduler="tcp://host:8786") as client:     # `dask scheduler` elsewhere

Each worker process runs one task at a time (one thread: the steps are CPU-bound numpy,
numba and scipy, and their BLAS and numba pools are held to one thread too, so N workers
use N cores without oversubscription). `WarmWorker`, a worker plugin, imports the steps
and compiles (or loads from the disk cache) the model's numba kernels once when a worker
starts, not in every task, with the simulator's truth fields (for scoring simulated
flights); the workers of one machine warm one after another (a lock file), so the first
compiles what the cache lacks and the others load it (and torch with the networks' code
when a
step uses a network: wind estimates by a wind net; no other step imports torch, so other
campaigns' workers skip its import and memory); a worker that restarts after a crash runs
it again. Workers of an existing cluster need `airwake` installed and the campaign's
files (and its output directory) at the same paths: a shared file system.
"""

from __future__ import annotations

import os
import sys
import tempfile
from contextlib import contextmanager
from pathlib import Path

from distributed import WorkerPlugin

# the steps are single-threaded by design: one core per worker
THREAD_ENV = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1",
              "NUMBA_NUM_THREADS": "1"}


def limit_threads() -> None:
    """Hold BLAS, numba and torch to one thread in this process (a worker's setting)."""
    from threadpoolctl import threadpool_limits

    threadpool_limits(1)
    _set_threads(1, 1)


def _set_threads(numba_threads: int, torch_threads: int) -> None:
    import numba

    numba.set_num_threads(min(numba_threads, numba.config.NUMBA_NUM_THREADS))
    if "torch" in sys.modules:  # set when a step uses it (OMP_NUM_THREADS=1 before that)
        sys.modules["torch"].set_num_threads(torch_threads)


@contextmanager
def single_threaded():
    """`limit_threads` for a block of this process, the previous setting restored after
    (a campaign run here, as `--workers 0` or a test, leaves its process as it found it)."""
    import numba
    from threadpoolctl import threadpool_limits

    torch = sys.modules.get("torch")
    before = numba.get_num_threads(), torch.get_num_threads() if torch else 1
    with threadpool_limits(1):
        _set_threads(1, 1)
        try:
            yield
        finally:
            _set_threads(*before)


@contextmanager
def one_process_at_a_time(name: str):
    """Hold a lock file (per user, in the temp directory) for the block: processes of this
    machine run it one after another. Without fcntl (not POSIX), no lock."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover — Linux and macOS have it
        yield
        return
    uid = os.getuid() if hasattr(os, "getuid") else "user"
    with open(Path(tempfile.gettempdir()) / f"{name}-{uid}.lock", "a") as f:
        fcntl.flock(f, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(f, fcntl.LOCK_UN)


def warm(models=("table52",), torch: bool = False) -> dict:
    """Import every step, hold threads to one and compile (or load) the kernels of the
    given model specs by one model evaluation each, and the simulator's truth fields; with
    `torch` (a step uses a network: wind estimates by a wind net) import torch and load the
    networks' code too. One process of the machine at a time (`one_process_at_a_time`):
    compiling the same kernels in every worker at once multiplies the time on shared
    cores, while after the first the others load them from the disk cache. Returns what
    it did (for logs)."""
    import time

    t0 = time.perf_counter()
    with one_process_at_a_time("airwake-kernels-warm"):
        info = _warm(models, torch)
    return {"seconds": time.perf_counter() - t0, **info}


def _warm(models, torch: bool) -> dict:
    if torch:
        import airwake.nets.wind_net  # noqa: F401 — torch and the nets' modules
    limit_threads()
    import importlib
    import io

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(1, 1))  # fonts and the PNG writer, once
    fig.savefig(io.BytesIO(), format="png")
    plt.close(fig)
    from airwake.estimate.truth import PROVIDERS

    truths = []
    for name in PROVIDERS:  # the simulator's truth field, for scoring simulated flights
        try:
            mod = importlib.import_module(name)
        except ModuleNotFoundError:
            continue
        if hasattr(mod, "warm"):
            truths += mod.warm()
    import airwake.calibrate  # noqa: F401
    import airwake.discrepancy.report  # noqa: F401
    import airwake.estimate.map_report  # noqa: F401
    import airwake.estimate.wind  # noqa: F401
    from airwake.calibrate.residuals import FlightData  # noqa: F401
    from airwake.heli import load_model

    warmed = []
    for spec in models:
        try:
            model = load_model(spec)
        except Exception:  # noqa: BLE001 — warming is best effort; the task will say why
            continue
        _evaluate_once(model)
        warmed.append(str(spec))
    return {"models": warmed, "truth_scenarios": truths}


def _evaluate_once(model) -> None:
    """One compiled evaluation of the model at rest (JIT compile or cache load)."""
    import numpy as np

    model.rates_and_measurement(model.zero_state(1), np.zeros((1, 4)))


class WarmWorker(WorkerPlugin):
    """Warm every worker once when it starts (module docstring)."""

    name = "airwake-campaign-warm"

    def __init__(self, models=("table52",), torch: bool = False) -> None:
        self.models = tuple(models)
        self.torch = torch

    def setup(self, worker) -> None:
        for k, v in THREAD_ENV.items():
            os.environ.setdefault(k, v)
        info = warm(self.models, self.torch)
        worker.log_event("airwake-campaign-warm", {"worker": worker.address, **info})


@contextmanager
def open_client(workers: int | None = None, scheduler: str | None = None,
                dashboard_address: str = "127.0.0.1:8787"):
    """A Dask client: of a new LocalCluster (`workers` processes, default one per core,
    one thread each, on the loopback) or of the scheduler at `scheduler`."""
    from distributed import Client, LocalCluster

    from airwake.campaign.errors import CampaignError

    if scheduler:
        try:
            client = Client(scheduler, timeout="20s")
        except OSError as exc:
            raise CampaignError(f"--scheduler {scheduler}: cannot connect: {exc}") from None
        try:
            yield client
        finally:
            client.close()
        return
    n = workers or os.cpu_count() or 1
    # the worker processes inherit these: numba and BLAS read them at import
    saved = {k: os.environ.get(k) for k in THREAD_ENV}
    os.environ.update(THREAD_ENV)
    try:
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                               host="127.0.0.1", dashboard_address=dashboard_address,
                               silence_logs=40)
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
    client = Client(cluster)
    try:
        yield client
    finally:
        client.close()
        cluster.close()
