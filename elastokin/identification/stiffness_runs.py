"""The stiffness fit's model runs (:mod:`elastokin.identification.stiffness`): each run solves
the test's load cases on the parametric model at one parameter point and gives, with the
sensitivities of every step, the weighted residuals and their exact Jacobian. The load cases
of a run are spread over worker processes (each with its own model); every solve is
deterministic, so the fit is the same for any number of workers.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Callable, Sequence

import numpy as np

from elastokin.errors import SolverError

#: a worker process' copy of the fit's :class:`~elastokin.identification.stiffness.Residuals`
_WORKER_RESIDUALS = None


def _start_worker(residuals) -> None:
    global _WORKER_RESIDUALS
    _WORKER_RESIDUALS = residuals


def _worker_run(values: dict, variations: list, indices: list[int]) -> tuple[list, list]:
    return _WORKER_RESIDUALS.run(values, variations, indices)


def fit_workers(n_load_cases: int) -> int:
    """Default worker processes of the fit: one per core, at most one per load case."""
    cores = (len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity")
             else os.cpu_count() or 1)
    return max(1, min(n_load_cases, cores))


def split_load_cases(steps: Sequence[int], workers: int) -> list[list[int]]:
    """Load-case indices per worker, balanced by step count (longest first to the least
    loaded worker); each worker's list in load-case order."""
    loads = [0] * workers
    out: list[list[int]] = [[] for _ in range(workers)]
    for i in sorted(range(len(steps)), key=lambda i: -steps[i]):
        w = int(np.argmin(loads))
        out[w].append(i)
        loads[w] += steps[i]
    return [sorted(ids) for ids in out if ids]


class FitRuns:
    """Model runs at parameter points ``x`` (optimisation variables of ``params``) of the
    fit's :class:`~elastokin.identification.stiffness.Residuals` ``res``: the
    weighted residuals and their Jacobian, computed together and kept for the last few
    points (least squares asks for the Jacobian where it has just evaluated)."""

    def __init__(self, res, params: list, workers: int,
                 progress: Callable[[str], None]):
        self.res, self.params, self.progress = res, params, progress
        # the last few points evaluated (least squares asks again for the point it accepts)
        self.kept: list[tuple[np.ndarray, np.ndarray, np.ndarray, list]] = []
        # the lowest-cost point (weights when evaluated; kept when a fit stops early)
        self.best: tuple[np.ndarray, float] | None = None
        self.split = split_load_cases([d.inputs.size for d in res.drives], workers)
        self.pool = None
        if len(self.split) > 1:
            import multiprocessing
            from concurrent.futures import ProcessPoolExecutor

            # fork where it is safe (Linux): no re-import of the caller's main module (a
            # script without a main guard) and no import cost; elsewhere spawn
            method = "fork" if sys.platform.startswith("linux") else "spawn"
            self.pool = ProcessPoolExecutor(len(self.split),
                                            multiprocessing.get_context(method),
                                            initializer=_start_worker, initargs=(res,))

    def close(self) -> None:
        if self.pool is not None:
            self.pool.shutdown(cancel_futures=True)

    def _failed(self, values: dict, exc: SolverError) -> SolverError:
        vals = ", ".join(f"{b}.{k}={v:.4g}" for b, kv in values.items() for k, v in kv.items())
        return SolverError(f"stiffness identification: the model does not solve at {vals}: "
                           f"{exc}")

    def _evaluate(self, values: dict, variations: list) -> tuple[list, list]:
        """Sweeps and curve blocks of one run, its load cases spread over the workers."""
        if self.pool is None:
            return self.res.run(values, variations)
        futures = [self.pool.submit(_worker_run, values, variations, ids)
                   for ids in self.split]
        sweeps, blocks = {}, []
        for ids, fut in zip(self.split, futures):
            part, part_blocks = fut.result()
            sweeps.update(zip(ids, part))
            blocks += part_blocks
        self.res.evaluations += 1
        return [sweeps[i] for i in sorted(sweeps)], blocks

    def _run(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, list]:
        """(residual differences, their Jacobian, sweeps with tangents) at ``x``."""
        for kept in self.kept:
            if np.array_equal(kept[0], x):
                return kept[1:]
        self.progress(f"stiffness fit: model run {self.res.evaluations + 1} "
                      "(with sensitivities)")
        values, variations = self.res.point(self.params, x)
        try:
            sweeps, blocks = self._evaluate(values, variations)
        except SolverError as exc:
            raise self._failed(values, exc) from None
        r, jac = self.res.assemble(blocks)
        self.kept = [(x.copy(), r, jac, sweeps), *self.kept[:3]]
        cost = float(np.sum((r / self.res.scale_vector()) ** 2))
        if self.best is None or cost < self.best[1]:
            self.best = (x.copy(), cost)
        return self.kept[0][1:]

    def differences(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The residual differences (mm, deg) and their Jacobian at ``x``."""
        return self._run(x)[:2]

    def evaluate(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, list]:
        """(weighted residuals, Jacobian, sweeps with tangents) at ``x``, weighted with the
        current curve scales."""
        r, jac, sweeps = self._run(x)
        scale = self.res.scale_vector()
        return r / scale, jac / scale[:, None], sweeps

    def residuals(self, x: np.ndarray) -> np.ndarray:
        return self.evaluate(x)[0]

    def jacobian(self, x: np.ndarray) -> np.ndarray:
        return self.evaluate(x)[1]

    def last_sweeps(self, x: np.ndarray) -> list:
        return self._run(x)[2]
