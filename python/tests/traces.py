"""Comparing the observation traces of repeated episodes, for the determinism tests of the
environments (test_env.py, test_env_descending.py)."""

from __future__ import annotations


def assert_bit_identical(runs: list[list[dict]]) -> None:
    """Every observation of every run equals the first run's, key by key, byte for byte."""
    for a, b in zip(*runs, strict=True):
        for key in a:
            assert a[key].tobytes() == b[key].tobytes(), key
