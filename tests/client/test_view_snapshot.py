"""The page's model of one instant (pure): bounded, nearest first."""

from __future__ import annotations


def test_a_crowd_is_sent_bounded_nearest_first_and_the_rest_counted():
    from facing_service.client.view.snapshot import MAX_DRAWN, snapshot
    from facing_service.client.watch import PersonView

    crowd = [
        PersonView(f"p{i}", 1.0 + i * 0.01, 0.0, 0.0, False, 90.0, 1.0, 20.0, None)
        for i in range(5000)
    ]
    model = snapshot("cam", crowd, [], [], True, {"cam": 5000, "map": 2})
    assert len(model["people"]) == MAX_DRAWN and model["not_drawn"] == 5000 - MAX_DRAWN
    assert {p["id"] for p in model["people"]} == {f"p{i}" for i in range(MAX_DRAWN)}
    assert model["elsewhere"] == {"map": 2} and model["service"] == "live"
    assert {p["threshold_deg"] for p in model["people"]} == {20.0}
