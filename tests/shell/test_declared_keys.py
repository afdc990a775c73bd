"""The per-body keys declared to zenoh: bounded, and forgotten with their body."""

from __future__ import annotations

from facing_service.shell.declared_keys import DeclaredKeys


def test_declared_keys_are_bounded_and_forgotten_with_their_body(net):
    """Room for two keys; a key beyond goes out as its string; forgetting frees one."""
    _service, ep = net.service()
    session = net.client(ep)
    rec = net.recorder(session, "test/**")
    declared = DeclaredKeys(session, capacity=2)
    result_a, engagement_a, result_b = (
        "test/bodies/a/facing/cam",
        "test/bodies/a/engagement/cam",
        "test/bodies/b/facing/cam",
    )
    try:
        session.put(declared.declare(result_a), b"{}")
        session.put(declared.declare(engagement_a), b"{}")
        assert list(declared.exprs) == [result_a, engagement_a]
        assert declared.declare(result_b) == result_b  # full: b goes out on its string
        session.put(result_b, b"{}")
        declared.forget(result_a)  # a is lost: its key goes, room is made
        assert list(declared.exprs) == [engagement_a]
        session.put(declared.declare(result_b), b"{}")
        assert list(declared.exprs) == [engagement_a, result_b]
        rec.wait_for(lambda i: True, count=4)  # every put went out, declared or not
        assert [i.key for i in rec.items] == [result_a, engagement_a, result_b, result_b]
    finally:
        declared.close()
    assert not declared.exprs
