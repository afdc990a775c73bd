"""Groups from the stream, as benchmarks/groups/stream.py judges them: the
memory the service ships is the one chosen held out, the made streams say what they
claim and the memory passes them, and a stream with the memory off is frame by frame."""

from __future__ import annotations

import itertools
import json
from dataclasses import asdict

import numpy as np
import pytest

from benchmarks.groups.replay import replay, shipped
from benchmarks.groups.scoring import f1
from benchmarks.groups.sequence_frame import Frame
from benchmarks.groups.stream import (
    FRAME_BY_FRAME,
    RESULTS,
    SAY_WITHIN_S,
    changes,
    in_time,
    scene_figures,
)
from benchmarks.groups.stream_scenes import streams
from facing_service.config.profiles import scene_params
from facing_service.config.settings import Settings

G = frozenset


def test_the_shipped_memory_is_the_one_chosen_on_all_six_sequences():
    """A default changed by hand fails here (the committed results' choice)."""
    chosen = json.loads(RESULTS.read_text())["default"]["memory"]
    assert chosen == asdict(scene_params(Settings()).memory)


def test_the_committed_results_hold_the_issues_targets():
    """Every shared sequence as a stream, held out by dataset: at least GCFF's one-set
    figure, and never worse than its own frame by frame beyond the paired interval (the
    memory chosen without a dataset can differ from the shipped one by a knife's edge:
    without CoffeeBreak, headings 4 s and pairs 2 s led the shipped memory by 0.004 on
    SALSA, and Seq1 scored 0.68 against 0.70 frame by frame, [-0.09, +0.05]); the mean
    above the frame-by-frame rule's 0.82. The shipped memory itself (chosen on all six)
    is at least frame by frame on every sequence."""
    results = json.loads(RESULTS.read_text())
    rows = results["sequences"]
    for row in rows.values():
        assert row["stream"]["f1_23"] >= row["gcff_one_set"]
        _, _, high = row["difference"]
        assert high >= 0
    assert np.mean([row["stream"]["f1_23"] for row in rows.values()]) > 0.82
    shipped = results["default"]["f1_23"]
    assert all(shipped[s] >= row["frame_by_frame"]["f1_23"] for s, row in rows.items())


def test_the_shipped_memory_says_every_made_change_within_3_s_and_fixes_the_flicker():
    ours, plain = scene_figures(scene_params(Settings()).memory), scene_figures(FRAME_BY_FRAME)
    assert in_time(ours)
    assert all(s <= SAY_WITHIN_S for f in ours.values() for s in f["said_after_s"])
    assert ours["90-degree flicker"]["f1_1"] > plain["90-degree flicker"]["f1_1"] + 0.1
    assert ours["walking through"]["f1_1"] == 1.0 > plain["walking through"]["f1_1"]
    assert ours["two pairs one frame"]["f1_1"] == 1.0 > plain["two pairs one frame"]["f1_1"]


def test_the_made_streams_are_what_they_say():
    made = streams()
    flicker = made["90-degree flicker"].frames
    quarter = np.pi / 2
    for frame in flicker:  # every heading on a 90-degree step
        steps = frame.headings / quarter
        assert np.allclose(steps, np.round(steps))
    changed = np.mean([(a.headings != b.headings).any() for a, b in itertools.pairwise(flicker)])
    assert changed > 0.5  # with seven people flipping one time in three, most frames change
    walk = made["walking through"]
    walker = np.array([f.positions[3] for f in walk.frames])
    speed = np.hypot(*np.diff(walker, axis=0).T) / walk.spacing_s
    assert np.allclose(speed, 1.2) and all(f.truth == (G({0, 1, 2}),) for f in walk.frames)
    leaving = made["member leaving"]
    assert [len(f.truth[0]) for f in leaving.frames[99:101]] == [4, 3]
    pairs = made["two pairs one frame"].frames
    assert all(f.truth == (G({0, 1}), G({2, 3})) for f in pairs)


def test_how_long_a_change_takes_is_counted_from_the_first_frame_that_shows_it():
    frame = Frame((1, 2), np.zeros((2, 2)), np.zeros(2), ())
    together = Frame((1, 2), np.zeros((2, 2)), np.zeros(2), (G({1, 2}),))
    frames = [frame, frame, together, together, together, frame]
    said = [[], [], [], [], [G({1, 2})], [G({1, 2})]]
    assert changes(frames, said, 0.5) == [1.5, None]  # frames 2..4 held; never apart


@pytest.mark.shared_data
def test_a_stream_with_the_memory_off_is_the_frame_by_frame_figure():
    """The replay (the service's scene, held frames, 10 Hz) with the memory off scores
    what the core's frame-by-frame run scores on the same frames."""
    from benchmarks.groups.held_out import run
    from benchmarks.groups.sequences import load

    frames = load("GDet/S2")
    plain = replay(frames, 2.0, shipped(FRAME_BY_FRAME))
    params = scene_params(Settings())
    core = run(frames, params.groups, params.scale)
    assert f1(frames, plain, 2 / 3) == pytest.approx(f1(frames, core, 2 / 3), abs=0.01)


@pytest.mark.shared_data
def test_synth_is_ten_situations_of_ten_frames():
    """The stated reason Synth's situations are streams of their own: within one nobody
    moves 5 cm; between them people move up to metres, ids reused."""
    from benchmarks.groups.sequences import SITUATION_FRAMES, load

    frames = load("Synth", every=1)
    size = SITUATION_FRAMES["Synth"]
    for k, (a, b) in enumerate(itertools.pairwise(frames), start=1):
        common = sorted(set(a.ids) & set(b.ids))
        pa = dict(zip(a.ids, a.positions, strict=True))
        pb = dict(zip(b.ids, b.positions, strict=True))
        moved = max(float(np.hypot(*(pa[i] - pb[i]))) for i in common)
        assert (moved > 1.0) if k % size == 0 else (moved < 0.05), k
