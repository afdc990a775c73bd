"""F-formations scored as GCFF scores them (benchmarks/groups/held_out.py): the port of
GCFF's ff_evalgroups on its own edge cases, and the method on the shared sequences with
GCFF's own per-scene parameters, where it must give GCFF's figures."""

from __future__ import annotations

import json
from dataclasses import asdict

import numpy as np
import pytest

from benchmarks.groups.held_out import RESULTS, gcff_params, run
from benchmarks.groups.scoring import evalgroups, f1
from benchmarks.groups.sequences import SHARED, load

G = frozenset


def test_evalgroups_is_gcffs_on_its_edge_cases():
    assert evalgroups([], [], 2 / 3) == (1.0, 1.0)
    assert evalgroups([], [G({1, 2})], 2 / 3) == (1.0, 0.0)  # "no groups" scores precision 1
    assert evalgroups([G({1, 2})], [], 2 / 3) == (0.0, 1.0)
    # 2 of 3 members: right at T = 2/3, wrong at T = 1
    assert evalgroups([G({1, 2})], [G({1, 2, 3})], 2 / 3) == (1.0, 1.0)
    assert evalgroups([G({1, 2})], [G({1, 2, 3})], 1.0) == (0.0, 0.0)
    # one detection cannot match two true groups twice over
    assert evalgroups([G({1, 2, 3, 4})], [G({1, 2}), G({3, 4})], 2 / 3) == (0.0, 0.0)


@pytest.mark.slow
@pytest.mark.parametrize(
    ("sequence", "gcff"),
    [
        ("CoffeeBreak/Seq1", 0.77),
        ("CoffeeBreak/Seq2", 0.94),
        ("Synth", 0.97),
        ("GDet/S1", 0.93),
        # GCFF's code breaks ties in the order its data lists people, and GDet lists each
        # group together: the port with index ties gave 0.927 as listed and 0.920 listed
        # the other way round; order-free, 0.920. Within 2.5 points here.
        ("GDet/S2", 0.94),
        ("SALSA/CocktailParty", 0.82),  # every third frame, as GCFF's figure
    ],
)
@pytest.mark.shared_data
def test_the_port_gives_gcffs_figures_with_gcffs_parameters(sequence, gcff):
    """GCFF's own per-scene parameters, read from the sequence's settings_gc.mat (stride
    in cm, MDL in cm², converted to metres): F1 (T = 2/3) within two points of GCFF's
    code run unchanged (its authors' table); GDet S2 within 2.5 (its comment above)."""
    from scipy.io import loadmat

    tuned = loadmat(SHARED / sequence / "settings_gc.mat")
    stride, mdl = float(tuned["stride"].item()) * 0.01, float(tuned["mdl"].item()) * 1e-4
    frames = load(sequence)
    found = run(frames, gcff_params(stride, mdl))
    near = 0.025 if sequence == "GDet/S2" else 0.02
    assert f1(frames, found, 2 / 3) == pytest.approx(gcff, abs=near)


def test_the_shipped_defaults_are_the_set_chosen_on_all_six_sequences():
    """What `python -m benchmarks.groups.held_out` chose on every shared sequence (its committed
    results: the preferred rule's set) is what the service runs: a default changed by
    hand fails here."""
    from facing_service.config.profiles import scene_params
    from facing_service.config.settings import Settings

    results = json.loads(RESULTS.read_text())
    chosen = results["default"][results["preferred"]]
    shipped = scene_params(Settings())
    assert chosen["groups"] == asdict(shipped.groups)
    assert chosen["scale"] == asdict(shipped.scale)


def test_the_shipped_rule_is_in_metres_eligible_and_beaten_by_none_that_may_ship():
    """The rule that ships is chosen by its worst sequence held out by dataset
    (not the mean), among those that fail no made scene another rule passes;
    only a rule in metres may ship. (Frame by frame with the order-free assignment, GCFF's
    one stride in metres is better at its worst, 0.69 against 0.66 on CoffeeBreak Seq1,
    and fails the wide circle: docs/groups.md.)"""
    from benchmarks.groups.held_out import IN_METRES, RULES, eligible, preferred

    results = json.loads(RESULTS.read_text())
    best = results["preferred"]
    assert preferred(results) == best
    assert all(set(RULES) <= set(scene) for scene in results["scenes"].values())
    assert best in IN_METRES and best in eligible(results)
    for step in results["steps"]:
        beaten = step["difference"][1] > 0 and step["incumbent"] == best
        assert not (beaten and step["challenger"] in IN_METRES), step


def test_the_scenes_made_for_the_failures_are_what_they_say():
    """The stress scenes (benchmarks/groups/scenes.py): loners hold no group, the wide
    circle one of five, the posters a crowd denser than its groups."""
    from benchmarks.groups.scenes import scenes
    from facing_service.core.social.groups import nearest_distances

    made = scenes()
    assert all(not frame.truth for frame in made["loners"])
    assert all(not frame.truth for frame in made["side by side"])
    for frame in made["dense room"]:  # groups of four to six, as dense as their groups
        assert {len(g) for g in frame.truth} <= {4, 5, 6}
        assert float(np.median(nearest_distances(frame.positions))) == pytest.approx(0.6, abs=0.05)
    for frame in made["close circle"]:  # five or six 0.8 m apart, headings rounded
        (circle,) = frame.truth
        ring = frame.positions[sorted(circle)]
        assert len(circle) in (5, 6) and nearest_distances(ring).max() == pytest.approx(0.8)
        steps = np.degrees(frame.headings) % 45
        assert np.allclose(np.minimum(steps, 45 - steps), 0, atol=1e-9)
    assert all([len(g) for g in frame.truth] == [5] for frame in made["wide circle"])
    poster = made["posters"][0]
    nearest = float(np.median(nearest_distances(poster.positions)))
    within = [
        np.hypot(*(poster.positions[a] - poster.positions[b]))
        for group in poster.truth
        for a in group
        for b in group
        if a < b
    ]
    assert nearest < float(np.median(within))  # denser than its groups


def test_the_order_harness_counts_frames_grouped_otherwise_and_groups_listed_together():
    """benchmarks.groups.order: a frame whose grouping follows the order its
    people are listed in is counted; one that does not is not; a true group listed
    consecutively is counted as such."""
    from benchmarks.groups.order import changed, first_look_f1, listed_together
    from benchmarks.groups.sequence_frame import Frame

    pair = Frame((1, 2, 3), np.array([[0.0, 0.0], [1.2, 0.0], [9.0, 9.0]]),
                 np.array([0.0, np.pi, 0.0]), (frozenset({1, 2}),))  # fmt: skip
    by_order = lambda ids, frame, order: frozenset({frozenset(ids[i] for i in order[:2])})  # noqa: E731
    by_place = lambda ids, frame, order: frozenset({frozenset(ids[:2])})  # noqa: E731
    assert changed([pair] * 4, by_order, orders=3) >= 1
    assert changed([pair] * 4, by_place, orders=3) == 0
    assert listed_together([pair])[0] == 1.0
    assert first_look_f1([pair], orders=2) == (1.0, 1.0)  # the pair found, however listed


def test_the_exact_assignment_is_the_optimum_of_small_rooms():
    """benchmarks.groups.exact's integer program against every subset of open centres
    (each person then at their cheapest open one), on 200 random small rooms."""
    import itertools

    import numpy as np

    from benchmarks.groups.exact import exact

    rng = np.random.default_rng(84)
    for _ in range(200):
        n, m = int(rng.integers(1, 7)), int(rng.integers(1, 6))
        unary, mdl = rng.uniform(0.0, 3.0, (n, m)), float(rng.uniform(0.1, 2.0))
        best = min(
            unary[:, list(opened)].min(axis=1).sum() + mdl * len(opened)
            for k in range(1, m + 1)
            for opened in itertools.combinations(range(m), k)
        )
        labels = exact(unary, mdl, np.arange(m))
        found = unary[np.arange(n), labels].sum() + mdl * len(set(labels.tolist()))
        assert found == pytest.approx(best, abs=1e-6)


def test_the_global_context_rule_solved_directly_is_gtcgs_recursion():
    """benchmarks.groups.dominant decides the global-context rule from the set's
    equilibrium; GTCG computes Pavan and Pelillo's weight by its recursion (``CalcWeight``,
    written out here as in xwasco/GTCG): the same decision on every random set whose
    members all weigh more than 0."""
    import numpy as np

    from benchmarks.groups.dominant import outsider_would_stay

    def w(a: np.ndarray, members: list[int], i: int) -> float:
        rest = [j for j in members if j != i]
        if not rest:
            return 1.0
        return sum((a[i, j] - a[rest[0], j]) * w(a, rest, j) for j in rest)

    rng = np.random.default_rng(84)
    checked = 0
    for _ in range(300):
        a = rng.uniform(0, 1, (7, 7))
        a = (a + a.T) / 2
        np.fill_diagonal(a, 0)
        members = [int(i) for i in rng.choice(7, int(rng.integers(1, 5)), replace=False)]
        if any(w(a, members, i) <= 0 for i in members):
            continue
        recursion = any(w(a, [*members, j], j) >= 0 for j in range(7) if j not in members)
        assert outsider_would_stay(a, members) == recursion
        checked += 1
    assert checked > 100


def test_dominant_sets_find_two_pairs_apart_and_leave_the_loner():
    """Two pairs facing each other 1 m apart, 4 m between the pairs, one person alone
    facing away: two groups, the loner in none, whatever order they are listed in."""
    import numpy as np

    from benchmarks.groups.dominant import DominantParams, affinity, dominant_sets

    where = np.array([[0, 0], [1, 0], [5, 0.3], [6, 0], [3, 4]], dtype=float)
    heading = np.array([0, np.pi, 0.1, np.pi, np.pi / 2])
    for order in ([0, 1, 2, 3, 4], [4, 3, 1, 2, 0]):
        labels = dominant_sets(affinity(where[order], heading[order], DominantParams(1.0, 0.1)))
        named = {frozenset(np.array(order)[labels == g].tolist()) for g in set(labels.tolist())}
        assert named == {frozenset({0, 1}), frozenset({2, 3}), frozenset({4})}


def test_a_pair_on_a_ring_it_faces_and_a_pair_one_behind_the_other():
    """benchmarks.groups.pair_ring: two facing each other, and two of a triangle facing its
    centre, stand on a ring they face (0°); one behind the other facing the same way on
    none (over 90°)."""
    import numpy as np

    from benchmarks.groups.pair_ring import ring_error

    pair = np.array([[0.0, 0.0], [1.0, 0.0]])
    assert ring_error(pair, np.array([0.0, np.pi])) < 0.5
    assert ring_error(pair, np.array([np.pi / 3, 2 * np.pi / 3])) < 0.5
    assert ring_error(pair, np.array([np.pi, np.pi])) > 90


def test_the_dominant_sets_page_is_the_results():
    from benchmarks.groups import dominant

    assert dominant.main(["--page", "--check"]) == 0, (
        "regenerate: python -m benchmarks.groups.dominant --page"
    )


def test_gcffs_own_run_reads_the_frames_in_its_units_and_refuses_an_unfinished_run():
    """benchmarks.groups.gcff_own hands GCFF's Octave code the frames in centimetres and
    reads one labelling per frame back, only from a run that wrote its last line."""
    from benchmarks.groups.gcff_own import frames_text, labels_read
    from benchmarks.groups.sequence_frame import Frame

    frames = [
        Frame((3, 7), np.array([[0.1234567891, -2.5], [1.0, 0.3]]), np.array([0.5, -3.0]), ()),
        Frame((), np.zeros((0, 2)), np.zeros(0), ()),
    ]
    lines = frames_text(frames, 40.0, 6000.0).splitlines()
    assert lines[0] == "40.0 6000.0 2" and lines[3] == "40.0 6000.0 0"
    row = [float(x) for x in lines[1].split()]
    assert row[0] == 3 and row[3] == 0.5
    assert np.allclose(row[1:3], [12.34567891, -250.0], rtol=1e-15)
    assert [lab.tolist() for lab in labels_read("0 0 \n\nEND\n", frames)] == [[0, 0], []]
    with pytest.raises(SystemExit, match="after 2 of 2 frames"):
        labels_read("0 0 \n\n", frames)
    with pytest.raises(SystemExit, match="every person"):
        labels_read("0 \n\nEND\n", frames)


def test_gcffs_own_run_refuses_a_folder_that_is_not_gcff(tmp_path, capsys):
    from benchmarks.groups.gcff_own import main

    with pytest.raises(SystemExit):
        main(["--gcff", str(tmp_path)])
    assert f"--gcff {tmp_path}: not a GCFF checkout" in capsys.readouterr().err


def test_the_page_says_the_energies_gcffs_own_run_reached():
    """The committed run reproduced GCFF's published figures (so it was GCFF's code that
    ran), and docs/groups.md says its counts."""
    results = json.loads((RESULTS.parent / "groups_gcff_own.json").read_text())["sequences"]
    for r in results.values():
        assert abs(r["f1"]["gcff"] - r["f1"]["gcff_published"]) <= 0.01, r  # (published to 0.01)
    total = {k: sum(r[k] for r in results.values()) for k in ("lower", "same", "higher")}
    frames = sum(r["frames"] for r in results.values())
    page = " ".join((RESULTS.parents[2] / "docs/groups.md").read_text().split())
    assert (f"same energy on {total['same']} of {frames} frames, lower on {total['lower']} "
            f"and higher on {total['higher']}") in page  # fmt: skip
