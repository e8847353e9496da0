"""Errors that elastokin reports to a user.

Every error raised for bad input or a failed solve is an :class:`ElastokinError`; the CLI prints
its message on one line and exits non-zero. Messages name the file, the key or the part, and what
was expected.
"""

from __future__ import annotations


class ElastokinError(Exception):
    """Base class of every error elastokin reports to a user."""


class ConfigError(ElastokinError):
    """A configuration file is malformed or describes an impossible suspension."""


class ModelError(ElastokinError):
    """The suspension cannot be assembled (missing joint, wrong degrees of freedom, ...)."""


class SolverError(ElastokinError):
    """A static solve did not converge."""


class MeasurementError(ElastokinError):
    """Measurement data are unreadable or inconsistent (marks that cannot be matched, ...)."""
