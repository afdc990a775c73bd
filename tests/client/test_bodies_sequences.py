"""The client's picture over sequences: live results and DELETEs, seeds (a query begun at
one moment, answered from the service's state at a later one, applied later still),
the service's token going and coming back, in any order. The real ``BodyCache`` is
checked at every step against what the service holds."""

from __future__ import annotations

from hypothesis import settings
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, invariant, precondition, rule

from facing_service.client.bodies import BodyCache
from facing_service.contract.schemas import FacingState

BODIES = ["a", "b", "c"]


def result(body: str, sec: int) -> FacingState:
    return FacingState.model_validate(
        {
            "body_id": body, "frame_id": "cam", "facing": True, "angle_deg": 0.0,
            "distance_m": 1.0, "threshold_deg": 20.0, "stamp": {"sec": sec, "nanosec": 0},
            "instance": "s1", "robot_in_body": {"x": 1.0, "y": 0.0, "z": 0.0},
            "position": {"x": 1.0, "y": 0.0, "z": 0.0}, "heading_deg": 180.0,
        }
    )  # fmt: skip


class ClientMachine(RuleBasedStateMachine):
    """The service ("s1") holds ``truth`` (body -> stamp of its latest result); the
    client hears each change live, at once, unless the service's token is gone."""

    def __init__(self) -> None:
        super().__init__()
        self.cache = BodyCache()
        self.cache.live.add("s1")
        self.truth: dict[str, int] = {}
        self.history: list[tuple[float, dict[str, int]]] = [(0.0, {})]  # (when, truth)
        self.seeds: list[float] = []  # queries begun, not answered yet: when
        self.now, self.stamp = 0.0, 0
        self.alive = True
        self.synced = True  # a seed begun since the token came back has been applied

    def _tick(self) -> None:
        self.now += 1.0
        self.history.append((self.now, dict(self.truth)))

    @rule(body=st.sampled_from(BODIES))
    def result_published(self, body: str) -> None:
        self.stamp += 1
        self.truth[body] = self.stamp
        self._tick()
        self.cache.apply(result(body, self.stamp))

    @rule(body=st.sampled_from(BODIES))
    def deleted(self, body: str) -> None:
        if self.truth.pop(body, None) is not None:
            self._tick()
            self.cache.delete(self.cache_key(body), self.now)

    @rule()
    def seed_begins(self) -> None:
        self._tick()
        self.seeds.append(self.now)

    @precondition(lambda self: bool(self.seeds))
    @rule(data=st.data())
    def seed_answered(self, data: st.DataObject) -> None:
        """A pending seed's answer: the service's state at some moment since it began."""
        began = self.seeds.pop(data.draw(st.integers(0, len(self.seeds) - 1)))
        answers = [truth for when, truth in self.history if when >= began]
        answer = data.draw(st.sampled_from(answers))
        self._tick()
        for body, sec in sorted(answer.items()):
            self.cache.apply(result(body, sec), began)
        if self.alive and began >= self.revived_at:
            self.synced = True

    @rule()
    def token_gone(self) -> None:
        if self.alive:
            self.alive, self.synced = False, False
            self._tick()
            self.cache.instance_gone("s1")

    @rule()
    def token_back(self) -> None:
        if not self.alive:
            self.alive = True
            self._tick()
            self.revived_at = self.now
            self.cache.live.add("s1")

    revived_at = 0.0

    @staticmethod
    def cache_key(body: str):
        from facing_service.contract.keys import BodyRef

        return BodyRef(frame_id="cam", body_id=body)

    def held(self) -> dict[str, int]:
        return {k.body_id: s.stamp.sec for k, s in self.cache.states.items()}

    @invariant()
    def no_ghost(self) -> None:
        """Nothing the service no longer holds, nothing older than it holds."""
        held = self.held()
        assert all(b in self.truth and sec <= self.truth[b] for b, sec in held.items()), (
            held,
            self.truth,
        )

    @invariant()
    def the_service_as_it_is_once_seeded(self) -> None:
        if self.synced:
            assert self.held() == self.truth


ClientMachine.TestCase.settings = settings(max_examples=300, stateful_step_count=40,
                                           deadline=None)  # fmt: skip
test_client_cache_sequences = ClientMachine.TestCase


def test_a_delete_heard_while_a_seed_is_under_way_is_never_undone():
    """Before: the seed's older answer, applied after the DELETE, brought the body back
    for good (no on_lost ever followed)."""
    cache = BodyCache()
    cache.live.add("s1")
    cache.apply(result("a", 1))
    began = 10.0  # the seeding query is asked; the service answers: a is there
    cache.delete(ClientMachine.cache_key("a"), 10.5)  # the DELETE arrives first
    assert cache.apply(result("a", 1), began) == [] and cache.states == {}
    assert cache.seeds_refused == 1
    assert cache.apply(result("a", 2), 20.0) != []  # a later seed: it came back
