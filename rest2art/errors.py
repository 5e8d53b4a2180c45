"""One exception hierarchy for the whole project.

Every message names the file, part or joint concerned and says what would be valid, so that the
CLI can print it as a one-line reason and exit non-zero.
"""


class Rest2ArtError(Exception):
    """Base class of every error rest2art raises on purpose."""


class InputError(Rest2ArtError):
    """The input mesh or option is unusable (missing, empty, NaN, wrong units, ...)."""


class ConfigError(Rest2ArtError):
    """A config file or value is invalid."""


class ReconstructionError(Rest2ArtError):
    """A reconstruction stage could not produce a valid result for this input."""


class ExportError(Rest2ArtError):
    """Writing the asset failed (folder not writable, already exists, ...)."""


class SimulationError(Rest2ArtError):
    """A simulator could not be started at all (not: an asset failed a check)."""
