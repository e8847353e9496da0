"""The command line (click): ``elastokin kc | identify | synthesize | doe | import-adams |
export-adams``. Commands only: the work is done by :mod:`elastokin.studies`."""

import os

# The models' matrices are small (tens to a few hundred unknowns): a second BLAS thread gains
# nothing and spin-waits against the solver on a busy machine (the twist beam's roll case
# 2.7 s -> 0.1 s with one thread under load). Set before numpy is first imported; a user's own
# setting wins.
for _variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

from elastokin.cli.main import main  # noqa: E402

__all__ = ["main"]
