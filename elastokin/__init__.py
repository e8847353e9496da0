"""elastokin: suspension elastokinematics and geometric identification on Exudyn.

Units at every interface: mm, N, N*mm, deg (see README, "Units and frames").
"""

from __future__ import annotations

from elastokin.version import __version__

__all__ = ["__version__"]
