"""glassmap: glass-aware laser mapping, vector floorplans and localization.

The functions run the same pipeline as the ``glassmap`` command, with the same defaults; their
keyword options are the command's long options with underscores (``--no-return-range`` ->
``no_return_range=``)::

    import glassmap
    log = glassmap.read_log("run.clf")
    result = glassmap.map_log(log, method="mrf")          # labels, geotransform, segments, stats
    track = glassmap.localize(result.floorplan, log, init=log[0].pose)

Errors of the pipeline (bad input, bad options, files that cannot be read or written) raise
``glassmap.Error`` (a RuntimeError) with the message the command line prints; unknown keyword
options raise TypeError.
"""

from ._glassmap import (
    Error,
    Floorplan,
    LocalizeResult,
    Log,
    MapResult,
    Scan,
    Segment,
    calibrate,
    localize,
    map_log,
    read_floorplan,
    read_log,
    read_sensor_profile,
    write_floorplan,
    write_sensor_profile,
)

__version__ = "0.1.0"

__all__ = [
    "Error",
    "Floorplan",
    "LocalizeResult",
    "Log",
    "MapResult",
    "Scan",
    "Segment",
    "calibrate",
    "localize",
    "map_log",
    "read_floorplan",
    "read_log",
    "read_sensor_profile",
    "write_floorplan",
    "write_sensor_profile",
]
