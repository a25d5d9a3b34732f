"""``RunResult.log_rerun()``: a run into a Rerun recording (the optional ``rerun-sdk``
package), for what ``rerun mcap convert`` of a ROS 2 file does not show: the path driven,
the reference path, and every column as a plot.

Entities, under ``entity`` (``wmr/run0`` by default), on the timeline ``timeline`` (the
simulation time, s):

- ``path``: the path of C, a line strip in the plane (z = 0), static;
- ``reference``: a tracking run's reference path (``x_ref``, ``y_ref``), static;
- ``base_link``: the robot's pose at each sample (a Transform3D, rotation about z);
- ``columns/NAME``: each other column as Scalars at each sample (``dl``, ``e_theta``,
  ``omega_r``, ...), so Rerun plots them.
"""

from __future__ import annotations

from typing import Any, Optional

import numpy as np

from ._results import require

#: Columns logged as the pose rather than as plots.
_POSE = ("t", "x", "y", "theta")


def run_result_log_rerun(r: Any, recording: Optional[Any] = None, entity: Optional[str] = None,
                         timeline: str = "sim_time") -> None:
    """Logs run ``r`` into ``recording`` (a ``rerun.RecordingStream``; the current one when
    None): see the module doc. ImportError naming rerun-sdk when it is not installed."""
    rr = require("rerun", "RunResult.log_rerun()")
    entity = f"wmr/run{r.run}" if entity is None else entity.rstrip("/")
    t = np.asarray(r.t, dtype=np.float64)
    x, y, theta = (np.asarray(r[k], dtype=np.float64) for k in ("x", "y", "theta"))
    zeros = np.zeros_like(x)
    rr.log(f"{entity}/path", rr.LineStrips3D([np.column_stack([x, y, zeros])]), static=True, recording=recording)
    if r.tracking:
        ref = np.column_stack([np.asarray(r["x_ref"]), np.asarray(r["y_ref"]), zeros])
        rr.log(f"{entity}/reference", rr.LineStrips3D([ref]), static=True, recording=recording)
    times = [rr.TimeColumn(timeline, duration=t)]
    half = 0.5 * theta
    quaternions = np.column_stack([zeros, zeros, np.sin(half), np.cos(half)])
    rr.send_columns(
        f"{entity}/base_link",
        indexes=times,
        columns=rr.Transform3D.columns(translation=np.column_stack([x, y, zeros]), quaternion=quaternions),
        recording=recording,
    )
    for name in r.column_names:
        if name in _POSE:
            continue
        values = np.asarray(r[name], dtype=np.float64)
        rr.send_columns(f"{entity}/columns/{name}", indexes=times, columns=rr.Scalars.columns(scalars=values),
                        recording=recording)
