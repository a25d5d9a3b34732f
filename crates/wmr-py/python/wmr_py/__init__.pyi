"""Type stubs of wmr_py (see _native.pyi for the native classes)."""

from __future__ import annotations

from typing import Any, Mapping, Optional, Sequence, Union

import numpy.typing as npt

from ._native import (
    PaperController as PaperController,
    ParameterError as ParameterError,
    PoseLike,
    Robot as Robot,
    RunResult as RunResult,
    ScenarioError as ScenarioError,
    run_scenario as run_scenario,
    sweep as sweep,
)

__all__: list[str]

def simulate(
    start: PoseLike,
    goal: PoseLike,
    robot: Union[None, Robot, Mapping[str, float]] = None,
    drive: Optional[Mapping[str, Any]] = None,
    controller: Optional[Mapping[str, Any]] = None,
    t_end: float = 60.0,
    dt: Optional[float] = None,
    log_dt: float = 0.01,
    label: Optional[str] = None,
) -> RunResult: ...
def run_batch(
    starts: Union[npt.ArrayLike, Sequence[Sequence[float]]],
    goal: PoseLike,
    robot: Union[None, Robot, Mapping[str, float]] = None,
    drive: Optional[Mapping[str, Any]] = None,
    controller: Optional[Mapping[str, Any]] = None,
    t_end: float = 60.0,
    dt: Optional[float] = None,
) -> dict[str, Any]: ...
