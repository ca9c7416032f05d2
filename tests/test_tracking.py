"""Tracking and facing from motion (vc.deploy.tracking): people keep their track, and the way they walk decides
which of each left/right pair is the left one where the network cannot tell."""

from __future__ import annotations

import warnings
from dataclasses import replace

import numpy as np
import pytest

from vc.deploy.facing import FACE_AHEAD_OF_EARS, MIRRORED_FROM_PX
from vc.deploy.heatmaps import PAIRS
from vc.deploy.runtime import Person
from vc.deploy.tracking import (
    Tracker,
    TrackingConfig,
    appearance,
    appearance_distance,
    facing_pairs,
    foot_speed,
)
from vc.keypoints import COCO_KEYPOINTS

HEIGHT = 100.0
LEFT_SHOULDER, RIGHT_SHOULDER = COCO_KEYPOINTS.index("left_shoulder"), COCO_KEYPOINTS.index("right_shoulder")
NOSE = COCO_KEYPOINTS.index("nose")
EYES = [COCO_KEYPOINTS.index("left_eye"), COCO_KEYPOINTS.index("right_eye")]
EARS = [COCO_KEYPOINTS.index("left_ear"), COCO_KEYPOINTS.index("right_ear")]


def _person(x: float, feet_y: float, handedness: float, height: float = HEIGHT) -> Person:
    """A person ``height`` px tall whose network read them as seen from the front (``handedness`` < 0: the
    image-left member of each pair decoded as the right one) or from behind (> 0), with the decoded pairs
    accordingly: left members at x + 10 for a front view, at x - 10 for a back view."""
    keypoints = np.zeros((17, 3))
    keypoints[:, 0], keypoints[:, 1], keypoints[:, 2] = x, feet_y - HEIGHT / 2, 0.9
    side = -10.0 if handedness >= 0 else 10.0
    for left, right in PAIRS:
        keypoints[left, 0], keypoints[right, 0] = x + side, x - side
    return Person("r", 0.9, np.array([x - 20, feet_y - height, x + 20, feet_y]), keypoints, np.zeros((0, 0), bool),
                  (0, 0), np.full(len(PAIRS), handedness))


def _walk(tracker: Tracker, speed_px_per_s: float, handedness: float, frames: int = 10, fps: float = 10.0,
          x: float = 300.0, jitter: float = 0.0, seed: int = 0) -> list[Person]:
    """One person walking down the image at ``speed_px_per_s`` (negative: up), one frame at a time."""
    noise = np.random.default_rng(seed).normal(0.0, jitter, frames)
    return [tracker.update([_person(x, 300.0 + speed_px_per_s * k / fps + noise[k], handedness)], k / fps)[0]
            for k in range(frames)]


def _seen_from_behind(person: Person) -> bool:
    return person.keypoints[LEFT_SHOULDER, 0] < person.keypoints[RIGHT_SHOULDER, 0]


def test_the_speed_of_a_straight_walk_is_exact_and_its_error_floored_by_the_jitter():
    times = np.arange(8) / 10.0
    speed, error = foot_speed(times, 200.0 - 50.0 * times, HEIGHT, jitter_heights=0.02)
    assert speed == pytest.approx(-0.5)  # 50 px/s up the image, 100 px tall: half a height per second
    assert error == pytest.approx(0.02 / np.sqrt(((times - times.mean()) ** 2).sum()))
    assert foot_speed(np.zeros(3), np.zeros(3), HEIGHT, 0.02) == (0.0, float("inf"))


@pytest.mark.parametrize("speed, behind", [(-60.0, True), (60.0, False)])
def test_walking_away_is_seen_from_behind_and_walking_closer_from_the_front(speed, behind):
    # The network hedges and reads the wrong way: the motion corrects it once enough frames are seen.
    people = _walk(Tracker(), speed, handedness=0.05 if not behind else -0.05)
    assert len({person.track for person in people}) == 1
    assert all(person.facing == "appearance" for person in people[:3])  # fewer than 4 observations
    assert all(person.facing == "motion" and _seen_from_behind(person) == behind for person in people[3:])


def test_standing_still_leaves_the_network_s_facing():
    people = _walk(Tracker(), 0.0, handedness=-0.05)
    assert all(person.facing == "appearance" and not _seen_from_behind(person) for person in people)


def test_a_clear_walk_is_read_through_the_detections_jitter():
    people = _walk(Tracker(), -40.0, handedness=-0.5, jitter=2.0, frames=12)
    assert all(person.facing == "motion" and _seen_from_behind(person) for person in people[4:])


def test_a_confident_network_keeps_its_facing_unless_the_motion_is_clear():
    config = TrackingConfig()
    # A slow drift (2 px/s, within the jitter) does not overrule a network that is sure...
    drifting = _walk(Tracker(config), -2.0, handedness=-(config.trust_network + 0.2))
    assert all(person.facing == "appearance" and not _seen_from_behind(person) for person in drifting)
    # ...but a hedging network yields to it, and a clear walk overrules even a sure one.
    assert _walk(Tracker(config), -2.0, handedness=-0.05)[-1].facing == "motion"
    walking = _walk(Tracker(config), -60.0, handedness=-(config.trust_network + 0.2))
    assert walking[-1].facing == "motion" and _seen_from_behind(walking[-1])


@pytest.mark.parametrize("growth_per_s, walk", [(0.25, True), (1.0, False)])
def test_a_box_growing_faster_than_a_walk_allows_leaves_the_facing_to_appearance(growth_per_s, walk):
    # The box's top stays and its bottom drops, the box growing by ``growth_per_s`` of its log height a second: a
    # walk toward a camera at eye level, or, faster than any walk, a person stepping out from behind another.
    tracker, fps = Tracker(), 10.0
    people = []
    for k in range(10):
        height = HEIGHT * np.exp(growth_per_s * k / fps)
        people.append(tracker.update([_person(300.0, 200.0 + height, handedness=0.05, height=height)], k / fps)[0])
    assert all(person.facing == ("motion" if walk else "appearance") for person in people[4:])
    assert all(_seen_from_behind(person) != walk for person in people[4:])  # coming closer: seen from the front



def _read_by_the_facing_model(person: Person) -> Person:
    """``person`` as the runtime leaves someone the bundle's facing model ordered: the networks hedging beside it."""
    return replace(person, network_handedness=0.0)


@pytest.mark.parametrize("height, read", [(MIRRORED_FROM_PX + 20.0, True), (MIRRORED_FROM_PX - 20.0, True),
                                          (MIRRORED_FROM_PX + 20.0, False)])
def test_a_person_standing_faces_the_way_the_facing_model_reads_them_over_the_track(height, read):
    """Someone standing (no walk to read) whom the facing model reads from behind in seven frames of ten, and from
    the front, less surely, in the others: read by it, tall (read twice) or small (read once by the head's
    colours), their track's vote orders every frame as seen from behind
    (docs/decisions/0047-small-people-voted-over-the-track.md); ordered by the networks alone, each frame keeps its
    own reading."""
    tracker, readings = Tracker(), [0.6, -0.3, 0.6, 0.6, -0.3, 0.6, 0.6, -0.3, 0.6, 0.6]
    people = [_person(300.0, 300.0, reading, height=height) for reading in readings]
    people = [tracker.update([_read_by_the_facing_model(person) if read else person], k / 10.0)[0]
              for k, person in enumerate(people)]
    if read:
        assert all(_seen_from_behind(person) and person.facing == "track" for person in people)
    else:
        assert [_seen_from_behind(person) for person in people] == [reading > 0 for reading in readings]
        assert all(person.facing == "appearance" for person in people)


@pytest.mark.parametrize("reading, by_the_walk", [(-0.3, True), (-0.9, False)])
def test_a_clear_walk_decides_unless_the_facing_model_is_surely_the_other_way(reading, by_the_walk):
    """The walk's facing is right more often than the model's where the walk is clear
    (docs/decisions/0044-facing-voted-over-the-track.md): a person walking up the image is seen from behind though
    the model reads them from the front, unsurely. Read from the front surely (a vote of 0.9 against the
    ``vote_overrules_walk`` of 0.5) over the track, they are seen from the front: someone stepping back, or stopped
    and turned, still drifts on their feet (docs/decisions/0049-a-sure-vote-overrules-the-walk.md)."""
    tracker, height = Tracker(), MIRRORED_FROM_PX + 20.0
    people = [tracker.update([_read_by_the_facing_model(_person(300.0, 300.0 - 80.0 * k / 10.0, reading,
                                                                height=height))], k / 10.0)[0] for k in range(10)]
    if by_the_walk:
        assert all(person.facing == "motion" and _seen_from_behind(person) for person in people[4:])
    else:
        assert all(person.facing == "track" and not _seen_from_behind(person) for person in people)


def test_a_walk_decides_against_any_vote_where_the_vote_may_never_overrule_it():
    tracker = Tracker(TrackingConfig(vote_overrules_walk=float("inf")))
    people = [tracker.update([_read_by_the_facing_model(_person(300.0, 300.0 - 80.0 * k / 10.0, -0.9))], k / 10.0)[0]
              for k in range(10)]
    assert all(person.facing == "motion" and _seen_from_behind(person) for person in people[4:])


def test_a_sighting_of_no_height_is_read_without_a_numerical_warning():
    tracker = Tracker()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        people = [tracker.update([_person(300.0, 300.0 + 6.0 * k, handedness=0.05, height=0.0 if k == 5 else HEIGHT)],
                                 k / 10.0)[0] for k in range(8)]
    assert len({person.track for person in people}) == 1

@pytest.mark.parametrize("across_px_per_s, share", [(30.0, 0.4), (-150.0, -1.0), (0.0, 0.0)])
def test_a_walker_s_face_turns_the_way_they_cross_the_view(across_px_per_s, share):
    """Nose and eyes go ahead of the ears' midpoint by the body model's distances times the share of the walk that
    crosses the view (0.3 heights a second of the 0.75 of a full profile: 0.4), the eyes' spacing kept."""
    tracker, fps, ears_x = Tracker(), 10.0, 300.0
    for k in range(8):
        person = _person(ears_x + across_px_per_s * k / fps, 300.0 + 60.0 * k / fps, handedness=0.05)
        person.keypoints[[NOSE, *EYES], 0] += [5.0, 1.0, 9.0]  # the network's own guesses, away from the ears
        walker = tracker.update([person], k / fps)[0]
    assert walker.facing == "motion"
    ears = float(walker.keypoints[EARS, 0].mean())
    assert walker.keypoints[NOSE, 0] - ears == pytest.approx(FACE_AHEAD_OF_EARS["nose"] * HEIGHT * share)
    eyes = walker.keypoints[EYES, 0]
    assert eyes.mean() - ears == pytest.approx(FACE_AHEAD_OF_EARS["eyes"] * HEIGHT * share)
    assert abs(eyes[0] - eyes[1]) == pytest.approx(abs(person.keypoints[EYES[0], 0] - person.keypoints[EYES[1], 0]))

def test_facing_exchanges_only_the_pairs_the_network_ordered_the_other_way():
    person = _person(300.0, 300.0, handedness=0.5)
    person.pair_handedness[0] = -0.5  # the eyes: decoded as seen from the front
    turned = facing_pairs(person, seen_from_behind=True)
    (left_eye, right_eye), rest = PAIRS[0], PAIRS[1:]
    np.testing.assert_array_equal(turned[[left_eye, right_eye]], person.keypoints[[right_eye, left_eye]])
    for left, right in rest:
        np.testing.assert_array_equal(turned[[left, right]], person.keypoints[[left, right]])


def test_people_passing_side_by_side_keep_their_tracks():
    tracker = Tracker()
    for k in range(12):
        # Two people 60 px apart (0.6 heights) walking in opposite directions across the image.
        people = tracker.update([_person(200.0 + 20.0 * k, 300.0 - 5.0 * k, 0.0),
                                 _person(460.0 - 20.0 * k, 300.0 + 5.0 * k, 0.0)][:: -1 if k % 2 else 1], k / 10.0)
        walking_up_first = sorted(people, key=lambda p: p.box[3])  # the one walking up has the higher feet
        assert [person.track for person in walking_up_first] == [1, 2]
    assert _seen_from_behind(walking_up_first[0]) and not _seen_from_behind(walking_up_first[1])


def test_a_track_unseen_for_too_long_ends_and_time_must_move_on():
    tracker = Tracker(TrackingConfig(max_gap_s=0.5))
    first = tracker.update([_person(300.0, 300.0, 0.0)], 0.0)[0]
    assert tracker.update([_person(300.0, 300.0, 0.0)], 0.4)[0].track == first.track
    assert tracker.update([_person(300.0, 300.0, 0.0)], 1.0)[0].track != first.track
    with pytest.raises(ValueError, match="time order"):
        tracker.update([], 1.0)


def test_a_person_too_far_from_every_track_starts_a_new_one():
    tracker = Tracker()
    tracker.update([_person(100.0, 300.0, 0.0)], 0.0)
    # 0.1 s later, 1.0 height away: beyond 0.15 + 1.5 * 0.1 heights.
    assert tracker.update([_person(200.0, 300.0, 0.0)], 0.1)[0].track == 2


def test_a_tracked_person_is_written_with_track_facing_and_the_network_s_handedness():
    people = _walk(Tracker(), -60.0, handedness=-0.1, frames=5)
    written = people[-1].to_dict()
    assert written["track"] == 1 and written["facing"] == "motion" and written["handedness"] == pytest.approx(-0.1)
    assert "track" not in _person(0.0, 100.0, 0.2).to_dict()


def _seen_then_lost(tracker: Tracker, seen: int, lost: int, fps: float = 10.0) -> list[list[Person]]:
    """A person walking right at 50 px/s, seen in ``seen`` frames and then in none for ``lost`` frames."""
    return [tracker.update([_person(300.0 + 50.0 * k / fps, 300.0, 0.5)] if k < seen else [], k / fps)
            for k in range(seen + lost)]


def test_a_person_lost_for_a_moment_is_carried_where_their_motion_puts_them():
    config = TrackingConfig()
    frames = _seen_then_lost(Tracker(config), seen=5, lost=2)
    last_seen, (carried,) = frames[4][0], frames[6]
    assert carried.coasted and not last_seen.coasted and carried.track == last_seen.track
    np.testing.assert_allclose(carried.box - last_seen.box, [10.0, 0.0, 10.0, 0.0], atol=1e-9)  # 0.2 s at 50 px/s
    np.testing.assert_allclose(carried.keypoints[:, 0] - last_seen.keypoints[:, 0], 10.0, atol=1e-9)
    assert carried.score == pytest.approx(last_seen.score * np.exp(-0.2 / config.coast_score_decay_s))
    assert carried.mask.size == 0 and carried.to_dict()["coasted"] is True


def test_only_confirmed_tracks_lost_briefly_are_carried():
    config = TrackingConfig(coast_s=0.5, coast_min_observations=3)
    assert all(len(people) == 1 for people in _seen_then_lost(Tracker(config), seen=3, lost=5))  # 0.5 s at most
    assert _seen_then_lost(Tracker(config), seen=3, lost=6)[-1] == []  # 0.6 s unseen
    assert _seen_then_lost(Tracker(config), seen=2, lost=1)[-1] == []  # seen twice: perhaps a false alarm
    assert _seen_then_lost(Tracker(TrackingConfig(coast_s=0.0)), seen=5, lost=1)[-1] == []


def test_given_the_frame_a_person_carried_out_of_it_walked_out_and_one_at_its_edge_is_clipped():
    """A person walking right at 50 px/s, seen at x 300-320 and then lost: 0.2 s later their track puts their feet
    at x 330, their box at 310-350."""
    def carried(width: int | None) -> list[Person]:
        tracker = Tracker(TrackingConfig(appearance_weight=0.0))
        frame = None if width is None else np.zeros((480, width, 3), np.uint8)
        people = [tracker.update([_person(300.0 + 5.0 * k, 300.0, 0.5)] if k < 5 else [], k / 10.0, frame)
                  for k in range(7)]
        return people[-1]

    (unclipped,) = carried(None)  # without the frame nothing is known of its edges
    assert unclipped.coasted and unclipped.box[2] == pytest.approx(350.0)
    (at_edge,) = carried(340)  # feet inside: boxed as the camera shows them
    assert at_edge.coasted and at_edge.box[[0, 2]].tolist() == pytest.approx([310.0, 339.5])
    assert carried(325) == []  # feet beyond the edge: walked out


def test_a_carried_box_on_top_of_a_person_seen_is_not_reported_twice():
    def last_frame(shift_px: float) -> list[Person]:
        # A gate of 1 % of a height: the person seen again a little aside starts a new track, and the old track
        # is unseen in that frame.
        tracker = Tracker(TrackingConfig(gate_heights=0.01, max_speed_heights_per_s=0.0))
        for k in range(5):
            tracker.update([_person(300.0, 300.0, 0.5)], k / 10.0)
        return tracker.update([_person(300.0 + shift_px, 300.0, 0.5)], 0.5)

    (alone,) = last_frame(5.0)  # IoU 0.78 with the old track's box: the same person
    assert alone.track == 2 and not alone.coasted
    assert [person.coasted for person in last_frame(15.0)] == [False, True]  # IoU 0.45: perhaps someone else


def test_a_long_track_keeps_only_its_window_and_its_identity():
    tracker = Tracker()
    for k in range(600):  # a minute at 10 frames/s
        (person,) = tracker.update([_person(300.0, 300.0 - 0.1 * k, 0.0)], k / 10.0)
    assert person.track == 1 and person.facing == "motion" and _seen_from_behind(person)
    assert len(tracker.tracks) == 1 and len(tracker.tracks[0].times) <= 11


def test_people_crossing_close_keep_their_tracks_by_their_velocity():
    tracker = Tracker()
    for k in range(16):
        # 20 px (0.2 heights) a frame toward each other, 5 px apart vertically: as they cross, matching each
        # person to the nearest last position exchanges them; matching to where each track is heading does not.
        walking_right = _person(200.0 + 20.0 * k, 300.0, 0.0)
        walking_left = _person(500.0 - 20.0 * k, 305.0, 0.0)
        people = tracker.update([walking_right, walking_left], k / 10.0)
        assert [person.track for person in people] == [1, 2]


def test_weak_people_only_continue_tracks_seen_before():
    def weak(person: Person) -> Person:
        return replace(person, score=0.15, weak=True)

    tracker = Tracker()
    for k in range(3):
        tracker.update([_person(300.0 + 5.0 * k, 300.0, 0.5)], k / 10.0)
    # The person fades below the threshold and a weak peak appears far from everyone: the first continues the
    # track with its own box, the second is dropped and starts no track.
    people = tracker.update([weak(_person(315.0, 300.0, 0.5)), weak(_person(600.0, 300.0, 0.5))], 0.3)
    assert [(p.track, p.weak, p.coasted) for p in people] == [(1, True, False)]
    assert len(tracker.tracks) == 1
    # A weak peak never starts a track, so it cannot continue one either.
    fresh = Tracker()
    assert fresh.update([weak(_person(300.0, 300.0, 0.5))], 0.0) == [] and fresh.tracks == []


def _dressed(frame: np.ndarray, x: float, top: tuple[int, int, int], bottom: tuple[int, int, int]) -> Person:
    """A person standing at ``x`` (feet at y 300) whose mask is a strip 10 px wide down their middle, painted into
    ``frame`` in ``top`` above the waist and ``bottom`` below it."""
    person = _person(x, 300.0, 0.0)
    left, head = int(x) - 5, int(300.0 - HEIGHT)
    frame[head:head + 50, left:left + 10] = top
    frame[head + 50:300, left:left + 10] = bottom
    return replace(person, mask=np.ones((int(HEIGHT), 10), bool), mask_origin=(left, head))


def test_a_person_s_colours_are_counted_above_and_below_the_waist():
    frame = np.zeros((400, 600, 3), np.uint8)
    person = _dressed(frame, 300.0, top=(250, 10, 10), bottom=(10, 10, 250))
    look = appearance(person, frame)
    assert look.shape == (2, 64) and np.allclose(look.sum(axis=1), 1.0)
    assert look[0].argmax() == 3 * 16 and look[1].argmax() == 3  # red above, blue below (4 levels a channel)
    assert appearance_distance(look, look) == pytest.approx(0.0)
    assert appearance_distance(look, look[::-1]) == pytest.approx(1.0)  # the same colours the other way up
    assert appearance(replace(person, mask=np.zeros((0, 0), bool)), frame) is None


@pytest.mark.parametrize("weight, kept", [(0.0, False), (0.3, True)])
def test_clothing_colours_keep_two_people_their_tracks_where_their_positions_swap(weight, kept):
    """Two people 0.4 heights apart stand still; then each is found nearer the other's place (as a detector's
    boxes jitter in a group). By position alone the tracks swap; their clothes keep them."""
    tracker = Tracker(TrackingConfig(appearance_weight=weight))
    red, blue = ((250, 10, 10), (250, 10, 10)), ((10, 10, 250), (10, 200, 10))
    for k, (x_red, x_blue) in enumerate([(300.0, 340.0)] * 3 + [(325.0, 315.0)]):
        frame = np.zeros((400, 600, 3), np.uint8)
        people = tracker.update([_dressed(frame, x_red, *red), _dressed(frame, x_blue, *blue)], k / 10.0, frame)
    assert ([person.track for person in people] == [1, 2]) == kept
