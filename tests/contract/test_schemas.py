"""The output models: the committed JSON schemas, the hand-written result JSON against
the model, and what a degenerate result says."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from facing_service.contract.poses import Stamp
from facing_service.contract.schemas import FacingState, Point, facing_state_json, json_schemas
from facing_service.contract.stamps import Time

SCHEMAS_DIR = Path(__file__).resolve().parents[2] / "schemas"


def test_degenerate_result_serializes_null_never_nan():
    state = FacingState(
        body_id="a",
        frame_id="cam",
        stamp=Stamp(sec=1, nanosec=0),
        facing=False,
        angle_deg=None,
        distance_m=None,
        robot_in_body=Point(x=0.0, y=0.0, z=1.5),
        threshold_deg=20.0,
        position=Point(x=0.0, y=0.0, z=-1.5),
        heading_deg=0.0,
    )
    text = state.model_dump_json()
    assert '"angle_deg":null' in text and '"distance_m":null' in text
    assert "NaN" not in text


@pytest.mark.parametrize("name", sorted(json_schemas()))
def test_committed_json_schemas_match_the_models(name):
    """Regenerate with: facing-service export-schemas schemas"""
    committed = json.loads((SCHEMAS_DIR / name).read_text())
    assert committed == json_schemas()[name], f"schemas/{name} drifted from the models"


def test_no_stray_schema_files():
    assert {p.name for p in SCHEMAS_DIR.glob("*.json")} == set(json_schemas())


names = st.from_regex(r"[A-Za-z0-9_.-]{1,64}", fullmatch=True)
finite = st.floats(allow_nan=False, allow_infinity=False, width=64)


@settings(max_examples=300)
@given(
    names,
    names,
    st.integers(0, 2**31 - 1),
    st.integers(0, 999_999_999),
    st.booleans(),
    st.none() | finite,
    st.none() | finite,
    st.tuples(finite, finite, finite),
    st.floats(0.001, 179.999),
    st.tuples(finite, finite, finite),
    st.floats(-180.0, 180.0),
    st.none() | names,
)
def test_hand_written_facing_state_json_matches_the_model(
    body, frame, sec, nanosec, facing, angle, distance, r, threshold, position, heading, instance
):
    fast = facing_state_json(
        body, frame, Time.of(sec, nanosec), facing, angle, distance, r, threshold, position,
        heading,
        instance,
    )  # fmt: skip
    model = FacingState(
        body_id=body,
        frame_id=frame,
        stamp=Stamp(sec=sec, nanosec=nanosec),
        facing=facing,
        angle_deg=angle,
        distance_m=distance,
        robot_in_body=Point(x=r[0], y=r[1], z=r[2]),
        threshold_deg=threshold,
        position=Point(x=position[0], y=position[1], z=position[2]),
        heading_deg=heading,
        instance=instance,
    )
    assert json.loads(fast) == json.loads(model.model_dump_json())
    assert FacingState.model_validate_json(fast) == model


def test_no_negative_zero_is_said():
    """A defect found: a body at z = 0 gave `"z": -0.0` (from -Rᵀt): correct, and confusing."""
    fast = facing_state_json(
        "a", "cam", Time.of(1), True, 10.0, 2.0, (2.0, -0.0, -0.0), 20.0, (-0.0, 0.0, -0.0), -0.0
    )
    assert b"-0.0" not in fast
    assert json.loads(fast)["robot_in_body"]["z"] == 0.0


def test_groups_and_gazing_name_their_frame_as_results_do():
    """A defect found: results said frame_id, groups and gazing said frame; both now say
    frame_id, and frame for the consumers that read it; a payload of either name reads."""
    from facing_service.contract.schemas import FrameGazing, FrameGroups

    old = {"frame": "map", "stamp": {"sec": 1, "nanosec": 0}, "pairs": [], "people_left_out": 0}
    gazing = FrameGazing.model_validate(old)
    assert gazing.frame_id == gazing.frame == "map"
    said = json.loads(FrameGroups(frame_id="map", frame="map", stamp=old["stamp"], groups=[],
                                  people_left_out=0).model_dump_json())  # fmt: skip
    assert said["frame_id"] == said["frame"] == "map"
    with pytest.raises(ValueError, match="differ"):
        FrameGazing.model_validate({**old, "frame_id": "base_link"})
