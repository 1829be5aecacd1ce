"""ISO 25178-71 SDF areal scans → ``areal/<cut>.nc`` (``robomill import sdf``): the areal
importer of :mod:`robomill.importers.topography` (SurfaceTopography) under the format's name.
An SDF *profile* (one of its rows) is ``robomill import smats``."""

from robomill.importers.topography import KIND, add_arguments, convert

FORMAT = "sdf"
DESCRIPTION = "ISO 25178-71 SDF areal scan (through SurfaceTopography) → areal/<cut>.nc"

__all__ = ["DESCRIPTION", "FORMAT", "KIND", "add_arguments", "convert"]
