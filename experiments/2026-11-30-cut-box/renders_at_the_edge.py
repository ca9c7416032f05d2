"""How often a compile's renders show a person the crop's side edge cuts, cut to a sliver (narrower than
:data:`SLIVER` of their height), or with their centre beyond the edge (the people a network must learn to find as
they walk in), per region (frozen experiment, decision 0031).

    PYTHONPATH=../.. python renders_at_the_edge.py RUN/renders > results/renders_at_the_edge_tud_seed0.json
    PYTHONPATH=../.. python renders_at_the_edge.py --real > results/real_at_the_edge.json

``--real``: the same counts for the annotated people of the real frames the decisions are measured on (boxes cut
by the frame's side; the real height is the annotated box's, so a sliver is narrower than 0.2 of that).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from vc.evaluation.mot import read_mot_boxes

DATA = Path(__file__).resolve().parents[2].parent / "shared" / "data"
#: camera -> (ground truth, frame width, the frames scored)
REAL = {"tud": (DATA / "tud_stadtmitte" / "gt_world.txt", 640, range(1, 180)),
        "pets": (DATA / "pets09_s2l1" / "gt_dev_frames_0001-0400.txt", 768, range(1, 401, 5))}

#: A box within this many pixels of a crop's side is cut by it (as vc.evaluation.misses.CUT_PX for frames).
CUT_PX = 2.0
#: A person the edge cuts to less than this share of their (amodal) height in width is a sliver.
SLIVER = 0.2


def count(renders: Path) -> dict:
    regions = {}
    for region in sorted(path for path in renders.iterdir() if path.is_dir()):
        people = cut = slivers = centre_beyond = 0
        for shard in sorted(region.glob("shard-*/annotations.json")):
            data = json.loads(shard.read_text())
            widths = {image["id"]: image["width"] for image in data["images"]}
            for person in data["annotations"]:
                people += 1
                width = widths[person["image_id"]]
                x, _, box_width, _ = person["bbox"]
                if x <= CUT_PX or x + box_width >= width - CUT_PX:
                    cut += 1
                    slivers += box_width < SLIVER * person["amodal_bbox"][3]
                    centre = person.get("center")
                    centre_beyond += centre is not None and not 0.0 <= centre[0] <= width
        regions[region.name] = {"people": people, "cut_by_a_side": cut, "slivers": slivers,
                                "centre_beyond_a_side": centre_beyond}
    return regions


def count_real() -> dict:
    cameras = {}
    for camera, (path, width, frames) in REAL.items():
        truth = read_mot_boxes(path)
        boxes = [box for frame in frames for box in truth.get(frame, [])]
        cut = [box for box in boxes if box[0] <= CUT_PX - 0.5 or box[2] >= width - 0.5 - CUT_PX]
        cameras[camera] = {"people": len(boxes), "cut_by_a_side": len(cut),
                           "slivers": int(sum(box[2] - box[0] < SLIVER * (box[3] - box[1]) for box in cut))}
    return cameras


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("renders", type=Path, nargs="?")
    parser.add_argument("--real", action="store_true")
    args = parser.parse_args()
    print(json.dumps(count_real() if args.real else count(args.renders), indent=1))


if __name__ == "__main__":
    main()
