"""One hierarchy for what a user can fix.

Only the command line turns these into messages and exit codes (status 2).  Any other
exception escaping the pipeline is a bug (status 1).
"""

from __future__ import annotations


class H2SError(Exception):
    """A problem the user can fix: the message is one line naming the file and field."""


class ConfigError(H2SError):
    """A config file is malformed: ``camera.yaml: views[1].elevation_deg: expected ...``."""


class ModelError(H2SError):
    """A model file or folder cannot be read or holds no usable geometry."""


class SelectionError(H2SError):
    """The candidate selection could not be solved (no feasible answer within the limits)."""


class RenderError(H2SError):
    """An output could not be laid out or written."""
