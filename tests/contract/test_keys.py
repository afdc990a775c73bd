import pytest

from facing_service.contract import keys


def test_build_and_parse_round_trip():
    key = keys.pose_key("robot1/hri", body_id="b-1.x_2", frame_id="camera_link")
    assert key == "robot1/hri/bodies/b-1.x_2/pose/camera_link"
    assert keys.parse_pose_key("robot1/hri", key) == keys.BodyRef(
        frame_id="camera_link", body_id="b-1.x_2"
    )


@pytest.mark.parametrize(
    "key",
    [
        "hri/bodies/a/facing/cam",
        "hri/bodies/a/pose",
        "hri/bodies/a/pose/cam/extra",
        "other/bodies/a/pose/cam",
        "hri/bodies/" + "a" * 65 + "/pose/cam",
        "hri/bodies/a b/pose/cam",
        "hri/bodies/a/pose/c@m",
        "hri/bodies/é/pose/cam",
    ],
)
def test_invalid_input_keys(key):
    assert keys.parse_pose_key("hri", key) is None


@pytest.mark.parametrize("name", ["", "a/b", "a*", "$x", "a#", "a?", "x" * 65, "sp ace"])
def test_invalid_names(name):
    assert not keys.is_name(name)
    with pytest.raises(ValueError):
        keys.validate_name(name)


@pytest.mark.parametrize("ns", ["", "a//b", "/a", "a/", "a/*", "ro bot/hri"])
def test_invalid_namespaces(ns):
    with pytest.raises(ValueError):
        keys.validate_namespace(ns)


def test_frame_filter_accepts_star_or_a_name():
    assert keys.validate_frame_filter("*") == "*"
    assert keys.validate_frame_filter("map") == "map"
    with pytest.raises(ValueError):
        keys.validate_frame_filter("**")


def test_output_key_spaces():
    assert keys.result_queryables("hri") == ("hri/bodies/*/facing/*", "hri/facing/*")
    assert keys.pose_subscription("hri", "cam") == "hri/bodies/*/pose/cam"


def test_the_body_of_any_per_body_key():
    body = keys.body_of("robot1/hri/bodies/p3/engagement/base_link")
    assert (body.body_id, body.frame_id) == ("p3", "base_link")
    body = keys.body_of(keys.facing_key("hri", body_id="a.b", frame_id="cam"))
    assert (body.body_id, body.frame_id) == ("a.b", "cam")


def test_the_remembering_parser_answers_as_the_parser_and_stays_bounded():
    from facing_service.contract.keys import PoseKeyParser, parse_pose_key

    parse = PoseKeyParser("hri", capacity=3)
    tried = [
        "hri/bodies/a/pose/cam",
        "hri/bodies/a/pose/cam",
        "hri/bodies/b$/pose/cam",
        "other/bodies/a/pose/cam",
        "hri/bodies/c/pose/map",
        "hri/bodies/a/pose/cam",
    ]
    for key in tried:
        assert parse(key) == parse_pose_key("hri", key)
        assert len(parse._known) <= 3


def test_a_service_token_names_its_instance():
    assert keys.instance_of(keys.service_token("robot1/hri", "front")) == "front"
