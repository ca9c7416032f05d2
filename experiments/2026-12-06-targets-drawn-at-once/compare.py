"""The training targets of every window a compile's region networks learn from, drawn by the codec as it was
before (main at 55b070c) and as it is now: equal bytes, and the time each takes (frozen experiment).

    PYTHONPATH=../../src python compare.py COMPILE_FOLDER REGION [--draws N] >> results/REGION.txt

The windows are the compile's own: its renders, its training config (``compile_config.yaml``) and seed, the draws
its trainer makes (steps x batch size), cut as ``TrainingStream`` cuts them. Each window is encoded by both codecs
in turn, in one process, and the time of each is summed over the windows.
"""

from __future__ import annotations

import argparse
import importlib.util
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import vc.model.codec as today
from vc.model.data import TrainingStream, shifted
from vc.render.dataset import open_region
from vc.stages.config import read_config

BEFORE = "55b070c"


def module_before(path: str, name: str) -> object:
    """The module at ``path`` (under ``src/``) as it was at :data:`BEFORE`, imported as ``name`` beside today's."""
    source = subprocess.run(["git", "show", f"{BEFORE}:src/{path}"], capture_output=True, text=True, check=True,
                            cwd=Path(__file__).parent).stdout
    file = Path(tempfile.mkdtemp()) / f"{name}.py"
    file.write_text(source)
    spec = importlib.util.spec_from_file_location(name, file)
    module = sys.modules[name] = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("compile", type=Path)
    parser.add_argument("region")
    parser.add_argument("--draws", type=int, help="the first N draws (default: every draw the trainer makes)")
    args = parser.parse_args()
    config = read_config(args.compile / "compile_config.yaml").train.train_config()
    data = open_region(args.compile / "renders", args.region, config.held_out_fraction)
    stream = TrainingStream(data.train, config.codec, data.input_size, config.crop, None, config.seed)
    before = module_before("vc/model/codec.py", "codec_before")
    draws = args.draws or config.steps * config.batch_size
    seconds, differing, people = {"before": 0.0, "today": 0.0}, 0, 0
    for draw in range(draws):
        index = stream.sample_index(draw)
        image, instances = stream._decoded(index)
        rng = np.random.default_rng([stream.seed, 1 << 32, draw])  # the stream's own window for this draw
        x0, y0, width, height = config.crop.window(stream.samples[index].annotations, stream.input_size,
                                                   config.codec.stride, rng)
        annotations = [shifted(annotation, -x0, -y0) for annotation in stream.samples[index].annotations]
        window = instances[y0:y0 + height, x0:x0 + width]
        people += len(annotations)
        maps = {}
        for name, module in (("before", before), ("today", today)):
            start = time.perf_counter()
            maps[name] = module.encode(annotations, window, config.codec)
            seconds[name] += time.perf_counter() - start
        differing += maps["before"].shape != maps["today"].shape or maps["before"].tobytes() != maps["today"].tobytes()
    print(f"{args.compile.name} {args.region}: {draws} windows, {people / draws:.1f} people a window, "
          f"{differing} with targets that differ; encode {seconds['before']:.1f} s before, {seconds['today']:.1f} s "
          f"today ({seconds['today'] / seconds['before']:.2f}x)")


if __name__ == "__main__":
    main()
