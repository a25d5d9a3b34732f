"""The column and outcome names come from one list (wmr-scenario's output module, the
outcome table of wmr-py) through the native module: RunResult, its pickled state, the
stubs, run_batch and _results.py agree with it, and it with the CSV the CLI writes."""

from __future__ import annotations

import pathlib
import pickle
import re

import numpy as np
import pytest

import wmr_py
from wmr_py import _native, _results

STUB = pathlib.Path(_native.__file__).with_name("_native.pyi")


def test_constants_are_the_native_lists() -> None:
    assert wmr_py.CSV_COLUMNS == ("run", *wmr_py.COLUMNS)
    assert len(wmr_py.COLUMN_UNITS) == len(wmr_py.COLUMNS)
    assert _results.OUTCOME_FIELDS is _native.OUTCOME_FIELDS
    assert _results.ARRIVAL_RADIUS_M == _native.ARRIVAL_RADIUS_M == 0.01
    assert wmr_py.BatchResult({}).arrival_radius == _native.ARRIVAL_RADIUS_M


def test_run_result_has_every_column_in_order() -> None:
    (res,) = wmr_py.run_scenario({"sim": {"t_end": 0.5}, "run": [{"goal": {"x": 1, "y": 1}}]})
    names = (*wmr_py.COLUMNS, *wmr_py.MEASURED_COLUMNS)
    assert list(res.columns()) == list(wmr_py.CSV_COLUMNS)
    for name in names:
        assert getattr(res, name) is res[name], name
        assert getattr(wmr_py.RunResult, name).__doc__, name
    state = res.__getstate__()
    assert [k for k in state if isinstance(state[k], np.ndarray)] == list(names)
    back = pickle.loads(pickle.dumps(res))
    for name in names:
        np.testing.assert_array_equal(back[name], res[name], err_msg=name)
    pytest.importorskip("pandas")  # optional: what follows needs it
    df = res.to_pandas()
    assert list(df.columns) == ["run", "label", *names]


def test_stub_declares_the_columns_in_order() -> None:
    body = STUB.read_text().split("class RunResult:", 1)[1].split("\n@final", 1)[0].split("\ndef ", 1)[0]
    declared = re.findall(r"^    @property\n    def (\w+)\(self\) -> _FloatArray: \.\.\.$", body, flags=re.M)
    assert declared == [*wmr_py.COLUMNS, *wmr_py.MEASURED_COLUMNS]


def test_batch_outcomes_follow_outcome_fields() -> None:
    res = wmr_py.run_batch(np.zeros((2, 3)), (1.0, 1.0, 0.0), t_end=0.2)
    assert [k for k in res if k in wmr_py.OUTCOME_FIELDS] == list(wmr_py.OUTCOME_FIELDS)
    pytest.importorskip("pandas")  # optional: what follows needs it
    assert list(res.to_pandas().columns)[-len(wmr_py.OUTCOME_FIELDS):] == list(wmr_py.OUTCOME_FIELDS)
