"""People coming into view: how soon after their first scored frame a detector finds them (numpy only).

A camera's people walk in at the frame's edges, cut by it, and a user who counts them or draws lines across the view
needs them from the frame they appear in, not once they are whole. Recall by the frame's edge
(:meth:`vc.evaluation.misses.MissAnalysis.recall_by_edge`) counts each frame's cut people; this follows each person
from the frame they come into view.

1. Every ground-truth identity of :func:`vc.evaluation.misses.analyse_misses`' people (their ``identity``) is followed
   over the scored frames in order. Identities already there in the first scored frame did not come into view
   while scored and are left out.
2. A person **walks in** when their first box lies within :data:`WALK_IN_HEIGHTS` of their own height of a frame edge
   (cut by it or near it); any other newcomer **appears inside the view** (from behind something, or where the
   annotation starts to count them).
3. Each arrival is **found** in the first scored frame, from their first on, in which the detector's kept detections
   (the operating point) match them; the delay is counted in video frames (and seconds, given the frame rate). A
   person never matched while annotated is never found.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from vc.evaluation.misses import CUT_PX, PersonOutcome

#: A newcomer whose first box lies nearer a frame edge than this share of their height walked in by that edge.
WALK_IN_HEIGHTS = 0.5
#: Arrivals found within this many seconds of their first scored frame count as found promptly.
PROMPT_S = 1.0
WALKING_IN, APPEARING_INSIDE = "walking in at an edge", "appearing inside the view"


@dataclass(frozen=True)
class Arrival:
    """One person coming into view during the scored frames."""

    identity: int
    first_frame: int  # their first scored frame
    edge_heights: float  # their first box's distance to the nearest frame edge, in their heights (<= 0: cut)
    found_frame: int | None  # the first scored frame from ``first_frame`` on in which they are found; None: never

    @property
    def walked_in(self) -> bool:
        return self.edge_heights < WALK_IN_HEIGHTS

    @property
    def delay_frames(self) -> int | None:
        return None if self.found_frame is None else self.found_frame - self.first_frame

    def to_dict(self) -> dict:
        return {"identity": self.identity, "first_frame": self.first_frame,
                "edge_heights": round(self.edge_heights, 3), "found_frame": self.found_frame}


def arrivals(people: Sequence[PersonOutcome], frames: Sequence[int]) -> list[Arrival]:
    """Steps 1-3 for ``people`` (every person of every scored frame, with their ``identity`` and ``edge_px``) over
    the scored ``frames``. People without an identity or an edge distance are not followed."""
    by_identity: dict[int, list[PersonOutcome]] = {}
    for person in people:
        if person.identity is not None and person.edge_px is not None:
            by_identity.setdefault(person.identity, []).append(person)
    first_scored = min(frames) if len(frames) else None
    result = []
    for identity, sightings in sorted(by_identity.items()):
        sightings = sorted(sightings, key=lambda person: person.frame)
        first = sightings[0]
        if first.frame == first_scored:
            continue
        edge_heights = (first.edge_px if first.edge_px > CUT_PX else 0.0) / max(first.height, 1.0)
        found = next((person.frame for person in sightings if person.outcome == "found"), None)
        result.append(Arrival(identity, first.frame, edge_heights, found))
    return result


def summarise(followed: Sequence[Arrival], fps: float | None) -> dict:
    """Per kind of arrival (:data:`WALKING_IN`, :data:`APPEARING_INSIDE`): how many, how many found in their first
    scored frame, within :data:`PROMPT_S` (given ``fps``) and never, and the median delay of those found, in frames
    and seconds."""
    summary = {}
    for kind, selected in ((WALKING_IN, [a for a in followed if a.walked_in]),
                           (APPEARING_INSIDE, [a for a in followed if not a.walked_in])):
        delays = [a.delay_frames for a in selected if a.delay_frames is not None]
        entry = {"people": len(selected), "found_in_first_frame": sum(delay == 0 for delay in delays),
                 "never_found": len(selected) - len(delays),
                 "median_delay_frames": float(np.median(delays)) if delays else None}
        if fps:
            entry["found_within"] = {"seconds": PROMPT_S, "people": sum(delay / fps <= PROMPT_S for delay in delays)}
            entry["median_delay_s"] = round(float(np.median(delays)) / fps, 3) if delays else None
        summary[kind] = entry
    return summary
