"""Detections drawn onto frames: what a person checks by eye (vc-run overlays, vc-eval contact sheets)."""

from __future__ import annotations

import cv2
import numpy as np

from vc.deploy.runtime import Person
from vc.evaluation.misses import OUTSIDE_ANNOTATED_AREA, FalsePositive, PersonOutcome
from vc.keypoints import COCO_SKELETON

#: Distinct colours (RGB) cycled over people.
PALETTE = np.array([(230, 25, 75), (60, 180, 75), (255, 225, 25), (0, 130, 200), (245, 130, 48), (145, 30, 180),
                    (70, 240, 240), (240, 50, 230), (210, 245, 60), (250, 190, 212)], np.uint8)
TRUTH_COLOUR = (255, 255, 255)
#: Ground-truth boxes by outcome in an error sheet, and the false positives' colour (RGB).
OUTCOME_COLOURS = {"found": (255, 255, 255), "near miss": (255, 160, 0), "missed": (255, 0, 0)}
FALSE_POSITIVE_COLOUR = (255, 0, 255)
#: What a false positive's kind is labelled with in an error sheet (vc.evaluation.misses.FALSE_POSITIVE_KINDS).
FALSE_POSITIVE_LABELS = {"duplicate": "dup", "merged": "mrg", "misplaced": "mis", OUTSIDE_ANNOTATED_AREA: "out",
                         "background": "bg"}
#: The area the ground truth annotates, outlined in an error sheet (RGB).
ANNOTATED_AREA_COLOUR = (0, 255, 255)
MASK_OPACITY = 0.4


def _point(xy: np.ndarray) -> tuple[int, int]:
    return int(round(float(xy[0]))), int(round(float(xy[1])))


def draw_people(frame: np.ndarray, people: list[Person], keypoint_threshold: float = 0.2,
                truth_boxes: np.ndarray | None = None) -> np.ndarray:
    """A copy of ``frame`` (RGB uint8) with each person's mask tinted, box, confident skeleton and score; truth
    boxes (x0, y0, x1, y1), when given, in thin white underneath. A tracked person keeps their track's colour from
    frame to frame and is labelled with its number; one carried by their track unseen has a thin box."""
    image = frame.copy()
    colours = [PALETTE[(index if person.track is None else person.track) % len(PALETTE)]
               for index, person in enumerate(people)]
    for person, colour in zip(people, colours, strict=True):
        x, y = person.mask_origin
        height, width = person.mask.shape
        patch = image[y:y + height, x:x + width]
        patch[person.mask] = (patch[person.mask] * (1 - MASK_OPACITY) + colour * MASK_OPACITY).astype(np.uint8)
    for box in np.asarray(truth_boxes if truth_boxes is not None else [], np.float64).reshape(-1, 4):
        cv2.rectangle(image, _point(box[:2]), _point(box[2:]), TRUTH_COLOUR, 1, cv2.LINE_AA)
    for person, colour_array in zip(people, colours, strict=True):
        colour = tuple(int(c) for c in colour_array)
        cv2.rectangle(image, _point(person.box[:2]), _point(person.box[2:]), colour, 1 if person.coasted else 2,
                      cv2.LINE_AA)
        confident = person.keypoints[:, 2] >= keypoint_threshold
        for a, b in COCO_SKELETON:
            if confident[a] and confident[b]:
                cv2.line(image, _point(person.keypoints[a]), _point(person.keypoints[b]), colour, 1, cv2.LINE_AA)
        for keypoint in person.keypoints[confident]:
            cv2.circle(image, _point(keypoint), 2, colour, -1, cv2.LINE_AA)
        label = f"{person.score:.2f}" if person.track is None else f"#{person.track} {person.score:.2f}"
        cv2.putText(image, label, (int(person.box[0]), max(int(person.box[1]) - 3, 10)),
                    cv2.FONT_HERSHEY_SIMPLEX, 0.4, colour, 1, cv2.LINE_AA)
    return image


def draw_errors(frame: np.ndarray, number: int, people: list[Person], outcomes: list[PersonOutcome],
                false_positives: list[FalsePositive], annotated_area: np.ndarray | None = None) -> np.ndarray:
    """A copy of ``frame`` with the detections (:func:`draw_people`), each ground-truth person's box in the colour of
    its outcome (white found, orange near miss, red missed), each false positive in magenta labelled with its kind
    (:data:`FALSE_POSITIVE_LABELS`), the outline of the area the ground truth annotates (a polygon (K, 2), when
    given) and a caption with the frame number and its errors."""
    image = draw_people(frame, people)
    if annotated_area is not None:
        cv2.polylines(image, [np.round(annotated_area).astype(np.int32)], True, ANNOTATED_AREA_COLOUR, 1, cv2.LINE_8)
    for person in outcomes:
        thickness = 1 if person.outcome == "found" else 2
        cv2.rectangle(image, _point(person.box[:2]), _point(person.box[2:]), OUTCOME_COLOURS[person.outcome],
                      thickness, cv2.LINE_AA)
    for false in false_positives:
        cv2.rectangle(image, _point(false.box[:2]), _point(false.box[2:]), FALSE_POSITIVE_COLOUR, 1, cv2.LINE_AA)
        cv2.putText(image, FALSE_POSITIVE_LABELS[false.kind], (int(false.box[0]) + 2, int(false.box[3]) - 3),
                    cv2.FONT_HERSHEY_SIMPLEX, 0.45, FALSE_POSITIVE_COLOUR, 1, cv2.LINE_AA)
    missed = sum(person.outcome == "missed" for person in outcomes)
    near = sum(person.outcome == "near miss" for person in outcomes)
    caption = f"frame {number}: {missed} missed, {near} near, {len(false_positives)} false"
    cv2.putText(image, caption, (8, 24), cv2.FONT_HERSHEY_SIMPLEX, 0.7, (0, 0, 0), 4, cv2.LINE_AA)
    cv2.putText(image, caption, (8, 24), cv2.FONT_HERSHEY_SIMPLEX, 0.7, (255, 255, 255), 1, cv2.LINE_AA)
    return image


def contact_sheet(images: list[np.ndarray], columns: int = 4, width: int = 1600) -> np.ndarray:
    """Images (all the same size) tiled ``columns`` wide and scaled so the sheet is ``width`` pixels wide."""
    if not images:
        raise ValueError("no images for a contact sheet")
    height, frame_width = images[0].shape[:2]
    tile_width = width // columns
    tile_height = round(height * tile_width / frame_width)
    rows = -(-len(images) // columns)
    sheet = np.zeros((rows * tile_height, columns * tile_width, 3), np.uint8)
    for index, image in enumerate(images):
        row, column = divmod(index, columns)
        sheet[row * tile_height:(row + 1) * tile_height, column * tile_width:(column + 1) * tile_width] = \
            cv2.resize(image, (tile_width, tile_height), interpolation=cv2.INTER_AREA)
    return sheet
