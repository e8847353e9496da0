"""elastokin: suspension elastokinematics and geometric identification on Exudyn.

Units at every interface: mm, N, N*mm, deg (see README, "Units and frames").
"""

from __future__ import annotations

__version__ = "0.1.0"
