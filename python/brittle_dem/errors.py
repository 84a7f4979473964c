"""The exceptions of brittle_dem: the library's errors with the messages `dem` prints."""


class DemError(ValueError):
    """An error of the DEM library (a parameter, a scene, a specimen, a run): the message is
    the one the `dem` command prints after ``error:``."""


class DemIOError(DemError, OSError):
    """A file that cannot be read or written (also an OSError)."""


class DemStopped(DemError):
    """A run stopped by its callback (returning False) before the end; run it again into the
    same folder to continue from its last checkpoint."""


__all__ = ["DemError", "DemIOError", "DemStopped"]
