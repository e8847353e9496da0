"""The command line (click): ``elastokin kc | identify | synthesize | doe | import-adams |
export-adams``. Commands only: the work is done by :mod:`elastokin.studies`."""

from elastokin.cli.main import main

__all__ = ["main"]
