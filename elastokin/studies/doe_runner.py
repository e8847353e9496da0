"""Running a DOE study's samples: serially or on ``dask.distributed`` (the only place dask
is imported), each finished sample appended to ``samples.jsonl`` so that an interrupted study
resumes where it stopped."""

from __future__ import annotations

import json
import logging
from collections.abc import Callable, Iterable
from pathlib import Path

import numpy as np

from elastokin.errors import ElastokinError
from elastokin.studies.doe import Study, evaluate_batch, evaluate_sample
from elastokin.studies.doe_sampling import EXTENSIBLE

STORE = "samples.jsonl"


class SampleStore:
    """``samples.jsonl``: a header line identifying the study, then one JSON record per
    finished sample, in the order they finished. Appending is flushed per record, so an
    interrupted study keeps what it finished; a torn last line is dropped on reading. A new
    (or ``restart``) store is written with its first record.

    A store of the same study with fewer samples is **extended** in place when the design
    extends (:data:`~elastokin.studies.doe_sampling.EXTENSIBLE`: Sobol and Monte Carlo, whose
    first n points do not depend on the sample count): its header is rewritten and only the
    new samples run (``extended_from`` says from how many). A Latin hypercube does not extend
    (its strata depend on the count) and is refused with the way out."""

    def __init__(self, path: Path, header: dict, restart: bool = False):
        self.path = Path(path)
        self.header = header
        self.records: dict[int, dict] = {}
        self.dropped_partial = False
        self.extended_from: int | None = None
        self._fresh = restart or not self.path.exists()  # header written with the 1st record
        if not self._fresh:
            self._read()

    def _check_header(self, found) -> None:
        """The stored study is this one, or (:class:`SampleStore`) one it extends."""
        def show(v):
            return f"{v[:12]}..." if isinstance(v, str) and len(v) == 64 else repr(v)

        if not isinstance(found, dict):
            diff = "unreadable header"
        else:
            diff = ", ".join(f"{k} {show(found.get(k))} (now {show(v)})"
                             for k, v in self.header.items() if found.get(k) != v)
            if {k for k, v in self.header.items() if found.get(k) != v} == {"samples"}:
                old, new, method = found["samples"], self.header["samples"], found["method"]
                if old < new and method in EXTENSIBLE:
                    self.extended_from = old
                    return
                if old < new:
                    raise ElastokinError(
                        f"{self.path}: holds a {old}-sample Latin hypercube, which cannot be "
                        f"extended to {new} samples (its strata depend on the sample count: "
                        f"the first {old} samples of a {new}-sample design are others); use "
                        f"--samples {old} to resume it, --restart to discard it, or --method "
                        "sobol or mc, whose designs extend in place")
                raise ElastokinError(
                    f"{self.path}: holds a {old}-sample study; ask for at least {old} "
                    "samples (a study is extended, never cut), or --restart to discard it")
        raise ElastokinError(f"{self.path}: holds samples of another study ({diff}); use "
                             "another --out, or --restart to discard them")

    def _read(self) -> None:
        lines = self.path.read_text().split("\n")
        try:
            found = json.loads(lines[0])
        except json.JSONDecodeError:
            found = None
        if found != self.header:
            self._check_header(found)
            lines[0] = json.dumps(self.header, sort_keys=True)
        good = [lines[0]]
        for line in lines[1:]:
            if not line.strip():
                continue
            try:
                rec = json.loads(line)
                k = int(rec["sample"])
            except (json.JSONDecodeError, KeyError, TypeError, ValueError):
                self.dropped_partial = True  # torn write of an interrupted run
                continue
            if 0 <= k < self.header["samples"] and k not in self.records:
                self.records[k] = rec
                good.append(line)
        if self.dropped_partial or self.extended_from is not None:
            self.path.write_text("\n".join(good) + "\n")

    def add(self, record: dict) -> None:
        self.records[record["sample"]] = record
        if self._fresh:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self.path.write_text(json.dumps(self.header, sort_keys=True) + "\n")
            self._fresh = False
        with open(self.path, "a") as fh:
            fh.write(json.dumps(record, sort_keys=True) + "\n")
            fh.flush()

    def check_design(self, shifts: Callable[[int], dict]) -> None:
        """Every stored sample is the sample ``shifts(k)`` of this study's design (an
        extended or resumed study must continue the same sequence; a changed sampler would
        mix two designs)."""
        for k, rec in self.records.items():
            new = shifts(k)
            if set(new) != set(rec["shifts_mm"]) or not all(
                    np.allclose(rec["shifts_mm"][j], new[j], rtol=0.0, atol=1e-12)
                    for j in new):
                raise ElastokinError(f"{self.path}: sample {k} is not sample {k} of this "
                                     "design (another sampler version?); --restart to "
                                     "discard the stored samples")

    def ordered(self) -> list[dict]:
        """Records in sample order, as read back from JSON (bit-identical floats)."""
        return [json.loads(json.dumps(self.records[k], sort_keys=True))
                for k in sorted(self.records)]


def run_serial(job: dict, items: Iterable[tuple[int, dict]],
               on_record: Callable[[dict], None]) -> None:
    """Evaluate samples one after the other in this process."""
    for k, sh in items:
        on_record(evaluate_sample(job, k, sh))


def run_dask(client, job: dict, items: list[tuple[int, dict]],
             on_record: Callable[[dict], None], batch: int = 1) -> None:
    """Evaluate samples on a ``dask.distributed`` client, ``batch`` samples per task; records
    arrive as tasks finish. A task lost by dask (e.g. a worker that died) is recorded as
    failed for each of its samples."""
    from distributed import as_completed

    if not items:
        return
    [job_future] = client.scatter([job], broadcast=True, hash=False)
    chunks = [items[i:i + batch] for i in range(0, len(items), batch)]
    futures = {client.submit(evaluate_batch, job_future, chunk, pure=False): chunk
               for chunk in chunks}
    try:
        for fut in as_completed(futures):
            try:
                records = fut.result()
            except Exception as exc:  # noqa: BLE001 - lost on the cluster, not a solve
                records = [{"sample": k, "shifts_mm": sh, "status": "failed",
                            "error": f"dask: {type(exc).__name__}: {exc}",
                            "characteristics": {}} for k, sh in futures[fut]]
            for rec in records:
                on_record(rec)
    finally:
        client.cancel(list(futures))


def batch_size(pending: int, workers: int) -> int:
    """Samples per dask task: about 8 tasks per worker, at most 4 samples each (a task of a
    few samples amortises the scheduler's round trip; benchmarks/bench_doe.py)."""
    return max(1, min(4, pending // (8 * max(1, workers))))


def run_study(study: Study, store: SampleStore, client=None, limit: int | None = None,
              progress: Callable[[int], None] = lambda n: None, batch: int = 1) -> int:
    """Evaluate the samples not yet in ``store`` (at most ``limit`` of them, lowest index
    first), serially or on a dask ``client``; returns how many were evaluated."""
    pending = [k for k in range(study.samples) if k not in store.records]
    if limit is not None:
        pending = pending[:limit]
    items = [(k, study.shifts(k)) for k in pending]

    def on_record(rec: dict) -> None:
        store.add(rec)
        progress(1)

    if client is None:
        run_serial(study.job, items, on_record)
    else:
        run_dask(client, study.job, items, on_record, batch)
    return len(items)


def dask_client(scheduler: str | None, workers: int):
    """A dask client: connected to ``scheduler``, or on a new LocalCluster of ``workers``
    single-threaded worker processes. Returns (client, cluster or None)."""
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        raise ElastokinError("dask.distributed is not installed: pip install "
                             "'dask[distributed]', or run serially with --workers 1") from None
    if scheduler is not None:
        try:
            return Client(scheduler, timeout="10s"), None
        except (OSError, TimeoutError, ValueError) as exc:
            detail = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            raise ElastokinError(f"--scheduler {scheduler}: cannot connect ({detail})") from None
    import dask

    # the workers' statistical profiler samples every 10 ms and costs ~10 % of a solve
    with dask.config.set({"distributed.worker.profile.enabled": False}):
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                               dashboard_address=None, silence_logs=logging.ERROR)
    return Client(cluster), cluster


def execute(study: Study, store: SampleStore, scheduler: str | None, workers: int,
            progress: Callable[[int], None] = lambda n: None) -> str:
    """Evaluate the study's pending samples: on the dask scheduler ``scheduler``, on a
    LocalCluster of ``workers`` processes, or (one worker, nothing pending) in this process.
    Returns where they ran."""
    pending = study.samples - len(store.records)
    if not pending or (scheduler is None and workers <= 1):
        run_study(study, store, None, progress=progress)
        return "serial"
    client, cluster = dask_client(scheduler, workers)
    try:
        n = len(client.scheduler_info().get("workers", {}))
        run_study(study, store, client, progress=progress, batch=batch_size(pending, n))
        return f"dask scheduler {client.scheduler.address}, {n} workers"
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
