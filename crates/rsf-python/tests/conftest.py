"""Shared paths of the package's tests."""

import pathlib

import pytest

REPO = pathlib.Path(__file__).resolve().parents[3]


@pytest.fixture
def repo():
    """The repository's root."""
    return REPO
