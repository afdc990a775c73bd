"""One base class for every error raised on purpose, each also the standard error it is."""

from __future__ import annotations

import pytest

from facing_service import errors
from facing_service.contract.errors import (
    ClientNotOpen,
    FacingError,
    NoService,
    QueryRefused,
    SettingsError,
    UnknownFrame,
)


@pytest.mark.parametrize(
    ("error", "standard"),
    [
        (SettingsError, ValueError),
        (QueryRefused, ValueError),
        (UnknownFrame, QueryRefused),
        (NoService, ConnectionError),
        (ClientNotOpen, RuntimeError),
    ],
)
def test_each_error_is_a_facing_error_and_its_standard_kind(error, standard):
    assert issubclass(error, FacingError) and issubclass(error, standard)


def test_a_refusal_keeps_the_reason_and_the_detail_apart():
    refused = UnknownFrame("unknown_frame", "frames tracked: cam")
    assert (refused.reason, refused.detail) == ("unknown_frame", "frames tracked: cam")
    assert str(refused) == "unknown_frame: frames tracked: cam"


def test_the_public_module_names_them_all():
    assert set(errors.__all__) == {
        "ClientNotOpen", "FacingError", "NoService", "QueryRefused", "SettingsError",
        "UnknownFrame",
    }  # fmt: skip


def test_an_unknown_frames_detail_says_whether_the_service_tracks_anything():
    """The service writes the detail and the client reads it back through one pair of
    functions: an empty service (every frame unknown) is not a misspelt frame."""
    from facing_service.contract.errors import UnknownFrame, unknown_frame_detail

    empty = unknown_frame_detail("base_lnk", {})
    assert empty == "no frame 'base_lnk' in this service; frames tracked: none"
    assert UnknownFrame("unknown_frame", empty).nothing_tracked
    known = unknown_frame_detail("base_lnk", {"map": 2, "base_link": 1})
    assert known.endswith("frames tracked: base_link, map")
    assert not UnknownFrame("unknown_frame", known).nothing_tracked
