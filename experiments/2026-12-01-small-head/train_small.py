"""A head network narrower than today's r0, to run beside it (frozen experiment, issue 57 item 2).

    PYTHONPATH=../.. python train_small.py RUN RENDERS OUT --width W

Trains r0's head network exactly as ``../2026-12-01-visible-anchor/anchors.py train ... --anchor head
--centre-sigma 0.05 --offset-unit 20 --size-unit 20`` does (decision 0035's network, the one 0036's union adds), with
the network ``W`` channels wide instead of RUN's (32). Writes OUT/checkpoints/r0.pt. (Run as measured:
``train_small.py RUN RENDERS r0 -o OUT --width 16``, the same training.)
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent.parent / "2026-12-01-visible-anchor"))
import anchors  # noqa: E402

from vc.model.trainer import Checkpoint  # noqa: E402

HEAD_SETTINGS = {"anchor": "head", "hidden_weight": 0.0, "steps_factor": 1.0, "centre_sigma": 0.05,
                 "offset_unit": 20.0, "size_unit": 20.0}


def narrowed(load, width: int):
    """``load`` (a checkpoint reader) whose checkpoints' training config asks for a network ``width`` wide."""
    def load_narrowed(*args, **kwargs) -> Checkpoint:
        checkpoint = load(*args, **kwargs)
        config = checkpoint.config
        checkpoint.__dict__["config"] = dataclasses.replace(
            config, network=dataclasses.replace(config.network, width=width))  # the cached property's slot
        return checkpoint
    return load_narrowed


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    for name, help_text in (("run", "a compile's run folder"), ("renders", "its renders"),
                            ("out", "where OUT/checkpoints/r0.pt is written")):
        parser.add_argument(name, type=Path, help=help_text)
    parser.add_argument("--width", type=int, required=True, help="channels (today's r0: 32)")
    args = parser.parse_args()
    anchors.load_checkpoint = narrowed(anchors.load_checkpoint, args.width)
    anchors.train(args.run, args.renders, "r0", args.out, **HEAD_SETTINGS)


if __name__ == "__main__":
    main()
